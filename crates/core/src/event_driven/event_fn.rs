//! The event functions' identities: which contact or hysteretic element, which crossing.

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum EventFn {
    /// g_N of an open contact (closing: an impact).
    Gap(usize),
    /// λ_N of a closed contact (detachment).
    Release(usize),
    /// μ λ_N − |λ_T| of a sticking contact (stick → slip).
    StickSlip(usize),
    /// s ġ_T of a sliding contact (slip → stick).
    SlideStop(usize),
    /// e − e_lower of a hysteretic element (branch end).
    Lower(usize),
    /// e_upper − e of a hysteretic element (branch end).
    Upper(usize),
    /// d ė of a hysteretic element (load reversal).
    Reversal(usize),
    /// width − g_N of the seat of `scene.seats[k]` (the deck end leaves its seat).
    Unseat(usize),
}

impl EventFn {
    /// A hysteretic branch event (not a contact event).
    pub(super) fn is_branch(self) -> bool {
        matches!(
            self,
            EventFn::Lower(_) | EventFn::Upper(_) | EventFn::Reversal(_)
        )
    }

    /// Its value is read from the bodies' motion alone (λ_N and the stick margin need the
    /// dynamics).
    pub(super) fn probed(self) -> bool {
        !matches!(self, EventFn::Release(_) | EventFn::StickSlip(_))
    }
}

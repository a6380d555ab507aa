//! The law of a contact: Coulomb friction and Newton restitution (paper eq. 2–4, 9).

/// The law of a contact (paper eq. 2–4, 9): Coulomb friction μ, |λ_T| ≤ μ λ_N with
/// λ_T = −μ s λ_N while sliding in direction s = sign ġ_T, and Newton restitution ε
/// (ġ_N⁺ = −ε ġ_N⁻ at an impact, eq. 4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    /// Coulomb coefficient μ.
    pub mu: f64,
    /// Newton restitution ε.
    pub restitution: f64,
}

impl ContactLaw {
    /// No friction (μ = 0; a model refuses μ < 0): no tangential rows in either LCP.
    #[inline]
    pub fn frictionless(&self) -> bool {
        self.mu.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
    }

    /// The friction force while sliding in direction `s`: λ_T = −μ s λ_N.
    #[inline]
    pub(crate) fn sliding_force(&self, s: f64, lam_n: f64) -> f64 {
        coulomb::sliding_force(self.mu, s, lam_n)
    }

    /// How far a sticking force lies inside the friction cone: μ λ_N − |λ_T| (< 0: it slips).
    #[inline]
    pub(crate) fn stick_margin(&self, lam_n: f64, lam_t: f64) -> f64 {
        coulomb::stick_margin(self.mu, lam_n, lam_t)
    }

    /// λ_T brought back onto the cone |λ_T| ≤ μ λ_N (a return map).
    #[inline]
    pub(crate) fn onto_cone(&self, lam_n: f64, lam_t: f64) -> f64 {
        coulomb::onto_cone(self.mu, lam_n, lam_t)
    }
}

/// Coulomb's law by its coefficient (the LCPs' per-row μ; [`ContactLaw`] for a contact).
pub mod coulomb {
    /// The friction force of a contact sliding in direction `s`: λ_T = −μ s λ_N.
    #[inline]
    pub(crate) fn sliding_force(mu: f64, s: f64, lam_n: f64) -> f64 {
        -mu * s * lam_n
    }

    /// How far a sticking force lies inside the friction cone: μ λ_N − |λ_T| (< 0: it slips).
    #[inline]
    pub(crate) fn stick_margin(mu: f64, lam_n: f64, lam_t: f64) -> f64 {
        mu * lam_n - lam_t.abs()
    }

    /// λ_T brought back onto the cone |λ_T| ≤ μ λ_N (a return map).
    #[inline]
    pub(crate) fn onto_cone(mu: f64, lam_n: f64, lam_t: f64) -> f64 {
        if lam_t.abs() > mu * lam_n {
            mu * lam_n * lam_t.signum()
        } else {
            lam_t
        }
    }
}

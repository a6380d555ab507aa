//! Recorded accelerograms → support motions for multi-support excitation.
//!
//! Readers: PEER NGA `.AT2` ([`read_at2`]) and two-column `t a` text ([`read_two_column`]).
//! Processing ([`GroundMotion::from_samples`]), in this order:
//!
//! 1. time scaling `t' = t·time_scale` (similitude: 1/4 scale → 0.5; accelerations unchanged);
//! 2. baseline correction ([`Baseline`]): fit to the displacement, subtract its second
//!    derivative at the nodes (Boore 2001; Boore & Bommer 2005);
//! 3. cosine (half-Hann) taper of `taper` s at both ends (processed time);
//! 4. `pad` s of zero acceleration appended;
//! 5. exact end correction (with a polynomial baseline only): two smooth shapes vanishing at
//!    both record ends are added to the acceleration, their weights solved so that the
//!    exactly integrated final velocity and displacement are zero (see [`END_TOLERANCE`]);
//! 6. amplitude scaling (`target_pga` or `scale`), last, so the processed PGA equals the
//!    target and the drift stays zero (both steps are linear).
//!
//! A `window` [s, e] (in the run's time, lag included) cuts the time-scaled samples after
//! step 1: steps 2–6 run once on the whole record, for the factor of step 6 only (the target
//! PGA is the whole record's), then steps 2–5 on the samples inside [s, e], then that factor.
//! Before step 2 the cut is the same scaled acceleration at the same times; after, it starts
//! at rest at s, its first sample (at or after s) at t = that time − s, and ends at rest.
//! [`GroundMotion::strong_motion_window`] gives the 5–95 % Arias window of a motion in that
//! time axis.
//!
//! Acceleration is piecewise linear between samples; velocity and displacement are its exact
//! integrals (piecewise quadratic / cubic), so `d' = v`, `v' = a` hold at every `t`.
//!
//! References: D. M. Boore (2001), BSSA 91(5) 1199–1211; D. M. Boore & J. J. Bommer (2005),
//! Soil Dyn. Earthq. Eng. 25, 93–115; A. Arias (1970); M. D. Trifunac & A. G. Brady (1975),
//! BSSA 65(3) 581–626 (5–95 % significant duration); PEER NGA AT2 format.

mod error;
mod motion;
mod processing;
mod readers;
mod stats;

pub use error::ExcitationError;
pub use motion::GroundMotion;
pub use processing::{Baseline, END_TOLERANCE, Processing};
pub use readers::{G, MAX_SAMPLES, Record, parse_at2, read_any, read_at2, read_two_column};
pub use stats::MotionStats;

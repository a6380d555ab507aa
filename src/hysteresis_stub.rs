//! Temporary stub (linear only) until the hysteresis module lands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branch { pub u_ref: f64, pub f_ref: f64, pub stiffness: f64, pub lower: f64, pub upper: f64, pub direction: f64, pub ends_on_reversal: bool }
impl Branch { pub fn force(&self, u: f64) -> f64 { self.f_ref + self.stiffness * (u - self.u_ref) } }
#[derive(Clone, Debug, serde::Deserialize, serde::Serialize, PartialEq)]
#[serde(tag = "law", rename_all = "lowercase", deny_unknown_fields)]
pub enum Law { Linear { stiffness: f64 } }
#[derive(Clone, Debug)]
pub struct Hysteretic { b: Branch }
#[derive(Debug, thiserror::Error)] pub enum HysteresisError { #[error("{field}: {reason}")] Invalid { field: &'static str, reason: String } }
impl Hysteretic {
    pub fn new(law: Law) -> Result<Self, HysteresisError> { let Law::Linear{stiffness} = law; Ok(Self { b: Branch { u_ref: 0.0, f_ref: 0.0, stiffness, lower: f64::NEG_INFINITY, upper: f64::INFINITY, direction: 1.0, ends_on_reversal: false } }) }
    pub fn branch(&self) -> &Branch { &self.b }
    pub fn force(&self, u: f64) -> f64 { self.b.force(u) }
    pub fn on_branch_end(&mut self, _u: f64, _d: f64) {}
    pub fn set_direction(&mut self, _u: f64, _d: f64) {}
}

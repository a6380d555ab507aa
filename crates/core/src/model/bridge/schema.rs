//! The bridge file's tables (TOML schema, units t, kN, m, s). One frame: `[deck]` and
//! `[[bent]]`; several frames in series: `[[frame]]` tables (each with its `[[frame.bent]]`)
//! separated by `[[joint]]` tables, in order from the left abutment to the right one.

use super::super::solver::SolverSpec;
use crate::hysteresis::Law;
use crate::model::check::{Check, ModelError};
use crate::model::limit_state::LimitStateSpec;
use serde::Deserialize;

/// Names of the four abutment corners (paper: point 1 is the left, upper corner).
pub(crate) const CORNERS: [&str; 4] = ["left_top", "left_bottom", "right_top", "right_bottom"];

/// The `[deck]` table of a bridge file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeckSpec {
    /// t (paper: 140.5).
    pub mass: f64,
    /// t·m² about the vertical axis (paper: 13090).
    pub inertia: f64,
    /// Corner-to-corner length along the centreline, m (32.2).
    pub length: f64,
    /// m (2.4).
    pub width: f64,
    /// Skew angle of deck ends and abutment faces, degrees (0: straight).
    #[serde(default)]
    pub skew: f64,
    /// false: a translating deck, θ held at 0 (no θ DOF, no column torsion springs).
    #[serde(default = "yes")]
    pub rotation: bool,
}

/// One frame of a multi-frame bridge: a rigid deck (x, y, θ) on its own bents.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameSpec {
    /// Body name (absent: `frame1`, `frame2`, … in file order).
    pub name: Option<String>,
    /// t.
    pub mass: f64,
    /// t·m² about the vertical axis.
    pub inertia: f64,
    /// Corner-to-corner length along the frame's centreline, m.
    pub length: f64,
    /// m.
    pub width: f64,
    /// Skew of the frame's ends and bents, degrees (a joint or abutment may set its own).
    #[serde(default)]
    pub skew: f64,
    /// Plan angle of the frame's centreline from the x axis, degrees (a curved alignment as a
    /// chain of straight frames).
    #[serde(default)]
    pub heading: f64,
    /// false: the frame translates, θ held at 0 (as `deck.rotation`).
    #[serde(default = "yes")]
    pub rotation: bool,
    /// The file's `bents`.
    #[serde(default, rename = "bent")]
    pub bents: Vec<BentSpec>,
}

/// An expansion joint (or in-span hinge) between frame k and frame k + 1: the two end corners
/// of frame k against the end face of frame k + 1.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Initial gaps of the left frame's corners (+y side, −y side), m: exactly two.
    #[serde(deserialize_with = "two_gaps")]
    pub gaps: [f64; 2],
    /// Absent: `contacts.mu`, `contacts.restitution`.
    pub mu: Option<f64>,
    /// The file's `restitution`.
    pub restitution: Option<f64>,
    /// Skew of the joint line, degrees, from the normal to the bisector of the two frames'
    /// centrelines (absent: the left frame's `skew`).
    pub skew: Option<f64>,
    /// Support length of the left frame's end on its seat at the reference configuration, m
    /// (absent: no seat output).
    pub seat_width: Option<f64>,
    /// The percentage of AASHTO LRFD 4.7.4.4's N to compare with (absent: 100).
    pub seat_percent: Option<f64>,
    /// Shear keys across the joint, one beside each side of the left frame's end, between the
    /// two frames.
    pub key: Option<KeySpec>,
}

/// The `[abutment]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AbutmentSpec {
    /// `actuators` (default: a block on two longitudinal spring–dampers, the specimen),
    /// `rigid` (no DOFs, moves with the ground in x and y), `backfill` (a backwall block on its
    /// two springs and the passive backfill behind it, moving with the ground in y).
    pub kind: Option<String>,
    /// t (0.65); `actuators` and `backfill` only.
    pub mass: Option<f64>,
    /// t·m² (0.31).
    pub inertia: Option<f64>,
    /// Each of the two longitudinal springs (the actuators; for `backfill` the stem and
    /// piles), kN/m.
    pub actuator_stiffness: Option<f64>,
    /// kN·s/m.
    #[serde(default)]
    pub actuator_damping: f64,
    /// Lateral offset ± of the two springs from the abutment centre, m.
    pub actuator_offset: Option<f64>,
    /// `backfill`: height of the backwall (the soil it mobilises), m.
    pub backwall_height: Option<f64>,
    /// `backfill`: Caltrans' passive stiffness and capacity of the whole backwall (absent: from
    /// its height, the deck's width along the skewed backwall and the skew reduction).
    pub backfill_stiffness: Option<f64>,
    /// The file's `backfill_capacity`.
    pub backfill_capacity: Option<f64>,
    /// Bearings under each deck end at an abutment: one at each end corner, in x and in y
    /// (world axes), to the ground (e.g. `{ law = "bilinear", … post_yield_ratio = 0 }` for
    /// sliding bearings, `{ law = "linear", stiffness = … }` for elastomeric pads).
    pub bearing: Option<Law>,
    /// Exterior shear keys at each deck end (both abutments).
    pub key: Option<KeySpec>,
    /// Support length of each deck corner on its seat at the reference configuration (AASHTO's
    /// N: from the deck end to the seat's edge), m (absent: no seat output).
    pub seat_width: Option<f64>,
    /// The percentage of AASHTO LRFD 4.7.4.4's N to compare with (absent: 100).
    pub seat_percent: Option<f64>,
    /// Skew of the left and right abutment faces, degrees (absent: the end frame's `skew`).
    pub left_skew: Option<f64>,
    /// The file's `right_skew`.
    pub right_skew: Option<f64>,
}

/// A pair of exterior shear keys (one beside each side of a deck end): compression-only,
/// elastic–plastic, gone at a failure displacement (the `key` law).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeySpec {
    /// Clear gap between the deck's side and the key, m.
    pub gap: f64,
    /// kN/m.
    pub stiffness: f64,
    /// kN.
    pub capacity: f64,
    /// Deformation beyond the gap at which the key is gone, m.
    pub failure_displacement: f64,
}

/// The `[contacts]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactsSpec {
    /// false: no deck–abutment contact (paper §4.2).
    #[serde(default = "yes")]
    pub enabled: bool,
    /// The file's `mu`.
    pub mu: f64,
    /// The file's `restitution`.
    pub restitution: f64,
    /// Initial gaps of corners 1–4 (left +y, left −y, right +y, right −y), m: exactly four.
    #[serde(deserialize_with = "four_gaps")]
    pub gaps: [f64; 4],
}

/// `gaps` with exactly N entries (a fixed-size array would drop an extra one silently); `what`
/// names them in the error.
fn exact_gaps<'de, D: serde::Deserializer<'de>, const N: usize>(
    d: D,
    what: &str,
) -> Result<[f64; N], D::Error> {
    let v = Vec::<f64>::deserialize(d)?;
    let n = v.len();
    v.try_into()
        .map_err(|_| serde::de::Error::custom(format!("expected {N} {what}, got {n}")))
}

fn four_gaps<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 4], D::Error> {
    exact_gaps(
        d,
        "contacts.gaps (left_top, left_bottom, right_top, right_bottom)",
    )
}

fn two_gaps<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    exact_gaps(d, "joint gaps (top: +y side, bottom: −y side)")
}

fn yes() -> bool {
    true
}

/// A `[[bent]]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BentSpec {
    /// The file's `name`.
    pub name: String,
    /// Plan position along the deck from its centre, m.
    pub x: f64,
    /// Clear column height, m (stiffness ∝ h⁻³, strength ∝ h⁻¹ for fixed–fixed columns).
    pub height: f64,
}

/// The `[column]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColumnSpec {
    /// Law of one column in x and in y at `reference_height` (uncoupled directions).
    pub law: Law,
    /// The file's `reference_height`.
    pub reference_height: f64,
    /// Lateral offset ± of the two columns of a bent from the centreline, m.
    pub offset: f64,
    /// Elastic torsional stiffness of one column at the reference height, kN·m/rad (∝ h⁻¹).
    pub torsion_stiffness: f64,
}

/// The `[damping]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// Rayleigh ζ at two modes of the initial system (paper: 2 % at modes 1 and 3).
    pub ratio: f64,
    /// The file's `modes`.
    pub modes: [usize; 2],
}

impl Default for DampingSpec {
    fn default() -> Self {
        Self {
            ratio: 0.02,
            modes: [1, 3],
        }
    }
}

/// A `[[run]]` table: a test run's target PGAs.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// The file's `name`.
    pub name: String,
    /// Target PGA, g, longitudinal and transverse.
    pub pga_x: f64,
    /// The file's `pga_y`.
    pub pga_y: f64,
    /// Gaps of corners 1–4 measured before this run, m: set at its start in a sequence
    /// (`deckspin sequence`); a single run uses `contacts.gaps`.
    pub gaps: Option<Vec<f64>>,
}

/// The `[excitation]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExcitationSpec {
    /// "record" or "harmonic".
    pub kind: String,
    /// Records (AT2 or two-column), relative to the model file.
    pub longitudinal: Option<String>,
    /// The file's `transverse`.
    pub transverse: Option<String>,
    /// Which `[[run]]` sets the target PGAs (1-based).
    #[serde(default)]
    pub run: Option<usize>,
    /// Similitude time scale (quarter scale: 0.5).
    #[serde(default = "one")]
    pub time_scale: f64,
    /// Polynomial baseline order.
    #[serde(default = "three")]
    pub baseline_order: usize,
    /// The file's `taper`.
    #[serde(default)]
    pub taper: Option<f64>,
    /// Per-bent and per-abutment time lags, s.
    #[serde(default)]
    pub lag_bents: Vec<f64>,
    /// The file's `lag_abutments`.
    #[serde(default)]
    pub lag_abutments: Vec<f64>,
    /// Harmonic input: displacement amplitude x and y (m), frequency (Hz).
    pub amplitude_x: Option<f64>,
    /// The file's `amplitude_y`.
    pub amplitude_y: Option<f64>,
    /// The file's `frequency`.
    pub frequency: Option<f64>,
    /// Abutment actuators follow the longitudinal input (true) or stay fixed.
    #[serde(default = "yes")]
    pub drive_abutments: bool,
    /// `"both"` (default) or `"longitudinal"`: the longitudinal record alone, every support
    /// at rest in y (`transverse` and the runs' `pga_y` not read).
    #[serde(default)]
    pub components: Option<String>,
    /// `[start, end]`, s of the run's time (after `time_scale`, lags included): every record
    /// cut to it, `start` becoming t = 0, the target PGA the whole record's (`Processing`).
    pub window: Option<Vec<f64>>,
}

fn one() -> f64 {
    1.0
}
fn three() -> usize {
    3
}

/// A bridge model file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BridgeFile {
    /// The file's `title`.
    pub title: Option<String>,
    /// The unit system (read before the rest: `Check::units`).
    #[allow(dead_code)]
    pub units: Option<String>,
    /// One frame (with `[[bent]]`), or none with `[[frame]]`.
    pub deck: Option<DeckSpec>,
    /// The file's `frames`.
    #[serde(default, rename = "frame")]
    pub frames: Vec<FrameSpec>,
    /// The file's `joints`.
    #[serde(default, rename = "joint")]
    pub joints: Vec<JointSpec>,
    /// The file's `abutment`.
    pub abutment: AbutmentSpec,
    /// The file's `contacts`.
    pub contacts: ContactsSpec,
    /// The file's `bents`.
    #[serde(default, rename = "bent")]
    pub bents: Vec<BentSpec>,
    /// The file's `column`.
    pub column: ColumnSpec,
    /// The file's `damping`.
    #[serde(default)]
    pub damping: DampingSpec,
    /// The file's `excitation`.
    pub excitation: Option<ExcitationSpec>,
    /// The file's `runs`.
    #[serde(default, rename = "run")]
    pub runs: Vec<RunSpec>,
    /// The file's `solver`.
    #[serde(default)]
    pub solver: SolverSpec,
    /// Limit states of the bridge's fragility (`deckspin fragility --model`).
    #[serde(default, rename = "limit_state")]
    pub limit_states: Vec<LimitStateSpec>,
    /// Uncertain inputs of `deckspin sensitivity` (a run ignores them).
    #[serde(default, rename = "uncertain")]
    pub uncertain: Vec<crate::model::uncertain::UncertainSpec>,
}

/// The kind of an abutment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// On two actuators (spring–dashpots to the table).
    Actuators,
    /// Rigid walls moved by the ground.
    Rigid,
    /// A backwall on passive backfill.
    Backfill,
}

impl Kind {
    /// The kind `abutment.kind` names (actuators when absent).
    pub fn of(a: &AbutmentSpec, ck: &Check) -> Result<Self, ModelError> {
        match a.kind.as_deref() {
            None | Some("actuators") => Ok(Kind::Actuators),
            Some("rigid") => Ok(Kind::Rigid),
            Some("backfill") => Ok(Kind::Backfill),
            Some(k) => Err(ck.err(
                "abutment.kind",
                format!("unknown abutment kind '{k}' (actuators, rigid, backfill)"),
            )),
        }
    }

    /// Its name in model files.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Actuators => "actuators",
            Kind::Rigid => "rigid",
            Kind::Backfill => "backfill",
        }
    }
}

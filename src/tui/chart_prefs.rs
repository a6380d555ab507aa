//! What the three time charts show and how: each chart's series (picked with `p`, else the
//! defaults: the rotation, the gaps, x and y), its y zoom and log scale, the unit of θ, the
//! chart in focus. The series, the log scales and θ's unit are remembered per model in
//! `<model stem>.runs/charts.json`, written atomically; a missing file gives the defaults, a
//! corrupt one the defaults and a message.

use crate::tui::runs::data::RunData;
use crate::tui::runs::series::{self, Dim, SeriesId};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The number of time charts.
pub const CHARTS: usize = 3;

/// The file's name in the model's runs folder.
pub const FILE: &str = crate::tui::runs::store::CHARTS_FILE;

/// The first field of the file.
const FORMAT: &str = "deckspin charts 1";

/// The unit θ and its rate are shown in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ThetaUnit {
    /// Radians with an SI prefix that fits (`µrad`, `mrad`).
    #[default]
    Rad,
    /// Milliradians, always.
    Mrad,
    /// Degrees.
    Deg,
}

impl ThetaUnit {
    pub fn next(self) -> Self {
        match self {
            ThetaUnit::Rad => ThetaUnit::Mrad,
            ThetaUnit::Mrad => ThetaUnit::Deg,
            ThetaUnit::Deg => ThetaUnit::Rad,
        }
    }

    /// Values in rad times this are in the unit.
    pub fn factor(self) -> f64 {
        match self {
            ThetaUnit::Rad => 1.0,
            ThetaUnit::Mrad => 1e3,
            ThetaUnit::Deg => 180.0 / std::f64::consts::PI,
        }
    }

    /// The unit's name (`rad`, `mrad`, `°`; `deg` in ASCII).
    pub fn name(self, ascii: bool) -> &'static str {
        match self {
            ThetaUnit::Rad => "rad",
            ThetaUnit::Mrad => "mrad",
            ThetaUnit::Deg if ascii => "deg",
            ThetaUnit::Deg => "°",
        }
    }
}

/// The model's units of length, force and energy (empty: a scene file's own).
#[derive(Clone, Copy, Debug)]
pub struct Units {
    pub length: &'static str,
    pub force: &'static str,
    pub energy: &'static str,
}

/// The unit a series of `dim` is drawn in and the factor from the model's numbers to it.
pub fn unit_of(dim: Dim, u: &Units, theta: ThetaUnit, ascii: bool) -> (String, f64) {
    let per_s = |s: &str| {
        if s.is_empty() {
            String::new()
        } else {
            format!("{s}/s")
        }
    };
    match dim {
        Dim::Length => (u.length.into(), 1.0),
        Dim::Velocity => (per_s(u.length), 1.0),
        Dim::Angle => (theta.name(ascii).into(), theta.factor()),
        Dim::AngularVelocity => (per_s(theta.name(ascii)), theta.factor()),
        Dim::Force => (u.force.into(), 1.0),
        Dim::Energy => (u.energy.into(), 1.0),
    }
}

/// One time chart: its series (None: the defaults), its y zoom (the axis spans the data's
/// range / 2^zoom) and log scale.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChartSpec {
    pub series: Option<Vec<SeriesId>>,
    pub y_zoom: u32,
    pub log: bool,
}

/// The three time charts, the one in focus (0–2) and θ's unit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChartPrefs {
    pub charts: [ChartSpec; CHARTS],
    pub focus: usize,
    pub theta: ThetaUnit,
}

#[derive(Serialize, Deserialize)]
struct FileChart {
    series: Option<Vec<String>>,
    #[serde(default)]
    log: bool,
}

#[derive(Serialize, Deserialize)]
struct File {
    format: String,
    #[serde(default)]
    theta: ThetaUnit,
    charts: Vec<FileChart>,
}

impl ChartPrefs {
    /// The series chart `k` shows of `run`: those picked that `run` records, else the
    /// defaults ([`series::defaults`]).
    pub fn series(&self, run: &RunData, k: usize) -> Vec<SeriesId> {
        match self.charts.get(k).and_then(|c| c.series.as_ref()) {
            Some(ids) => (ids.iter())
                .filter(|id| series::column(run, id).is_some())
                .cloned()
                .collect(),
            None => series::defaults(run, k),
        }
    }

    /// The file's text: the series picked, the log scales, θ's unit.
    pub fn to_text(&self) -> String {
        let f = File {
            format: FORMAT.into(),
            theta: self.theta,
            charts: (self.charts.iter())
                .map(|c| FileChart {
                    series: c
                        .series
                        .as_ref()
                        .map(|v| v.iter().map(SeriesId::key).collect()),
                    log: c.log,
                })
                .collect(),
        };
        serde_json::to_string_pretty(&f).unwrap_or_default() + "\n"
    }

    /// The preferences of a file's text; a series key that names no kind is left out.
    pub fn from_text(text: &str) -> Result<Self, String> {
        let f: File = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if f.format != FORMAT {
            return Err(format!("format `{}`, not `{FORMAT}`", f.format));
        }
        if f.charts.len() != CHARTS {
            return Err(format!("{} charts, not {CHARTS}", f.charts.len()));
        }
        let mut p = ChartPrefs {
            theta: f.theta,
            ..Self::default()
        };
        for (c, fc) in p.charts.iter_mut().zip(f.charts) {
            c.log = fc.log;
            c.series = fc
                .series
                .map(|v| v.iter().filter_map(|k| SeriesId::parse(k)).collect());
        }
        Ok(p)
    }
}

/// `models/four-span.runs/charts.json` for `models/four-span.toml`.
pub fn path(model: &Path) -> PathBuf {
    crate::tui::runs::store::runs_dir(model).join(FILE)
}

/// The preferences stored for `model`: the defaults when there are none; the defaults and
/// why when the file does not read.
pub fn load(model: &Path) -> (ChartPrefs, Option<String>) {
    let p = path(model);
    match std::fs::read_to_string(&p) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => (ChartPrefs::default(), None),
        Err(e) => (
            ChartPrefs::default(),
            Some(format!("{}: {e}: the default charts", p.display())),
        ),
        Ok(text) => match ChartPrefs::from_text(&text) {
            Ok(prefs) => (prefs, None),
            Err(e) => (
                ChartPrefs::default(),
                Some(format!("{}: {e}: the default charts", p.display())),
            ),
        },
    }
}

/// Writes the preferences' file (its folder created if need be) atomically.
pub fn store(path: &Path, text: &str) -> Result<(), String> {
    if let Some(d) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    crate::tui::runs::store::write_atomic(path, text)
}

/// The series of `run` whose label or key holds `query` (any case).
pub fn matching(run: &RunData, query: &str) -> Vec<SeriesId> {
    let q = query.to_lowercase();
    series::catalogue(run)
        .into_iter()
        .filter(|id| {
            q.is_empty()
                || id.label().to_lowercase().contains(&q)
                || id.key().to_lowercase().contains(&q)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tui::runs::series::Kind;

    #[test]
    fn the_file_reads_back_and_refuses_what_it_is_not() {
        let mut p = ChartPrefs::default();
        p.charts[1].series = Some(vec![SeriesId::new(Kind::Force, "col1")]);
        p.charts[2].log = true;
        p.theta = ThetaUnit::Deg;
        let back = ChartPrefs::from_text(&p.to_text()).unwrap();
        assert_eq!(back, p);
        assert!(ChartPrefs::from_text("{").is_err());
        assert!(ChartPrefs::from_text("[]").is_err());
        let other = p.to_text().replace("deckspin charts 1", "other");
        assert!(
            ChartPrefs::from_text(&other)
                .unwrap_err()
                .contains("format")
        );
        let two = r#"{"format":"deckspin charts 1","charts":[{"series":null},{"series":null}]}"#;
        assert!(ChartPrefs::from_text(two).unwrap_err().contains("2 charts"));
    }
}

//! What a suite records of a run, from its output: the deck's peak and residual rotation and
//! peak translations over all its frames ([`crate::studies::DeckPeaks`]), the smallest
//! seat margin, the failed shear keys, the impacts and the energy ledger's impact, friction
//! and hysteretic terms at the end; and, watched sample by sample, the largest column drift
//! ratio √(u_x² + u_y²)/h over the columns and the recorded samples (output grid and event
//! instants), u the column's deformations in x and y, h its bent's clear height.

use crate::output::{EventRecord, Sample};
use crate::run::{Observer, Run};
use crate::studies::DeckPeaks;

/// The clear heights of a bridge file's bents by name (`[[bent]]` and `[[frame.bent]]`).
pub fn bent_heights(text: &str) -> Vec<(String, f64)> {
    let Ok(doc) = toml::from_str::<toml::Table>(text) else {
        return Vec::new();
    };
    let bents = |t: &toml::Table| -> Vec<(String, f64)> {
        let list = t.get("bent").and_then(|b| b.as_array());
        (list.into_iter().flatten())
            .filter_map(|b| {
                let name = b.get("name")?.as_str()?.to_string();
                let h = b.get("height")?;
                let h = h.as_float().or_else(|| h.as_integer().map(|i| i as f64))?;
                Some((name, h))
            })
            .collect()
    };
    let mut out = bents(&doc);
    let frames = doc.get("frame").and_then(|f| f.as_array());
    for f in frames.into_iter().flatten() {
        if let Some(t) = f.as_table() {
            out.extend(bents(t));
        }
    }
    out
}

/// The columns of a scene: for each bent's `top` and `bottom` column, the indices of its
/// hysteretic elements in x and y (`{bent}_{top|bottom}.{x|y}`) and its height.
#[derive(Clone, Debug, Default)]
pub struct Columns(Vec<(usize, usize, f64)>);

impl Columns {
    pub fn of(element_names: &[String], heights: &[(String, f64)]) -> Self {
        let at = |n: String| element_names.iter().position(|e| *e == n);
        let mut out = Vec::new();
        for (bent, h) in heights {
            for side in ["top", "bottom"] {
                let x = at(format!("{bent}_{side}.x"));
                let y = at(format!("{bent}_{side}.y"));
                if let (Some(x), Some(y)) = (x, y)
                    && *h > 0.0
                {
                    out.push((x, y, *h));
                }
            }
        }
        Columns(out)
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The largest drift ratio of the columns in one sample's elements.
    fn drift(&self, elements: &[(f64, f64)]) -> f64 {
        (self.0.iter())
            .filter_map(|&(x, y, h)| Some(elements.get(x)?.0.hypot(elements.get(y)?.0) / h))
            .fold(0.0, f64::max)
    }
}

/// An observer that keeps the largest column drift ratio of every sample it is handed (and
/// lets the run drop them).
pub(crate) struct DriftWatch {
    columns: Columns,
    pub max: f64,
}

impl DriftWatch {
    pub fn new(columns: Columns) -> Self {
        Self { columns, max: 0.0 }
    }

    fn see(&mut self, samples: &[Sample]) {
        for s in samples {
            self.max = self.max.max(self.columns.drift(&s.elements));
        }
    }

    /// The largest drift ratio over the run (the samples it still holds included); none
    /// without columns.
    pub fn finish(mut self, run: &Run) -> Option<f64> {
        self.see(&run.output.samples);
        (!self.columns.is_empty()).then_some(self.max)
    }
}

impl Observer for DriftWatch {
    fn batch(&mut self, samples: &[Sample], _: &[EventRecord], _: f64) -> bool {
        self.see(samples);
        true
    }

    fn keeps_samples(&self) -> bool {
        true
    }
}

/// `scene` run with its history kept and its column drift watched (the bents' `heights`):
/// the run and its metrics in the order of `row::METRICS`.
pub(crate) fn run_measured(
    mut scene: crate::scene::Scene,
    heights: &[(String, f64)],
) -> (Run, [Option<f64>; 11]) {
    scene.settings.keep_history = true;
    let names: Vec<String> = scene.hysteretic.iter().map(|h| h.name.clone()).collect();
    let mut watch = DriftWatch::new(Columns::of(&names, heights));
    let run = crate::simulate::integrate(&scene, &mut watch);
    let drift = watch.finish(&run);
    let m = metrics(&run, drift);
    (run, m)
}

/// The metrics of a run in the order of `row::METRICS`, `drift` the largest column drift
/// ratio watched.
pub fn metrics(run: &Run, drift: Option<f64>) -> [Option<f64>; 11] {
    let out = &run.output;
    let s = &out.summary;
    let deck = DeckPeaks::of(out);
    let finite = |x: f64| x.is_finite().then_some(x);
    let seats = (s.seats.iter()).map(|x| x.min_margin).reduce(f64::min);
    let e = &s.energy_final;
    [
        finite(deck.rotation),
        finite(deck.residual.abs()),
        finite(deck.x),
        finite(deck.y),
        seats,
        s.key_failures.as_ref().map(|k| k.len() as f64),
        drift,
        Some(s.stats.impacts as f64),
        Some(e.impact_normal + e.impact_tangential),
        Some(e.friction),
        Some(e.hysteretic),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_found_by_bent_and_their_drift_is_the_resultant() {
        let text = "[[bent]]\nname = \"b1\"\nheight = 2.0\n[[bent]]\nname = \"b2\"\nheight = 4\n";
        let heights = bent_heights(text);
        assert_eq!(heights, vec![("b1".into(), 2.0), ("b2".into(), 4.0)]);
        let names: Vec<String> = ["b1_top.x", "b1_top.y", "b2_bottom.y", "b2_bottom.x", "key"]
            .map(String::from)
            .to_vec();
        let cols = Columns::of(&names, &heights);
        assert_eq!(cols.0, vec![(0, 1, 2.0), (3, 2, 4.0)]);
        // b1_top: (0.03, 0.04) → 0.05 / 2; b2_bottom: (−0.3, 0.4) → 0.5 / 4; `key` no column
        let mut e = [
            (0.03, 9.0),
            (0.04, 9.0),
            (0.4, 9.0),
            (-0.3, 9.0),
            (5.0, 9.0),
        ];
        assert!((cols.drift(&e) - 0.125).abs() < 1e-15);
        e[2].0 = 0.0;
        assert!((cols.drift(&e) - 0.075).abs() < 1e-15);
        let frames = "[[frame]]\nmass = 1\n[[frame.bent]]\nname = \"f\"\nheight = 1.5\n";
        assert_eq!(bent_heights(frames), vec![("f".into(), 1.5)]);
        assert!(Columns::of(&names, &[]).is_empty());
    }
}

//! Drawing caches (decimated series, loops, event strips), owned by the runtime loop and
//! passed to [`super::draw`]; each entry is keyed by what it depends on (run, its length, time
//! window, plot size, …).

use crate::tui::chart::downsample_minmax;
use crate::tui::runs::data::RunData;
use std::collections::HashMap;
use std::time::{Duration, Instant};

pub(super) type Points = Vec<(f64, f64)>;

/// The drawing caches.
#[derive(Default)]
pub struct Cache {
    series: HashMap<String, (Key, Points)>,
    strips: HashMap<u64, (Key, Vec<Vec<char>>)>,
    memo: HashMap<String, (Vec<u64>, Points)>,
    /// The instant the readouts show while a running run is followed: (run, time, when taken).
    readout: Option<(u64, f64, Instant)>,
}

/// How often the readouts at the cursor (the values in the charts' headers, the contact
/// states, the loop's deformation and force) and the plan, drawn at their instant, are
/// refreshed while a running run is followed: twice a second. The charts, the cursor line and
/// the column loop go on with every frame.
pub const READOUT_PERIOD: Duration = Duration::from_millis(500);

#[derive(Clone, Copy, PartialEq, Debug)]
pub(super) struct Key {
    pub len: usize,
    pub events: usize,
    pub t0: u64,
    pub t1: u64,
    pub cols: u16,
    pub extra: u64,
}

/// The key of a time-axis drawing of `r` over `t0..t1` on `cols` columns.
pub(super) fn time_key(r: &RunData, t0: f64, t1: f64, cols: u16) -> Key {
    Key {
        len: r.t.len(),
        events: r.events.len(),
        t0: t0.to_bits(),
        t1: t1.to_bits(),
        cols,
        extra: 0,
    }
}

impl Cache {
    /// The time the readouts are drawn at: the cursor time `tc`, except while run `run` is
    /// running and followed (`held`), when it is the latest sample at most
    /// [`READOUT_PERIOD`] ago, so that the numbers do not change with every frame.
    pub(super) fn readout_time(&mut self, run: u64, tc: f64, held: bool) -> f64 {
        if !held {
            self.readout = None;
            return tc;
        }
        match self.readout {
            Some((r, t, at)) if r == run && t <= tc && at.elapsed() < READOUT_PERIOD => t,
            _ => {
                self.readout = Some((run, tc, Instant::now()));
                tc
            }
        }
    }

    /// Cached computation of points under `name`, recomputed when `key` changes.
    pub(super) fn memo(
        &mut self,
        name: String,
        key: Vec<u64>,
        f: impl FnOnce() -> Points,
    ) -> Points {
        if let Some((k, v)) = self.memo.get(&name)
            && *k == key
        {
            return v.clone();
        }
        let v = f();
        if self.memo.len() > 64 {
            self.memo.clear();
        }
        self.memo.insert(name, (key, v.clone()));
        v
    }

    /// Decimated column `y` (named `what`) of a run.
    pub(super) fn decimated(
        &mut self,
        r: &RunData,
        what: &str,
        y: &[f64],
        t0: f64,
        t1: f64,
        cols: u16,
    ) -> Points {
        let key = time_key(r, t0, t1, cols);
        let name = format!("{}:{what}", r.token);
        if let Some((k, v)) = self.series.get(&name)
            && *k == key
        {
            return v.clone();
        }
        let v = downsample_minmax(&r.t, y, t0, t1, cols as usize);
        if self.series.len() > 256 {
            self.series.clear();
        }
        self.series.insert(name, (key, v.clone()));
        v
    }

    /// The event strips of run `id`, recomputed when `key` changes.
    pub(super) fn strips(
        &mut self,
        id: u64,
        key: Key,
        f: impl FnOnce() -> Vec<Vec<char>>,
    ) -> Vec<Vec<char>> {
        match self.strips.get(&id) {
            Some((k, v)) if *k == key => v.clone(),
            _ => {
                let v = f();
                if self.strips.len() > 8 {
                    self.strips.clear();
                }
                self.strips.insert(id, (key, v.clone()));
                v
            }
        }
    }
}

//! The studies view's state: the list of studies (one entry per [`StudyKind`]), and for each
//! the last one run or reopened — where its model came from, how far it got, its table.
//!
//! A study is added to the view by a variant of [`StudyKind`] (with its plan, runner and CSV
//! in the library: `study_table`, `study_csv`), its texts in [`title`], [`what`] and
//! [`plan`] below, and its panel in `ui/studies.rs`.

pub mod design_rows;
pub mod files;
pub mod points;

use crate::study_table::{RunTable, StudyKind, StudyTable, SuiteSubset};
use std::path::{Path, PathBuf};

/// Where a study's model came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// The form's model when the study started (`file`: the model file's name); `edited`: it
    /// held unsaved edits.
    Form { file: String, edited: bool },
    /// Reopened from this CSV.
    Csv(PathBuf),
}

/// How far a study got.
#[derive(Clone, Debug, PartialEq)]
pub enum Phase {
    Running,
    /// Esc was pressed; the runs already started finish.
    Cancelling,
    Finished,
    /// Cancelled: the runs finished before are kept.
    Cancelled,
    /// No run could start (the model does not compile, a panic): the reason.
    Failed(String),
}

/// The last study of one kind.
#[derive(Clone, Debug)]
pub struct Entry {
    /// Messages of its worker carry this id.
    pub id: u64,
    pub source: Source,
    pub phase: Phase,
    /// The runs so far (the PGA and μ studies: their plan at the start); the screening's
    /// once it is done.
    pub table: Option<StudyTable>,
    /// Where its CSV was written (or the CSV it was read from).
    pub csv: Option<PathBuf>,
    /// (runs done, runs planned) as its worker counts them, for a study whose table comes
    /// whole at its end (the ladder, the swings).
    pub count: (usize, usize),
}

impl Entry {
    /// (runs done, runs in all): its table's, else its worker's count; (0, 0) while the
    /// screening computes.
    pub fn progress(&self) -> (usize, usize) {
        self.table.as_ref().map_or(self.count, StudyTable::progress)
    }

    pub fn running(&self) -> bool {
        matches!(self.phase, Phase::Running | Phase::Cancelling)
    }
}

/// What a study worker needs: the study, the model text and path (records are found from
/// it), overrides applied to every run (`key=value`, as `--set`), the μ values of the μ study.
#[derive(Clone, Debug)]
pub struct StudySpec {
    pub kind: StudyKind,
    pub text: String,
    pub path: PathBuf,
    pub overrides: Vec<String>,
    pub mus: Vec<f64>,
    /// The record suite's subset.
    pub suite: SuiteSubset,
}

/// The studies view.
#[derive(Clone, Debug)]
pub struct Studies {
    /// The selected entry of [`StudyKind::ALL`].
    pub selected: usize,
    /// The last study of each kind, in [`StudyKind::ALL`]'s order.
    pub entries: Vec<Option<Entry>>,
    pub next_id: u64,
    /// Overrides applied to every run of a study (none by default; tests shorten the runs).
    pub overrides: Vec<String>,
    /// The μ values of the μ study ([`crate::studies::fig8_mus`] by default).
    pub mus: Vec<f64>,
    /// The record suite's subset (None: [`SuiteSubset::near`] the model); `+`/`-` change its
    /// number of pairs.
    pub suite: Option<SuiteSubset>,
    /// The cursor of each study (in [`StudyKind::ALL`]'s order): a row of its table of
    /// points (`crate::tui::studies::points`), moved by `[` and `]` (the rows of the ladder's and the
    /// swings' tables by `j`/`k` too).
    pub cursor: Vec<usize>,
    /// The quantity of the swings' table and tornado (an index into their quantities), `n`
    /// the next.
    pub quantity: usize,
    /// The ladder's variant last applied to the form, which `u` takes back.
    pub applied: Option<Applied>,
}

/// A variant of the ladder applied to the form's model: the draft before and after, so that
/// `u` restores the one before while the draft is still the one after.
#[derive(Clone, Debug, PartialEq)]
pub struct Applied {
    pub name: String,
    /// The keys it changed.
    pub keys: usize,
    pub before: String,
    pub after: String,
}

impl Default for Studies {
    fn default() -> Self {
        Self {
            selected: 0,
            entries: vec![None; StudyKind::ALL.len()],
            next_id: 1,
            overrides: Vec::new(),
            mus: crate::studies::fig8_mus(),
            suite: None,
            cursor: vec![0; StudyKind::ALL.len()],
            quantity: 0,
            applied: None,
        }
    }
}

impl Studies {
    /// The suite subset of the model at `path` (chosen, or the default near it).
    pub fn suite_for(&self, path: &Path) -> SuiteSubset {
        self.suite
            .clone()
            .unwrap_or_else(|| SuiteSubset::near(path))
    }

    pub fn kind(&self) -> StudyKind {
        StudyKind::ALL[self.selected.min(StudyKind::ALL.len() - 1)]
    }

    pub fn index_of(kind: StudyKind) -> usize {
        (StudyKind::ALL.iter())
            .position(|k| *k == kind)
            .unwrap_or(0)
    }

    pub fn entry(&self, kind: StudyKind) -> Option<&Entry> {
        self.entries[Self::index_of(kind)].as_ref()
    }

    pub fn entry_mut(&mut self, kind: StudyKind) -> Option<&mut Entry> {
        self.entries[Self::index_of(kind)].as_mut()
    }

    /// The selected study's cursor.
    pub fn cursor(&self) -> usize {
        self.cursor.get(self.selected).copied().unwrap_or(0)
    }

    /// The entry whose worker has this id.
    pub fn by_id(&mut self, id: u64) -> Option<&mut Entry> {
        (self.entries.iter_mut().flatten()).find(|e| e.id == id)
    }

    /// The study running, if any (one at a time).
    pub fn running(&self) -> Option<(StudyKind, &Entry)> {
        (StudyKind::ALL.iter().zip(&self.entries))
            .find_map(|(k, e)| e.as_ref().filter(|e| e.running()).map(|e| (*k, e)))
    }
}

/// The study's name in the list.
pub fn title(kind: StudyKind) -> &'static str {
    match kind {
        StudyKind::Pga => "PGA (Fig. 7)",
        StudyKind::Mu => "μ (Fig. 8)",
        StudyKind::Suite => "suite",
        StudyKind::Screen => "screen",
        StudyKind::Precision => "work-precision",
        StudyKind::Adequacy => "adequacy",
        StudyKind::Sensitivity => "sensitivity",
    }
}

/// The study's name in the header's progress.
pub fn short_title(kind: StudyKind) -> &'static str {
    match kind {
        StudyKind::Pga => "PGA",
        StudyKind::Mu => "μ",
        StudyKind::Suite => "suite",
        StudyKind::Screen => "screen",
        StudyKind::Precision => "precision",
        StudyKind::Adequacy => "adequacy",
        StudyKind::Sensitivity => "sensitivity",
    }
}

/// What the study computes, in a sentence.
pub fn what(kind: StudyKind) -> &'static str {
    match kind {
        StudyKind::Pga => {
            "Peak deck rotation |θ| against the target PGA of each [[run]] of the model, with \
             contact and without (the paper's Fig. 7): two runs per [[run]] table."
        }
        StudyKind::Mu => {
            "The increase of peak |θ| over the run without contact, against μ, one curve per \
             [[run]] (the paper's Fig. 8): one run without contact and one per μ for each \
             [[run]] table."
        }
        StudyKind::Suite => {
            "A record suite: the first pairs of the far-field set (+/- more or fewer), both \
             components scaled to each PGA, 0.2 to 1.2 g; peak |θ| of every run against PGA, \
             and the median per level (as deckspin suite computes it)."
        }
        StudyKind::Screen => {
            "The impact law in closed form, before any run: where over L/B × skew a flush end \
             impact turns the deck, which corners stick when struck alone, this model marked; \
             the model's ends and corners."
        }
        StudyKind::Precision => {
            "Work-precision and stability: every method over its quick knobs (tolerance, step, \
             contact stiffness), CPU time against the peak error of the watched rotation from \
             the event-driven reference at rtol 1e-10; g shows the stability grid (ok, \
             inaccurate above 5 %, unstable, failed)."
        }
        StudyKind::Adequacy => {
            "Model adequacy (deckspin adequacy): the model ladder - rigid abutments, bilinear or \
             linear columns, no friction, plastic impacts, no contacts, ... and some of them \
             together - run on the model's [[run]]s; each variant's error per quantity against \
             the full model, its CPU time, and the cheapest within 5 %. a applies the selected \
             variant to the form as an edit, u takes it back."
        }
        StudyKind::Sensitivity => {
            "Sensitivity (deckspin sensitivity): every default uncertain input (gaps, mu, \
             restitution, stiffnesses, damping, the PGA, ...) at its low and its high value on \
             the model's [[run]]s; the swing of each quantity's median, widest first, and its \
             tornado; n shows the next quantity."
        }
    }
}

/// The study's table before any run, from the model text (None: the screening, whose table
/// comes whole); Err: why it cannot run on this model.
pub fn plan(
    kind: StudyKind,
    text: &str,
    mus: &[f64],
    suite: &SuiteSubset,
) -> Result<Option<RunTable>, String> {
    let table = match kind {
        StudyKind::Pga => RunTable::pga_plan(text),
        StudyKind::Mu => RunTable::mu_plan(text, mus),
        StudyKind::Suite => {
            let pairs = suite.read_pairs()?;
            RunTable::suite_plan(pairs.len(), &suite.levels)
        }
        // the screening's, the ladder's and the swings' tables come whole; work-precision's
        // plan needs the compiled model
        StudyKind::Screen | StudyKind::Precision | StudyKind::Adequacy | StudyKind::Sensitivity => {
            return Ok(None);
        }
    };
    if table.runs.is_empty() {
        return Err(format!(
            "the {} study needs [[run]] tables (a bridge with its runs): this model has none",
            title(kind)
        ));
    }
    Ok(Some(table))
}

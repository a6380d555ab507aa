//! Messages into [`super::update`] and the effects it returns.

use super::keymap::Action;
use super::results::{ModesData, RecordsData, ResultSpec};
use crate::output::{EventRecord, RunOutput, Sample};
use crate::precision::Point;
use crate::scene::Scene;
use crate::studies::Row;
use crate::study_table::StudyTable;
use crate::tui::runs::data::{RunData, RunFailure};
use crate::tui::runs::store as run_store;
use crate::tui::studies::StudySpec;
use crossterm::event::KeyEvent;
use std::path::PathBuf;
use std::sync::Arc;

/// How a run ended.
#[derive(Debug)]
pub enum RunOutcome {
    Finished(Box<RunOutput>),
    Cancelled {
        t: f64,
    },
    Failed(Arc<RunFailure>),
    /// Finished outside its accuracy bounds (`SolverError::Inaccurate`): failed, its output
    /// kept (the closure it reached is compared).
    Inaccurate {
        output: Box<RunOutput>,
        failure: Arc<RunFailure>,
    },
}

/// How a study ended: its table (rows not run marked so when cancelled), or why none ran.
#[derive(Debug)]
pub enum StudyOutcome {
    Finished(Box<StudyTable>),
    Cancelled(Box<StudyTable>),
    /// Cancelled before it had anything to keep (the model ladder: its errors need every run).
    Abandoned,
    Failed(String),
}

/// What a results computation gives ([`crate::tui::workers::results`]).
#[derive(Debug)]
pub enum ResultData {
    Modes(Box<ModesData>),
    Records(Box<RecordsData>),
}

/// How a results computation ended.
#[derive(Debug)]
pub enum ResultOutcome {
    Done(ResultData),
    Cancelled,
    Failed(String),
}

/// Input of [`super::update`].
#[derive(Debug)]
pub enum Msg {
    Key(KeyEvent),
    Action(Action),
    Resize(u16, u16),
    /// New samples and events of run `run` (simulated time `t`).
    Batch {
        run: u64,
        samples: Vec<Sample>,
        events: Vec<EventRecord>,
        t: f64,
    },
    RunDone {
        run: u64,
        outcome: RunOutcome,
    },
    /// Run `run` finished outside its accuracy bounds with a step its method chose: it starts
    /// again at the finer step `why` names (`simulate::refined`); what it sent so far is void.
    Refined {
        run: u64,
        why: String,
    },
    /// The model file's content after a change on disk.
    FileChanged(String),
    FileUnreadable(String),
    /// How the file is watched ("notify", "polling every 1 s", …).
    WatchMode(String),
    /// Result of [`Effect::Save`].
    Saved {
        text: String,
        result: Result<PathBuf, String>,
    },
    /// [`Effect::Save`] found the file on disk changed (its content) and wrote nothing.
    SaveConflict(String),
    /// SIGTERM, SIGHUP or SIGINT arrived (the runtime ends the loop; `update` ignores it).
    Signal(i32),
    /// Result of [`Effect::Export`]: the written paths.
    Exported(Result<Vec<PathBuf>, String>),
    /// Row `index` of study `id`'s table is final.
    StudyRow {
        id: u64,
        index: usize,
        row: Box<Row>,
    },
    /// Study `id` (one whose table comes whole at its end: the ladder, the swings) has done
    /// `done` of its `all` runs.
    StudyProgress {
        id: u64,
        done: usize,
        all: usize,
    },
    StudyDone {
        id: u64,
        outcome: StudyOutcome,
    },
    /// Result of [`Effect::WriteStudy`]: the CSV written.
    StudyWritten {
        id: u64,
        result: Result<PathBuf, String>,
    },
    /// Result of [`Effect::ListStudies`]: the study CSVs found, newest first.
    StudyFiles(Result<Vec<PathBuf>, String>),
    /// Result of [`Effect::LoadStudy`].
    StudyLoaded {
        path: PathBuf,
        result: Result<Box<StudyTable>, String>,
    },
    /// Result of [`Effect::StoreRuns`].
    RunsStored(Result<(), String>),
    /// Result of [`Effect::StoreCharts`].
    ChartsStored(Result<(), String>),
    /// Result of [`Effect::LoadSeries`]: each run's series, or why it does not read.
    SeriesLoaded {
        dir: PathBuf,
        loaded: Vec<(u64, Result<RunData, String>)>,
    },
    // -- the results pages and the work-precision study
    /// Point `index` of work-precision study `id` is final.
    StudyPoint {
        id: u64,
        index: usize,
        point: Box<Point>,
    },
    /// Results computation `id` has done `done` of `all` steps.
    ResultProgress {
        id: u64,
        done: usize,
        all: usize,
    },
    ResultDone {
        id: u64,
        outcome: ResultOutcome,
    },
    // another model
    /// Result of [`Effect::ListModels`]: the model files found.
    ModelFiles(Result<Vec<PathBuf>, String>),
    /// Result of [`Effect::ReadModel`]: the model's text.
    ModelRead {
        path: PathBuf,
        result: Result<String, String>,
    },
}

/// Output of [`super::update`], executed by [`super::effects::perform`].
#[derive(Debug)]
pub enum Effect {
    StartRun {
        id: u64,
        scene: Box<Scene>,
    },
    CancelRun {
        id: u64,
    },
    /// Write `text` to `path` atomically (temporary file in the same directory, then rename).
    /// With `base`, the file is read first and written only if its content hashes to `base`
    /// (or it is gone); otherwise the answer is [`Msg::SaveConflict`].
    Save {
        path: PathBuf,
        text: String,
        base: Option<u64>,
    },
    /// Format the charted columns of `run` in `window`, the whole run and its event log as
    /// CSV (off the UI thread) and write them as `export-<n>-chart.csv`, `-history.csv`,
    /// `-events.csv` (the first free n) into the first directory of `dirs` that accepts them.
    Export {
        dirs: Vec<PathBuf>,
        run: Box<RunData>,
        window: (f64, f64),
        element: usize,
    },
    /// Run a study in a worker thread ([`crate::tui::workers::study`]).
    StartStudy {
        id: u64,
        spec: Box<StudySpec>,
    },
    CancelStudy {
        id: u64,
    },
    /// Write study `id`'s table as `<kind>-<n>.csv` (the first free n) into the first of
    /// `dirs` that accepts it (created if need be).
    WriteStudy {
        id: u64,
        dirs: Vec<PathBuf>,
        table: Box<StudyTable>,
    },
    /// List the CSV files of `dirs`.
    ListStudies {
        dirs: Vec<PathBuf>,
    },
    /// Read a study's CSV.
    LoadStudy {
        path: PathBuf,
    },
    /// Write runs of the run list into `dir` (each file atomically) and remove the files of
    /// the runs `remove`, in the order asked (one writer).
    StoreRuns {
        dir: PathBuf,
        jobs: Vec<run_store::Job>,
        remove: Vec<u64>,
    },
    /// Write the time charts' preferences to `path` atomically
    /// ([`super::chart_prefs::store`]), in order with the run list's files.
    StoreCharts {
        path: PathBuf,
        text: String,
    },
    /// Read the series of the stored runs `runs` (number, `t_end`) from `dir`, after the
    /// files asked to be written before.
    LoadSeries {
        dir: PathBuf,
        runs: Vec<(u64, f64)>,
    },
    // -- the results pages
    /// Compute a results page's data in a worker ([`crate::tui::workers::results`]).
    StartResult {
        id: u64,
        spec: Box<ResultSpec>,
    },
    CancelResult {
        id: u64,
    },
    // another model
    /// List the model files of `dir` and its subfolders ([`crate::tui::form::model_files`]).
    ListModels {
        dir: PathBuf,
    },
    /// Read a model file to open it.
    ReadModel {
        path: PathBuf,
    },
    /// Watch `path` for changes from now on (the watcher of the model before it stops).
    Watch {
        path: PathBuf,
    },
    Quit,
    /// Ctrl-Z: restore the terminal, stop the process (SIGTSTP) and, once continued, take
    /// the terminal back and redraw it whole.
    Suspend,
}

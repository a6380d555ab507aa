//! Workbench state: [`App`], its modes and presentation options. Changed only by
//! [`super::update`]; drawn by [`super::ui`].

use super::keymap::{self, Ctx};
use super::results::Results;
use super::term::{ColorDepth, Glyphs};
use crate::scene::Scene;
pub use crate::tui::form::merge::Conflict;
use crate::tui::form::{self, Form};
use crate::tui::runs::data::RunData;
use crate::tui::runs::list::Runs;
use crate::tui::studies::Studies;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

/// Smallest usable terminal; below it the workbench shows a "terminal too small" screen.
pub const MIN_WIDTH: u16 = 60;
pub const MIN_HEIGHT: u16 = 18;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Charts,
    Form,
    Studies,
    /// The run list, its model diffs and the comparison (`#`).
    Runs,
}

/// What the status message is about: it stays until a newer one, or until that changes.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum About {
    /// Stays until a newer message.
    #[default]
    Anything,
    /// Run `id` started or ended; `lead`: what was said before it (a reload, a merge, the runs
    /// reopened), kept in front of it until the run ends.
    Run { id: u64, lead: String },
    /// The runs overlaid and the baseline, as [`App::overlay_key`] gives them: gone when they
    /// change, or in a view without runs (the studies).
    Overlay(String),
}

#[derive(Clone, Debug, PartialEq)]
pub enum Confirm {
    /// Values changed both on disk and in the workbench (the first is asked about; the draft
    /// holds mine until answered). `resume`: the field path and the value being typed when
    /// the change arrived, given back after the last answer.
    Merge {
        conflicts: Vec<Conflict>,
        resume: Option<(String, String)>,
    },
    /// `s` found the file on disk changed since the version the edits were based on, and the
    /// change not merged: `text` is what is on disk now.
    SaveConflict { text: String },
    /// Quit with unsaved edits.
    Quit,
    /// Delete run `number` of the run list and its files.
    DeleteRun { number: u64 },
    /// Open another model (chosen in the list of models) and lose the unsaved edits.
    OpenModel { path: PathBuf },
    /// A swap file of unsaved edits found at the start (`tui::form::swap`), with the values that
    /// differ from the model.
    Recover {
        found: crate::tui::form::swap::Found,
        differences: Vec<String>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub enum Mode {
    Normal,
    /// Typing a new value for the selected field; `check` is the live validation.
    Editing {
        buffer: String,
        check: Result<(), String>,
    },
    Confirm(Confirm),
    Help,
    /// The message log (`tui::messages`).
    Messages,
    /// Choosing a study's CSV to reopen (the files found, newest first).
    Pick {
        files: Vec<PathBuf>,
        selected: usize,
    },
    /// Typing a name for run `number` of the run list.
    Naming {
        number: u64,
        buffer: String,
    },
    // the form's search and the list of models
    /// Typing a search in the form (`/`): the selection follows the first match; `from` is
    /// where it was (Esc goes back there).
    Search {
        query: String,
        from: form::Spot,
    },
    /// Choosing a model to open (the model files of the model's folder and its subfolders).
    OpenModel {
        files: Vec<PathBuf>,
        selected: usize,
    },
    /// Choosing the series of time chart `chart` (0–2): the series whose name holds `query`,
    /// the `selected` one of them.
    ChartPick {
        chart: usize,
        query: String,
        selected: usize,
    },
    /// A run's whole status (`i`): its failure's reason, time reached, method and step.
    RunInfo(Box<crate::tui::runs::info::Info>),
}

pub use super::messages::StatusKind;

/// Presentation options (from the environment and the command line in the real terminal).
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// false when the terminal shows no colour (`NO_COLOR`, `TERM=dumb`).
    pub color: bool,
    /// Start in ASCII mode: nothing above 0x7E on screen ([`Glyphs::Ascii`]: `TERM=dumb`,
    /// `linux`, `vt100`, …, `DECKSPIN_GLYPHS=ascii` or `--glyphs ascii`); `m` toggles it.
    pub ascii: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            color: true,
            ascii: false,
        }
    }
}

impl Options {
    /// The options of this process's environment, the glyphs overridden by `glyphs` (the
    /// command line's `--glyphs`) when given.
    pub fn from_env(glyphs: Option<Glyphs>) -> Result<Self, String> {
        let mut o = Self::from_vars(&|k| std::env::var(k).ok())?;
        if let Some(g) = glyphs {
            o.ascii = g == Glyphs::Ascii;
        }
        Ok(o)
    }

    /// The options told by environment variables read through `get`: no colour when the
    /// terminal shows none ([`ColorDepth::None`]: `NO_COLOR`, `TERM=dumb`); ASCII when the
    /// glyphs are ([`Glyphs::from_vars`]: `DECKSPIN_GLYPHS`, `DECKSPIN_ASCII`, `TERM`). An
    /// unknown `DECKSPIN_GLYPHS` is an error naming it.
    pub fn from_vars(get: &dyn Fn(&str) -> Option<String>) -> Result<Self, String> {
        Ok(Self {
            color: ColorDepth::from_vars(get) != ColorDepth::None,
            ascii: Glyphs::from_vars(get)? == Glyphs::Ascii,
        })
    }
}

/// A model error shown on screen: message, line and column, the offending source line.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadError {
    /// `file:line:col: message`.
    pub message: String,
    /// The message without its location.
    pub detail: String,
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub source_line: Option<String>,
}

impl LoadError {
    pub fn new(e: &crate::ModelError, text: &str) -> Self {
        let (message, detail, at) = form::describe_error(e, text);
        let source_line =
            at.and_then(|(l, _)| text.lines().nth(l.saturating_sub(1)).map(str::to_string));
        Self {
            message,
            detail,
            line: at.map(|a| a.0),
            column: at.map(|a| a.1),
            source_line,
        }
    }
}

pub fn hash_text(text: &str) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    text.hash(&mut h);
    h.finish()
}

/// The workbench state.
pub struct App {
    pub path: PathBuf,
    pub opts: Options,
    /// Model text as last loaded or saved (the last good one).
    pub text: String,
    /// `text` plus the accepted form edits.
    pub draft: String,
    /// Hash of the file content last seen on disk (good or bad).
    pub disk_hash: u64,
    /// Hash of a save in flight (its watcher event is not a foreign change).
    pub expected_save: Option<u64>,
    /// Compiled `draft` (None only when no version of the file has loaded yet).
    pub scene: Option<Scene>,
    pub form: Form,
    pub view: View,
    pub mode: Mode,
    pub current: Option<RunData>,
    /// The runs kept: numbered, named, one the baseline; stored beside the model.
    pub runs: Runs,
    /// The number of the model's next run (after the highest of its stored runs).
    pub next_run: u64,
    /// The next worker token ([`RunData::token`]): never reused in the session, whatever
    /// model is open.
    pub next_token: u64,
    /// Time cursor (when not following the latest sample).
    pub cursor: f64,
    pub follow: bool,
    /// Visible time window (None: the whole run).
    pub zoom: Option<(f64, f64)>,
    /// Charted hysteretic element.
    pub element: usize,
    pub ascii: bool,
    pub overlay: bool,
    pub status: String,
    pub status_kind: StatusKind,
    pub status_about: About,
    /// The file on disk does not load (the last good model stays on screen).
    pub load_error: Option<LoadError>,
    pub size: (u16, u16),
    pub quit: bool,
    pub watch_mode: String,
    /// Bumped whenever charted data changes (keys the drawing caches).
    pub generation: u64,
    /// The studies view: the last study of each kind, running or done.
    pub studies: Studies,
    /// Runs found on disk beyond the bound, removed with the next store.
    pub runs_older: Vec<u64>,
    // navigation: the event list
    /// The event list is shown (charts view, in place of the side panels).
    pub events_open: bool,
    /// The event list's selected row, in time order (None: the row at the cursor).
    pub event_sel: Option<usize>,
    // any terminal
    /// First line of the help shown (the help scrolls when taller than the screen).
    pub help_scroll: usize,
    /// The results pages of the studies view (energy, contacts, modes, records).
    pub results: Results,
    // the form and the model file
    /// "save and quit" was answered: quit once the save is done.
    pub quit_after_save: bool,
    /// The value being typed (not valid yet) when a quit was asked: given back on "stay".
    pub typing_before_quit: Option<Mode>,
    /// Every status message said (`tui::messages`), and the first line of the log shown.
    pub messages: Vec<super::messages::Said>,
    pub log_scroll: usize,
    /// What the time charts show (series, y zoom, log scale, θ's unit), remembered per model.
    pub charts: super::chart_prefs::ChartPrefs,
    /// The first line of the run info shown.
    pub info_scroll: usize,
    /// What opening the run list read ([`crate::tui::runs::store::ReadCount`]), and the runs whose
    /// model diff it computed (stored again at the start).
    pub runs_read: crate::tui::runs::store::ReadCount,
    pub runs_rediffed: Vec<u64>,
}

impl App {
    /// An app on model text (nothing is read from disk except files the model refers to).
    pub fn new_from_text(text: &str, path: &Path) -> App {
        Self::with_options(text, path, Options::default())
    }

    pub fn with_options(text: &str, path: &Path, opts: Options) -> App {
        let mut app = App {
            path: path.to_path_buf(),
            opts,
            text: text.to_string(),
            draft: text.to_string(),
            disk_hash: hash_text(text),
            expected_save: None,
            scene: None,
            form: form::build(text, text),
            view: View::Charts,
            mode: Mode::Normal,
            current: None,
            runs: Runs::default(),
            next_run: 1,
            next_token: 1,
            cursor: 0.0,
            follow: true,
            zoom: None,
            element: 0,
            ascii: opts.ascii,
            overlay: true,
            status: String::new(),
            status_kind: StatusKind::Info,
            status_about: About::Anything,
            load_error: None,
            size: (80, 24),
            quit: false,
            watch_mode: String::new(),
            generation: 0,
            studies: Studies::default(),
            runs_older: Vec::new(),
            events_open: false,
            event_sel: None,
            help_scroll: 0,
            results: Results::default(),
            quit_after_save: false,
            typing_before_quit: None,
            messages: Vec::new(),
            log_scroll: 0,
            charts: Default::default(),
            info_scroll: 0,
            runs_read: Default::default(),
            runs_rediffed: Vec::new(),
        };
        match form::validate(text, path) {
            Ok(scene) => {
                app.scene = Some(scene);
                app.set_status(StatusKind::Info, format!("loaded {}", app.file_name()));
            }
            Err(e) => {
                let le = LoadError::new(&e, text);
                app.set_status(
                    StatusKind::Error,
                    format!("the model does not load: {}", le.message),
                );
                app.load_error = Some(le);
            }
        }
        app
    }

    /// Reads the model file (an unreadable file is an error; one that does not parse opens
    /// with the error on screen and loads once fixed).
    pub fn new_from_path(path: &Path, opts: Options) -> Result<App, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        let mut app = Self::with_options(&text, path, opts);
        app.open_runs();
        Ok(app)
    }

    /// Reads the runs stored beside the model (`<stem>.runs/`) and keeps storing there; says
    /// on the status line what came back and what was skipped.
    pub fn open_runs(&mut self) {
        let dir = crate::tui::runs::store::runs_dir(&self.path);
        let loaded = crate::tui::runs::store::load(&dir);
        self.runs = loaded.runs;
        self.runs_older = loaded.older;
        self.runs_read = loaded.read;
        self.runs_rediffed = loaded.rediffed;
        self.next_run = self.next_run.max(self.runs.last_number() + 1);
        let mut notes = Vec::new();
        let (charts, trouble) = super::chart_prefs::load(&self.path);
        self.charts = charts;
        let warn = trouble.is_some();
        notes.extend(trouble);
        if !self.runs.list.is_empty() {
            let base = self
                .runs
                .baseline
                .map_or(String::new(), |b| format!(", baseline #{b}"));
            // the folder beside the model, by its name
            let n = self.runs.list.len();
            notes.push(format!(
                "{n} run{} reopened from {}/{base}",
                if n == 1 { "" } else { "s" },
                dir.file_name().map_or_else(
                    || dir.display().to_string(),
                    |f| f.to_string_lossy().into_owned()
                )
            ));
        }
        let kind = if loaded.skipped.is_empty() {
            if warn {
                StatusKind::Warn
            } else {
                self.status_kind
            }
        } else {
            notes.push(format!(
                "skipped in {}: {}",
                dir.display(),
                loaded.skipped.join("; ")
            ));
            StatusKind::Warn
        };
        if !notes.is_empty() {
            let lead = self.status.clone();
            self.say(kind, &lead, notes.join(" · "), About::Anything);
        }
    }

    pub fn dirty(&self) -> bool {
        self.draft != self.text
    }

    pub fn file_name(&self) -> String {
        self.path.file_name().map_or_else(
            || self.path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        )
    }

    pub fn title(&self) -> String {
        self.scene
            .as_ref()
            .map_or_else(|| self.file_name(), |s| s.title.clone())
    }

    /// A status message, in the log too; it stays until a newer one.
    pub fn set_status(&mut self, kind: StatusKind, s: impl Into<String>) {
        self.say(kind, "", s.into(), About::Anything);
    }

    /// A status message `text` about `about` (gone when that changes), after `lead` (which
    /// the log has already).
    pub fn say(&mut self, kind: StatusKind, lead: &str, text: String, about: About) {
        super::messages::push(&mut self.messages, kind, &text);
        self.status = if lead.is_empty() {
            text
        } else {
            format!("{lead} · {text}")
        };
        self.status_kind = kind;
        self.status_about = about;
    }

    /// A message about the runs overlaid and the baseline.
    pub fn say_overlay(&mut self, kind: StatusKind, text: String) {
        let key = self.overlay_key();
        self.say(kind, "", text, About::Overlay(key));
    }

    /// The runs overlaid and the baseline, and whether they are shown.
    pub fn overlay_key(&self) -> String {
        let on: Vec<String> = (self.runs.list.iter())
            .filter(|e| e.overlay)
            .map(|e| e.number.to_string())
            .collect();
        format!("{:?} {} {}", self.runs.baseline, on.join(","), self.overlay)
    }

    /// Drops a message whose state has changed or that the view shown has nothing to do with
    /// (it stays in the log).
    pub fn drop_stale_status(&mut self) {
        let stale = match &self.status_about {
            About::Overlay(key) => self.view == View::Studies || *key != self.overlay_key(),
            _ => false,
        };
        if stale {
            self.status.clear();
            self.status_kind = StatusKind::Info;
            self.status_about = About::Anything;
        }
    }

    /// What a run's messages are said after: the message shown when it is about nothing in
    /// particular (a reload, a merge, the runs reopened), kept in front of a run's start.
    pub fn status_lead(&self) -> String {
        match &self.status_about {
            About::Anything => self.status.clone(),
            _ => String::new(),
        }
    }

    pub fn too_small(&self) -> bool {
        self.size.0 < MIN_WIDTH || self.size.1 < MIN_HEIGHT
    }

    /// End of the time axis.
    pub fn t_end(&self) -> f64 {
        let t = self
            .current
            .as_ref()
            .map(|r| r.t_end)
            .or(self.scene.as_ref().map(|s| s.settings.t_end))
            .unwrap_or(1.0);
        if t > 0.0 { t } else { 1.0 }
    }

    /// The visible time window.
    pub fn window(&self) -> (f64, f64) {
        self.zoom.unwrap_or((0.0, self.t_end()))
    }

    /// Cursor time (the latest sample while following).
    pub fn cursor_time(&self) -> f64 {
        if self.follow {
            self.current
                .as_ref()
                .and_then(|r| r.t.last().copied())
                .unwrap_or(0.0)
        } else {
            self.cursor
        }
    }

    pub fn running(&self) -> bool {
        self.current.as_ref().is_some_and(RunData::running)
    }

    /// The active keymap contexts.
    pub fn contexts(&self) -> Vec<Ctx> {
        let mode = match self.mode {
            Mode::Normal => None,
            Mode::Editing { .. } => Some(Ctx::Edit),
            Mode::Confirm(Confirm::Merge { .. }) => Some(Ctx::Merge),
            Mode::Confirm(Confirm::Quit) => Some(Ctx::Quit),
            Mode::Confirm(Confirm::Recover { .. }) => Some(Ctx::Recover),
            Mode::Search { .. } => Some(Ctx::Search),
            Mode::OpenModel { .. } => Some(Ctx::OpenModel),
            Mode::Confirm(_) => Some(Ctx::Confirm),
            Mode::Help => Some(Ctx::Help),
            Mode::Messages => Some(Ctx::Messages),
            Mode::Pick { .. } => Some(Ctx::Pick),
            Mode::Naming { .. } => Some(Ctx::Naming),
            Mode::ChartPick { .. } => Some(Ctx::ChartPick),
            Mode::RunInfo(_) => Some(Ctx::RunInfo),
        };
        let mut ctxs = keymap::active(mode, self.view_ctx());
        if mode.is_none() && self.view == View::Charts && self.events_open {
            ctxs.insert(0, Ctx::Events);
        }
        ctxs
    }

    /// The keymap context of the view shown.
    pub fn view_ctx(&self) -> Ctx {
        match self.view {
            View::Charts => Ctx::Charts,
            View::Form => Ctx::Form,
            View::Studies => Ctx::Studies,
            View::Runs => Ctx::Runs,
        }
    }

    /// Rebuilds the form from the draft, keeping the selected field, the folded groups and
    /// the last search.
    pub(crate) fn rebuild_form(&mut self) {
        let old = std::mem::take(&mut self.form);
        self.form = form::build(&self.draft, &self.text);
        self.form.keep_from(&old);
    }

    /// Live check of an edit buffer: the engine's verdict on the model with this value.
    pub fn check_edit(&self, buffer: &str) -> Result<String, String> {
        let f = self.form.selected().ok_or("no field selected")?;
        let text = form::set_value(&self.draft, &f.path, f.kind, buffer, f.dim)?;
        match form::validate(&text, &self.path) {
            Ok(_) => Ok(text),
            Err(e) => {
                let msg = form::error_with_column(&e, &text).0;
                // a file that never loaded takes edits that leave it invalid (so it can be
                // repaired in the form); a valid model refuses them
                if self.scene.is_none() && form::validate(&self.draft, &self.path).is_err() {
                    Ok(text)
                } else {
                    Err(msg)
                }
            }
        }
    }
}

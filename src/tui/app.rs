//! Workbench state and the update function. `update(app, msg)` changes the state and returns
//! effects (start or cancel a run, save, export, quit) that the runtime executes; nothing here
//! touches the terminal, threads or (except for validating model text) the file system, so
//! every user action is unit-testable.

use super::form::{self, Form};
use super::keymap::{self, Action, Ctx};
use crate::output::{ContactState, EventKind, EventRecord, RunOutput, Sample, Summary};
use crate::scene::Scene;
use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use std::cell::RefCell;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

/// Smallest usable terminal; below it the workbench shows a "terminal too small" screen.
pub const MIN_WIDTH: u16 = 60;
pub const MIN_HEIGHT: u16 = 18;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Charts,
    Form,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Confirm {
    /// The file changed on disk while the form has unsaved edits.
    Reload { text: String },
    /// Quit with unsaved edits.
    Quit,
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
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusKind {
    Info,
    Ok,
    Warn,
    Error,
}

/// Presentation options (from the environment in the real terminal).
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// false when NO_COLOR is set: no colours at all.
    pub color: bool,
    /// Start with ASCII (Dot) chart markers instead of Braille (DECKSPIN_ASCII=1).
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
    pub fn from_env() -> Self {
        let set = |k: &str| std::env::var_os(k).is_some_and(|v| !v.is_empty());
        Self {
            color: !set("NO_COLOR"),
            ascii: std::env::var("DECKSPIN_ASCII").is_ok_and(|v| !v.is_empty() && v != "0"),
        }
    }
}

/// How a run ended.
#[derive(Debug)]
pub enum RunOutcome {
    Finished(Box<RunOutput>),
    Cancelled { t: f64 },
    Failed(String),
}

/// Input of [`update`].
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
    /// Result of [`Effect::Export`]: the written paths.
    Exported(Result<Vec<PathBuf>, String>),
}

/// Output of [`update`], executed by the runtime.
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
    Save {
        path: PathBuf,
        text: String,
    },
    /// Write the files into the first directory of `dirs` that accepts them.
    /// Format the charted columns of `run` in `window` and its event log as CSV (off the UI
    /// thread) and write `<stem>-chart.csv`, `<stem>-events.csv` into the first directory of
    /// `dirs` that accepts them.
    Export {
        dirs: Vec<PathBuf>,
        stem: String,
        run: Box<RunData>,
        window: (f64, f64),
        element: usize,
    },
    Quit,
}

#[derive(Clone, Debug, PartialEq)]
pub enum RunStatus {
    Running,
    Cancelling,
    Finished,
    Cancelled,
    Failed(String),
}

/// Peak and residual rotation, impacts and stick time of a run so far (definitions as in the
/// engine's [`Summary`]).
#[derive(Clone, Debug, Default)]
pub struct Digest {
    pub rot_name: String,
    pub peak_rot: f64,
    pub peak_rot_at: f64,
    pub residual_rot: f64,
    pub impacts: Vec<usize>,
    pub stick_time: Vec<f64>,
    pub min_gap: Vec<f64>,
    pub events: usize,
}

impl Digest {
    pub fn total_impacts(&self) -> usize {
        self.impacts.iter().sum()
    }
    pub fn total_stick_time(&self) -> f64 {
        self.stick_time.iter().sum()
    }
    pub fn min_gap(&self) -> f64 {
        self.min_gap.iter().copied().fold(f64::INFINITY, f64::min)
    }
}

/// The charted history of one run, in columns.
#[derive(Clone, Debug)]
pub struct RunData {
    pub id: u64,
    /// "run 3" or "run 3 (unsaved edits)".
    pub label: String,
    pub dof_names: Vec<String>,
    pub contact_names: Vec<String>,
    pub element_names: Vec<String>,
    pub t: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    pub gap: Vec<Vec<f64>>,
    pub state: Vec<Vec<ContactState>>,
    /// (deformation, force) columns per hysteretic element.
    pub el: Vec<(Vec<f64>, Vec<f64>)>,
    pub events: Vec<EventRecord>,
    pub t_sim: f64,
    pub t_end: f64,
    pub status: RunStatus,
    pub summary: Option<Summary>,
    pub steps: Option<usize>,
    pub digest: Digest,
    /// Peak |q| per DOF and (min, max) of deformation and force per element, so far.
    pub q_peak: Vec<f64>,
    pub el_range: Vec<[f64; 4]>,
    /// Index of the charted rotation DOF and of the x/y DOFs.
    pub rot: Option<usize>,
    pub xy: Vec<usize>,
}

/// The rotation to chart: `deck.theta`, else the first `*.theta`, else the first DOF.
pub fn rotation_dof(names: &[String]) -> Option<usize> {
    names
        .iter()
        .position(|n| n == "deck.theta")
        .or_else(|| names.iter().position(|n| n.ends_with(".theta")))
        .or(if names.is_empty() { None } else { Some(0) })
}

/// The translations to chart: x and y of the rotation's body, else the first DOFs.
pub fn xy_dofs(names: &[String], rot: Option<usize>) -> Vec<usize> {
    let body = rot
        .and_then(|r| names[r].rsplit_once('.'))
        .map(|(b, _)| b.to_string())
        .unwrap_or_default();
    let found: Vec<usize> = ["x", "y"]
        .iter()
        .filter_map(|a| names.iter().position(|n| *n == format!("{body}.{a}")))
        .filter(|&i| Some(i) != rot)
        .collect();
    if !found.is_empty() {
        return found;
    }
    (0..names.len())
        .filter(|&i| Some(i) != rot)
        .take(2)
        .collect()
}

impl RunData {
    pub fn new(
        id: u64,
        label: String,
        dof_names: Vec<String>,
        contact_names: Vec<String>,
        element_names: Vec<String>,
        t_end: f64,
    ) -> Self {
        let rot = rotation_dof(&dof_names);
        let xy = xy_dofs(&dof_names, rot);
        let nc = contact_names.len();
        Self {
            id,
            label,
            q: vec![Vec::new(); dof_names.len()],
            gap: vec![Vec::new(); nc],
            state: vec![Vec::new(); nc],
            el: vec![(Vec::new(), Vec::new()); element_names.len()],
            q_peak: vec![0.0; dof_names.len()],
            el_range: vec![
                [
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY
                ];
                element_names.len()
            ],
            digest: Digest {
                rot_name: rot.map(|r| dof_names[r].clone()).unwrap_or_default(),
                impacts: vec![0; nc],
                stick_time: vec![0.0; nc],
                min_gap: vec![f64::INFINITY; nc],
                ..Digest::default()
            },
            dof_names,
            contact_names,
            element_names,
            t: Vec::new(),
            events: Vec::new(),
            t_sim: 0.0,
            t_end,
            status: RunStatus::Running,
            summary: None,
            steps: None,
            rot,
            xy,
        }
    }

    pub fn for_scene(id: u64, label: String, scene: &Scene) -> Self {
        Self::new(
            id,
            label,
            scene.dof_names.clone(),
            scene.contacts.iter().map(|c| c.name.clone()).collect(),
            scene.hysteretic.iter().map(|h| h.name.clone()).collect(),
            scene.settings.t_end,
        )
    }

    /// Appends samples and events (one observer batch).
    pub fn push(&mut self, samples: &[Sample], events: &[EventRecord], t: f64) {
        for s in samples {
            if let Some(&tp) = self.t.last() {
                let dt = s.t - tp;
                for (i, st) in self.state.iter().enumerate() {
                    if st.last() == Some(&ContactState::Stick) {
                        self.digest.stick_time[i] += dt;
                    }
                }
            }
            self.t.push(s.t);
            for (k, col) in self.q.iter_mut().enumerate() {
                let v = s.q.get(k).copied().unwrap_or(f64::NAN);
                col.push(v);
                if v.abs() > self.q_peak[k] {
                    self.q_peak[k] = v.abs();
                }
            }
            for (i, c) in s.contacts.iter().enumerate().take(self.gap.len()) {
                self.gap[i].push(c.gap);
                self.state[i].push(c.state);
                self.digest.min_gap[i] = self.digest.min_gap[i].min(c.gap);
            }
            for (j, &(d, f)) in s.elements.iter().enumerate().take(self.el.len()) {
                self.el[j].0.push(d);
                self.el[j].1.push(f);
                let r = &mut self.el_range[j];
                if d.is_finite() && f.is_finite() {
                    *r = [r[0].min(d), r[1].max(d), r[2].min(f), r[3].max(f)];
                }
            }
            if let Some(r) = self.rot {
                let v = s.q.get(r).copied().unwrap_or(0.0);
                if v.abs() > self.digest.peak_rot {
                    self.digest.peak_rot = v.abs();
                    self.digest.peak_rot_at = s.t;
                }
                self.digest.residual_rot = v;
            }
        }
        for e in events {
            if e.kind == EventKind::Impact
                && let Some(n) = self.digest.impacts.get_mut(e.contact)
            {
                *n += 1;
            }
        }
        self.digest.events += events.len();
        self.events.extend_from_slice(events);
        if let Some(&tl) = self.t.last() {
            self.t_sim = self.t_sim.max(tl);
        }
        self.t_sim = self.t_sim.max(t.min(self.t_end));
    }

    /// Takes the final output of a run (its samples replace the streamed ones if they differ).
    pub fn finish(&mut self, out: RunOutput) {
        if out.samples.len() != self.t.len() || out.events.len() != self.events.len() {
            let mut fresh = RunData::new(
                self.id,
                self.label.clone(),
                out.dof_names.clone(),
                out.contact_names.clone(),
                out.element_names.clone(),
                self.t_end,
            );
            fresh.push(&out.samples, &out.events, out.summary.t_end);
            *self = fresh;
        }
        self.t_sim = out.summary.t_end.max(self.t_sim);
        self.steps = Some(out.summary.stats.steps_accepted);
        // the engine's peak also sees the dense output between samples
        if let Some(p) = out
            .summary
            .peaks
            .iter()
            .find(|p| p.name == self.digest.rot_name)
            && p.max_abs > self.digest.peak_rot
        {
            self.digest.peak_rot = p.max_abs;
            self.digest.peak_rot_at = p.at;
        }
        self.summary = Some(out.summary);
        self.status = RunStatus::Finished;
    }

    pub fn running(&self) -> bool {
        matches!(self.status, RunStatus::Running | RunStatus::Cancelling)
    }

    pub fn count(&self, kind: EventKind) -> usize {
        self.events.iter().filter(|e| e.kind == kind).count()
    }

    /// Index of a DOF, contact or element column by name.
    pub fn dof(&self, name: &str) -> Option<usize> {
        self.dof_names.iter().position(|n| n == name)
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
    pub previous: Option<RunData>,
    pub next_run: u64,
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
    /// The file on disk does not load (the last good model stays on screen).
    pub load_error: Option<LoadError>,
    pub size: (u16, u16),
    pub quit: bool,
    pub watch_mode: String,
    /// Bumped whenever charted data changes (keys the drawing caches).
    pub generation: u64,
    pub(crate) cache: RefCell<super::ui::Cache>,
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
            previous: None,
            next_run: 1,
            cursor: 0.0,
            follow: true,
            zoom: None,
            element: 0,
            ascii: opts.ascii,
            overlay: true,
            status: String::new(),
            status_kind: StatusKind::Info,
            load_error: None,
            size: (80, 24),
            quit: false,
            watch_mode: String::new(),
            generation: 0,
            cache: RefCell::new(Default::default()),
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
        Ok(Self::with_options(&text, path, opts))
    }

    /// The first run.
    pub fn start(&mut self) -> Vec<Effect> {
        if self.scene.is_some() {
            start_run(self)
        } else {
            Vec::new()
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

    pub fn set_status(&mut self, kind: StatusKind, s: impl Into<String>) {
        self.status = s.into();
        self.status_kind = kind;
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
            Mode::Confirm(_) => Some(Ctx::Confirm),
            Mode::Help => Some(Ctx::Help),
        };
        let view = match self.view {
            View::Charts => Ctx::Charts,
            View::Form => Ctx::Form,
        };
        keymap::active(mode, view)
    }

    fn rebuild_form(&mut self) {
        let sel = self.form.selected().map(|f| f.path.clone());
        let old = self.form.selected;
        self.form = form::build(&self.draft, &self.text);
        self.form.selected = sel
            .and_then(|p| self.form.index_of(&p))
            .unwrap_or(old.min(self.form.fields.len().saturating_sub(1)));
    }

    /// Live check of an edit buffer: the engine's verdict on the model with this value.
    pub fn check_edit(&self, buffer: &str) -> Result<String, String> {
        let f = self.form.selected().ok_or("no field selected")?;
        let text = form::set_value(&self.draft, &f.path, f.kind, buffer, &f.unit)?;
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

/// Handles one message.
pub fn update(app: &mut App, msg: Msg) -> Vec<Effect> {
    match msg {
        Msg::Key(ev) => on_key(app, ev),
        Msg::Action(a) => on_action(app, a),
        Msg::Resize(w, h) => {
            app.size = (w, h);
            Vec::new()
        }
        Msg::Batch {
            run,
            samples,
            events,
            t,
        } => {
            if let Some(cur) = app.current.as_mut().filter(|c| c.id == run) {
                cur.push(&samples, &events, t);
                app.generation += 1;
            }
            Vec::new()
        }
        Msg::RunDone { run, outcome } => on_done(app, run, outcome),
        Msg::FileChanged(text) => on_file_changed(app, text),
        Msg::FileUnreadable(e) => {
            app.set_status(
                StatusKind::Warn,
                format!(
                    "cannot read {}: {e} (keeping the last good model)",
                    app.file_name()
                ),
            );
            Vec::new()
        }
        Msg::WatchMode(m) => {
            app.watch_mode = m;
            Vec::new()
        }
        Msg::Saved { text, result } => on_saved(app, text, result),
        Msg::Exported(r) => {
            match r {
                Ok(paths) => {
                    let list: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
                    app.set_status(StatusKind::Ok, format!("exported {}", list.join(", ")));
                }
                Err(e) => app.set_status(StatusKind::Error, format!("export failed: {e}")),
            }
            Vec::new()
        }
    }
}

fn on_key(app: &mut App, ev: KeyEvent) -> Vec<Effect> {
    if ev.kind == KeyEventKind::Release {
        return Vec::new();
    }
    // Ctrl-C quits from anywhere (asking first when there are unsaved edits)
    if ev.code == KeyCode::Char('c') && ev.modifiers.contains(KeyModifiers::CONTROL) {
        return on_action(app, Action::Quit);
    }
    if let Some(a) = keymap::lookup(&app.contexts(), &ev) {
        return on_action(app, a);
    }
    if let Mode::Editing { buffer, .. } = &mut app.mode
        && let KeyCode::Char(c) = ev.code
        && !ev.modifiers.contains(KeyModifiers::CONTROL)
    {
        buffer.push(c);
        recheck(app);
    }
    Vec::new()
}

fn recheck(app: &mut App) {
    if let Mode::Editing { buffer, .. } = &app.mode {
        let check = app.check_edit(buffer).map(|_| ());
        if let Mode::Editing { check: c, .. } = &mut app.mode {
            *c = check;
        }
    }
}

fn on_action(app: &mut App, a: Action) -> Vec<Effect> {
    use Action as A;
    match a {
        A::Quit => {
            if app.dirty() {
                app.mode = Mode::Confirm(Confirm::Quit);
                app.set_status(
                    StatusKind::Warn,
                    "unsaved edits: quit anyway and lose them? (y/n)",
                );
                Vec::new()
            } else {
                quit(app)
            }
        }
        A::Help => {
            app.mode = Mode::Help;
            Vec::new()
        }
        A::CloseHelp => {
            app.mode = Mode::Normal;
            Vec::new()
        }
        A::SwitchView => {
            app.view = match app.view {
                View::Charts => View::Form,
                View::Form => View::Charts,
            };
            Vec::new()
        }
        A::Rerun => {
            if app.scene.is_none() {
                app.set_status(StatusKind::Error, "nothing to run: the model does not load");
                return Vec::new();
            }
            start_run(app)
        }
        A::Cancel => match app.current.as_mut() {
            Some(cur) if cur.status == RunStatus::Running => {
                cur.status = RunStatus::Cancelling;
                let id = cur.id;
                app.set_status(StatusKind::Info, format!("cancelling run {id}…"));
                vec![Effect::CancelRun { id }]
            }
            _ => {
                app.set_status(StatusKind::Info, "no run in progress");
                Vec::new()
            }
        },
        A::Save => save(app),
        A::Export => export(app),
        A::ToggleMarker => {
            app.ascii = !app.ascii;
            app.generation += 1;
            let m = if app.ascii { "ASCII (dots)" } else { "Braille" };
            app.set_status(StatusKind::Info, format!("chart markers: {m}"));
            Vec::new()
        }
        A::ToggleOverlay => {
            app.overlay = !app.overlay;
            app.generation += 1;
            let m = if app.overlay { "shown" } else { "hidden" };
            app.set_status(StatusKind::Info, format!("previous run {m}"));
            Vec::new()
        }
        A::CursorLeft => move_cursor(app, -0.01),
        A::CursorRight => move_cursor(app, 0.01),
        A::CursorLeftFast => move_cursor(app, -0.1),
        A::CursorRightFast => move_cursor(app, 0.1),
        A::CursorHome => {
            app.follow = false;
            app.cursor = 0.0;
            pan_to_cursor(app);
            Vec::new()
        }
        A::CursorEnd => {
            app.follow = true;
            if let Some((a, b)) = app.zoom {
                let end = app.t_end();
                app.zoom = Some((end - (b - a), end));
            }
            Vec::new()
        }
        A::ZoomIn => {
            zoom(app, 0.5);
            Vec::new()
        }
        A::ZoomOut => {
            zoom(app, 2.0);
            Vec::new()
        }
        A::ZoomReset => {
            app.zoom = None;
            Vec::new()
        }
        A::NextElement | A::PrevElement => {
            let n = app.current.as_ref().map_or(0, |r| r.element_names.len());
            if n == 0 {
                app.set_status(StatusKind::Info, "this model has no hysteretic elements");
            } else {
                app.element = if a == A::NextElement {
                    (app.element + 1) % n
                } else {
                    (app.element + n - 1) % n
                };
                let name = app
                    .current
                    .as_ref()
                    .map(|r| r.element_names[app.element].clone());
                app.set_status(
                    StatusKind::Info,
                    format!("column element: {}", name.unwrap_or_default()),
                );
            }
            Vec::new()
        }
        A::FieldUp => select(app, -1),
        A::FieldDown => select(app, 1),
        A::FieldPageUp => select(app, -10),
        A::FieldPageDown => select(app, 10),
        A::FieldEdit => {
            if let Some(f) = app.form.selected() {
                let buffer = f.edit_text();
                app.mode = Mode::Editing {
                    buffer,
                    check: Ok(()),
                };
                recheck(app);
            }
            Vec::new()
        }
        A::FieldRevert => revert(app),
        A::EditCommit => commit(app),
        A::EditCancel => {
            app.mode = Mode::Normal;
            app.set_status(StatusKind::Info, "edit abandoned");
            Vec::new()
        }
        A::EditBackspace | A::EditClear => {
            if let Mode::Editing { buffer, .. } = &mut app.mode {
                if a == A::EditClear {
                    buffer.clear();
                } else {
                    buffer.pop();
                }
            }
            recheck(app);
            Vec::new()
        }
        A::Yes | A::No => answer(app, a == A::Yes),
    }
}

fn quit(app: &mut App) -> Vec<Effect> {
    app.quit = true;
    let mut fx = Vec::new();
    if let Some(cur) = app.current.as_ref().filter(|c| c.running()) {
        fx.push(Effect::CancelRun { id: cur.id });
    }
    fx.push(Effect::Quit);
    fx
}

fn answer(app: &mut App, yes: bool) -> Vec<Effect> {
    let Mode::Confirm(c) = std::mem::replace(&mut app.mode, Mode::Normal) else {
        return Vec::new();
    };
    match (c, yes) {
        (Confirm::Quit, true) => quit(app),
        (Confirm::Quit, false) => {
            app.set_status(StatusKind::Info, "not quitting");
            Vec::new()
        }
        (Confirm::Reload { text }, true) => {
            let fx = apply_reload(app, text, true);
            if app.load_error.is_none() {
                app.set_status(
                    StatusKind::Ok,
                    format!("reloaded {} (your edits were discarded)", app.file_name()),
                );
            }
            fx
        }
        (Confirm::Reload { text }, false) => {
            app.disk_hash = hash_text(&text);
            app.set_status(
                StatusKind::Warn,
                format!(
                    "kept your edits; {} changed on disk (s overwrites it)",
                    app.file_name()
                ),
            );
            Vec::new()
        }
    }
}

fn select(app: &mut App, d: i64) -> Vec<Effect> {
    let n = app.form.fields.len() as i64;
    if n > 0 {
        app.form.selected = (app.form.selected as i64 + d).clamp(0, n - 1) as usize;
    }
    Vec::new()
}

fn commit(app: &mut App) -> Vec<Effect> {
    let Mode::Editing { buffer, .. } = &app.mode else {
        return Vec::new();
    };
    let buffer = buffer.clone();
    let Some(f) = app.form.selected().cloned() else {
        return Vec::new();
    };
    match app.check_edit(&buffer) {
        Ok(text) => {
            accept_draft(app, text);
            app.mode = Mode::Normal;
            let v = app
                .form
                .selected()
                .and_then(|f| f.value.clone())
                .unwrap_or_default();
            let unit = if f.unit.is_empty() || f.unit == "–" || f.unit.contains('|') {
                String::new()
            } else {
                format!(" {}", f.unit)
            };
            app.set_status(
                StatusKind::Ok,
                format!(
                    "{} = {v}{unit} (unsaved: s saves and reruns, r runs the edits)",
                    f.path
                ),
            );
        }
        Err(reason) => {
            app.mode = Mode::Editing {
                buffer,
                check: Err(reason.clone()),
            };
            app.set_status(StatusKind::Error, format!("refused: {reason}"));
        }
    }
    Vec::new()
}

fn accept_draft(app: &mut App, text: String) {
    if let Ok(scene) = form::validate(&text, &app.path) {
        app.scene = Some(scene);
    }
    app.draft = text;
    app.rebuild_form();
}

fn revert(app: &mut App) -> Vec<Effect> {
    let Some(f) = app.form.selected().cloned() else {
        return Vec::new();
    };
    if !f.edited() {
        app.set_status(StatusKind::Info, format!("{} is not edited", f.path));
        return Vec::new();
    }
    let r = match &f.saved {
        Some(v) => form::set_value(&app.draft, &f.path, f.kind, v, ""),
        None => form::remove_value(&app.draft, &f.path),
    };
    match r.and_then(|t| {
        form::validate(&t, &app.path)
            .map(|_| t)
            .map_err(|e| e.to_string())
    }) {
        Ok(t) => {
            accept_draft(app, t);
            app.set_status(StatusKind::Ok, format!("{} reverted", f.path));
        }
        Err(e) => app.set_status(StatusKind::Error, format!("cannot revert {}: {e}", f.path)),
    }
    Vec::new()
}

fn save(app: &mut App) -> Vec<Effect> {
    if !app.dirty() && app.load_error.is_none() {
        app.set_status(StatusKind::Info, "no unsaved edits");
        return Vec::new();
    }
    if let Err(e) = form::validate(&app.draft, &app.path) {
        app.set_status(
            StatusKind::Error,
            format!("not saved: {}", form::error_with_column(&e, &app.draft).0),
        );
        return Vec::new();
    }
    app.expected_save = Some(hash_text(&app.draft));
    app.set_status(StatusKind::Info, format!("saving {}…", app.path.display()));
    vec![Effect::Save {
        path: app.path.clone(),
        text: app.draft.clone(),
    }]
}

fn on_saved(app: &mut App, text: String, result: Result<PathBuf, String>) -> Vec<Effect> {
    app.expected_save = None;
    match result {
        Ok(p) => {
            app.disk_hash = hash_text(&text);
            app.text = text;
            app.load_error = None;
            app.rebuild_form();
            let fx = start_run(app);
            app.set_status(StatusKind::Ok, format!("saved {} — rerunning", p.display()));
            fx
        }
        Err(e) => {
            app.set_status(StatusKind::Error, format!("save failed: {e}"));
            Vec::new()
        }
    }
}

fn on_file_changed(app: &mut App, text: String) -> Vec<Effect> {
    let h = hash_text(&text);
    if h == app.disk_hash {
        return Vec::new();
    }
    if app.expected_save == Some(h) {
        app.disk_hash = h;
        return Vec::new();
    }
    let editing = matches!(app.mode, Mode::Editing { .. });
    let pending = matches!(app.mode, Mode::Confirm(Confirm::Reload { .. }));
    if app.dirty() || editing || pending {
        app.mode = Mode::Confirm(Confirm::Reload { text });
        app.set_status(
            StatusKind::Warn,
            format!(
                "{} changed on disk and you have unsaved edits: reload and discard them? (y/n)",
                app.file_name()
            ),
        );
        return Vec::new();
    }
    apply_reload(app, text, false)
}

fn apply_reload(app: &mut App, text: String, discard: bool) -> Vec<Effect> {
    app.disk_hash = hash_text(&text);
    match form::validate(&text, &app.path) {
        Ok(scene) => {
            app.text = text.clone();
            app.draft = text;
            app.scene = Some(scene);
            app.load_error = None;
            app.rebuild_form();
            app.mode = Mode::Normal;
            let fx = start_run(app);
            app.set_status(
                StatusKind::Ok,
                format!("reloaded {} — rerunning", app.file_name()),
            );
            fx
        }
        Err(e) => {
            let le = LoadError::new(&e, &text);
            let keep = if discard {
                " (your edits are kept)"
            } else {
                ""
            };
            app.set_status(
                StatusKind::Error,
                format!(
                    "reload failed, keeping the last good model{keep}: {}",
                    le.message
                ),
            );
            app.load_error = Some(le);
            Vec::new()
        }
    }
}

/// Starts a run of the current draft: the finished current run becomes the overlay.
fn start_run(app: &mut App) -> Vec<Effect> {
    let Some(scene) = app.scene.clone() else {
        return Vec::new();
    };
    let mut fx = Vec::new();
    if let Some(cur) = app.current.take() {
        if cur.running() {
            fx.push(Effect::CancelRun { id: cur.id });
        }
        if cur.status == RunStatus::Finished {
            app.previous = Some(cur);
        }
    }
    let id = app.next_run;
    app.next_run += 1;
    let label = if app.dirty() {
        format!("run {id} (unsaved edits)")
    } else {
        format!("run {id}")
    };
    app.set_status(StatusKind::Info, format!("{label} started"));
    app.current = Some(RunData::for_scene(id, label, &scene));
    app.follow = true;
    let end = app.t_end();
    if let Some((a, b)) = app.zoom
        && (b > end || a >= end)
    {
        app.zoom = None;
    }
    app.generation += 1;
    fx.push(Effect::StartRun {
        id,
        scene: Box::new(scene),
    });
    fx
}

fn on_done(app: &mut App, run: u64, outcome: RunOutcome) -> Vec<Effect> {
    let Some(cur) = app.current.as_mut().filter(|c| c.id == run) else {
        return Vec::new();
    };
    let label = cur.label.clone();
    match outcome {
        RunOutcome::Finished(out) => {
            cur.finish(*out);
            let (imp, st, sl, re) = (
                cur.count(EventKind::Impact),
                cur.count(EventKind::Stick),
                cur.count(EventKind::Slip),
                cur.count(EventKind::Release),
            );
            let t = cur.t_sim;
            // a run started by a reload keeps saying so
            let prefix = if app.status.starts_with("reloaded") {
                format!("reloaded {} · ", app.file_name())
            } else {
                String::new()
            };
            app.set_status(
                StatusKind::Ok,
                format!("{prefix}{label} finished at t = {t:.3} s: {imp} impacts, {st} sticks, {sl} slips, {re} releases"),
            );
        }
        RunOutcome::Cancelled { t } => {
            cur.status = RunStatus::Cancelled;
            app.set_status(
                StatusKind::Warn,
                format!("{label} cancelled at t = {t:.3} s"),
            );
        }
        RunOutcome::Failed(e) => {
            cur.status = RunStatus::Failed(e.clone());
            app.set_status(StatusKind::Error, format!("{label} failed: {e}"));
        }
    }
    app.generation += 1;
    Vec::new()
}

fn move_cursor(app: &mut App, frac: f64) -> Vec<Effect> {
    let (a, b) = app.window();
    let now = app.cursor_time();
    app.follow = false;
    app.cursor = (now + frac * (b - a)).clamp(0.0, app.t_end());
    pan_to_cursor(app);
    Vec::new()
}

fn pan_to_cursor(app: &mut App) {
    if let Some((a, b)) = app.zoom {
        let w = b - a;
        let c = app.cursor;
        if c < a {
            app.zoom = Some((c, c + w));
        } else if c > b {
            app.zoom = Some((c - w, c));
        }
    }
}

fn zoom(app: &mut App, factor: f64) {
    let end = app.t_end();
    let (a, b) = app.window();
    let w = ((b - a) * factor).max(end * 1e-4);
    if w >= end {
        app.zoom = None;
        return;
    }
    let c = app.cursor_time().clamp(a, b);
    let frac = if b > a { (c - a) / (b - a) } else { 0.5 };
    let mut lo = c - frac * w;
    lo = lo.clamp(0.0, end - w);
    app.zoom = Some((lo, lo + w));
}

/// CSV of what is charted (full resolution, in the time window) and of the event log (the
/// engine's `events.csv` columns).
pub fn export_csv(run: &RunData, window: (f64, f64), element: usize) -> (String, String) {
    use std::fmt::Write;
    let (t0, t1) = window;
    let mut cols: Vec<(String, &Vec<f64>)> = Vec::new();
    if let Some(r) = run.rot {
        cols.push((run.dof_names[r].clone(), &run.q[r]));
    }
    for (i, n) in run.contact_names.iter().enumerate() {
        cols.push((format!("{n}.gap"), &run.gap[i]));
    }
    for &k in &run.xy {
        cols.push((run.dof_names[k].clone(), &run.q[k]));
    }
    if !run.element_names.is_empty() {
        let j = element % run.element_names.len();
        cols.push((
            format!("{}.deformation", run.element_names[j]),
            &run.el[j].0,
        ));
        cols.push((format!("{}.force", run.element_names[j]), &run.el[j].1));
    }
    let mut chart = String::from("t");
    for (n, _) in &cols {
        chart.push(',');
        chart.push_str(n);
    }
    chart.push('\n');
    for i in super::chart::window(&run.t, t0, t1) {
        let _ = write!(chart, "{:.12e}", run.t[i]);
        for (_, c) in &cols {
            let _ = write!(chart, ",{:.12e}", c[i]);
        }
        chart.push('\n');
    }
    let ev = crate::output::events_csv(&run.events, &run.contact_names);
    (chart, ev)
}

/// The export files of an [`Effect::Export`]: (file name, content).
pub fn export_files(
    stem: &str,
    run: &RunData,
    window: (f64, f64),
    element: usize,
) -> Vec<(String, String)> {
    let (chart, events) = export_csv(run, window, element);
    vec![
        (format!("{stem}-chart.csv"), chart),
        (format!("{stem}-events.csv"), events),
    ]
}

fn export(app: &mut App) -> Vec<Effect> {
    let Some(run) = app
        .current
        .as_ref()
        .filter(|r| !r.t.is_empty())
        .or(app.previous.as_ref())
    else {
        app.set_status(StatusKind::Info, "nothing to export yet");
        return Vec::new();
    };
    let stem = app
        .path
        .file_stem()
        .map_or("model".into(), |s| s.to_string_lossy().into_owned());
    let mut dirs = Vec::new();
    if let Some(d) = app.path.parent() {
        dirs.push(if d.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            d.to_path_buf()
        });
    }
    dirs.push(PathBuf::from("."));
    let fx = vec![Effect::Export {
        dirs,
        stem,
        run: Box::new(run.clone()),
        window: app.window(),
        element: app.element,
    }];
    app.set_status(StatusKind::Info, "exporting…");
    fx
}

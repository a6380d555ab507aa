//! Another model in the same session (`O`): the model files of the model's folder listed, one
//! chosen (asking first when there are unsaved edits), read and opened by [`App::open_model`].

use crate::tui::app::{App, Confirm, Mode, StatusKind};
use crate::tui::form::model_files::folder_of;
use crate::tui::keymap::Action;
use crate::tui::msg::Effect;
use std::path::{Path, PathBuf};

/// `O` and the keys of the list of models.
pub(super) fn open_action(app: &mut App, a: Action) -> Vec<Effect> {
    match a {
        Action::OpenModel => {
            let dir = folder_of(&app.path);
            app.set_status(
                StatusKind::Info,
                format!("looking for models in {}…", dir.display()),
            );
            return vec![Effect::ListModels { dir }];
        }
        Action::ModelUp | Action::ModelDown => {
            if let Mode::OpenModel { files, selected } = &mut app.mode {
                let k = files.len().max(1);
                *selected = if a == Action::ModelDown {
                    (*selected + 1) % k
                } else {
                    (*selected + k - 1) % k
                };
            }
        }
        Action::ModelOpen => {
            let Mode::OpenModel { files, selected } =
                std::mem::replace(&mut app.mode, Mode::Normal)
            else {
                return Vec::new();
            };
            if let Some(path) = files.get(selected).cloned() {
                return choose(app, path);
            }
        }
        Action::ModelClose => app.mode = Mode::Normal,
        _ => {}
    }
    Vec::new()
}

/// A model chosen: read it, or ask first when there are unsaved edits.
fn choose(app: &mut App, path: PathBuf) -> Vec<Effect> {
    if app.dirty() {
        app.set_status(
            StatusKind::Warn,
            format!(
                "unsaved edits of {}: open {} and lose them? (y/n)",
                app.file_name(),
                path.display()
            ),
        );
        app.mode = Mode::Confirm(Confirm::OpenModel { path });
        return Vec::new();
    }
    app.set_status(StatusKind::Info, format!("reading {}…", path.display()));
    vec![Effect::ReadModel { path }]
}

/// The answer to "open and lose the unsaved edits?".
pub(super) fn answer(app: &mut App, path: PathBuf, yes: bool) -> Vec<Effect> {
    if yes {
        app.set_status(StatusKind::Info, format!("reading {}…", path.display()));
        vec![Effect::ReadModel { path }]
    } else {
        app.set_status(
            StatusKind::Info,
            format!("staying on {} (s saves the edits)", app.file_name()),
        );
        Vec::new()
    }
}

/// The model files were listed: choose one (the open model selected first).
pub(super) fn on_files(app: &mut App, result: Result<Vec<PathBuf>, String>) -> Vec<Effect> {
    match result {
        Ok(files) if files.is_empty() => {
            let dir = folder_of(&app.path);
            app.set_status(
                StatusKind::Info,
                format!("no model files in {}", dir.display()),
            );
        }
        Ok(files) if app.mode == Mode::Normal => {
            let selected = files.iter().position(|p| *p == app.path).unwrap_or(0);
            app.set_status(
                StatusKind::Info,
                format!("{} models: Enter opens one, Esc closes", files.len()),
            );
            app.mode = Mode::OpenModel { files, selected };
        }
        Ok(_) => {}
        Err(e) => app.set_status(StatusKind::Error, format!("cannot list the models: {e}")),
    }
    Vec::new()
}

/// The chosen model was read: open it.
pub(super) fn on_read(app: &mut App, path: PathBuf, result: Result<String, String>) -> Vec<Effect> {
    match result {
        Ok(text) => app.open_model(&path, &text),
        Err(e) => {
            app.set_status(StatusKind::Error, format!("not opened: {e}"));
            Vec::new()
        }
    }
}

impl App {
    /// Opens the model `path` (its text read) in this session: the model, its form, runs,
    /// charts and studies are the new model's (the old model's runs and studies cancelled and
    /// cleared); the view, the presentation, the terminal size, the study numbering
    /// and the folded groups of the form stay. The file watcher is moved to the new path and
    /// the new model runs. Whatever else belongs to a model is reset here.
    pub fn open_model(&mut self, path: &Path, text: &str) -> Vec<Effect> {
        let mut fx = Vec::new();
        if let Some(cur) = self.current.as_ref().filter(|c| c.running()) {
            fx.push(Effect::CancelRun { id: cur.token });
        }
        if let Some((_, e)) = self.studies.running() {
            fx.push(Effect::CancelStudy { id: e.id });
        }
        if let Some(id) = self.results.running_id() {
            fx.push(Effect::CancelResult { id });
        }
        let mut fresh = App::with_options(text, path, self.opts);
        fresh.size = self.size;
        fresh.view = self.view;
        fresh.ascii = self.ascii;
        fresh.overlay = self.overlay;
        fresh.next_token = self.next_token.max(self.next_run);
        fresh.generation = self.generation + 1;
        fresh.watch_mode = std::mem::take(&mut self.watch_mode);
        fresh.studies.next_id = self.studies.next_id;
        fresh.studies.overrides = std::mem::take(&mut self.studies.overrides);
        fresh.studies.mus = std::mem::take(&mut self.studies.mus);
        fresh.form.folded = std::mem::take(&mut self.form.folded);
        if self.runs.dir.is_some() {
            // the run list is the new model's, from beside it
            fresh.open_runs();
        }
        *self = fresh;
        fx.push(Effect::Watch {
            path: path.to_path_buf(),
        });
        if self.load_error.is_none() {
            fx.extend(self.start());
            let msg = format!("opened {}: {}", self.file_name(), self.title());
            self.set_status(StatusKind::Ok, msg);
        }
        fx
    }
}

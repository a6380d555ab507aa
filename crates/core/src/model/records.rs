//! The excitation records of a model: found relative to the model file, read and processed
//! once per (file, processing) and shared.

use super::check::{Check, ModelError};
use crate::excitation::{ExcitationError, GroundMotion, Processing, Record};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};

/// The record file a model names: relative to the model file, else to the working directory,
/// else to a directory above the model (the project root above `models/`).
fn resolve_record(model: &Path, file: &str) -> PathBuf {
    let base = model.parent().unwrap_or(Path::new("."));
    let rp = base.join(file);
    if rp.exists() {
        return rp;
    }
    let alt = PathBuf::from(file);
    if alt.exists() {
        alt
    } else if let Some(root) = base.ancestors().find(|a| a.join(file).exists()) {
        root.join(file)
    } else {
        rp
    }
}

/// Processed ground motions by (record file, processing): the supports of one model that share
/// a record share one motion, and the loads of one study (its sweeps) read and parse each record
/// file once, and process it once per processing (a sweep over runs scales it to each run's
/// PGA).
#[derive(Debug, Default)]
pub struct Motions {
    motions: Mutex<Vec<(PathBuf, Processing, Arc<GroundMotion>)>>,
    /// The records read, by resolved path.
    records: Mutex<Vec<(PathBuf, Arc<Record>)>>,
}

/// The list a mutex holds: a panic elsewhere while it was held leaves it intact, so use it.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl Motions {
    /// The motion of `file` (named relative to `model`) processed by `p`, read at first use.
    pub fn get(
        &self,
        model: &Path,
        file: &str,
        p: Processing,
    ) -> Result<Arc<GroundMotion>, ModelError> {
        let rp = resolve_record(model, file);
        let known = |list: &[(PathBuf, Processing, Arc<GroundMotion>)]| {
            list.iter()
                .find(|(f, q, _)| *f == rp && *q == p)
                .map(|(_, _, m)| m.clone())
        };
        if let Some(m) = known(&lock(&self.motions)) {
            return Ok(m);
        }
        let err = |e| ModelError::Excitation {
            path: model.to_path_buf(),
            source: e,
        };
        let rec = self.record(&rp).map_err(err)?;
        let g = Arc::new(GroundMotion::from_record(&rec, &p).map_err(err)?);
        let mut list = lock(&self.motions);
        // another thread may have processed it meanwhile: keep one
        if let Some(m) = known(&list) {
            return Ok(m);
        }
        list.push((rp, p, g.clone()));
        Ok(g)
    }

    /// The record at the resolved path `rp`, read and parsed at first use.
    fn record(&self, rp: &Path) -> Result<Arc<Record>, ExcitationError> {
        let known = |list: &[(PathBuf, Arc<Record>)]| {
            (list.iter().find(|(f, _)| f == rp)).map(|(_, r)| r.clone())
        };
        if let Some(r) = known(&lock(&self.records)) {
            return Ok(r);
        }
        let rec = Arc::new(crate::excitation::read_any(rp)?);
        let mut list = lock(&self.records);
        if let Some(r) = known(&list) {
            return Ok(r);
        }
        list.push((rp.to_path_buf(), rec.clone()));
        Ok(rec)
    }

    /// A cache holding the records read so far and no processed motion: for loads whose
    /// processing is each its own (a record suite's scaling), so that the motions of one run
    /// are dropped with it.
    pub fn sharing_records(&self) -> Motions {
        Motions {
            motions: Mutex::new(Vec::new()),
            records: Mutex::new(lock(&self.records).clone()),
        }
    }

    /// Record files read and parsed so far (each once).
    pub fn records_read(&self) -> usize {
        lock(&self.records).len()
    }

    /// Motions processed so far (each (record, processing) once).
    pub fn motions_processed(&self) -> usize {
        lock(&self.motions).len()
    }
}

/// An error of reading or processing the record `file` that model field `field` names, located
/// at that field (or at the model field of the processing parameter it is about); when the processing field it is about was written by a `--set` argument
/// (`model_field` maps processing fields to model fields), the argument is named instead.
pub(super) fn record_error(
    e: ModelError,
    ck: &Check,
    field: &str,
    file: &str,
    model_field: &dyn Fn(&str) -> Option<String>,
) -> ModelError {
    let ModelError::Excitation { source, .. } = e else {
        return e;
    };
    if let ExcitationError::Invalid { field: f, .. } = &source
        && let Some(mf) = model_field(f)
        && let Some(a) = ck.set_by(&mf)
    {
        return ModelError::OverrideInvalid {
            argument: a.argument.clone(),
            field: mf,
            reason: source.to_string(),
        };
    }
    // about a processing parameter the model file gives: located there
    let field = match &source {
        ExcitationError::Invalid { field: f, .. } => model_field(f),
        _ => None,
    }
    .unwrap_or_else(|| field.to_string());
    ModelError::Record {
        path: ck.path.to_path_buf(),
        line: ck.line(&field),
        field,
        record: file.to_string(),
        source: Box::new(source),
    }
}

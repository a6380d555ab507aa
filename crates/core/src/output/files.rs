//! Output files as transactions: a file is replaced whole or not at all ([`write_atomic`]);
//! an output folder is written by one process at a time ([`FolderLock`]); a run's files are
//! made in a staging folder beside the result and moved in at its end ([`Staging`]), so the
//! folder holds the previous complete result, or the new one whose `summary.json` says what
//! it is, never a mix.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The lock file of an output folder.
pub(crate) const LOCK_FILE: &str = ".deckspin.lock";
/// The prefix of a staging folder inside an output folder.
const STAGING_PREFIX: &str = ".deckspin-staging-";

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A fresh name beside `path` for its temporary copy: `.NAME.tmp-PID-N`.
fn temp_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.tmp-{}-{n}", std::process::id()))
}

/// `bytes` into the new file `tmp` (created exclusively: nothing planted there is followed),
/// flushed to disk.
fn write_temp(tmp: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = File::options().write(true).create_new(true).open(tmp)?;
    f.write_all(bytes)?;
    f.sync_all()
}

/// `bytes` to `path` as one transaction: written to a new temporary file beside it (created
/// exclusively, so nothing planted at that name is followed), flushed to disk, then renamed
/// over `path` (a symlink planted at `path` is replaced, not followed). On any error the
/// temporary file is removed and `path` keeps its old content (a full disk leaves no 0-byte
/// file).
pub fn write_atomic(path: impl AsRef<Path>, bytes: impl AsRef<[u8]>) -> std::io::Result<()> {
    let (path, bytes) = (path.as_ref(), bytes.as_ref());
    let tmp = temp_beside(path);
    let r = write_temp(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r
}

/// `bytes` to `path` as one transaction that never replaces a file: written to a temporary
/// file beside it and flushed, then linked to `path` (refused with `AlreadyExists` when a
/// file is there, whatever wrote it in the meantime), the temporary name removed. Where the
/// file system has no hard links, renamed to `path` if nothing is there. On any error `path`
/// is left as it was.
pub fn write_new(path: impl AsRef<Path>, bytes: impl AsRef<[u8]>) -> std::io::Result<()> {
    let (path, bytes) = (path.as_ref(), bytes.as_ref());
    let tmp = temp_beside(path);
    let r = write_temp(&tmp, bytes).and_then(|()| match std::fs::hard_link(&tmp, path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Err(e),
        Err(_) if std::fs::symlink_metadata(path).is_ok() => Err(std::io::Error::new(
            std::io::ErrorKind::AlreadyExists,
            "a file is already there",
        )),
        Err(_) => std::fs::rename(&tmp, path),
    });
    let _ = std::fs::remove_file(&tmp);
    r
}

/// An advisory lock on an output folder (`flock` on its [`LOCK_FILE`], which holds the owner's
/// process id), held until dropped. A second process is refused, naming the folder and the
/// owner.
#[derive(Debug)]
pub struct FolderLock {
    file: File,
    path: PathBuf,
}

impl FolderLock {
    /// Locks `dir` (which must exist), or says who holds it.
    pub fn acquire(dir: &Path) -> std::io::Result<Self> {
        Self::acquire_at(dir.join(LOCK_FILE), dir)
    }

    /// Locks the output file `file` (its folder created if needed) by `.NAME.lock` beside it:
    /// a second job writing the same file is refused, naming the process that holds it.
    pub fn for_file(file: &Path) -> std::io::Result<Self> {
        let dir = file.parent().filter(|d| !d.as_os_str().is_empty());
        if let Some(d) = dir {
            std::fs::create_dir_all(d)?;
        }
        let name = file
            .file_name()
            .map_or_else(|| "out".into(), |n| n.to_string_lossy());
        Self::acquire_at(file.with_file_name(format!(".{name}.lock")), file)
    }

    fn acquire_at(path: PathBuf, dir: &Path) -> std::io::Result<Self> {
        // no O_TRUNC before the lock is ours: the owner's pid stays readable
        let mut file = File::options()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)?;
        #[cfg(unix)]
        {
            use std::os::fd::AsRawFd;
            // SAFETY: flock on a descriptor this function owns
            let r = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
            if r != 0 {
                let err = std::io::Error::last_os_error();
                if err.raw_os_error() == Some(libc::EWOULDBLOCK) {
                    let owner = std::fs::read_to_string(&path).unwrap_or_default();
                    let owner = owner.trim();
                    let who = if owner.is_empty() {
                        "another process".into()
                    } else {
                        format!("process {owner}")
                    };
                    return Err(std::io::Error::new(
                        std::io::ErrorKind::WouldBlock,
                        format!(
                            "{} is being written by {who} (its lock {}); wait for it or choose another --out",
                            dir.display(),
                            path.display()
                        ),
                    ));
                }
                return Err(err);
            }
        }
        file.set_len(0)?;
        write!(file, "{}", std::process::id())?;
        file.flush()?;
        Ok(Self { file, path })
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // the file goes while still locked, so no one locks a name about to vanish
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.flush();
    }
}

/// A run's files made in a staging folder inside the output folder, moved into it at the
/// end ([`Staging::commit`]); the output folder locked meanwhile. Staging folders left by a
/// killed process are removed when the next one locks the folder.
#[derive(Debug)]
pub(crate) struct Staging {
    dir: PathBuf,
    stage: PathBuf,
    _lock: FolderLock,
}

impl Staging {
    /// Creates `dir` if needed, locks it, clears staging folders of earlier killed runs and
    /// makes a new one.
    pub(crate) fn begin(dir: &Path) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        let lock = FolderLock::acquire(dir)?;
        if let Ok(entries) = std::fs::read_dir(dir) {
            for e in entries.flatten() {
                let name = e.file_name();
                let name = name.to_string_lossy();
                let stale = name.starts_with(STAGING_PREFIX)
                    || (name.starts_with('.') && name.contains(".tmp-"));
                if stale && e.file_type().is_ok_and(|t| t.is_dir() && !t.is_symlink()) {
                    let _ = std::fs::remove_dir_all(e.path());
                } else if stale && e.file_type().is_ok_and(|t| t.is_file()) {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
        let stage = dir.join(format!("{STAGING_PREFIX}{}", std::process::id()));
        std::fs::create_dir(&stage)?;
        Ok(Self {
            dir: dir.to_path_buf(),
            stage,
            _lock: lock,
        })
    }

    /// Where a file of the new result is written before the commit.
    pub fn path(&self, name: &str) -> PathBuf {
        self.stage.join(name)
    }

    /// Moves the staged files into the output folder: first `summary.json` is replaced by
    /// `interim` (a summary whose status says the result is being replaced), then each staged
    /// file but the summary is renamed over its old one, then the staged `summary.json` (the
    /// new status) last. An instant of the folder holds the old result, the interim status or
    /// the new result. The staging folder is removed and the lock released.
    pub fn commit(self, interim: &str) -> std::io::Result<()> {
        let summary = "summary.json";
        write_atomic(self.dir.join(summary), interim)?;
        let mut names: Vec<String> = std::fs::read_dir(&self.stage)?
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n != summary)
            .collect();
        names.sort();
        for n in &names {
            std::fs::rename(self.stage.join(n), self.dir.join(n))?;
        }
        if self.stage.join(summary).exists() {
            std::fs::rename(self.stage.join(summary), self.dir.join(summary))?;
        }
        std::fs::remove_dir_all(&self.stage)
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        // a staging folder not committed (an error on the way) goes; the result stays
        let _ = std::fs::remove_dir_all(&self.stage);
    }
}

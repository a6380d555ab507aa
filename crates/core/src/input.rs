//! Input files read with bounds: only regular files (a FIFO, a device or a directory given as a
//! model or a record is refused before it is opened, so nothing blocks or reads forever), and
//! never more than a limit of bytes (a file past it is refused by its size, without reading the
//! rest).

use std::io::Read;
use std::path::Path;

/// The largest model file read, bytes.
pub const MAX_MODEL_BYTES: u64 = 16 << 20;
/// The largest record file read when its header gives no count, bytes.
pub(crate) const MAX_RECORD_BYTES: u64 = 512 << 20;

/// The text of the regular file at `path`, at most `limit` bytes: a path that is not a regular
/// file (after symlinks) or a file longer than `limit` is an error of kind `InvalidInput`
/// saying which.
pub fn read_bounded(path: &Path, limit: u64) -> std::io::Result<String> {
    let (buf, more) = read_prefix(path, limit)?;
    if more {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "larger than {} MiB: refused without reading the rest",
                limit >> 20
            ),
        ));
    }
    String::from_utf8(buf).map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e))
}

/// The first `limit` bytes of the regular file at `path` and whether more follow.
pub(crate) fn read_prefix(path: &Path, limit: u64) -> std::io::Result<(Vec<u8>, bool)> {
    let bad = |msg: String| std::io::Error::new(std::io::ErrorKind::InvalidInput, msg);
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        let what = file_kind(&meta);
        return Err(bad(format!(
            "not a regular file ({what}): refused before reading"
        )));
    }
    let mut buf = Vec::new();
    std::fs::File::open(path)?
        .take(limit.saturating_add(1))
        .read_to_end(&mut buf)?;
    let more = buf.len() as u64 > limit;
    buf.truncate(limit as usize);
    Ok((buf, more))
}

fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a directory"
    } else {
        "not a file"
    }
}

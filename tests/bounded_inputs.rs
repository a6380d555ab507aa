//! Bounded readers: a FIFO, a device or a directory given as a model or a record is refused
//! before it is opened (nothing blocks); an AT2 file is read no further than its header's
//! count allows (a 150 MB file that says NPTS = 1000 is refused within a 300 MB address
//! space); a model larger than its limit is refused by its size.
mod common;

use std::path::PathBuf;
use std::process::{Command, Stdio};

fn tmp(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bounded");
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join(name);
    let _ = std::fs::remove_file(&p);
    p
}

/// `deckspin args` through `sh` with `prelude` (e.g. a `ulimit`): (exit code, stderr). A child
/// that blocks (no CPU for 120 s) is killed and the test fails.
fn deckspin(prelude: &str, args: &[&str]) -> (Option<i32>, String) {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    let script = format!(
        "{prelude}\nexec '{}' {}",
        env!("CARGO_BIN_EXE_deckspin"),
        quoted.join(" ")
    );
    let mut child = Command::new("sh")
        .args(["-c", &script])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut watch = common::HangWatch::new(child.id(), 60.0, 120);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read;
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            return (status.code(), err);
        }
        if let Some(why) = watch.hangs() {
            let _ = child.kill();
            panic!("deckspin {args:?} hangs: {why}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

#[cfg(unix)]
#[test]
fn fifos_devices_and_directories_are_refused_before_they_are_read() {
    let fifo = tmp("record.AT2");
    let c = std::ffi::CString::new(fifo.display().to_string()).unwrap();
    // SAFETY: mkfifo with a valid C string
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let f = fifo.display().to_string();
    let (code, err) = deckspin("", &["excitation", &f]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("not a regular file (a FIFO)"), "{err}");
    let model = tmp("model.toml");
    let c = std::ffi::CString::new(model.display().to_string()).unwrap();
    // SAFETY: as above
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let out = tmp("out").display().to_string();
    let m = model.display().to_string();
    for args in [
        vec!["run", &m[..], "--out", &out[..]],
        vec!["run", "/dev/zero", "--out", &out[..]],
        vec!["modes", "/tmp"],
    ] {
        let (code, err) = deckspin("", &args);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(err.contains("not a regular file"), "{args:?}: {err}");
    }
    let _ = std::fs::remove_file(&fifo);
    let _ = std::fs::remove_file(&model);
}

#[test]
fn an_at2_file_is_read_no_further_than_its_count() {
    let path = tmp("lying.AT2");
    {
        use std::io::Write;
        let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
        write!(
            f,
            "PEER\nlying\nACCELERATION IN G\nNPTS=  1000, DT=   .0100 SEC\n"
        )
        .unwrap();
        let line = "  .1000000E-02  .2000000E-02  .3000000E-02  .4000000E-02  .5000000E-02\n";
        for _ in 0..(150 << 20) / line.len() {
            f.write_all(line.as_bytes()).unwrap();
        }
    }
    let p = path.display().to_string();
    // 300 MB of address space: reading the file whole would need more than it has left
    let (code, err) = deckspin("ulimit -v 300000", &["excitation", &p]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("NPTS = 1000") && err.contains("refused without reading the rest"),
        "{err}"
    );
    assert!(err.contains("lying.AT2:4"), "{err}");
    let _ = std::fs::remove_file(&path);
}

#[test]
fn a_model_past_its_size_limit_is_refused() {
    let path = tmp("huge.toml");
    let mut text =
        std::fs::read_to_string(common::model("models/validation/bouncing-ball.toml")).unwrap();
    let pad = "# padding\n".repeat((deckspin::input::MAX_MODEL_BYTES as usize / 10) + 1);
    text.push_str(&pad);
    std::fs::write(&path, text).unwrap();
    let out = tmp("huge-out").display().to_string();
    let (code, err) = deckspin("", &["run", &path.display().to_string(), "--out", &out]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("larger than 16 MiB"), "{err}");
    let _ = std::fs::remove_file(&path);
}

#[test]
fn a_bad_record_is_named_by_file_and_line_by_excitation() {
    let bad = tmp("bad-value.AT2");
    std::fs::write(
        &bad,
        "PEER\nbad\nACCELERATION IN G\nNPTS=  3, DT= .01 SEC\n0.1 0.2 x\n",
    )
    .unwrap();
    let (code, err) = deckspin("", &["excitation", &bad.display().to_string()]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("bad-value.AT2:5") && err.contains("\"x\""),
        "{err}"
    );
    let short = tmp("short.AT2");
    std::fs::write(
        &short,
        "PEER\nshort\nACCELERATION IN G\nNPTS=  3, DT= .01 SEC\n0.1 0.2\n",
    )
    .unwrap();
    let (code, err) = deckspin("", &["excitation", &short.display().to_string()]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("short.AT2") && err.contains("NPTS = 3, found 2"),
        "{err}"
    );
}

//! Every output a transaction (`run`): a killed rerun leaves the previous result whole, a
//! second run on a folder is refused while the first holds it, SIGINT / SIGTERM / SIGHUP end
//! a run as cancelled with consistent files, a symlink planted at an output's name is replaced
//! and not followed; a full standard output is an error, not a panic.
mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_deckspin"))
}

fn dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("transactions")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.parent().unwrap()).unwrap();
    d
}

fn model() -> String {
    common::model("models/four-span.toml").display().to_string()
}

/// A run that writes a long history (a sample every 10 µs) into `out`.
fn long_run(out: &Path) -> Child {
    bin()
        .args(["run", &model(), "--out", &out.display().to_string()])
        .args(["--set", "solver.output_dt=1e-5"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits until the child's staged history has grown past 1 MB (it is running and writing): a
/// hang is judged by the child's CPU, not the wall clock.
fn wait_writing(child: &mut Child, out: &Path) {
    let mut watch = common::HangWatch::new(child.id(), 120.0, 300);
    let staged = out.join(format!(".deckspin-staging-{}/history.csv", child.id()));
    loop {
        if std::fs::metadata(&staged).is_ok_and(|m| m.len() > 1 << 20) {
            return;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before writing"
        );
        if let Some(why) = watch.hangs() {
            panic!("the run hangs: {why}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

fn signal(child: &Child, sig: i32) {
    // SAFETY: kill(2) on our own child's pid
    assert_eq!(unsafe { libc::kill(child.id() as i32, sig) }, 0);
}

fn finish(child: Child) -> (Option<i32>, String) {
    let out = child.wait_with_output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn status(out: &Path) -> serde_json::Value {
    serde_json::from_slice(&read(&out.join("summary.json"))).unwrap()
}

/// Every line of history.csv has the header's number of fields, and the last ends the file.
fn assert_whole_csv(p: &Path) {
    let text = String::from_utf8(read(p)).unwrap();
    assert!(text.ends_with('\n'), "{} cut mid-line", p.display());
    let mut lines = text.lines();
    let n = lines.next().unwrap().split(',').count();
    for (k, l) in lines.enumerate() {
        assert_eq!(l.split(',').count(), n, "{} line {}", p.display(), k + 2);
    }
}

#[test]
fn a_killed_rerun_leaves_the_previous_result_whole() {
    let out = dir("killed");
    let o = out.display().to_string();
    let first = bin()
        .args(["run", &model(), "--out", &o, "--set", "solver.t_end=3"])
        .output()
        .unwrap();
    assert!(first.status.success());
    let before: Vec<Vec<u8>> = ["history.csv", "events.csv", "summary.json"]
        .iter()
        .map(|f| read(&out.join(f)))
        .collect();
    let mut child = long_run(&out);
    wait_writing(&mut child, &out);
    signal(&child, libc::SIGKILL);
    let _ = child.wait();
    for (f, old) in ["history.csv", "events.csv", "summary.json"]
        .iter()
        .zip(&before)
    {
        assert!(
            read(&out.join(f)) == *old,
            "{f} changed by the killed rerun"
        );
    }
    assert_eq!(status(&out)["status"], "finished");
    // the next run clears what the killed one left and writes its own result
    let again = bin()
        .args(["run", &model(), "--out", &o, "--set", "solver.t_end=2"])
        .output()
        .unwrap();
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    let left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    assert_eq!(status(&out)["t_end"], 2.0);
}

/// A disk that fills up (here: a file-size limit of 64 kB, EFBIG as ENOSPC would be, with
/// SIGXFSZ ignored so that the write fails instead of killing the process) during a rerun: an
/// error, no panic, and the folder still holds the previous result byte for byte, with no
/// empty or partial file in it.
#[cfg(unix)]
#[test]
fn a_rerun_that_runs_out_of_space_leaves_the_previous_result_whole() {
    let out = dir("no-space");
    let o = out.display().to_string();
    let first = bin()
        .args(["run", &model(), "--out", &o, "--set", "solver.t_end=0.5"])
        .args(["--set", "solver.output_dt=0.05"])
        .output()
        .unwrap();
    assert!(first.status.success());
    let files = ["history.csv", "events.csv", "summary.json"];
    let before: Vec<Vec<u8>> = files.iter().map(|f| read(&out.join(f))).collect();
    assert!(
        before[0].len() < 64 * 1024,
        "the first result fits the limit"
    );
    let script = format!(
        "trap '' XFSZ; ulimit -f 128; exec '{}' run '{}' --out '{o}' --set solver.t_end=3",
        env!("CARGO_BIN_EXE_deckspin"),
        model()
    );
    let r = Command::new("sh").args(["-c", &script]).output().unwrap();
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success(), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains(&format!("{o}: cannot write results: File too large")),
        "{err}"
    );
    for (f, old) in files.iter().zip(&before) {
        assert!(
            read(&out.join(f)) == *old,
            "{f} changed by the failed rerun"
        );
    }
    assert_eq!(status(&out)["status"], "finished");
}

#[test]
fn a_second_run_is_refused_and_signals_cancel_with_consistent_files() {
    for (sig, code) in [
        (libc::SIGINT, 130),
        (libc::SIGTERM, 143),
        (libc::SIGHUP, 129),
    ] {
        let out = dir(&format!("signal-{sig}"));
        let mut child = long_run(&out);
        wait_writing(&mut child, &out);
        if sig == libc::SIGINT {
            let second = bin()
                .args(["run", &model(), "--out", &out.display().to_string()])
                .output()
                .unwrap();
            assert_eq!(second.status.code(), Some(1));
            let e = String::from_utf8_lossy(&second.stderr);
            assert!(
                e.contains(&format!("is being written by process {}", child.id())),
                "{e}"
            );
        }
        signal(&child, sig);
        let (code_got, stderr) = finish(child);
        assert_eq!(code_got, Some(code), "{stderr}");
        assert!(stderr.contains("cancelled by SIG"), "{stderr}");
        let s = status(&out);
        assert_eq!(s["status"], "cancelled", "{s}");
        let t = s["cancelled_at"].as_f64().unwrap();
        assert!(t > 0.0 && t < 16.0, "{t}");
        assert_whole_csv(&out.join("history.csv"));
        assert_whole_csv(&out.join("events.csv"));
        assert!(!out.join(".deckspin.lock").exists());
    }
}

#[cfg(unix)]
#[test]
fn a_symlink_planted_at_an_output_name_is_replaced_not_followed() {
    let out = dir("symlink");
    std::fs::create_dir_all(&out).unwrap();
    let victim = out.with_file_name("symlink-victim.txt");
    std::fs::write(&victim, "keep me").unwrap();
    for f in ["summary.json", "history.csv", "events.csv"] {
        std::os::unix::fs::symlink(&victim, out.join(f)).unwrap();
    }
    let r = bin()
        .args(["run", &model(), "--out", &out.display().to_string()])
        .args(["--set", "solver.t_end=1"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    for f in ["summary.json", "history.csv", "events.csv"] {
        let m = std::fs::symlink_metadata(out.join(f)).unwrap();
        assert!(m.file_type().is_file(), "{f} is still a link");
    }
}

#[test]
fn a_full_standard_output_is_an_error_not_a_panic() {
    let full = std::fs::File::options().write(true).open("/dev/full");
    let Ok(full) = full else {
        println!("no /dev/full here: skipped");
        return;
    };
    let d = dir("dev-full");
    let out = |n: &str| d.join(n).display().to_string();
    let record = common::root()
        .join("excitations/NORTHR_LOS000.AT2")
        .display()
        .to_string();
    let short = "solver.t_end=0.2";
    let cases: Vec<Vec<String>> = vec![
        strings(&["modes", &model()]),
        strings(&["run", &model(), "--set", short, "--out", &out("run")]),
        strings(&["excitation", &record]),
        strings(&[
            "sweep",
            &model(),
            "--set",
            short,
            "--set",
            "contacts.mu=0.3,0.5",
        ])
        .into_iter()
        .chain(strings(&["--out", &out("sweep.csv")]))
        .collect(),
        strings(&["--help"]),
        strings(&["--version"]),
        strings(&["excitation", "--help"]),
        strings(&["stress", "--help"]),
    ];
    for args in cases {
        let r = bin()
            .args(&args)
            .stdout(full.try_clone().unwrap())
            .output()
            .unwrap();
        let e = String::from_utf8_lossy(&r.stderr);
        assert!(!e.contains("panicked"), "{args:?}: {e}");
        assert_eq!(r.status.code(), Some(74), "{args:?}: {e}");
        assert!(e.contains("cannot write to stdout"), "{args:?}: {e}");
    }
}

#[test]
fn a_time_that_is_not_finite_is_refused() {
    for at in ["inf", "nan", "-1"] {
        let out = dir(&format!("at-{at}"));
        let r = bin()
            .args(["run", &model(), "--out", &out.display().to_string()])
            .arg(format!("--at={at}"))
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(2), "--at {at}");
        assert!(String::from_utf8_lossy(&r.stderr).contains("finite number of seconds"));
        assert!(!out.exists(), "nothing written for --at {at}");
    }
}

#[test]
fn a_second_sweep_on_one_output_file_is_refused_and_a_killed_one_leaves_no_part() {
    let d = dir("sweep-lock");
    std::fs::create_dir_all(&d).unwrap();
    let out = d.join("s.csv");
    let o = out.display().to_string();
    let args = |mu: &str| {
        vec![
            "sweep".to_string(),
            model(),
            "--set".into(),
            format!("contacts.mu={mu}"),
            "--set".into(),
            "excitation.run=1:7:1".into(),
            "--out".into(),
            o.clone(),
        ]
    };
    let mut first = bin()
        .args(args("0:1:0.01"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let lock = d.join(".s.csv.lock");
    let mut watch = common::HangWatch::new(first.id(), 120.0, 300);
    while !lock.exists() {
        assert!(first.try_wait().unwrap().is_none(), "the sweep ended first");
        assert!(watch.hangs().is_none());
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let second = bin().args(args("0.3")).output().unwrap();
    assert_eq!(second.status.code(), Some(1));
    let e = String::from_utf8_lossy(&second.stderr);
    assert!(
        e.contains(&format!("is being written by process {}", first.id())),
        "{e}"
    );
    signal(&first, libc::SIGKILL);
    let _ = first.wait();
    // the CSV is written whole at the end: a killed sweep leaves none
    assert!(!out.exists());
    let again = bin().args(args("0.3")).output().unwrap();
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap().lines().count(), 8);
}

/// Rows in a journal (its lines after the two header lines).
fn journal_rows(journal: &Path) -> usize {
    std::fs::read_to_string(journal).map_or(0, |t| t.lines().count().saturating_sub(2))
}

/// Starts `deckspin args`, waits until its journal holds `rows` rows, sends `sig`; returns the
/// exit code and stderr. A hang is judged by the child's CPU.
fn interrupt_when_journaled(
    args: &[String],
    journal: &Path,
    rows: usize,
    sig: i32,
) -> (Option<i32>, String) {
    let mut child = bin()
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut watch = common::HangWatch::new(child.id(), 120.0, 300);
    while journal_rows(journal) < rows {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the job ended before {rows} rows were journaled"
        );
        if let Some(why) = watch.hangs() {
            panic!("the job hangs: {why}");
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    signal(&child, sig);
    finish(child)
}

fn run_ok(args: &[String]) -> String {
    let out = bin().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn strings(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// Two short record pairs, listed with absolute paths.
fn pair_list(d: &Path) -> String {
    let r = |f: &str| common::root().join("excitations/far-field").join(f);
    let list = d.join("pairs.txt");
    let body = format!(
        "{} {}\n{} {} pel\n",
        r("NORTHR_LOS000.AT2").display(),
        r("NORTHR_LOS270.AT2").display(),
        r("SFERN_PEL090.AT2").display(),
        r("SFERN_PEL180.AT2").display()
    );
    std::fs::write(&list, body).unwrap();
    list.display().to_string()
}

#[test]
fn an_interrupted_suite_resumes_to_the_uninterrupted_output_byte_for_byte() {
    let d = dir("suite-resume");
    std::fs::create_dir_all(&d).unwrap();
    let list = pair_list(&d);
    let args = |out: &Path| {
        let mut a = strings(&["suite", &model(), "--records", &list, "--measure", "pga"]);
        a.extend(strings(&[
            "--levels",
            "0.1:2.0:0.1",
            "--set",
            "contacts.mu=0.2,0.4,0.6,0.8",
        ]));
        a.extend(strings(&[
            "--tail",
            "1",
            "--out",
            &out.display().to_string(),
        ]));
        a
    };
    let whole = d.join("whole/suite.csv");
    run_ok(&args(&whole));
    let files = [
        "suite.csv",
        "suite-stats.csv",
        "suite-stats.json",
        "suite.svg",
    ];
    for (sig, name) in [(libc::SIGINT, "int"), (libc::SIGKILL, "kill")] {
        let out = d.join(name).join("suite.csv");
        let journal = d.join(name).join("suite.csv.journal");
        let (code, err) = interrupt_when_journaled(&args(&out), &journal, 3, sig);
        if sig == libc::SIGINT {
            assert_eq!(code, Some(130), "{err}");
            assert!(
                err.contains("runs kept in") && err.contains("--resume"),
                "{err}"
            );
        } else {
            assert_eq!(code, None, "killed");
            // a kill inside a row leaves it cut: that run is run again
            let mut f = std::fs::File::options()
                .append(true)
                .open(&journal)
                .unwrap();
            std::io::Write::write_all(&mut f, b"159,NORTHR_LOS,cut").unwrap();
        }
        assert!(!out.exists(), "{name}: no output until the job is whole");
        let kept = journal_rows(&journal);
        assert!((3..160).contains(&kept), "{name}: {kept} rows kept");
        // not resumed: refused, the journal kept
        let again = bin().args(args(&out)).output().unwrap();
        let msg = String::from_utf8_lossy(&again.stderr);
        assert!(!again.status.success() && msg.contains("--resume"), "{msg}");
        assert!(journal.exists());
        // resumed with other arguments: refused, naming what differs
        let mut other = args(&out);
        other.extend(strings(&["--fix", "contacts.restitution=0.3", "--resume"]));
        let o = bin().args(&other).output().unwrap();
        let msg = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && msg.contains("another job") && msg.contains("arguments"),
            "{msg}"
        );
        let mut resume = args(&out);
        resume.push("--resume".into());
        let out_text = bin().args(&resume).output().unwrap();
        let msg = String::from_utf8_lossy(&out_text.stderr);
        assert!(out_text.status.success(), "{msg}");
        assert!(msg.contains("of them from the journal"), "{msg}");
        for f in files {
            assert!(
                read(&whole.with_file_name(f)) == read(&out.with_file_name(f)),
                "{name}: {f} differs from the uninterrupted job's"
            );
        }
        assert!(
            !journal.exists(),
            "the journal is removed once the job is written"
        );
    }
}

#[test]
fn an_interrupted_sweep_and_stress_resume_to_the_uninterrupted_output() {
    let d = dir("sweep-resume");
    std::fs::create_dir_all(&d).unwrap();
    let sweep = |out: &Path| {
        let mut a = strings(&["sweep", &model(), "--set", "contacts.restitution=0:1:0.25"]);
        a.extend(strings(&[
            "--set",
            "contacts.mu=0.2,0.6",
            "--out",
            &out.display().to_string(),
        ]));
        a
    };
    let whole = d.join("sweep.csv");
    run_ok(&sweep(&whole));
    let out = d.join("sweep-r.csv");
    let (code, err) = interrupt_when_journaled(
        &sweep(&out),
        &d.join("sweep-r.csv.journal"),
        2,
        libc::SIGTERM,
    );
    assert_eq!(code, Some(143), "{err}");
    let mut resume = sweep(&out);
    resume.push("--resume".into());
    run_ok(&resume);
    assert!(read(&whole) == read(&out), "the resumed sweep differs");

    // stress: two pairs, byte for byte but for its two timing columns
    let records = d.join("records");
    std::fs::create_dir_all(&records).unwrap();
    for f in [
        "NORTHR_LOS000",
        "NORTHR_LOS270",
        "SFERN_PEL090",
        "SFERN_PEL180",
    ] {
        let from = common::root().join(format!("excitations/far-field/{f}.AT2"));
        std::fs::copy(from, records.join(format!("{f}.AT2"))).unwrap();
    }
    let stress = |out: &Path| {
        let mut a = strings(&[
            "stress",
            &model(),
            "--records",
            &records.display().to_string(),
        ]);
        a.extend(strings(&[
            "--runs", "1,2", "--eps", "0,0.5", "--mu", "0.3,0.7",
        ]));
        a.extend(strings(&["--out", &out.display().to_string()]));
        a
    };
    let whole = d.join("stress.csv");
    run_ok(&stress(&whole));
    let out = d.join("stress-r.csv");
    let (code, err) = interrupt_when_journaled(
        &stress(&out),
        &d.join("stress-r.csv.journal"),
        3,
        libc::SIGINT,
    );
    assert_eq!(code, Some(130), "{err}");
    let mut resume = stress(&out);
    resume.push("--resume".into());
    run_ok(&resume);
    let untimed = |p: &Path| -> Vec<String> {
        let t = String::from_utf8(read(p)).unwrap();
        t.lines()
            .map(|l| l.rsplitn(3, ',').nth(2).unwrap().to_string())
            .collect()
    };
    let (a, b) = (untimed(&whole), untimed(&out));
    assert_eq!(a.len(), 2 * 2 * 2 * 2 * 2 + 1);
    assert_eq!(a, b, "the resumed stress test differs");
    // cpu_s is the run's thread CPU time: never above its wall time (one thread a run)
    let t = String::from_utf8(read(&whole)).unwrap();
    assert!(t.lines().next().unwrap().ends_with("wall_s,cpu_s"));
    for l in t.lines().skip(1) {
        let f: Vec<f64> = l
            .rsplitn(3, ',')
            .take(2)
            .map(|x| x.parse().unwrap())
            .collect();
        let (cpu, wall) = (f[0], f[1]);
        assert!(cpu >= 0.0 && cpu <= wall + 2e-4, "{l}");
    }
}

#[test]
fn every_study_refuses_a_folder_another_process_writes() {
    let d = dir("study-locks");
    std::fs::create_dir_all(&d).unwrap();
    // a suite CSV for fragility
    let list = pair_list(&d);
    let suite = d.join("suite.csv").display().to_string();
    run_ok(&strings(&[
        "suite",
        &model(),
        "--records",
        &list,
        "--measure",
        "pga",
        "--levels",
        "0.2,0.4",
        "--tail",
        "1",
        "--out",
        &suite,
    ]));
    let out = d.join("held");
    std::fs::create_dir_all(&out).unwrap();
    let o = out.display().to_string();
    // this process holds the folder
    let _held = deckspin::output::files::FolderLock::acquire(&out).unwrap();
    let m = model();
    let jobs: Vec<Vec<&str>> = vec![
        vec!["study", "pga", &m, "--out", &o],
        vec!["precision", &m, "--quick", "--out", &o],
        vec!["stability", &m, "--quick", "--out", &o],
        vec!["screen", &m, "--out", &o],
        vec![
            "fragility",
            &suite,
            "--limit",
            "peak_rotation>0.0005",
            "--out",
            &o,
        ],
        vec!["sequence", &m, "--out", &o],
        vec!["run", &m, "--out", &o],
    ];
    for args in jobs {
        let r = bin().args(&args).output().unwrap();
        let e = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{args:?}: {e}");
        assert!(
            e.contains(&format!(
                "is being written by process {}",
                std::process::id()
            )),
            "{args:?}: {e}"
        );
    }
}

#[test]
fn the_state_at_a_time_is_aligned_whatever_the_names() {
    let d = dir("at-aligned");
    let r = bin()
        .args([
            "run",
            &common::model("models/three-frame.toml")
                .display()
                .to_string(),
        ])
        .args(["--out", &d.display().to_string(), "--at", "5"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let out = String::from_utf8_lossy(&r.stdout).into_owned();
    // the value columns start at one column in every DOF row, and in every contact row
    let column = |prefix: &str, field: &str| -> Vec<usize> {
        (out.lines())
            .filter(|l| l.starts_with(prefix) && l.contains(field))
            .map(|l| l.find(field).unwrap())
            .collect()
    };
    let rates = column("    ", " rate ");
    let gaps = column("    contact ", " g_N ");
    assert!(rates.len() > 10 && gaps.len() == 8, "{out}");
    assert!(rates.windows(2).all(|w| w[0] == w[1]), "{out}");
    assert!(gaps.windows(2).all(|w| w[0] == w[1]), "{out}");
}

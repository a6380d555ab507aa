//! The parent side: children over ranges of inputs, their protocol lines read with a
//! timeout, a child that stops answering killed (a hang) or that dies (a crash, e.g. a memory
//! abort) restarted after the input it was on; the tally.

use crate::exec::Outcome;
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

/// A child's answer for one input: its class, findings, seconds and detail.
pub fn line(case: u64, out: &Outcome, secs: f64) -> String {
    let detail = format!("{out:?}").replace(['\t', '\n'], " ");
    format!(
        "FUZZ\tdone\t{case}\t{}\t{}\t{secs:.4}\t{detail}",
        out.class(),
        out.findings().join(",")
    )
}

/// Address space of the child, so that a runaway allocation aborts it quickly.
pub fn limit_memory(mb: u64) {
    let bytes = mb * 1024 * 1024;
    let lim = libc::rlimit {
        rlim_cur: bytes,
        rlim_max: bytes,
    };
    // SAFETY: setrlimit reads the struct it is given
    unsafe {
        libc::setrlimit(libc::RLIMIT_AS, &lim);
    }
}

/// One finding: the input, its category and how it ended.
#[derive(Clone, Debug)]
pub struct Finding {
    pub case: u64,
    pub category: String,
    pub detail: String,
}

#[derive(Clone, Debug, Default)]
pub struct Tally {
    pub inputs: u64,
    pub classes: BTreeMap<String, u64>,
    pub findings: Vec<Finding>,
    pub slowest: (f64, u64),
    pub wall: f64,
}

impl Tally {
    fn add(&mut self, case: u64, class: &str, findings: &str, secs: f64, detail: &str) {
        self.inputs += 1;
        *self.classes.entry(class.to_string()).or_default() += 1;
        for f in findings.split(',').filter(|f| !f.is_empty()) {
            self.findings.push(Finding {
                case,
                category: f.to_string(),
                detail: detail.to_string(),
            });
        }
        if secs > self.slowest.0 {
            self.slowest = (secs, case);
        }
    }

    fn merge(&mut self, o: Tally) {
        self.inputs += o.inputs;
        for (k, v) in o.classes {
            *self.classes.entry(k).or_default() += v;
        }
        self.findings.extend(o.findings);
        if o.slowest.0 > self.slowest.0 {
            self.slowest = o.slowest;
        }
    }

    /// The tally as text: inputs, each class, findings by category, each finding, slowest.
    pub fn report(&self, seed: u64) -> String {
        let mut s = format!(
            "fuzz seed {seed:#x}: {} inputs in {:.0} s ({:.1} inputs/s)\n",
            self.inputs,
            self.wall,
            self.inputs as f64 / self.wall.max(1e-9)
        );
        let group = |p: &str| -> u64 {
            self.classes
                .iter()
                .filter(|(k, _)| k.starts_with(p))
                .map(|(_, v)| v)
                .sum()
        };
        s += &format!(
            "refused {}, finished {}, failed {}, hang {}, panic {}, crash {}\n",
            group("refused"),
            group("finished"),
            group("failed"),
            group("hang"),
            group("panic"),
            group("crash"),
        );
        for (k, v) in &self.classes {
            s += &format!("  {k:<28} {v}\n");
        }
        let mut cats: BTreeMap<&str, u64> = BTreeMap::new();
        for f in &self.findings {
            *cats.entry(&f.category).or_default() += 1;
        }
        s += &format!("findings: {} {:?}\n", self.findings.len(), cats);
        // every finding, but only the first 50 of the penalty methods' penetrations
        let fixed = |f: &&Finding| f.category.ends_with(":penalty");
        let shown = self.findings.iter().filter(|f| !fixed(f));
        for f in shown.chain(self.findings.iter().filter(fixed).take(50)) {
            s += &format!("  case {} [{}] {}\n", f.case, f.category, f.detail);
        }
        s += &format!(
            "slowest input: case {} in {:.2} s\n",
            self.slowest.1, self.slowest.0
        );
        s
    }
}

/// A child that gains no CPU time for this long while not answering is blocked.
const BLOCKED: Duration = Duration::from_secs(300);

fn spawn(seed: u64, from: u64, to: u64, limit: Duration) -> Child {
    Command::new(std::env::current_exe().unwrap())
        .args([
            "fuzz_child",
            "--exact",
            "--ignored",
            "--nocapture",
            "--test-threads=1",
        ])
        .env("FUZZ_CHILD", "1")
        .env("FUZZ_SEED", seed.to_string())
        .env("FUZZ_FROM", from.to_string())
        .env("FUZZ_TO", to.to_string())
        .env("FUZZ_LIMIT_MS", limit.as_millis().to_string())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("fuzz child")
}

/// Inputs `from..to` through children, one after another; a child that hangs is killed and
/// one that dies is counted. A hang is judged by the child's CPU time, never by the wall clock:
/// a child past `limit` + 30 s of CPU on one input (its own watchdog cancels at `limit`), or one
/// that used no CPU at all for [`BLOCKED`] while not answering (blocked, e.g. on a FIFO; a child
/// that only waits for a core on a busy machine still gains CPU).
fn worker(seed: u64, from: u64, to: u64, limit: Duration) -> Tally {
    let mut tally = Tally::default();
    let mut next = from;
    while next < to {
        let mut child = spawn(seed, next, to, limit);
        let (tx, rx) = mpsc::channel();
        let stdout = child.stdout.take().unwrap();
        std::thread::spawn(move || {
            for l in BufReader::new(stdout).lines().map_while(Result::ok) {
                if tx.send(l).is_err() {
                    break;
                }
            }
        });
        let budget = limit.as_secs_f64() * crate::exec::SLOW + 30.0;
        let mut input_cpu0 = crate::common::child_cpu_seconds(child.id()).unwrap_or(0.0);
        let mut idle = (std::time::Instant::now(), input_cpu0);
        let mut current = None;
        loop {
            match rx.recv_timeout(Duration::from_secs(1)) {
                Ok(l) => {
                    let f: Vec<&str> = l.splitn(7, '\t').collect();
                    match f.as_slice() {
                        ["FUZZ", "start", c] => {
                            current = c.parse::<u64>().ok();
                            input_cpu0 =
                                crate::common::child_cpu_seconds(child.id()).unwrap_or(input_cpu0);
                        }
                        ["FUZZ", "done", c, class, finds, secs, detail] => {
                            let c: u64 = c.parse().unwrap();
                            tally.add(c, class, finds, secs.parse().unwrap_or(0.0), detail);
                            current = None;
                            next = c + 1;
                        }
                        _ => {}
                    }
                    idle = (
                        std::time::Instant::now(),
                        crate::common::child_cpu_seconds(child.id()).unwrap_or(0.0),
                    );
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    let cpu = crate::common::child_cpu_seconds(child.id()).unwrap_or(f64::NAN);
                    if cpu > idle.1 + 1e-2 {
                        idle = (std::time::Instant::now(), cpu);
                    }
                    let over = cpu - input_cpu0 > budget;
                    let blocked = idle.0.elapsed() > BLOCKED;
                    if !(over || blocked) {
                        continue;
                    }
                    let _ = child.kill();
                    let _ = child.wait();
                    let c = current.unwrap_or(next);
                    let why = if over {
                        format!("child past {budget:.0} s of CPU: killed")
                    } else {
                        format!("child blocked (no CPU for {} s): killed", BLOCKED.as_secs())
                    };
                    tally.add(c, "hang", "hang", cpu - input_cpu0, &why);
                    next = c + 1;
                    break;
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let status = child.wait().map(|s| format!("{s}")).unwrap_or_default();
                    if let Some(c) = current {
                        tally.add(c, "crash", "crash", 0.0, &format!("child died: {status}"));
                        next = c + 1;
                    } else if next < to {
                        // the child ended without starting its next input: give up on it
                        tally.add(
                            next,
                            "crash",
                            "crash",
                            0.0,
                            &format!("child ended: {status}"),
                        );
                        next += 1;
                    }
                    break;
                }
            }
        }
    }
    tally
}

/// Inputs `0..cases` of `seed` over `jobs` workers: the merged tally.
pub fn fuzz(seed: u64, cases: u64, jobs: usize, limit: Duration) -> Tally {
    let t0 = std::time::Instant::now();
    let per = cases.div_ceil(jobs as u64);
    let handles: Vec<_> = (0..jobs as u64)
        .map(|j| {
            let (from, to) = (j * per, ((j + 1) * per).min(cases));
            std::thread::spawn(move || worker(seed, from, to, limit))
        })
        .collect();
    let mut tally = Tally::default();
    for h in handles {
        tally.merge(h.join().unwrap());
    }
    tally.findings.sort_by_key(|f| f.case);
    tally.wall = t0.elapsed().as_secs_f64();
    tally
}

//! CPU time: of the calling thread (one run, whatever else the host runs) and of the whole
//! process (a parallel sweep, all its threads). Time spent waiting for a core does not count;
//! a core the host slows still does. NaN where the clock is not available.

/// CPU seconds the calling thread has used (`CLOCK_THREAD_CPUTIME_ID`).
pub fn thread_cpu_seconds() -> f64 {
    #[cfg(unix)]
    return clock(libc::CLOCK_THREAD_CPUTIME_ID);
    #[cfg(not(unix))]
    f64::NAN
}

/// CPU seconds all threads of the process have used (`CLOCK_PROCESS_CPUTIME_ID`).
pub fn process_cpu_seconds() -> f64 {
    #[cfg(unix)]
    return clock(libc::CLOCK_PROCESS_CPUTIME_ID);
    #[cfg(not(unix))]
    f64::NAN
}

#[cfg(unix)]
fn clock(id: libc::clockid_t) -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes the timespec it is given; an unknown clock is an error
    // return, not undefined behaviour
    let r = unsafe { libc::clock_gettime(id, &mut ts) };
    if r != 0 {
        return f64::NAN;
    }
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The CPU seconds of the calling thread while `f` runs, with its result.
pub fn thread_cpu<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let c0 = thread_cpu_seconds();
    let out = f();
    (out, thread_cpu_seconds() - c0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clocks_count_the_work_of_this_thread() {
        let t0 = thread_cpu_seconds();
        // work that cannot be optimized away
        let (sum, worked) = thread_cpu(|| {
            (0..5_000_000u64).fold(0u64, |a, k| a.wrapping_add(std::hint::black_box(k) ^ a))
        });
        assert!(sum != 1 && worked > 0.0, "{worked}");
        let t1 = thread_cpu_seconds();
        assert!(
            t0.is_finite() && t1 - t0 >= worked * (1.0 - 1e-9),
            "{t0} {worked} {t1}"
        );
        // read after the thread's clock, the process's includes all of it
        let p = process_cpu_seconds();
        assert!(p >= t1, "process {p} s, thread {t1} s");
    }
}

//! A small pool that runs independent jobs on every core, the dearest first, and the profile
//! of its jobs (`MSS_PROFILE=1 make report`: one line per job on stderr with its thread's CPU
//! time, the measurements behind `docs/performance.md`).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

/// Whether `MSS_PROFILE` is set (read once per process).
fn profiling() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("MSS_PROFILE").is_some())
}

/// The CPU time of the calling thread, s; None where the platform has no such clock.
pub fn thread_cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
        Some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// Runs `work` on this thread and, when `MSS_PROFILE` is set, prints `profile: WHAT: CPU s`
/// (and what `detail` says of the outcome) to stderr: the thread's CPU time is the cost of one
/// job even when other jobs and processes share the cores.
pub fn profiled<R>(
    what: impl FnOnce() -> String,
    detail: impl FnOnce(&R) -> String,
    work: impl FnOnce() -> R,
) -> R {
    if !profiling() {
        return work();
    }
    let before = thread_cpu_seconds();
    let out = work();
    if let Some(cpu) = before.zip(thread_cpu_seconds()).map(|(b, a)| a - b) {
        eprintln!("profile: {}{}: {cpu:.4} s CPU", what(), detail(&out));
    }
    out
}

/// Runs `run` on every job in parallel over the available cores, the jobs of highest `cost`
/// first (so the long ones do not start last); `progress(done, total)` is called after each.
/// The outcomes come back in the jobs' order.
pub fn run_parallel<J: Sync, R: Send>(
    jobs: &[J],
    cost: impl Fn(&J) -> f64,
    run: impl Fn(&J) -> R + Sync,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<R> {
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| cost(&jobs[b]).total_cmp(&cost(&jobs[a])));
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let outcomes: Mutex<Vec<Option<R>>> = Mutex::new((0..jobs.len()).map(|_| None).collect());
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|scope| {
        for _ in 0..threads.min(jobs.len()) {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(&i) = order.get(k) else { break };
                let outcome = profiled(
                    || format!("{} job {i} of {}", std::any::type_name::<J>(), jobs.len()),
                    |_| String::new(),
                    || run(&jobs[i]),
                );
                outcomes.lock().expect("no panics while holding the lock")[i] = Some(outcome);
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, jobs.len());
            });
        }
    });
    outcomes
        .into_inner()
        .expect("no panics while holding the lock")
        .into_iter()
        .map(|r| r.expect("every job ran"))
        .collect()
}

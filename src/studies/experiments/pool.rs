//! A small pool that runs independent jobs on every core, the dearest first; the CPU time a
//! piece of work costs over every thread it starts ([`charged_cpu`], so that phases of the
//! report that run side by side each get their own); and the profile of the jobs
//! (`MSS_PROFILE=1 make report`: one line per job on stderr with its thread's CPU time, the
//! measurements behind `docs/performance.md`).

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::{Scope, ScopedJoinHandle};
use std::time::Instant;

thread_local! {
    /// Where the threads this thread starts charge their CPU time, ns: the account of the
    /// [`charged_cpu`] call it works for, if any.
    static ACCOUNT: RefCell<Option<Arc<AtomicU64>>> = const { RefCell::new(None) };
}

/// Runs `work` and returns with it the CPU time it cost, s: this thread's, and that of every
/// thread started for it by [`spawn_charged`] (the pool's workers, and theirs); None without
/// a thread CPU clock. Unlike the process's CPU time, it is the work's own when other work of
/// the process runs beside it.
pub fn charged_cpu<T>(work: impl FnOnce() -> T) -> (T, Option<f64>) {
    let account = Arc::new(AtomicU64::new(0));
    let outer = ACCOUNT.with(|a| a.replace(Some(account.clone())));
    let before = thread_cpu_seconds();
    let out = work();
    let own = before.zip(thread_cpu_seconds()).map(|(b, a)| a - b);
    ACCOUNT.with(|a| *a.borrow_mut() = outer.clone());
    let started = account.load(Ordering::Relaxed);
    // An enclosing account measures this thread itself; the started threads it must be told.
    if let Some(outer) = outer {
        outer.fetch_add(started, Ordering::Relaxed);
    }
    (out, own.map(|own| own + started as f64 * 1e-9))
}

/// [`Scope::spawn`], the new thread's CPU time charged to the account of the calling thread
/// (see [`charged_cpu`]), as are the threads it starts in turn.
pub fn spawn_charged<'scope, T: Send + 'scope>(
    scope: &'scope Scope<'scope, '_>,
    work: impl FnOnce() -> T + Send + 'scope,
) -> ScopedJoinHandle<'scope, T> {
    let account = ACCOUNT.with(|a| a.borrow().clone());
    scope.spawn(move || {
        ACCOUNT.with(|a| *a.borrow_mut() = account.clone());
        let before = thread_cpu_seconds();
        let out = work();
        let cpu = before.zip(thread_cpu_seconds()).map(|(b, a)| a - b);
        if let Some((account, cpu)) = account.zip(cpu) {
            account.fetch_add((cpu * 1e9) as u64, Ordering::Relaxed);
        }
        out
    })
}

/// Gives the cores to the process's other threads first: the calling thread's scheduling
/// priority drops to the lowest (nice 19), so that while a thread of the default priority
/// waits for a core it gets it, and this thread runs on what they leave idle. On Linux a
/// thread's nice value is its own, and the threads it starts inherit it; elsewhere (where it
/// would be the whole process's) this does nothing. Work whose wall time nobody waits on
/// first (the report's chapters beyond the thesis, beside the thesis's runs) calls it.
pub fn yield_cores_to_other_threads() {
    #[cfg(target_os = "linux")]
    {
        // Lowering one's own priority needs no privilege; failing, the thread keeps its own.
        let _ = rustix::process::setpriority_process(None, 19);
    }
}

/// Whether `MSS_PROFILE` is set (read once per process).
fn profiling() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("MSS_PROFILE").is_some())
}

/// Wall time since the first profiled job began, s (the profile's clock, so that its lines
/// show which jobs ran when: the critical path).
fn profile_clock() -> f64 {
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
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
/// (and what `detail` says of the outcome, and the wall-clock interval it ran in) to stderr:
/// the thread's CPU time is the cost of one job even when other jobs and processes share the
/// cores.
pub fn profiled<R>(
    what: impl FnOnce() -> String,
    detail: impl FnOnce(&R) -> String,
    work: impl FnOnce() -> R,
) -> R {
    if !profiling() {
        return work();
    }
    let (began, before) = (profile_clock(), thread_cpu_seconds());
    let out = work();
    if let Some(cpu) = before.zip(thread_cpu_seconds()).map(|(b, a)| a - b) {
        let ended = profile_clock();
        eprintln!(
            "profile: {}{}: {cpu:.4} s CPU, wall {began:.2}-{ended:.2} s",
            what(),
            detail(&out)
        );
    }
    out
}

/// Runs `run` on every job in parallel over the available cores, the jobs of highest `cost`
/// first (so the long ones do not start last); `progress(done, total)` is called after each.
/// The outcomes come back in the jobs' order.
pub fn run_parallel<J: Sync + std::fmt::Debug, R: Send>(
    jobs: &[J],
    cost: impl Fn(&J) -> f64,
    run: impl Fn(&J) -> R + Sync,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<R> {
    // Each cost once: a comparison sort would evaluate it twice per comparison, and a cost
    // may build the job's system (the benchmark's flop model: 30,000 builds for 1449 jobs).
    let costs: Vec<f64> = jobs.iter().map(&cost).collect();
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| costs[b].total_cmp(&costs[a]));
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let outcomes: Mutex<Vec<Option<R>>> = Mutex::new((0..jobs.len()).map(|_| None).collect());
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|scope| {
        for _ in 0..threads.min(jobs.len()) {
            spawn_charged(scope, || loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(&i) = order.get(k) else { break };
                let outcome = profiled(
                    || format!("job {i} of {}: {:?}", jobs.len(), jobs[i]),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Spins until this thread has used `seconds` of CPU.
    fn busy(seconds: f64) -> f64 {
        let start = thread_cpu_seconds().unwrap();
        let mut x = 0.0f64;
        while thread_cpu_seconds().unwrap() - start < seconds {
            x = std::hint::black_box(x + 1.0);
        }
        x
    }

    /// A thread that yields its cores lowers its own priority and its new threads', not its
    /// caller's (Linux: fails if the nice value were the process's).
    #[cfg(target_os = "linux")]
    #[test]
    fn yielding_the_cores_lowers_this_thread_and_its_children_only() {
        use rustix::process::getpriority_process;
        let caller = getpriority_process(None).unwrap();
        let (own, child) = std::thread::spawn(|| {
            yield_cores_to_other_threads();
            let child = std::thread::spawn(|| getpriority_process(None).unwrap());
            (getpriority_process(None).unwrap(), child.join().unwrap())
        })
        .join()
        .unwrap();
        assert_eq!((own, child), (19, 19));
        assert_eq!(getpriority_process(None).unwrap(), caller);
    }

    /// The CPU time of a piece of work counts its pool's workers, and theirs in a nested pool
    /// started from a charged thread: the calling thread itself only waits, so its own clock
    /// alone (the wrong account) would give almost nothing.
    #[cfg(unix)]
    #[test]
    fn charged_cpu_counts_the_workers() {
        let jobs = [0.05, 0.05, 0.05];
        let (_, cpu) = charged_cpu(|| {
            std::thread::scope(|scope| {
                let nested = spawn_charged(scope, || {
                    run_parallel(&jobs, |_| 1.0, |&s| busy(s), &|_, _| {})
                });
                run_parallel(&jobs, |_| 1.0, |&s| busy(s), &|_, _| {});
                nested.join().unwrap();
            })
        });
        let cpu = cpu.unwrap();
        assert!((0.3..0.6).contains(&cpu), "{cpu}");
        // Outside a charged call nothing is accounted, and a nested call adds to its caller.
        let (inner, outer) = charged_cpu(|| {
            charged_cpu(|| run_parallel(&jobs, |_| 1.0, |&s| busy(s), &|_, _| {})).1
        });
        assert!(outer.unwrap() >= inner.unwrap() && inner.unwrap() >= 0.15);
    }
}

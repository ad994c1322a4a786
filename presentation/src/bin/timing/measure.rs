//! How `make timing` measures: repeated batches on one thread, in wall and thread CPU time, and
//! who measured (the machine, the toolchain, the commit, the load).

use mass_spring_report::benchmark::wall::Machine;
use mass_spring_solvers::error::Result;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Each timed batch runs at least this long, s, so that the clock's resolution is negligible.
pub const BATCH_SECONDS: f64 = 0.02;
/// Timed batches per measurement (the least batch mean is reported, the spread beside it).
pub const REPEATS: usize = 5;

/// A time: the least batch mean over the repeats and the spreads, in wall and thread CPU
/// seconds.
#[derive(Debug, Clone, Copy, Default)]
pub struct Time {
    pub wall: f64,
    pub cpu: f64,
    /// Largest over least wall time of the batch means.
    pub spread: f64,
    /// Largest over least CPU time of the batch means.
    pub cpu_spread: f64,
    pub repeats: usize,
    /// Calls per timed batch.
    pub batch: usize,
}

/// The CPU time of the calling thread, s (`CLOCK_THREAD_CPUTIME_ID`).
pub fn thread_cpu() -> f64 {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// Times `f` per call: one call first, then `repeats(its seconds)` batches of enough calls to
/// last `batch_seconds` (a scheduler's interruption spreads over a batch instead of
/// dominating one short call); the least batch mean, and the spreads of the batch means.
pub fn time_batches(
    mut f: impl FnMut() -> Result<()>,
    batch_seconds: f64,
    repeats: impl Fn(f64) -> usize,
) -> Result<Time> {
    let t = Instant::now();
    f()?;
    let once = t.elapsed().as_secs_f64();
    let batch = ((batch_seconds / once.max(1e-9)).ceil() as usize).clamp(1, 1 << 20);
    let repeats = repeats(once);
    let (mut walls, mut cpus) = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        let (c, t) = (thread_cpu(), Instant::now());
        for _ in 0..batch {
            f()?;
        }
        walls.push(t.elapsed().as_secs_f64() / batch as f64);
        cpus.push((thread_cpu() - c) / batch as f64);
    }
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    Ok(Time {
        wall: min(&walls),
        cpu: min(&cpus),
        spread: max(&walls) / min(&walls),
        cpu_spread: max(&cpus) / min(&cpus),
        repeats,
        batch,
    })
}

impl Time {
    /// What `self` takes beyond `part`, a part of it timed alone: the differences of the least
    /// times, the larger spreads, `self`'s batches.
    pub fn beyond(&self, part: &Time) -> Time {
        Time {
            wall: self.wall - part.wall,
            cpu: self.cpu - part.cpu,
            spread: self.spread.max(part.spread),
            cpu_spread: self.cpu_spread.max(part.cpu_spread),
            ..*self
        }
    }
}

/// A duration for a table: `1.23 s`, `4.567 ms`, `8.90 µs`.
pub fn seconds(t: f64) -> String {
    if !t.is_finite() {
        "–".into()
    } else if t >= 1.0 {
        format!("{t:.2} s")
    } else if t >= 1e-3 {
        format!("{:.3} ms", t * 1e3)
    } else {
        format!("{:.2} µs", t * 1e6)
    }
}

fn git(args: &[&str], root: &Path) -> String {
    Command::new("git")
        .args(args)
        .current_dir(root)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into())
}

fn cpu_model() -> String {
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    info.lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map_or("unknown".into(), |m| m.trim().to_string())
}

fn rustc_version() -> String {
    Command::new(std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into()))
        .arg("-V")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// The load averages over 1, 5 and 15 minutes.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// The commit checked out at `root` and whether the working tree had changes outside
/// `report/timing/` (which a run replaces): read before the measurements, the state of the
/// code that runs.
pub fn checkout(root: &Path) -> (String, bool) {
    let status = [
        "status",
        "--porcelain",
        "--untracked-files=no",
        "--",
        ".",
        ":!report/timing",
    ];
    (
        git(&["rev-parse", "HEAD"], root),
        !git(&status, root).is_empty(),
    )
}

/// Who measured: the checkout of [`checkout`], the machine, the toolchain, now.
pub fn machine(checkout: (String, bool), load_before: String, run_time_s: f64) -> Machine {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    Machine {
        commit: checkout.0,
        uncommitted_changes: checkout.1,
        cpu: cpu_model(),
        cores: std::thread::available_parallelism().map_or(0, |n| n.get()),
        toolchain: rustc_version(),
        measured_utc: mass_spring_report::output::utc(now),
        load_before,
        load_after: load_average(),
        run_time_s,
    }
}

/// TIMING.md's lines on who measured.
pub fn machine_md(m: &Machine) -> String {
    format!(
        "- measured: {}, in {:.0} s\n- machine: {}, {} cores available\n- toolchain: {}\n\
         - commit: {}{}\n- load average (1, 5, 15 min): {} before, {} after\n\n",
        m.measured_utc,
        m.run_time_s,
        m.cpu,
        m.cores,
        m.toolchain,
        m.commit,
        if m.uncommitted_changes {
            " (with uncommitted changes)"
        } else {
            ""
        },
        m.load_before,
        m.load_after
    )
}

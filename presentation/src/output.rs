//! The report's files, and the run information that changes from run to run. Writing them is
//! [`crate::publish`]'s concern.

use mass_spring_solvers::studies::experiments::pool::charged_cpu;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// A file of the report: path relative to the output directory, and contents.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputFile {
    pub path: PathBuf,
    pub contents: Vec<u8>,
}

impl OutputFile {
    /// A file from text.
    pub fn text(path: impl Into<PathBuf>, contents: String) -> Self {
        Self {
            path: path.into(),
            contents: contents.into_bytes(),
        }
    }
}

/// What varies from run to run, for `run-info.md`.
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// Each phase's times.
    pub phases: Vec<Phase>,
    /// The rows run, out of 56.
    pub rows_run: usize,
    /// The whole run's wall time, and its process's CPU time (the phases overlap).
    pub wall: Duration,
    pub cpu: Option<Duration>,
}

/// One timed phase of a run: a chapter's computations, the rendering.
#[derive(Debug, Clone, PartialEq)]
pub struct Phase {
    pub label: String,
    pub wall: Duration,
    /// CPU time of the whole process (user + system, every thread) during the phase; None
    /// where the platform does not tell it.
    pub cpu: Option<Duration>,
    /// The phase's budget in wall time on two idle cores, if it has one.
    pub budget: Option<Duration>,
}

impl Phase {
    /// Whether it took longer than its budget: in wall time, and in CPU time over `cores` too
    /// (on a loaded machine the wall time of a phase says little, but the CPU time of a phase
    /// that keeps every core busy, divided by the cores, is its wall time on idle cores).
    pub fn over_budget(&self, cores: usize) -> bool {
        self.budget.is_some_and(|b| {
            self.wall > b && self.cpu.is_none_or(|cpu| cpu > b * cores.max(1) as u32)
        })
    }

    /// `<label>: 10.4 s (CPU 20.1 s, budget 20 s)`, the line the report prints on stderr.
    pub fn summary(&self) -> String {
        let mut detail = Vec::new();
        if let Some(cpu) = self.cpu {
            detail.push(format!("CPU {:.1} s", cpu.as_secs_f64()));
        }
        if let Some(b) = self.budget {
            detail.push(format!("budget {} s", b.as_secs_f64()));
        }
        let detail = if detail.is_empty() {
            String::new()
        } else {
            format!(" ({})", detail.join(", "))
        };
        format!("{}: {:.1} s{detail}", self.label, self.wall.as_secs_f64())
    }
}

/// User + system CPU time of this process so far (every thread), from `/proc/self/stat`
/// (fields 14-15, in the kernel's user-visible ticks of 1/100 s); None elsewhere.
pub fn process_cpu_time() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) may hold spaces; the fields after it are plain numbers.
    let after_name = &stat[stat.rfind(')')? + 1..];
    let fields: Vec<&str> = after_name.split_whitespace().collect();
    // after_name starts at field 3, so fields 14 and 15 are at 11 and 12.
    let ticks = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
}

/// The phases of a run, timed as they go: `phases.run("label", budget, || work())` runs the
/// work, records its wall and CPU time and prints [`Phase::summary`] on stderr (a line per
/// phase, terminal or not), so that every chapter reports its own time the same way.
#[derive(Debug, Default)]
pub struct Phases {
    phases: Vec<Phase>,
}

impl Phases {
    /// Runs `work` as the phase `label` with an optional wall-time `budget`.
    pub fn run<T>(
        &mut self,
        label: impl Into<String>,
        budget: Option<Duration>,
        work: impl FnOnce() -> T,
    ) -> T {
        let started = Instant::now();
        // The phase's own CPU time over its threads: phases may run side by side.
        let (out, cpu) = charged_cpu(work);
        let phase = Phase {
            label: label.into(),
            wall: started.elapsed(),
            cpu: cpu.map(Duration::from_secs_f64),
            budget,
        };
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let over = if phase.over_budget(cores) {
            " — over budget"
        } else {
            ""
        };
        eprintln!("report: {}{over}", phase.summary());
        self.phases.push(phase);
        out
    }

    /// The phases so far, in order.
    pub fn into_phases(self) -> Vec<Phase> {
        self.phases
    }

    /// Appends the phases of `other` (phases run beside these, on another thread).
    pub fn extend(&mut self, other: Phases) {
        self.phases.extend(other.phases);
    }
}

fn command_output(program: &str, args: &[&str]) -> Option<String> {
    let out = std::process::Command::new(program)
        .args(args)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
}

/// Civil date and time (UTC) of a Unix time, `2026-03-21 14:05:09 UTC`.
pub fn utc(seconds: u64) -> String {
    let days = (seconds / 86_400) as i64;
    let rem = seconds % 86_400;
    // Howard Hinnant's days-to-civil algorithm.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

fn cpu_model() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    info.lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split_once(':'))
        .map(|(_, m)| m.trim().to_string())
}

impl RunInfo {
    /// `run-info.md`: git commit, machine, toolchain, time of the run and its phases.
    pub fn render(&self, root: &Path) -> String {
        let root_str = root.to_string_lossy().into_owned();
        let git = |args: &[&str]| {
            let mut all = vec!["-C", root_str.as_str()];
            all.extend_from_slice(args);
            command_output("git", &all)
        };
        let commit = match git(&["rev-parse", "HEAD"]) {
            Some(sha) => {
                let dirty = git(&["status", "--porcelain"]).is_some();
                format!(
                    "{sha}{}",
                    if dirty {
                        " (with uncommitted changes)"
                    } else {
                        ""
                    }
                )
            }
            None => "unknown (git not available or not a repository)".into(),
        };
        let now = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let mut out = String::from("# Run information\n\nWhat changes from run to run; git-ignored, and left out of the determinism test.\n\n");
        out += &format!("- generated: {}\n", utc(now));
        out += &format!("- git commit: {commit}\n");
        out += &format!(
            "- machine: {} {}, {}, {cores} cores available\n",
            std::env::consts::OS,
            std::env::consts::ARCH,
            cpu_model().unwrap_or_else(|| "unknown CPU".into())
        );
        out += &format!(
            "- toolchain: {}\n",
            command_output("rustc", &["--version"]).unwrap_or_else(|| "rustc not found".into())
        );
        out += &format!("- experiment rows run: {} of 56\n", self.rows_run);
        out += "\nA phase's CPU time is its own, over every thread it started (their thread CPU \
                clocks); the total's is the process's user + system time. On a loaded machine \
                CPU time, divided by the cores, is the figure to judge a phase by. The chapters \
                beyond the thesis run beside the thesis's experiments and forensics, at a lower \
                priority (they have the cores the thesis's runs leave idle), so the phases' wall \
                times overlap and add up to more than the total.\n";
        out += "\n| phase | wall time (s) | CPU time (s) | budget, wall on idle cores (s) |\n| --- | ---: | ---: | ---: |\n";
        let seconds =
            |d: Option<Duration>| d.map_or("–".into(), |d| format!("{:.2}", d.as_secs_f64()));
        for p in &self.phases {
            let budget = match p.budget {
                Some(b) if p.over_budget(cores) => format!("{} (over)", b.as_secs_f64()),
                Some(b) => b.as_secs_f64().to_string(),
                None => "–".into(),
            };
            out += &format!(
                "| {} | {:.2} | {} | {budget} |\n",
                p.label,
                p.wall.as_secs_f64(),
                seconds(p.cpu)
            );
        }
        out += &format!(
            "| total | {:.2} | {} | |\n",
            self.wall.as_secs_f64(),
            seconds(self.cpu)
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mass_spring_solvers::studies::experiments::pool::thread_cpu_seconds;

    #[test]
    fn a_phase_records_its_time_and_its_budget() {
        let mut phases = Phases::default();
        let start_cpu = thread_cpu_seconds();
        // Busy until this thread has used 30 ms of CPU, however loaded the machine (a phase's
        // CPU time is its threads', not the process's: other tests run beside this one).
        let busy = phases.run("busy", Some(Duration::from_secs(20)), || {
            let started = Instant::now();
            let mut x = 0u64;
            while started.elapsed() < Duration::from_secs(10)
                && thread_cpu_seconds()
                    .zip(start_cpu)
                    .is_none_or(|(now, start)| now < start + 0.03)
            {
                for _ in 0..1000 {
                    x = std::hint::black_box(x.wrapping_add(1));
                }
            }
            x
        });
        assert!(busy > 0);
        assert_eq!(phases.run("quick", None, || 7), 7);
        let phases = phases.into_phases();
        let labels: Vec<&str> = phases.iter().map(|p| p.label.as_str()).collect();
        assert_eq!(labels, ["busy", "quick"]);
        if cfg!(target_os = "linux") {
            let cpu = phases[0].cpu.expect("Linux has a thread CPU clock");
            assert!(cpu >= Duration::from_millis(20), "{cpu:?}");
        }
        assert!(!phases[0].over_budget(2));
        assert!(phases[0].summary().starts_with("busy: "));
        assert!(phases[0].summary().ends_with(" s, budget 20 s)"));
        assert_eq!(phases[1].budget, None);
        let slow = |cpu: u64| Phase {
            label: "slow".into(),
            wall: Duration::from_secs(30),
            cpu: Some(Duration::from_secs(cpu)),
            budget: Some(Duration::from_secs(20)),
        };
        // 30 s of wall against a 20 s budget: over when the CPU time, over the cores, is too.
        assert!(slow(50).over_budget(2));
        assert!(!slow(35).over_budget(2));
        assert_eq!(slow(50).summary(), "slow: 30.0 s (CPU 50.0 s, budget 20 s)");
    }

    #[test]
    fn civil_time() {
        assert_eq!(utc(0), "1970-01-01 00:00:00 UTC");
        assert_eq!(utc(951_782_400), "2000-02-29 00:00:00 UTC");
        assert_eq!(utc(1_700_000_000), "2023-11-14 22:13:20 UTC");
    }
}

//! The report's files, and the run information that changes from run to run. Writing them is
//! [`crate::report::publish`]'s concern.

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

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
    /// Wall time of each phase.
    pub phases: Vec<(String, Duration)>,
    /// The rows run, out of 56.
    pub rows_run: usize,
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
        out += "\n| phase | wall time (s) |\n| --- | ---: |\n";
        let mut total = Duration::ZERO;
        for (name, d) in &self.phases {
            total += *d;
            out += &format!("| {name} | {:.2} |\n", d.as_secs_f64());
        }
        out += &format!("| total | {:.2} |\n", total.as_secs_f64());
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_time() {
        assert_eq!(utc(0), "1970-01-01 00:00:00 UTC");
        assert_eq!(utc(951_782_400), "2000-02-29 00:00:00 UTC");
        assert_eq!(utc(1_700_000_000), "2023-11-14 22:13:20 UTC");
    }
}

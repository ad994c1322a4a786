//! What the reliability tests of issue 27 share: a directory tree's exact state, a binary run
//! with a deadline (a test of a hang fails instead of hanging), and the three environments the
//! adversarial cases need: another user (`setpriv` to `nobody`), a private mount namespace
//! (`unshare -m`) and a 4 GiB address-space limit (`prlimit --as`). Where one cannot be made
//! the test says why and skips.
#![allow(dead_code)] // each test binary uses its own part

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Every entry under `dir`, `dir` itself included, with its type, permission bits and bytes
/// (a symbolic link by its target): two equal trees are byte-identical.
pub fn tree(dir: &Path) -> BTreeMap<PathBuf, String> {
    use std::os::unix::fs::PermissionsExt;
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(path) = stack.pop() {
        let rel = path.strip_prefix(dir).unwrap().to_path_buf();
        let meta = std::fs::symlink_metadata(&path).unwrap();
        let mode = meta.permissions().mode() & 0o7777;
        let entry = if meta.file_type().is_symlink() {
            format!("link -> {}", std::fs::read_link(&path).unwrap().display())
        } else if meta.is_dir() {
            let mut names: Vec<PathBuf> = std::fs::read_dir(&path)
                .unwrap()
                .map(|e| e.unwrap().path())
                .collect();
            names.sort();
            stack.extend(names);
            format!("dir {mode:o}")
        } else if meta.is_file() {
            let bytes = std::fs::read(&path).unwrap();
            format!("file {mode:o} {}", String::from_utf8_lossy(&bytes))
        } else {
            format!("special {mode:o}")
        };
        out.insert(rel, entry);
    }
    out
}

/// Runs `command` to its end or for at most `limit`, then kills it: `None` if it was killed.
pub fn run_for(command: &mut Command, limit: Duration) -> Option<Output> {
    let mut child = command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts");
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > limit {
            child.kill().unwrap();
            child.wait().unwrap();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    Some(child.wait_with_output().unwrap())
}

/// `run_for`, failing the test if the run had to be killed.
pub fn run_within(command: &mut Command, limit: Duration, what: &str) -> Output {
    run_for(command, limit).unwrap_or_else(|| panic!("{what}: still running after {limit:?}"))
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// A fresh scratch directory under the system's temporary directory (which every user may
/// search), world-writable and sticky like `/tmp` itself.
pub fn shared_scratch(name: &str) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let dir = std::env::temp_dir().join(format!("mss-i27-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o1777)).unwrap();
    dir
}

fn is_root() -> bool {
    std::fs::metadata("/proc/self")
        .map(|m| std::os::unix::fs::MetadataExt::uid(&m) == 0)
        .unwrap_or(false)
}

/// `program args` as the unprivileged user `nobody`, or `None` (and why, on stderr) where this
/// process cannot drop to it (not root, or no `setpriv`).
pub fn as_nobody(program: &str, args: &[&str]) -> Option<Command> {
    if !is_root() {
        eprintln!("skipped: the test runs as a user that cannot switch to nobody (not root)");
        return None;
    }
    let probe = Command::new("setpriv")
        .args([
            "--reuid=nobody",
            "--regid=nogroup",
            "--clear-groups",
            "true",
        ])
        .output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!("skipped: setpriv cannot switch to nobody/nogroup here");
        return None;
    }
    let mut command = Command::new("setpriv");
    command
        .args([
            "--reuid=nobody",
            "--regid=nogroup",
            "--clear-groups",
            program,
        ])
        .args(args);
    Some(command)
}

/// `sh -c script` in a private mount namespace, or `None` (and why, on stderr) where one
/// cannot be made (no `unshare`, or no privilege for it).
pub fn in_mount_namespace(script: &str) -> Option<Command> {
    let probe = Command::new("unshare")
        .args(["-m", "--propagation", "private", "true"])
        .output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!("skipped: no private mount namespace here (unshare -m is refused or missing)");
        return None;
    }
    let mut command = Command::new("unshare");
    command.args(["-m", "--propagation", "private", "sh", "-c", script]);
    Some(command)
}

/// The address-space limit of the option-boundary tests: 4 GiB.
pub const ADDRESS_SPACE: u64 = 4 << 30;

/// `program args` under an address-space limit of [`ADDRESS_SPACE`] (`prlimit --as`), or `None`
/// (and why) where `prlimit` is missing.
pub fn under_address_limit(program: &str, args: &[&str]) -> Option<Command> {
    under_address_limit_of(ADDRESS_SPACE, program, args)
}

/// `program args` under an address-space limit of `bytes` (`prlimit --as`), or `None` (and
/// why) where `prlimit` is missing: a small limit shows an allocation sized by an option with
/// a small value of it, in a run that ends at once.
pub fn under_address_limit_of(bytes: u64, program: &str, args: &[&str]) -> Option<Command> {
    let limit = format!("--as={bytes}");
    let probe = Command::new("prlimit").args([&limit, "true"]).output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!("skipped: prlimit cannot set an address-space limit here");
        return None;
    }
    let mut command = Command::new("prlimit");
    command.args([&limit, "--", program]).args(args);
    Some(command)
}

/// Shell-quotes a path for a script.
pub fn quoted(path: &Path) -> String {
    format!("'{}'", path.display().to_string().replace('\'', r"'\''"))
}

/// Runs `program` with `args` under the 4 GiB address-space limit: it must exit 0 or 2 (refused
/// before any allocation), never end by a signal or a panic.
pub fn exits_2_or_succeeds(program: &str, args: &[&str]) {
    let Some(mut command) = under_address_limit(program, args) else {
        return;
    };
    let out = run_within(&mut command, Duration::from_secs(60), &format!("{args:?}"));
    let code = out.status.code();
    assert!(
        matches!(code, Some(0) | Some(2)),
        "{args:?} ended with {:?}: {}",
        out.status,
        stderr(&out)
    );
    assert!(!stderr(&out).contains("panicked"), "{}", stderr(&out));
}

//! The report directory is replaced as a whole, and never loses a file it did not write:
//! the writer interrupted at every checkpoint (crash and I/O error, both swaps), the real
//! binary killed at seeded moments, foreign entries carried over, directories refused.

use mass_spring_solvers::report::output::OutputFile;
use mass_spring_solvers::report::publish::{
    fixture, write_report, Fault, ReportTarget, Swap, MANIFEST, REPORT_TITLE,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// A fresh directory holding the output directory `out` (not created).
fn scratch(name: &str) -> PathBuf {
    let base = std::env::temp_dir().join(format!("mss-publish-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    std::fs::create_dir_all(&base).unwrap();
    base.join("out")
}

/// Every non-directory under `dir` with its bytes (symbolic links as `-> target`).
fn contents(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            let rel = path.strip_prefix(dir).unwrap().to_path_buf();
            let meta = std::fs::symlink_metadata(&path).unwrap();
            if meta.is_dir() {
                stack.push(path);
            } else if meta.file_type().is_symlink() {
                let target = std::fs::read_link(&path).unwrap();
                out.insert(rel, format!("-> {}", target.display()).into_bytes());
            } else {
                out.insert(rel, std::fs::read(&path).unwrap());
            }
        }
    }
    out
}

fn report(tag: &str, names: &[&str]) -> Vec<OutputFile> {
    names
        .iter()
        .map(|n| OutputFile::text(*n, format!("{tag}: {n}\n")))
        .collect()
}

/// What the directory must hold after publishing `files` with the user's `user` files beside
/// them; the manifest is checked on its own ([`manifest_lists`]).
fn expected(files: &[OutputFile], user: &BTreeMap<PathBuf, Vec<u8>>) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = user.clone();
    out.extend(files.iter().map(|f| (f.path.clone(), f.contents.clone())));
    out
}

fn without_manifest(mut state: BTreeMap<PathBuf, Vec<u8>>) -> BTreeMap<PathBuf, Vec<u8>> {
    state.remove(Path::new(MANIFEST));
    state
}

/// The manifest lists exactly the report's files and itself.
fn manifest_lists(dir: &Path, files: &[OutputFile]) -> bool {
    let text = std::fs::read_to_string(dir.join(MANIFEST)).unwrap_or_default();
    let listed: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    let mut want: Vec<String> = files
        .iter()
        .map(|f| f.path.to_string_lossy().into_owned())
        .chain([MANIFEST.to_string()])
        .collect();
    want.sort();
    listed == want
}

/// Entries beside `out` (the lock file apart): what a run left.
fn leftovers(out: &Path) -> Vec<String> {
    std::fs::read_dir(out.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "out" && n != ".out.lock")
        .collect()
}

fn user_files(out: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    std::fs::write(out.join("data/notes.txt"), "my notes").unwrap();
    std::fs::create_dir_all(out.join("timing/2026")).unwrap();
    std::fs::write(out.join("timing/2026/run.csv"), "t,1").unwrap();
    std::fs::write(out.join("README.user"), "mine").unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink("../REPORT.md", out.join("timing/link")).unwrap();
    contents(out)
        .into_iter()
        .filter(|(p, _)| {
            p.starts_with("timing")
                || p == Path::new("data/notes.txt")
                || p == Path::new("README.user")
        })
        .collect()
}

#[test]
fn every_interruption_leaves_the_previous_or_the_new_report_complete() {
    let old = report(
        "old",
        &["REPORT.md", "data/a.csv", "data/b.csv", "figures/x.svg"],
    );
    let new = report(
        "new",
        &[
            "REPORT.md",
            "data/a.csv",
            "data/c.csv",
            "figures/y.svg",
            "run-info.md",
        ],
    );
    for swap in [Swap::Exchange, Swap::Journal] {
        for crash in [true, false] {
            let mut fired = 0;
            for n in 0.. {
                let out = scratch(&format!("interrupt-{swap:?}-{crash}"));
                write_report(&out, &old).unwrap();
                let user = user_files(&out);
                let (before, after) = (expected(&old, &user), expected(&new, &user));
                let fault = if crash {
                    Fault::Crash(n)
                } else {
                    Fault::IoError(n)
                };
                let result =
                    ReportTarget::open(&out)
                        .unwrap()
                        .publish_with(&new, swap, Some(fault));
                let Err(e) = result else {
                    // n is past the last checkpoint: the run completed.
                    assert_eq!(without_manifest(contents(&out)), after);
                    assert!(manifest_lists(&out, &new));
                    assert_eq!(leftovers(&out), Vec::<String>::new());
                    break;
                };
                assert!(e.to_string().contains("injected"), "{e}");
                fired += 1;
                // A crash between the journal's two renames leaves no output directory: the
                // previous report is beside it and the next open puts it back.
                let target = ReportTarget::open(&out).unwrap();
                let state = without_manifest(contents(&out));
                let is_old = state == before && manifest_lists(&out, &old);
                let is_new = state == after && manifest_lists(&out, &new);
                assert!(
                    is_old || is_new,
                    "{swap:?}, crash {crash}, checkpoint {n}: {e}\n{state:?}"
                );
                if !crash {
                    assert!(
                        is_old || e.to_string().contains("new report is in place"),
                        "{e}"
                    );
                }
                target.publish(&new).unwrap();
                assert_eq!(without_manifest(contents(&out)), after, "{swap:?} {n}");
                assert!(manifest_lists(&out, &new));
                assert_eq!(leftovers(&out), Vec::<String>::new(), "{swap:?} {n}");
            }
            // 5 files, the manifest, 3 carried-over entries, the swap, the removal (+1 journal).
            let checkpoints = if swap == Swap::Journal { 12 } else { 11 };
            assert_eq!(fired, checkpoints, "{swap:?}");
        }
    }
}

#[test]
fn foreign_entries_are_carried_over_and_owned_files_replaced() {
    let out = scratch("carry");
    write_report(
        &out,
        &report("one", &["REPORT.md", "data/a.csv", "figures/x.svg"]),
    )
    .unwrap();
    let user = user_files(&out);
    let two = report("two", &["REPORT.md", "data/b.csv"]);
    write_report(&out, &two).unwrap();
    assert_eq!(without_manifest(contents(&out)), expected(&two, &user));
    // figures/ held only the report's file: it goes with it.
    assert!(!out.join("figures").exists());
}

#[test]
fn a_foreign_file_where_the_report_writes_is_refused_before_anything_changes() {
    let out = scratch("conflict");
    write_report(&out, &report("one", &["REPORT.md", "figures/x.svg"])).unwrap();
    std::fs::write(out.join("data"), "a user's file named data").unwrap();
    let before = contents(&out);
    let e = ReportTarget::open(&out).unwrap_err().to_string();
    assert!(
        e.contains("/data was not written by the report") && e.contains("Move it away"),
        "{e}"
    );
    assert_eq!(contents(&out), before);
    assert_eq!(leftovers(&out), Vec::<String>::new());
}

#[test]
fn a_directory_without_manifest_is_refused_and_untouched() {
    let out = scratch("foreign-dir");
    std::fs::create_dir_all(out.join("data")).unwrap();
    std::fs::write(out.join("data/thesis_results.csv"), "precious").unwrap();
    std::fs::write(out.join("Cargo.toml"), "[package]").unwrap();
    let before = contents(&out);
    let e = write_report(&out, &report("x", &["REPORT.md", "data/a.csv"]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("is not empty and has no MANIFEST"), "{e}");
    assert_eq!(contents(&out), before);
    // Not even a lock file beside a refused directory.
    let beside: Vec<_> = std::fs::read_dir(out.parent().unwrap()).unwrap().collect();
    assert_eq!(beside.len(), 1);
}

#[test]
fn a_report_from_before_manifests_is_accepted_once_and_its_user_files_kept() {
    let out = scratch("legacy");
    std::fs::create_dir_all(out.join("data")).unwrap();
    std::fs::create_dir_all(out.join("figures")).unwrap();
    std::fs::write(out.join("REPORT.md"), format!("{REPORT_TITLE} — old\n")).unwrap();
    std::fs::write(out.join("data/table1.csv"), "old").unwrap();
    std::fs::write(out.join("figures/fig01.svg"), "old").unwrap();
    std::fs::create_dir(out.join(".tmp-123-456")).unwrap();
    std::fs::write(out.join("data/notes.txt"), "mine").unwrap();
    let new = report("new", &["REPORT.md", "data/results.csv"]);
    write_report(&out, &new).unwrap();
    let mut want = expected(&new, &BTreeMap::new());
    want.insert("data/notes.txt".into(), b"mine".to_vec());
    assert_eq!(without_manifest(contents(&out)), want);
    assert!(!out.join(".tmp-123-456").exists());
}

#[test]
fn stale_runs_are_cleaned_and_a_second_writer_is_refused() {
    let out = scratch("lock");
    write_report(&out, &report("one", &["REPORT.md"])).unwrap();
    let parent = out.parent().unwrap();
    std::fs::create_dir_all(parent.join(".out.tmp-1-2/data")).unwrap();
    std::fs::create_dir_all(parent.join(".out.old-3-4")).unwrap();
    let first = ReportTarget::open(&out).unwrap();
    assert_eq!(first.notes().len(), 2, "{:?}", first.notes());
    let e = ReportTarget::open(&out).unwrap_err().to_string();
    assert!(e.contains("another report run is writing"), "{e}");
    drop(first);
    assert_eq!(leftovers(&out), Vec::<String>::new());
    ReportTarget::open(&out).unwrap();
}

#[cfg(unix)]
#[test]
fn a_read_only_directory_in_the_previous_report_does_not_mix_old_and_new() {
    use std::os::unix::fs::PermissionsExt;
    let out = scratch("read-only");
    write_report(&out, &report("one", &["REPORT.md", "data/a.csv"])).unwrap();
    std::fs::set_permissions(out.join("data"), std::fs::Permissions::from_mode(0o555)).unwrap();
    let two = report("two", &["REPORT.md", "data/a.csv"]);
    write_report(&out, &two).unwrap();
    assert_eq!(
        without_manifest(contents(&out)),
        expected(&two, &BTreeMap::new())
    );
    assert_eq!(leftovers(&out), Vec::<String>::new());
}

#[test]
fn report_out_dot_in_the_repository_refuses_and_deletes_nothing() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let before = contents(&root.join("data"));
    let out = Command::new(env!("CARGO_BIN_EXE_report"))
        .args(["--out", ".", "--tables", "1"])
        .current_dir(root)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("is not empty and has no MANIFEST"),
        "{stderr}"
    );
    assert_eq!(contents(&root.join("data")), before);
    assert!(root.join("data/thesis_results.csv").exists());
    let lock = root.parent().unwrap().join(format!(
        ".{}.lock",
        root.file_name().unwrap().to_string_lossy()
    ));
    assert!(!lock.exists(), "a refused run wrote {}", lock.display());
}

/// The size of `report --fixture`.
const FIXTURE_FILES: usize = 400;

/// The fixture's files all name one tag, and there are all of them.
fn fixture_tag(out: &Path) -> Option<String> {
    let state = without_manifest(contents(out));
    ["A", "B"].into_iter().map(String::from).find(|tag| {
        let want = expected(&fixture(tag, FIXTURE_FILES), &BTreeMap::new());
        state
            .iter()
            .filter(|(p, _)| !p.starts_with("timing"))
            .eq(want.iter())
    })
}

#[test]
fn the_binary_killed_at_seeded_moments_leaves_a_complete_report() {
    let out = scratch("kill");
    let run = |tag: &str| {
        Command::new(env!("CARGO_BIN_EXE_report"))
            .args(["--out", out.to_str().unwrap(), "--fixture", tag])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap()
    };
    assert!(run("A").wait().unwrap().success());
    std::fs::create_dir_all(out.join("timing")).unwrap();
    std::fs::write(out.join("timing/t.csv"), "mine").unwrap();
    // The kills land within the first 70% of a whole run's time, the shorter of two measured
    // here under the machine's load of the moment.
    let timed = |tag: &str| {
        let t = Instant::now();
        assert!(run(tag).wait().unwrap().success());
        t.elapsed()
    };
    let full = timed("B").min(timed("A"));
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut kills = 0;
    for i in 0..6 {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let delay = full.mul_f64((seed >> 11) as f64 / (1u64 << 53) as f64 * 0.7);
        let tag = if i % 2 == 0 { "B" } else { "A" };
        let mut child = run(tag);
        std::thread::sleep(delay);
        if child.try_wait().unwrap().is_none() {
            child.kill().unwrap();
            kills += 1;
        }
        child.wait().unwrap();
        // The output path holds a complete report, or a crash between the journal's renames
        // left it beside (only where the exchange is refused); the next run puts it back.
        if cfg!(target_os = "linux") {
            assert!(fixture_tag(&out).is_some(), "kill {i} after {delay:?}");
        }
        assert_eq!(std::fs::read(out.join("timing/t.csv")).unwrap(), b"mine");
    }
    assert!(
        kills >= 3,
        "only {kills} of 8 runs were killed before they ended"
    );
    assert!(run("B").wait().unwrap().success());
    assert_eq!(fixture_tag(&out).as_deref(), Some("B"));
    assert_eq!(leftovers(&out), Vec::<String>::new());
}

#[test]
fn an_output_path_that_is_a_file_is_refused_and_kept() {
    let out = scratch("is-a-file");
    std::fs::write(&out, "not a report").unwrap();
    let e = write_report(&out, &report("x", &["REPORT.md"]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("is not a directory"), "{e}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "not a report");
}

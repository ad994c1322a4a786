//! The report directory is replaced as a whole, and never loses a file it did not write:
//! the writer interrupted at every checkpoint (crash and I/O error, both swaps), the real
//! binary killed at seeded moments, foreign entries carried over, directories refused.

use mass_spring_report::output::OutputFile;
use mass_spring_report::publish::{
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
    // The journal's own names: `tmp-<pid>-<nanoseconds>`, `old-<pid>-<nanoseconds>`.
    std::fs::create_dir_all(parent.join(".out.tmp-4242-1767225600123456789/data")).unwrap();
    std::fs::create_dir_all(parent.join(".out.old-4243-1767225600123456790")).unwrap();
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
    let root = &mass_spring_report::crate_root();
    let before = contents(&root.join("data"));
    let out = Command::new(env!("CARGO_BIN_EXE_report"))
        .args(["--out", ".", "--tables", "1"])
        .current_dir(root)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    // Refused before anything runs: bad input, exit 2.
    assert_eq!(out.status.code(), Some(2), "{stderr}");
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

// Issue 27: ownership that cannot be forged by accident, journal names in their exact shape,
// mount points and the lock, each a case of `shared/docs/reliability-cases.md` ([n]).

#[path = "../../tests/sandbox/mod.rs"]
mod sandbox;
use sandbox::{as_nobody, in_mount_namespace, quoted, run_within, shared_scratch, tree};
use std::time::Duration;

/// The fixture runs of the real binary: well under a second each.
const QUICK_RUN: Duration = Duration::from_secs(20);

fn report_in(dir: &Path, args: &[&str]) -> std::process::Output {
    run_within(
        Command::new(env!("CARGO_BIN_EXE_report"))
            .args(args)
            .current_dir(dir),
        QUICK_RUN,
        &format!("report {args:?}"),
    )
}

fn err(output: &std::process::Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// [1] A Perl-style tree whose `MANIFEST` lists its own files: `report --out DIR` and
/// `report --out .` refuse it before anything runs (exit 2), and the directory and its parent
/// are byte-identical afterwards (not even a lock file beside it).
#[test]
fn a_foreign_manifest_is_refused_and_the_directory_left_byte_identical() {
    let out = scratch("foreign-manifest");
    std::fs::create_dir_all(out.join("lib")).unwrap();
    std::fs::write(out.join(MANIFEST), "README\nMakefile.PL\nlib/Foo.pm\n").unwrap();
    std::fs::write(out.join("README"), "mine").unwrap();
    std::fs::write(out.join("Makefile.PL"), "mine").unwrap();
    std::fs::write(out.join("lib/Foo.pm"), "package Foo;").unwrap();
    let parent = out.parent().unwrap().to_path_buf();
    let before = tree(&parent);
    for (cwd, arg) in [(&parent, out.to_str().unwrap()), (&out, ".")] {
        let output = report_in(cwd, &["--out", arg, "--fixture", "A"]);
        let e = err(&output);
        assert_eq!(output.status.code(), Some(2), "--out {arg}: {e}");
        assert!(
            e.contains("not a report this program wrote") && e.contains("nothing was changed"),
            "{e}"
        );
        assert_eq!(tree(&parent), before, "--out {arg}");
    }
    // The library refuses it the same way.
    let e = write_report(&out, &report("x", &["REPORT.md"]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("not a report this program wrote"), "{e}");
    assert_eq!(tree(&parent), before);
}

/// [1] A manifest with the report's header owns only regular files inside the directory: one
/// that lists a directory or a symbolic link is not the report's and is refused untouched.
#[test]
fn a_manifest_listing_a_directory_or_a_link_is_refused() {
    for (name, listed) in [("lists-dir", "lib"), ("lists-link", "link")] {
        let out = scratch(name);
        write_report(&out, &report("one", &["REPORT.md"])).unwrap();
        let manifest = std::fs::read_to_string(out.join(MANIFEST)).unwrap();
        std::fs::write(out.join(MANIFEST), format!("{manifest}{listed}\n")).unwrap();
        std::fs::create_dir_all(out.join("lib")).unwrap();
        std::fs::write(out.join("lib/Foo.pm"), "package Foo;").unwrap();
        std::os::unix::fs::symlink("lib/Foo.pm", out.join("link")).unwrap();
        let parent = out.parent().unwrap().to_path_buf();
        let before = tree(&parent);
        let e = write_report(&out, &report("two", &["REPORT.md"]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(listed) && e.contains("not a regular file"),
            "{e}"
        );
        assert_eq!(tree(&parent), before, "{name}");
    }
}

/// [2] Entries beside the output whose names only start like the journal's (a user's
/// `.out.old-2024-backup/`, `.out.tmp-notes.txt`, `.out.tmp-1-2`) are left alone by a run.
#[test]
fn entries_beside_the_output_named_like_the_journal_are_left_alone() {
    let out = scratch("journal-names");
    let parent = out.parent().unwrap().to_path_buf();
    assert!(report_in(&parent, &["--out", "out", "--fixture", "A"])
        .status
        .success());
    std::fs::create_dir(parent.join(".out.old-2024-backup")).unwrap();
    std::fs::write(parent.join(".out.old-2024-backup/REPORT.md"), "mine").unwrap();
    std::fs::write(parent.join(".out.tmp-notes.txt"), "notes").unwrap();
    std::fs::create_dir(parent.join(".out.tmp-1-2")).unwrap();
    std::fs::write(parent.join(".out.tmp-1-2/keep"), "mine").unwrap();
    let users = |parent: &Path| {
        let mut t = tree(parent);
        t.retain(|p, _| p.to_string_lossy().starts_with(".out.") && !p.ends_with(".out.lock"));
        t
    };
    let before = users(&parent);
    let output = report_in(&parent, &["--out", "out", "--fixture", "B"]);
    assert!(output.status.success(), "{}", err(&output));
    assert!(!err(&output).contains("removed"), "{}", err(&output));
    assert_eq!(users(&parent), before);
    assert_eq!(fixture_tag(&out).as_deref(), Some("B"));
}

/// [2] With the output missing, a user's `.out.old-mine` is not taken for the previous report:
/// it stays where it is and a new report is written.
#[test]
fn a_user_backup_beside_a_missing_output_is_not_moved_into_place() {
    let out = scratch("backup-missing-output");
    let parent = out.parent().unwrap().to_path_buf();
    std::fs::create_dir_all(parent.join(".out.old-mine/data")).unwrap();
    std::fs::write(parent.join(".out.old-mine/thesis.tex"), "x").unwrap();
    let before = tree(&parent.join(".out.old-mine"));
    let output = report_in(&parent, &["--out", "out", "--fixture", "A"]);
    assert!(output.status.success(), "{}", err(&output));
    assert_eq!(tree(&parent.join(".out.old-mine")), before);
    assert_eq!(fixture_tag(&out).as_deref(), Some("A"));
}

/// [3] A file system mounted inside the report directory is refused before the run: its files
/// stay in it and the directory is unchanged (in a private mount namespace).
#[test]
fn a_mount_inside_the_report_is_refused_and_its_files_kept() {
    let out = scratch("mount-inside");
    let base = out.parent().unwrap().to_path_buf();
    let ext = base.join("ext");
    std::fs::create_dir(&ext).unwrap();
    std::fs::write(ext.join("precious.txt"), "precious").unwrap();
    assert!(report_in(&base, &["--out", "out", "--fixture", "A"])
        .status
        .success());
    std::fs::create_dir(out.join("ext")).unwrap();
    let before = tree(&base);
    let script = format!(
        "mount --bind {ext} {inside} && exec {report} --out {out} --fixture B",
        ext = quoted(&ext),
        inside = quoted(&out.join("ext")),
        report = quoted(Path::new(env!("CARGO_BIN_EXE_report"))),
        out = quoted(&out),
    );
    let Some(mut command) = in_mount_namespace(&script) else {
        return;
    };
    let output = run_within(&mut command, QUICK_RUN, "report with a mount inside");
    let e = err(&output);
    assert_eq!(output.status.code(), Some(2), "{e}");
    assert!(e.contains("mount point") && e.contains("ext"), "{e}");
    assert_eq!(tree(&base), before);
}

/// [8] The output directory itself a mount point is refused before the run, not after it.
#[test]
fn the_output_directory_as_a_mount_point_is_refused_before_the_run() {
    let out = scratch("mount-output");
    let base = out.parent().unwrap().to_path_buf();
    assert!(report_in(&base, &["--out", "out", "--fixture", "A"])
        .status
        .success());
    let before = tree(&base);
    let script = format!(
        "mount --bind {out} {out} && exec {report} --out {out} --fixture B",
        report = quoted(Path::new(env!("CARGO_BIN_EXE_report"))),
        out = quoted(&out),
    );
    let Some(mut command) = in_mount_namespace(&script) else {
        return;
    };
    let output = run_within(&mut command, QUICK_RUN, "report --out a mount point");
    let e = err(&output);
    assert_eq!(output.status.code(), Some(2), "{e}");
    assert!(e.contains("mount point"), "{e}");
    assert_eq!(tree(&base), before);
}

/// [3] The clean-up of a crashed run's staging directory never crosses into a file system
/// mounted inside it: the mounted files survive and the run says what it left.
#[test]
fn clean_up_never_crosses_into_a_mounted_file_system() {
    let out = scratch("cleanup-mount");
    let base = out.parent().unwrap().to_path_buf();
    let staging = base.join(".out.tmp-4242-1767225600123456789");
    std::fs::create_dir_all(staging.join("mnt")).unwrap();
    let script = format!(
        "mount -t tmpfs none {mnt} && echo precious > {mnt}/p.txt && \
         {report} --out {out} --fixture B; echo \"status=$?\"; cat {mnt}/p.txt",
        mnt = quoted(&staging.join("mnt")),
        report = quoted(Path::new(env!("CARGO_BIN_EXE_report"))),
        out = quoted(&out),
    );
    let Some(mut command) = in_mount_namespace(&script) else {
        return;
    };
    let output = run_within(
        &mut command,
        QUICK_RUN,
        "report with a mount in its leftovers",
    );
    let (o, e) = (String::from_utf8_lossy(&output.stdout), err(&output));
    assert!(
        o.contains("precious"),
        "the mounted file was deleted: {o}\n{e}"
    );
    assert!(e.contains("mount"), "{e}");
    assert!(!e.contains("panicked"), "{e}");
}

/// [5] A symbolic link planted as the lock file is refused (exit 2): nothing is created at its
/// target.
#[test]
fn a_lock_that_is_a_symlink_is_refused_and_its_target_not_created() {
    let out = scratch("lock-symlink");
    let base = out.parent().unwrap().to_path_buf();
    let victim = base.join("victim-created");
    std::os::unix::fs::symlink(&victim, base.join(".out.lock")).unwrap();
    let output = report_in(&base, &["--out", "out", "--fixture", "T"]);
    let e = err(&output);
    assert_eq!(output.status.code(), Some(2), "{e}");
    assert!(
        e.contains(".out.lock") && e.contains("not a regular file"),
        "{e}"
    );
    assert!(!victim.exists(), "the lock link's target was created");
    assert!(!out.exists());
}

/// [5] A FIFO under the lock's name is refused at once with a named error, not waited on.
#[test]
fn a_lock_that_is_a_fifo_is_refused_at_once() {
    use rustix::fs::{mknodat, FileType, Mode, CWD};
    let out = scratch("lock-fifo");
    let base = out.parent().unwrap().to_path_buf();
    mknodat(
        CWD,
        base.join(".out.lock"),
        FileType::Fifo,
        Mode::from_raw_mode(0o600),
        0,
    )
    .unwrap();
    let output = report_in(&base, &["--out", "out", "--fixture", "T"]);
    let e = err(&output);
    assert_eq!(output.status.code(), Some(2), "{e}");
    assert!(
        e.contains(".out.lock") && e.contains("not a regular file"),
        "{e}"
    );
    assert!(!out.exists());
}

/// [14] A lock file left by root does not stop another user: the lock is taken on a descriptor
/// opened for reading (run as nobody in a sticky, world-writable directory).
#[test]
fn a_lock_left_by_root_does_not_stop_another_user() {
    use std::os::unix::fs::PermissionsExt;
    let base = shared_scratch("lock-root");
    let lock = base.join(".out.lock");
    std::fs::write(&lock, "").unwrap();
    std::fs::set_permissions(&lock, std::fs::Permissions::from_mode(0o644)).unwrap();
    let out = base.join("out");
    let Some(mut command) = as_nobody(
        env!("CARGO_BIN_EXE_report"),
        &["--out", out.to_str().unwrap(), "--fixture", "A"],
    ) else {
        return;
    };
    let output = run_within(&mut command, QUICK_RUN, "report as nobody");
    assert!(output.status.success(), "{}", err(&output));
    assert_eq!(fixture_tag(&out).as_deref(), Some("A"));
    std::fs::remove_dir_all(&base).unwrap();
}

/// [14] `--tables` out of range is bad input, exit 2, as clap's own errors are.
#[test]
fn report_tables_out_of_range_exit_2_like_every_bad_option() {
    let base = scratch("tables");
    for tables in ["0", "8", "256"] {
        let output = report_in(
            base.parent().unwrap(),
            &["--out", "out", "--tables", tables],
        );
        let e = err(&output);
        assert_eq!(output.status.code(), Some(2), "--tables {tables}: {e}");
        assert!(e.contains("--tables"), "{e}");
    }
    assert!(!base.exists(), "a refused run wrote its output");
}

/// [14] `--out a/b/c/report` with missing parents is refused, naming the missing directory,
/// and creates nothing.
#[test]
fn an_output_whose_parent_is_missing_is_refused_and_creates_nothing() {
    let out = scratch("missing-parents");
    let base = out.parent().unwrap().to_path_buf();
    let before = tree(&base);
    let output = report_in(&base, &["--out", "a/b/c/report", "--fixture", "A"]);
    let e = err(&output);
    assert_eq!(output.status.code(), Some(2), "{e}");
    assert!(e.contains("a/b/c") && e.contains("does not exist"), "{e}");
    assert_eq!(tree(&base), before);
}

/// The promises about files each name their test: every test named in the section "What the
/// tools promise about files" of `docs/building.md` (linked from the README) exists, and the
/// section names at least the tests of this issue's cases.
#[test]
fn every_promise_about_files_in_the_readme_names_a_test_that_exists() {
    let root = &mass_spring_report::crate_root();
    let readme = std::fs::read_to_string(root.join("docs/building.md")).unwrap();
    let start = readme
        .find("## What the tools promise about files")
        .expect("docs/building.md has the section");
    let section = &readme[start..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |e| e + 3)];
    // The tests of both crates of the workspace.
    let mut sources = String::new();
    for dir in ["tests", "presentation/tests"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "rs") {
                sources += &std::fs::read_to_string(path).unwrap();
            }
        }
    }
    let named: Vec<&str> = section
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|w| {
            w.matches('_').count() >= 3
                && w.chars()
                    .all(|c| c.is_ascii_lowercase() || c == '_' || c.is_ascii_digit())
        })
        .collect();
    assert!(named.len() >= 30, "{named:?}");
    for test in named {
        assert!(
            sources.contains(&format!("fn {test}()")),
            "docs/building.md names {test}, which is no test"
        );
    }
}

// Issue 48: the target checked again at publication, no open that can block, and every entry
// this user could not carry over or remove found before the run.

/// Opens the FIFO `pause` for writing once the paused `report --fixture` has opened it for
/// reading (it does so after its checks), waiting at most [`QUICK_RUN`].
fn release_handle(pause: &Path) -> std::fs::File {
    use rustix::fs::{openat, Mode, OFlags, CWD};
    let started = Instant::now();
    loop {
        match openat(CWD, pause, OFlags::WRONLY | OFlags::NONBLOCK, Mode::empty()) {
            Ok(fd) => return std::fs::File::from(fd),
            Err(rustix::io::Errno::NXIO) if started.elapsed() < QUICK_RUN => {
                std::thread::sleep(Duration::from_millis(10))
            }
            Err(e) => panic!("the paused report never opened {}: {e}", pause.display()),
        }
    }
}

/// Waits for `child` at most [`QUICK_RUN`], killing it and failing the test after that.
fn finish(mut child: std::process::Child) -> std::process::Output {
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > QUICK_RUN {
            child.kill().unwrap();
            panic!("report still running after {QUICK_RUN:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    child.wait_with_output().unwrap()
}

/// [1] The output directory replaced while the run computes (`mv out out.moved; mkdir out;
/// echo mine > out/REPORT.md`), or one of its report files replaced by the user's: the run
/// exits 1 at publication and both directories are as the user left them, nothing staged
/// beside them.
#[test]
fn a_target_replaced_during_the_run_is_refused_and_the_users_files_kept() {
    use rustix::fs::{mknodat, FileType, Mode, CWD};
    for (case, replaced) in ["the directory", "a report file"].into_iter().enumerate() {
        let out = scratch(&format!("replaced-{case}"));
        let base = out.parent().unwrap().to_path_buf();
        let moved = base.join("out.moved");
        assert!(report_in(&base, &["--out", "out", "--fixture", "A"])
            .status
            .success());
        let pause = base.join("pause");
        mknodat(CWD, &pause, FileType::Fifo, Mode::from_raw_mode(0o600), 0).unwrap();
        let child = Command::new(env!("CARGO_BIN_EXE_report"))
            .args(["--out", out.to_str().unwrap(), "--fixture", "B"])
            .env("REPORT_FIXTURE_PAUSE", &pause)
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let release = release_handle(&pause);
        if replaced == "the directory" {
            std::fs::rename(&out, &moved).unwrap();
            std::fs::create_dir(&out).unwrap();
            std::fs::write(out.join("notes.txt"), "mine").unwrap();
        } else {
            std::fs::remove_file(out.join("data/f00007.csv")).unwrap();
            std::fs::write(out.join("data/f00007.csv"), "mine").unwrap();
        }
        std::fs::write(out.join("REPORT.md"), "mine").unwrap();
        let before = (tree(&out), moved.exists().then(|| tree(&moved)));
        drop(release);
        let output = finish(child);
        let e = err(&output);
        assert_eq!(output.status.code(), Some(1), "{replaced}: {e}");
        assert!(e.contains("during the run"), "{replaced}: {e}");
        let after = (tree(&out), moved.exists().then(|| tree(&moved)));
        assert_eq!(after, before, "{replaced}: {e}");
        assert_eq!(
            leftovers(&out)
                .into_iter()
                .filter(|n| n.starts_with(".out."))
                .collect::<Vec<_>>(),
            Vec::<String>::new(),
            "{replaced}"
        );
    }
}

/// A report written as `nobody` into `out` under a fresh shared scratch directory, to which
/// the test (root) then adds another user's entries; `None` where `nobody` is out of reach.
fn nobodys_report(name: &str) -> Option<(PathBuf, PathBuf)> {
    let base = shared_scratch(name);
    let out = base.join("out");
    let mut command = as_nobody(
        env!("CARGO_BIN_EXE_report"),
        &["--out", out.to_str().unwrap(), "--fixture", "A"],
    )?;
    let output = run_within(&mut command, QUICK_RUN, "report as nobody");
    assert!(output.status.success(), "{}", err(&output));
    Some((base, out))
}

/// Runs `report --fixture B` as `nobody` on `out`, for at most 10 s (a hang fails the test).
fn nobodys_second_run(out: &Path) -> Option<std::process::Output> {
    let mut command = as_nobody(
        env!("CARGO_BIN_EXE_report"),
        &["--out", out.to_str().unwrap(), "--fixture", "B"],
    )?;
    Some(
        sandbox::run_for(&mut command, Duration::from_secs(10))
            .expect("report as nobody hung on an entry of its target"),
    )
}

/// [2] Another user's FIFO in the target (`mkfifo -m 644 out/pipe` as root): the run as
/// `nobody` is refused before it starts (exit 2), instead of hanging in the copy that stood in
/// for the refused hard link; nothing changed.
#[test]
fn another_users_fifo_in_the_target_is_refused_before_the_run() {
    use rustix::fs::{mknodat, FileType, Mode, CWD};
    let Some((base, out)) = nobodys_report("fifo-of-root") else {
        return;
    };
    mknodat(
        CWD,
        out.join("pipe"),
        FileType::Fifo,
        Mode::from_raw_mode(0o644),
        0,
    )
    .unwrap();
    let before = tree(&base);
    let Some(output) = nobodys_second_run(&out) else {
        return;
    };
    let e = err(&output);
    assert_eq!(output.status.code(), Some(2), "{e}");
    assert!(e.contains("/pipe is a named pipe"), "{e}");
    assert_eq!(tree(&base), before);
    std::fs::remove_dir_all(&base).unwrap();
}

/// Makes one entry at the path it is given.
type MakeEntry = fn(&Path);

/// [2] What `nobody` could not carry over or remove, refused before the run (exit 2) with
/// everything kept: another user's mode-600 file, a socket, another user's unreadable
/// directory, and another user's readable directory (which the carry-over can copy but the
/// removal of the previous report cannot empty, leaving a staging directory no later run
/// cleared).
#[test]
fn entries_this_user_cannot_carry_over_or_remove_are_refused_before_the_run() {
    use std::os::unix::fs::PermissionsExt;
    let cases: [(&str, MakeEntry); 4] = [
        ("private.txt", |p| {
            std::fs::write(p, "root's").unwrap();
            std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o600)).unwrap();
        }),
        ("socket", |p| {
            std::os::unix::net::UnixListener::bind(p).unwrap();
        }),
        ("closed", |p| {
            std::fs::create_dir(p).unwrap();
            std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o700)).unwrap();
        }),
        ("roots", |p| {
            std::fs::create_dir(p).unwrap();
            std::fs::write(p.join("kept.txt"), "root's").unwrap();
        }),
    ];
    for (name, make) in cases {
        let Some((base, out)) = nobodys_report(&format!("foreign-{name}")) else {
            return;
        };
        make(&out.join(name));
        let before = tree(&base);
        let Some(output) = nobodys_second_run(&out) else {
            return;
        };
        let e = err(&output);
        assert_eq!(output.status.code(), Some(2), "{name}: {e}");
        assert!(
            e.contains(name) && e.contains("nothing was changed"),
            "{name}: {e}"
        );
        assert_eq!(tree(&base), before, "{name}");
        std::fs::remove_dir_all(&base).unwrap();
    }
}

/// [4] A 240-byte `--out` name leaves no room for the staging directory's name beside it
/// (`.<name>.tmp-<pid>-<ns>`, over 255 bytes): refused before anything runs (exit 2) with the
/// longest name that fits, and no lock file is left beside it (it said "parent is not
/// writable" and left `.<name>.lock`).
#[test]
fn an_output_name_too_long_for_the_staging_directory_is_refused_and_leaves_no_lock() {
    let out = scratch("long-name");
    let base = out.parent().unwrap().to_path_buf();
    let name = "r".repeat(240);
    let output = report_in(&base, &["--out", &name, "--fixture", "A"]);
    let e = err(&output);
    assert_eq!(output.status.code(), Some(2), "{e}");
    assert!(
        e.contains("240 bytes") && e.contains("at most 219") && e.contains("nothing was changed"),
        "{e}"
    );
    assert_eq!(tree(&base).len(), 1, "{:?}", tree(&base).keys());
}

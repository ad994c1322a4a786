//! The hostile user's cases of issue 9, each a named regression test: `mss` output paths that
//! must not be harmed, and inputs past the limits, all refused before the run with exit 2 and
//! the option or field named.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn mss_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mss"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the mss binary starts")
}

fn mss(args: &[&str]) -> Output {
    mss_in(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

/// A fresh scratch directory.
fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("adversarial-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Exit status 2, every needle in the message, and no panic.
fn refused(output: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{err}");
    for needle in needles {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

const QUICK: [&str; 2] = ["--max-time", "0.05"];

#[cfg(unix)]
#[test]
fn ke_csv_dev_null_stays_a_device() {
    use std::os::unix::fs::FileTypeExt;
    let out = mss(&[&QUICK[..], &["--ke-csv", "/dev/null"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
}

#[test]
fn ke_csv_dev_stdout_is_streamed_in_place() {
    let out = mss(&[&QUICK[..], &["--ke-csv", "/dev/stdout"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("time_s,kinetic_energy_j\n0,0\n"), "{text}");
    assert!(text.contains("KE peaks"), "{text}");
}

#[cfg(unix)]
#[test]
fn a_read_only_file_is_refused_and_kept() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch("read-only");
    let file = dir.join("ke.csv");
    std::fs::write(&file, "keep me").unwrap();
    std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o444)).unwrap();
    let out = mss(&[&QUICK[..], &["--ke-csv", file.to_str().unwrap()]].concat());
    refused(&out, &["--ke-csv", "read-only"]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me");
}

#[cfg(unix)]
#[test]
fn a_symlink_is_followed_and_stays_a_link() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch("symlink");
    std::fs::write(dir.join("real.csv"), "old").unwrap();
    let mode = std::fs::Permissions::from_mode(0o640);
    std::fs::set_permissions(dir.join("real.csv"), mode).unwrap();
    std::os::unix::fs::symlink("real.csv", dir.join("link.csv")).unwrap();
    let out = mss_in(&dir, &[&QUICK[..], &["--ke-csv", "link.csv"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::symlink_metadata(dir.join("link.csv"))
        .unwrap()
        .file_type()
        .is_symlink());
    let series = std::fs::read_to_string(dir.join("real.csv")).unwrap();
    assert!(series.starts_with("time_s,kinetic_energy_j\n"), "{series}");
    assert_eq!(entries(&dir), ["link.csv", "real.csv"]);
    let meta = std::fs::metadata(dir.join("real.csv")).unwrap();
    assert_eq!(
        meta.permissions().mode() & 0o777,
        0o640,
        "the replaced file keeps its mode"
    );
}

#[cfg(target_os = "linux")]
#[test]
fn a_fifo_is_written_in_place() {
    use rustix::fs::{mknodat, FileType, Mode, CWD};
    use std::os::unix::fs::FileTypeExt;
    let dir = scratch("fifo");
    let fifo = dir.join("ke.fifo");
    mknodat(CWD, &fifo, FileType::Fifo, Mode::from_raw_mode(0o600), 0).unwrap();
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let out = mss(&[&QUICK[..], &["--ke-csv", fifo.to_str().unwrap()]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(reader
        .join()
        .unwrap()
        .starts_with("time_s,kinetic_energy_j\n"));
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
}

#[test]
fn the_scene_file_as_output_is_refused_and_kept() {
    let dir = scratch("scene-as-output");
    let scene = dir.join("s.toml");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/thesis-rope.toml"),
        &scene,
    )
    .unwrap();
    let before = std::fs::read(&scene).unwrap();
    let out = mss_in(&dir, &["--scene-file", "s.toml", "--ke-csv", "./s.toml"]);
    refused(&out, &["--ke-csv", "not the scene file"]);
    assert_eq!(std::fs::read(&scene).unwrap(), before);
}

#[test]
fn a_directory_is_refused_before_the_run() {
    let dir = scratch("directory");
    // Without the check this run would take minutes: the refusal comes first.
    let out = mss(&["--dt", "1e-5", "--ke-csv", dir.to_str().unwrap()]);
    refused(&out, &["--ke-csv", "not a directory"]);
}

#[test]
fn one_file_for_both_series_is_refused() {
    let dir = scratch("twice");
    let out = mss_in(
        &dir,
        &[
            &QUICK[..],
            &["--ke-csv", "o.csv", "--positions-csv", "./o.csv"],
        ]
        .concat(),
    );
    refused(&out, &["--positions-csv", "--ke-csv"]);
    assert_eq!(entries(&dir), Vec::<String>::new());
}

/// Linux: the series goes to an anonymous file (elsewhere a named one, left by a kill).
#[cfg(target_os = "linux")]
#[test]
fn an_interrupted_run_leaves_no_partial_file() {
    let dir = scratch("interrupted");
    std::fs::write(dir.join("ke.csv"), "previous").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mss"))
        .args(["--dt", "1e-5", "--max-work", "1e12", "--ke-csv", "ke.csv"])
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run ended before it was killed"
    );
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(entries(&dir), ["ke.csv"]);
    assert_eq!(
        std::fs::read_to_string(dir.join("ke.csv")).unwrap(),
        "previous"
    );
}

#[test]
fn a_tiny_dt_is_over_the_work_budget() {
    refused(&mss(&["--dt", "1e-9"]), &["--max-work", "--dt"]);
    // Below its range (issue 48), before the work budget is reckoned.
    refused(&mss(&["--dt", "1e-300"]), &["--dt", "from 1e-9"]);
    // The budget is the option's: a small one refuses a short run, the default allows it.
    refused(
        &mss(&[&QUICK[..], &["--max-work", "100"]].concat()),
        &["--max-work"],
    );
    assert!(mss(&QUICK).status.success());
}

#[test]
fn a_huge_iteration_count_is_over_the_work_budget() {
    refused(
        &mss(&["--iterations", "9223372036854775807"]),
        &["--max-work", "iterations"],
    );
}

#[test]
fn a_billion_nodes_are_refused_before_any_allocation() {
    refused(
        &mss(&["--scene", "rope", "--nodes", "1000000000"]),
        &["--nodes", "1000000000", "memory"],
    );
}

#[test]
fn dt_longer_than_max_time_is_refused() {
    refused(
        &mss(&["--dt", "20", "--max-time", "10"]),
        &["--dt", "--max-time"],
    );
}

#[cfg(unix)]
#[test]
fn dev_zero_as_scene_file_is_refused() {
    refused(
        &mss(&["--scene-file", "/dev/zero"]),
        &["/dev/zero", "16 MiB"],
    );
}

fn rope_with(from: &str, to: &str) -> String {
    let rope = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/thesis-rope.toml"),
    )
    .unwrap();
    assert!(rope.contains(from), "{from}");
    rope.replacen(from, to, 1)
}

fn refused_scene(name: &str, text: &str, needles: &[&str]) {
    let dir = scratch(name);
    std::fs::write(dir.join("s.toml"), text).unwrap();
    refused(&mss_in(&dir, &["--scene-file", "s.toml"]), needles);
}

#[test]
fn extra_array_elements_are_refused() {
    refused_scene(
        "gravity-4",
        &rope_with(
            "gravity = [0.0, -9.81, 0.0]",
            "gravity = [0, -9.81, 0, 12345]",
        ),
        &["exactly 3", "line 8"],
    );
    refused_scene(
        "position-junk",
        &rope_with(
            "position = [1.0, 0.0, 0.0]",
            "position = [1, 0, 0, \"junk\"]",
        ),
        &["line"],
    );
}

#[test]
fn absurd_finite_values_are_input_errors_naming_the_field() {
    refused_scene(
        "tiny-mass",
        &rope_with("mass = 1.0", "mass = 1e-320"),
        &["nodes[0].mass", "1e-9", "line"],
    );
    refused_scene(
        "huge-gravity",
        &rope_with(
            "gravity = [0.0, -9.81, 0.0]",
            "gravity = [0.0, -1e300, 0.0]",
        ),
        &["gravity[1]", "-1e300", "line 8"],
    );
    refused(&mss(&["--gravity", "1e300"]), &["--gravity", "1e4"]);
    refused(&mss(&["--stiffness", "1e300"]), &["--stiffness", "1e12"]);
}

// Issue 27: output paths settled before the run, regular files replaced atomically wherever
// they live, descriptors and devices written in place, FIFOs and dangling links refused; each a
// case of `shared/docs/reliability-cases.md` ([n]).

mod sandbox;
use sandbox::{as_nobody, in_mount_namespace, quoted, run_for, run_within, shared_scratch};
use std::time::Duration;

/// A run of about a minute (the thesis rope to 3000 s): a refusal "before the run" must come
/// long before it would end.
const LONG: [&str; 2] = ["--threshold", "1e-30"];
/// What a refusal before the run may take at most (it takes milliseconds).
const PROMPTLY: Duration = Duration::from_secs(15);

fn mss_for(dir: &Path, args: &[&str], limit: Duration) -> Output {
    run_within(
        Command::new(env!("CARGO_BIN_EXE_mss"))
            .args(args)
            .current_dir(dir),
        limit,
        &format!("mss {args:?}"),
    )
}

/// The CSV of a kinetic-energy series read back strictly: its header, then rows of two numbers.
fn assert_whole_ke_csv(text: &str) {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("time_s,kinetic_energy_j"), "{text:.200}");
    let mut rows = 0;
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), 2, "not a row of the series: {line:?}");
        for f in fields {
            assert!(f.parse::<f64>().is_ok(), "{line:?}");
        }
        rows += 1;
    }
    assert!(rows > 10, "{rows} rows");
}

/// [4] A regular file reached through `/dev/..` is a regular file: replaced whole (atomically),
/// not overwritten from its start with the old tail left.
#[test]
fn a_regular_file_reached_through_dev_is_replaced_whole() {
    let dir = scratch("through-dev");
    let file = dir.join("ke.csv");
    let old: String = (1..=100_000).map(|i| format!("{i}\n")).collect();
    std::fs::write(&file, &old).unwrap();
    let through = format!("/dev/..{}", file.display());
    let out = mss(&[&QUICK[..], &["--ke-csv", &through]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_whole_ke_csv(&std::fs::read_to_string(&file).unwrap());
    assert_eq!(entries(&dir), ["ke.csv"]);
}

/// [4] On `/dev/shm`: an existing file is replaced only when the run succeeds (a diverging run
/// leaves it as it was), and a new file is created.
#[test]
fn a_regular_file_on_dev_shm_is_replaced_only_when_the_run_succeeds() {
    let shm = Path::new("/dev/shm");
    if !shm.is_dir() {
        eprintln!("skipped: no /dev/shm on this machine");
        return;
    }
    let file = shm.join(format!("mss-i27-{}-ke.csv", std::process::id()));
    let old = "1\n2\n3\n".repeat(10_000);
    std::fs::write(&file, &old).unwrap();
    let path = file.to_str().unwrap();
    let diverging = mss(&[
        "--solver",
        "explicit_euler",
        "--dt",
        "0.01",
        "--ke-csv",
        path,
    ]);
    assert_eq!(
        diverging.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&diverging.stderr)
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), old);
    let out = mss(&[&QUICK[..], &["--ke-csv", path]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_whole_ke_csv(&std::fs::read_to_string(&file).unwrap());
    std::fs::remove_file(&file).unwrap();
    let out = mss(&[&QUICK[..], &["--ke-csv", path]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_whole_ke_csv(&std::fs::read_to_string(&file).unwrap());
    std::fs::remove_file(&file).unwrap();
}

/// [8] A file name over NAME_MAX (255 bytes) is refused before the run, not after it.
#[test]
fn a_file_name_over_name_max_is_refused_before_the_run() {
    let dir = scratch("name-max");
    let name = format!("{}.csv", "a".repeat(252));
    let out = mss_for(&dir, &[&LONG[..], &["--ke-csv", &name]].concat(), PROMPTLY);
    refused(&out, &["--ke-csv", "255 bytes"]);
    assert_eq!(entries(&dir), Vec::<String>::new());
}

/// [8] An existing file of a 254-byte name is replaced: the temporary name beside it does not
/// grow with the file's.
#[test]
fn an_existing_file_with_a_254_byte_name_is_replaced() {
    let dir = scratch("name-254");
    let name = format!("{}.csv", "a".repeat(250));
    std::fs::write(dir.join(&name), "old").unwrap();
    let out = mss_for(&dir, &[&QUICK[..], &["--ke-csv", &name]].concat(), PROMPTLY);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_whole_ke_csv(&std::fs::read_to_string(dir.join(&name)).unwrap());
    assert_eq!(entries(&dir), [name]);
}

/// [8] A path ending in `/` names a directory: refused before the run, whether or not a file of
/// that name exists.
#[test]
fn a_trailing_slash_is_refused_before_the_run() {
    let dir = scratch("trailing-slash");
    std::fs::write(dir.join("f.csv"), "old").unwrap();
    for path in ["new.csv/", "f.csv/"] {
        let out = mss_for(&dir, &[&LONG[..], &["--ke-csv", path]].concat(), PROMPTLY);
        refused(&out, &["--ke-csv", path]);
    }
    assert_eq!(entries(&dir), ["f.csv"]);
    assert_eq!(std::fs::read_to_string(dir.join("f.csv")).unwrap(), "old");
}

/// [8] As `nobody`, another user's file in a sticky world-writable directory (like `/tmp`)
/// cannot be replaced by a rename: refused before the run, the file kept.
#[test]
fn another_users_file_in_a_sticky_directory_is_refused_before_the_run() {
    use std::os::unix::fs::PermissionsExt;
    let dir = shared_scratch("sticky");
    let file = dir.join("w.csv");
    std::fs::write(&file, "root's").unwrap();
    std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o666)).unwrap();
    let Some(mut command) = as_nobody(
        env!("CARGO_BIN_EXE_mss"),
        &[&LONG[..], &["--ke-csv", file.to_str().unwrap()]].concat(),
    ) else {
        return;
    };
    let out = run_within(&mut command, PROMPTLY, "mss as nobody");
    refused(&out, &["--ke-csv", "sticky"]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "root's");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// [8] A bind-mounted file cannot be replaced by a rename: refused before the run (in a private
/// mount namespace).
#[test]
fn a_bind_mounted_file_is_refused_before_the_run() {
    let dir = scratch("bind-file");
    std::fs::write(dir.join("src.csv"), "source").unwrap();
    std::fs::write(dir.join("ke.csv"), "mount point").unwrap();
    let script = format!(
        "cd {dir} && mount --bind src.csv ke.csv && exec {mss} {long} --ke-csv ke.csv",
        dir = quoted(&dir),
        mss = quoted(Path::new(env!("CARGO_BIN_EXE_mss"))),
        long = LONG.join(" "),
    );
    let Some(mut command) = in_mount_namespace(&script) else {
        return;
    };
    let out = run_within(&mut command, PROMPTLY, "mss onto a bind mount");
    refused(&out, &["--ke-csv", "mount point"]);
    assert_eq!(
        std::fs::read_to_string(dir.join("src.csv")).unwrap(),
        "source"
    );
}

/// [8] Without `/proc` (a chroot or a minimal container) the output is still replaced: the
/// anonymous file that needs `/proc/self/fd` gives way to a named one, before the run.
#[test]
fn without_proc_the_output_is_still_replaced() {
    let dir = scratch("no-proc");
    std::fs::write(dir.join("ke.csv"), "old").unwrap();
    let script = format!(
        "cd {dir} && umount -l /proc && exec {mss} --max-time 0.05 --ke-csv ke.csv",
        dir = quoted(&dir),
        mss = quoted(Path::new(env!("CARGO_BIN_EXE_mss"))),
    );
    let Some(mut command) = in_mount_namespace(&script) else {
        return;
    };
    let out = run_within(&mut command, PROMPTLY, "mss without /proc");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_whole_ke_csv(&std::fs::read_to_string(dir.join("ke.csv")).unwrap());
    assert_eq!(entries(&dir), ["ke.csv"]);
}

/// [9] A symbolic link whose target does not exist (or whose directory does not, or a loop) is
/// refused and kept a link; two options reaching one file through a dangling link are refused.
#[test]
fn a_dangling_symlink_is_refused_and_kept() {
    use std::os::unix::fs::symlink;
    let dir = scratch("dangling");
    symlink("target.csv", dir.join("link.csv")).unwrap();
    symlink("nodir/target.csv", dir.join("deep.csv")).unwrap();
    symlink("loop-b.csv", dir.join("loop-a.csv")).unwrap();
    symlink("loop-a.csv", dir.join("loop-b.csv")).unwrap();
    symlink("a.csv", dir.join("b.csv")).unwrap();
    for link in ["link.csv", "deep.csv", "loop-a.csv"] {
        let out = mss_for(&dir, &[&QUICK[..], &["--ke-csv", link]].concat(), PROMPTLY);
        refused(&out, &["--ke-csv", link, "symbolic link"]);
    }
    let out = mss_for(
        &dir,
        &[
            &QUICK[..],
            &["--ke-csv", "a.csv", "--positions-csv", "b.csv"],
        ]
        .concat(),
        PROMPTLY,
    );
    refused(&out, &["--positions-csv", "symbolic link"]);
    assert_eq!(
        entries(&dir),
        ["b.csv", "deep.csv", "link.csv", "loop-a.csv", "loop-b.csv"]
    );
    for link in entries(&dir) {
        assert!(std::fs::symlink_metadata(dir.join(&link))
            .unwrap()
            .file_type()
            .is_symlink());
    }
}

fn mkfifo(path: &Path) {
    use rustix::fs::{mknodat, FileType, Mode, CWD};
    mknodat(CWD, path, FileType::Fifo, Mode::from_raw_mode(0o600), 0).unwrap();
}

/// [10] A FIFO with no reader as an output waits a short stated time, then is refused (exit 2,
/// before the run), instead of blocking without a word.
#[test]
fn a_fifo_without_a_reader_is_refused_after_a_short_wait() {
    let dir = scratch("fifo-no-reader");
    mkfifo(&dir.join("f"));
    let out = run_for(
        Command::new(env!("CARGO_BIN_EXE_mss"))
            .args([&LONG[..], &["--ke-csv", "f"]].concat())
            .current_dir(&dir),
        PROMPTLY,
    )
    .expect("mss blocked on a FIFO with no reader");
    refused(&out, &["--ke-csv", "reader", "1 s"]);
}

/// [10] A FIFO with no writer as the scene file: the same short wait, then a refusal.
#[test]
fn a_fifo_as_scene_file_without_a_writer_is_refused_after_a_short_wait() {
    let dir = scratch("fifo-scene");
    mkfifo(&dir.join("s.toml"));
    let out = run_for(
        Command::new(env!("CARGO_BIN_EXE_mss"))
            .args(["--scene-file", "s.toml"])
            .current_dir(&dir),
        PROMPTLY,
    )
    .expect("mss blocked on a FIFO with no writer");
    refused(&out, &["s.toml", "writer", "1 s"]);
}

/// [14] A sink device for both series is not "one file given twice".
#[test]
fn dev_null_for_both_series_is_accepted() {
    let out = mss(&[
        &QUICK[..],
        &["--ke-csv", "/dev/null", "--positions-csv", "/dev/null"],
    ]
    .concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// [3 of What to build] `--ke-csv /dev/stdout` with stdout a file opened for appending
/// (`>> log.csv`) keeps appending: the descriptor is written, not the file reopened.
#[test]
fn dev_stdout_appends_to_a_file_opened_for_appending() {
    let dir = scratch("append");
    let log = dir.join("log.csv");
    std::fs::write(&log, "earlier\n").unwrap();
    let appending = std::fs::OpenOptions::new().append(true).open(&log).unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_mss"))
        .args([&QUICK[..], &["--ke-csv", "/dev/stdout"]].concat())
        .stdout(appending)
        .status()
        .unwrap();
    assert!(status.success());
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(
        text.starts_with("earlier\ntime_s,kinetic_energy_j\n0,0\n"),
        "{text:.300}"
    );
    assert!(text.contains("KE peaks"), "{text:.300}");
}

/// [14] As another user, `--ke-csv /dev/stdout` into a pipe that root made is written: the
/// descriptor is duplicated, not the pipe reopened (which its owner's mode refuses).
#[test]
fn dev_stdout_is_written_in_place_as_another_user() {
    let Some(mut command) = as_nobody(
        env!("CARGO_BIN_EXE_mss"),
        &[&QUICK[..], &["--ke-csv", "/dev/stdout"]].concat(),
    ) else {
        return;
    };
    let out = run_within(command.current_dir("/"), PROMPTLY, "mss as nobody");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("time_s,kinetic_energy_j\n0,0\n"),
        "{text:.300}"
    );
}

/// [14] With stdout closed (`>&-`) the runtime gives the process `/dev/null` as its stdout: a
/// run succeeds and nothing panics (what it prints is lost, as with `> /dev/null`).
#[test]
fn a_closed_stdout_exits_0_without_a_panic() {
    let out = Command::new("sh")
        .args([
            "-c",
            &format!(
                "exec {} --max-time 0.05 --ke-csv /dev/stdout >&-",
                quoted(Path::new(env!("CARGO_BIN_EXE_mss")))
            ),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

// Issue 27: every budget counted, every size bounded before allocation, option ranges and
// numbers in short form, a scene's general refusals in scene validation ([n] as above).

/// Exit status 1 (the run stopped), every needle in the message, no panic.
fn stopped(output: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{err}");
    for needle in needles {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

/// No number printed as a long run of digits (1e308 as its 309 digits).
fn no_long_numbers(output: &Output) {
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(!err.contains("0000000000"), "{err}");
}

fn here(args: &[&str]) -> Output {
    mss_for(Path::new(env!("CARGO_MANIFEST_DIR")), args, PROMPTLY)
}

/// [6] rk45's adaptive steps are counted: a stiff run is refused before it starts when its
/// estimate (the stiffest mode's frequency over Dormand-Prince's stability bound) is over the
/// budget, and the issue's own commands end at once (a tolerance below round-off, a 1e-9 kg
/// node on a 1e12 N/m spring, the stiff cloth).
#[test]
fn rk45_stiff_runs_are_refused_by_their_adaptive_step_estimate() {
    let rk45 = ["--solver", "rk45"];
    for args in [
        &[
            "--stiffness",
            "1e12",
            "--dt",
            "0.1",
            "--max-time",
            "1",
            "--max-work",
            "1e7",
        ][..],
        &[
            "--scene",
            "rope",
            "--node-mass",
            "1e-9",
            "--stiffness",
            "1e12",
        ],
        &[
            "--scene",
            "hanging_cloth",
            "--stiffness",
            "1e12",
            "--dt",
            "0.01",
            "--max-time",
            "0.2",
            "--max-work",
            "1e8",
        ],
    ] {
        let out = here(&[&rk45[..], args].concat());
        refused(&out, &["--max-work", "adaptive steps"]);
    }
    let out = here(&[
        "--solver",
        "rk45",
        "--tolerance",
        "1e-16",
        "--stiffness",
        "1e12",
        "--max-time",
        "1e-3",
    ]);
    refused(&out, &["--tolerance", "1e-16", "1e-12"]);
}

/// [6] Past the estimate, a hard stop: the adaptive steps a tight tolerance takes are capped
/// by the same budget, and the run stops saying when and why (exit 1).
#[test]
fn rk45_adaptive_steps_past_the_budget_stop_the_run() {
    let out = here(&[
        "--solver",
        "rk45",
        "--stiffness",
        "1e3",
        "--tolerance",
        "1e-10",
        "--dt",
        "0.1",
        "--max-time",
        "10",
        "--max-work",
        "1e5",
    ]);
    stopped(&out, &["work budget", "--max-work", "t = "]);
}

/// [6] `--compare-reference` counts the reference at its own length (the thesis's stopping
/// rule, up to 3000 s at dt = 1e-3 s), not at this run's `--max-time`.
#[test]
fn compare_reference_counts_the_reference_at_its_own_length() {
    let out = here(&[
        "--scene",
        "sheet",
        "--solver",
        "xpbd",
        "--max-time",
        "0.001",
        "--compare-reference",
        "--max-work",
        "1e9",
    ]);
    refused(&out, &["--max-work", "reference"]);
}

/// [7] `--history` has a named range, checked before L-BFGS reserves anything (4294967295
/// once asked for 275 GB and aborted).
#[test]
fn lbfgs_history_is_bounded_before_any_allocation() {
    for history in ["4294967295", "100000000", "101"] {
        let out = here(&[
            "--solver",
            "lbfgs",
            "--history",
            history,
            "--max-time",
            "0.05",
        ]);
        refused(&out, &["--history", "from 1 to 100"]);
    }
}

/// [7] Backward Euler on a 1000 × 1000 sheet needs some 10 GB (its factor grows as N log N):
/// under a 4 GiB address-space limit its memory estimate refuses it at once, where it used
/// to abort after half a minute; an explicit `--max-memory` is honoured the same way.
#[test]
fn backward_euler_on_a_large_sheet_is_refused_by_its_memory_estimate() {
    let args = ["--scene", "sheet", "--n", "1000", "--max-time", "0.001"];
    if let Some(mut command) = sandbox::under_address_limit(env!("CARGO_BIN_EXE_mss"), &args) {
        let out = run_within(&mut command, PROMPTLY, "mss on a large sheet");
        refused(&out, &["--max-memory", "backward_euler", "estimate"]);
    }
    let out = here(&["--scene", "sheet", "--n", "300", "--max-memory", "1e8"]);
    refused(&out, &["--max-memory", "backward_euler", "estimate"]);
    no_long_numbers(&out);
}

/// [14] `--n` far past its range is refused with the range, not as a saturated node count.
#[test]
fn n_at_i64_max_is_refused_with_its_range() {
    let out = here(&["--scene", "sheet", "--n", "9223372036854775807"]);
    refused(&out, &["--n", "from 3 to"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("18446744073709551615"), "{err}");
}

/// [10] [11] Rayleigh damping has upper bounds, the same for both damped solvers, named with
/// their option and printed in short form.
#[test]
fn rayleigh_damping_is_bounded_and_printed_in_short_form() {
    for solver in ["damped_admm", "damped_backward_euler"] {
        for option in ["--alpha", "--beta"] {
            let out = here(&["--solver", solver, option, "1e308"]);
            refused(&out, &[option, "1e308", "from 0 to"]);
            no_long_numbers(&out);
        }
    }
}

/// [11] A value far out of range is printed in short scientific form.
#[test]
fn huge_values_print_in_short_scientific_form() {
    let out = here(&["--dt", "1e300"]);
    refused(&out, &["--dt", "1e300"]);
    no_long_numbers(&out);
    let out = here(&["--max-time", "-1e300"]);
    refused(&out, &["--max-time", "-1e300"]);
    no_long_numbers(&out);
}

/// [11] rk45's tolerance has a range: below 1e-12 it cannot be met in double precision, above
/// 0.1 it is no error control.
#[test]
fn rk45_tolerance_is_bounded() {
    for tolerance in ["1e308", "1e-16", "5e-324"] {
        let out = here(&["--solver", "rk45", "--tolerance", tolerance]);
        refused(&out, &["--tolerance", "from 1e-12 to"]);
        no_long_numbers(&out);
    }
}

/// [11] `--first-iterate` (once `--initialization`) reads `_` as `-`, as `--solver` does.
#[test]
fn vbd_first_iterate_accepts_underscores() {
    let out = here(&[
        "--solver",
        "vbd",
        "--first-iterate",
        "previous_position",
        "--max-time",
        "0.05",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// [12] A spring of stiffness 0 is refused by the scene file's validation, with the file, the
/// line and the field, for every solver (six refused it by themselves, without the file).
#[test]
fn zero_stiffness_in_a_scene_file_is_refused_with_file_line_and_field() {
    let dir = scratch("zero-stiffness");
    std::fs::write(
        dir.join("s.toml"),
        rope_with("stiffness = 1e6", "stiffness = 0"),
    )
    .unwrap();
    for solver in ["xpbd", "explicit_euler", "backward_euler"] {
        let out = mss_for(
            &dir,
            &["--scene-file", "s.toml", "--solver", solver],
            PROMPTLY,
        );
        refused(&out, &["s.toml", "line", "springs[0].stiffness"]);
    }
}

const COINCIDENT: &str = "gravity = [0.0, -9.81, 0.0]
[[nodes]]
mass = 1.0
position = [0.0, 0.0, 0.0]
fixed = true
[[nodes]]
mass = 1.0
position = [0.0, 0.0, 0.0]
[[springs]]
a = 0
b = 1
rest_length = 1.0
stiffness = 1e6
";

/// [12] Two nodes at one point joined by a spring of rest length 1 m: the spring has no
/// direction, refused by the scene's validation (file, line, field) instead of a Cholesky or
/// spectral-radius failure inside three solvers.
#[test]
fn coincident_nodes_are_refused_by_scene_validation() {
    let dir = scratch("coincident");
    std::fs::write(dir.join("coincident_rest1.toml"), COINCIDENT).unwrap();
    for solver in ["backward_euler", "chebyshev_admm", "xpbd"] {
        let out = mss_for(
            &dir,
            &["--scene-file", "coincident_rest1.toml", "--solver", solver],
            PROMPTLY,
        );
        refused(&out, &["coincident_rest1.toml", "line 9", "springs[0]"]);
    }
}

/// [12] A span that crushes every spring of the rope to nothing is refused, naming `--span`.
#[test]
fn a_span_that_crushes_the_rope_is_refused() {
    for span in ["1e-300", "1e-9"] {
        let out = here(&["--scene", "rope", "--span", span]);
        refused(&out, &["--span", span]);
    }
}

/// [12] A scene file with no nodes says so, not "all fixed".
#[test]
fn a_scene_file_without_nodes_is_refused_naming_nodes() {
    let dir = scratch("no-nodes");
    std::fs::write(dir.join("s.toml"), "gravity = [0.0, -9.81, 0.0]\n").unwrap();
    let out = mss_for(&dir, &["--scene-file", "s.toml"], PROMPTLY);
    refused(&out, &["s.toml", "nodes", "no nodes"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("nodes[*].fixed"), "{err}");
}

// Issue 48: every allocation an option sizes counted before the run, and every numeric option
// bounded.

/// [3] The per-step histogram of iterations holds only the counts the steps took (one here),
/// where it allocated 8·(N+1) bytes for `--iterations N`: the issue's `--iterations
/// 1000000000` under 4 GiB aborted ("memory allocation of 8000000008 bytes failed"); here
/// 50,000,000 (400 MB) under 256 MiB, which aborted the same way and now ends at once.
#[test]
fn a_large_iteration_count_allocates_no_histogram_of_that_size() {
    let args = [
        "--solver",
        "fast_mass_spring",
        "--iterations",
        "50000000",
        "--max-time",
        "0.001",
    ];
    let program = env!("CARGO_BIN_EXE_mss");
    let Some(mut command) = sandbox::under_address_limit_of(256 << 20, program, &args) else {
        return;
    };
    let out = run_within(&mut command, PROMPTLY, "mss --iterations 50000000");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{:?}: {err}", out.status);
}

/// [3] What a run keeps per step (its histogram of iterations and the energy peaks of its
/// stopping rule) is in the memory estimate before the run: 3·10⁹ steps of one iteration are
/// within the work budget, but their records are not within 1 GB.
#[test]
fn per_step_records_are_counted_in_the_memory_estimate() {
    let out = here(&[
        "--solver",
        "xpbd",
        "--iterations",
        "1",
        "--dt",
        "1e-6",
        "--max-time",
        "3000",
        "--max-memory",
        "1e9",
    ]);
    refused(&out, &["--max-memory", "histogram of iterations", "peaks"]);
}

/// The paragraph of `mss --help` describing `option`.
fn help_of(help: &str, option: &str) -> String {
    let start = help
        .find(&format!("      {option} <"))
        .unwrap_or_else(|| panic!("{option} is not in mss --help"));
    let rest = &help[start + 6..];
    let end = rest
        .find("\n      -")
        .or(rest.find("\n  -"))
        .unwrap_or(rest.len());
    rest[..end].split_whitespace().collect::<Vec<_>>().join(" ")
}

/// [4] Every numeric option without a range before has one, stated in `mss --help` in the
/// words its refusal uses, and a value past it is refused naming the option (exit 2), printed
/// in short form: `--drag 1e308` gave a 309-digit solver name or "invalid node_weights[1]:
/// inf", `--dt 1e-300` 300-digit times.
#[test]
fn every_numeric_option_is_bounded_and_its_bounds_stated_in_help() {
    let cases: [(&[&str], &str, &str, &str); 16] = [
        (
            &["--solver", "damped_admm"],
            "--drag",
            "1e308",
            "from 0 to 1e9",
        ),
        (
            &["--solver", "damped_admm"],
            "--drag",
            "-1",
            "from 0 to 1e9",
        ),
        (
            &["--solver", "xpbd_substeps"],
            "--constraint-damping",
            "1e308",
            "from 0 to 1e9",
        ),
        (&[], "--dt", "1e-300", "from 1e-9 to 1e9"),
        (&[], "--max-time", "1e300", "from 1e-9 to 1e9"),
        (&[], "--threshold", "1e300", "> 0 and at most 1e12"),
        (&[], "--velocity-damping", "1e308", "from 0 to 1e6"),
        (&[], "--stop-tolerance", "1e308", "> 0 and at most 1e6"),
        (&[], "--max-work", "1e300", "from 1 to 1e18"),
        (&[], "--max-memory", "1e300", "from 1e6 to 1e18"),
        (&[], "--stiffness", "1e300", "from 1e-9 to 1e12"),
        (&[], "--gravity", "1e300", "from -1e4 to 1e4"),
        (
            &["--scene", "rope"],
            "--rest-length",
            "1e300",
            "from 1e-9 to 1e6",
        ),
        (
            &["--scene", "rope"],
            "--node-mass",
            "1e300",
            "from 1e-9 to 1e9",
        ),
        (
            &["--scene", "rope"],
            "--span",
            "1e300",
            "> 0 and at most 1e6",
        ),
        (
            &["--solver", "chebyshev_liu"],
            "--warmup",
            "1e300",
            "from 0 to 4294967295",
        ),
    ];
    let help = String::from_utf8_lossy(&here(&["--help"]).stdout).into_owned();
    for (before, option, value, range) in cases {
        let out = here(&[before, &[option, value]].concat());
        refused(&out, &[option, range]);
        no_long_numbers(&out);
        let paragraph = help_of(&help, option);
        assert!(
            paragraph.contains(range),
            "mss --help does not state {option}'s range {range:?}: {paragraph}"
        );
    }
}

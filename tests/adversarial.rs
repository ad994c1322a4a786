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
    for dt in ["1e-300", "1e-9"] {
        refused(&mss(&["--dt", dt]), &["--max-work", "--dt"]);
    }
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

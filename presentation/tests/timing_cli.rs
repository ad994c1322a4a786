//! `make timing`'s binary: bad input is named before anything runs, and one point is measured
//! in its own process and printed as one row (the scaling study itself takes minutes: run by
//! `make timing`, not here). The benchmark in wall time: the comparisons of the two costs
//! recomputed on rows built to a known answer, the files read back strictly, and the files of
//! a quick run (no time is asserted).

use mass_spring_report::benchmark::rows_csv;
use mass_spring_report::benchmark::wall::*;
use mass_spring_solvers::solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::studies::benchmark::sweep::{configurations, Configuration};
use mass_spring_solvers::studies::benchmark::truth::CaseTruth;
use mass_spring_solvers::studies::benchmark::Case;
use std::process::Command;

#[path = "../../tests/figure_check/mod.rs"]
mod figure_check;
#[path = "../../tests/sandbox/mod.rs"]
mod sandbox;

fn timing(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_timing"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn bad_input_is_named() {
    let (code, _, err) = timing(&["--point", "nope", "10"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--point SOLVER") && err.contains("fast_mass_spring"),
        "{err}"
    );
    let (code, _, err) = timing(&["--point", "fast_mass_spring", "ten"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--point N"), "{err}");
    // [13] N has a range: the study's sizes (3000 aborted on a 4 GB limit after 14 s).
    for n in ["1", "2", "321", "3000", "100000000"] {
        let (code, _, err) = timing(&["--point", "fast_mass_spring", n]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("--point N") && err.contains("from 3 to 320"),
            "{err}"
        );
    }
    let dir = std::env::temp_dir().join(format!("timing-cli-{}", std::process::id()));
    let (code, _, err) = timing(&["--max-side", "5", "--out", dir.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--max-side"), "{err}");
    assert!(
        !dir.exists(),
        "nothing is written before the input is checked"
    );
}

/// A point's row: the sheet's counts, a factor for Liu, times that are positive and finite.
#[test]
fn a_point_is_one_row_of_positive_times() {
    let (code, out, err) = timing(&["--point", "fast_mass_spring", "20"]);
    assert_eq!(code, 0, "{err}");
    let row: Vec<&str> = out.trim().split(',').collect();
    assert_eq!(row.len(), 21, "{out}");
    assert_eq!(&row[..4], ["fast_mass_spring", "20", "400", "1482"]);
    assert!(
        row[4].parse::<usize>().unwrap() > 1482,
        "the factor fills in: {out}"
    );
    for (i, v) in row.iter().enumerate().skip(5) {
        if let Ok(v) = v.parse::<f64>() {
            assert!(v.is_finite() && v >= 0.0, "column {i}: {v}");
        }
    }
    assert!(row[14].parse::<f64>().unwrap() > 0.0, "{out}");
}

/// A row of the soft rope: `id` with one iteration at `dt_s`, its two costs and its error.
fn row(id: SolverId, dt_s: f64, wall_s: f64, flops: f64, physical_rel: f64) -> WallRow {
    let configuration = Configuration {
        case: Case::ALL[0],
        spec: SolverSpec::new(id, 1),
        dt_s,
    };
    let time = RunTime {
        wall_s,
        cpu_s: wall_s,
        wall_spread: 0.01,
    };
    WallRow::new(&configuration, time, flops, physical_rel)
}

/// Kendall's τ recomputed here from its definition: (concordant − discordant) / pairs.
fn tau(a: &[SolverId], b: &[SolverId]) -> f64 {
    let at = |l: &[SolverId], x| l.iter().position(|&y| y == x).unwrap();
    let (mut c, mut d) = (0, 0);
    for i in 0..a.len() {
        for j in i + 1..a.len() {
            if (at(b, a[i]) < at(b, a[j])) == (i < j) {
                c += 1;
            } else {
                d += 1;
            }
        }
    }
    (c - d) as f64 / (c + d) as f64
}

/// Three solvers that reach 10 %: by flops XPBD, Liu, ADMM; by wall time ADMM, Liu, XPBD, Liu
/// within a tie of XPBD in wall time. τ is recomputed from its definition; the reversed pairs
/// are those apart by more than a tie in both costs (a rule that ignored ties would also name
/// XPBD < Liu); a configuration that does not reach the level does not count, and the cheapest
/// of each cost may be another configuration.
#[test]
fn the_two_rankings_are_compared_at_matched_accuracy() {
    let (xpbd, liu, admm) = (SolverId::Xpbd, SolverId::FastMassSpring, SolverId::AdmmPd);
    let rows = vec![
        row(xpbd, 0.1, 2.0e-3, 100.0, 0.05),
        row(liu, 0.1, 1.95e-3, 200.0, 0.08),
        row(admm, 0.1, 1.0e-3, 400.0, 0.09),
        // Cheaper in both costs but not accurate enough.
        row(admm, 0.05, 1e-6, 1.0, 0.5),
        // ADMM's cheapest in flops at 1 %, dearer in wall time than its other configuration.
        row(admm, 0.02, 9e-3, 500.0, 0.005),
        row(admm, 0.01, 8e-3, 900.0, 0.005),
    ];
    let case = Case::ALL[0];
    // No explicit baseline here: RK4's limit does not matter.
    let limit = 1.0;
    let c = compare(&rows, case, 0.1, limit);
    let ids = |r: &[(SolverId, &WallRow)]| r.iter().map(|x| x.0).collect::<Vec<_>>();
    assert_eq!(ids(&c.by_flops), [xpbd, liu, admm]);
    assert_eq!(ids(&c.by_wall), [admm, liu, xpbd]);
    let expected = tau(&ids(&c.by_flops), &ids(&c.by_wall));
    assert_eq!(c.tau, Some(expected));
    assert_eq!(expected, -1.0);
    assert_eq!(c.reversed, [(xpbd, admm), (liu, admm)]);
    // ADMM's batch means spread to twice its least: its slowest (2e-3 s) no longer beats
    // XPBD's or Liu's least by a tie, so neither pair is reversed (a rule reading the least
    // batch mean alone keeps both, as above).
    let mut spread = rows.clone();
    spread[2].wall_spread = 1.0;
    assert_eq!(compare(&spread, case, 0.1, limit).reversed, []);
    // An explicit baseline counts only within its margin: symplectic Euler at dt = 1e-3 s
    // is cheapest in both costs when its limit (RK4's over √2) is 1.2e-3 s (83 %), and left
    // out when it is 1.05e-3 s (95 %).
    let mut explicit = rows.clone();
    explicit.push(row(SolverId::SymplecticEuler, 1e-3, 1e-7, 10.0, 0.05));
    let first = |rk4: f64| compare(&explicit, case, 0.1, rk4).by_flops[0].0;
    assert_eq!(
        first(1.2e-3 * std::f64::consts::SQRT_2),
        SolverId::SymplecticEuler
    );
    assert_eq!(first(1.05e-3 * std::f64::consts::SQRT_2), xpbd);
    // The summary reads the rankings it recomputes: τ = −1 with three solvers, two pairs.
    let timing = WallTiming::new(rows.clone(), machine()).unwrap();
    let text = summary(&timing);
    assert!(text.contains("is -1.00 to -1.00, and 2 pairs"), "{text}");
    assert!(text.contains("the wall time reorders"), "{text}");
    let mut agreeing = timing.clone();
    agreeing.rows[1].wall_s = 2.5e-3;
    agreeing.rows[2].wall_s = 3e-3;
    let text = summary(&agreeing);
    assert!(text.contains("is 1.00 to 1.00, and 0 pairs"), "{text}");
    assert!(text.contains("nearly as the wall time does"), "{text}");
    let at_one_percent = compare(&rows, case, 0.01, limit);
    let costs = |r: &[(SolverId, &WallRow)], cost: Cost| {
        r.iter().map(|x| (x.0, cost.of(x.1))).collect::<Vec<_>>()
    };
    assert_eq!(
        costs(&at_one_percent.by_flops, Cost::Flops),
        [(admm, 500.0)]
    );
    assert_eq!(costs(&at_one_percent.by_wall, Cost::Wall), [(admm, 8e-3)]);
    assert_eq!(at_one_percent.tau, None);
    // Wall time per flop: the sums' ratio, ns.
    let admm_ns = (1.0e-3 + 1e-6 + 9e-3 + 8e-3) / (400.0 + 1.0 + 500.0 + 900.0) * 1e9;
    assert!((ns_per_flop(&rows, case, admm).unwrap() - admm_ns).abs() < 1e-6 * admm_ns);
    let (least, largest) = ns_per_flop_range(&rows, case).unwrap();
    assert_eq!((least.0, largest.0), (liu, xpbd));
    assert_eq!(ns_per_flop(&rows, Case::ALL[1], admm), None);
}

/// Every configuration of the benchmark has its own key columns: a dimension the key misses
/// would give two configurations one row.
#[test]
fn every_configuration_has_its_own_key() {
    let time = RunTime {
        wall_s: 1.0,
        cpu_s: 1.0,
        wall_spread: 0.0,
    };
    for case in Case::ALL {
        let mut keys: Vec<String> = configurations(case)
            .iter()
            .map(|c| {
                let r = WallRow::new(c, time, 1.0, 1.0);
                format!(
                    "{:?}",
                    (
                        r.scene,
                        r.stiffness_n_per_m,
                        r.solver,
                        r.iterations,
                        r.integrator,
                        r.stopping,
                        r.dt_s
                    )
                )
            })
            .collect();
        let n = keys.len();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), n, "{}", case.label());
    }
}

fn machine() -> Machine {
    Machine {
        commit: "0123456789abcdef0123456789abcdef01234567".into(),
        uncommitted_changes: false,
        cpu: "AMD EPYC".into(),
        cores: 2,
        toolchain: "rustc 1.95.0".into(),
        measured_utc: "2026-12-01 20:57:14 UTC".into(),
        load_before: "1.00 1.00 1.00".into(),
        load_after: "1.00 1.00 1.00".into(),
        run_time_s: 400.0,
    }
}

/// The files read back strictly: what was written, None without the wall-time file, an error
/// naming the file and field for a bad value or a missing machine; the subsection says there is
/// no measurement, or quotes its commit and machine and links TIMING.md.
#[test]
fn the_measurement_reads_back_and_the_report_quotes_it() {
    let dir = std::env::temp_dir().join(format!("timing-read-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    assert_eq!(WallTiming::load(&dir).unwrap(), None);
    let md = section("12.7", None, &[]);
    assert!(
        md.starts_with("### 12.7 Costs in wall time")
            && md.contains("no `timing/benchmark_wall.csv`"),
        "{md}"
    );
    let rows = vec![
        row(SolverId::Xpbd, 0.1, 2.0e-3, 100.0, 0.05),
        row(SolverId::FastMassSpring, 0.1, 2.1e-3, 400.0, 0.08),
    ];
    std::fs::write(dir.join(WALL_CSV), rows_csv(&rows)).unwrap();
    let err = WallTiming::load(&dir).unwrap_err().to_string();
    assert!(err.contains(MACHINE_CSV), "{err}");
    std::fs::write(dir.join(MACHINE_CSV), rows_csv(&[machine()])).unwrap();
    let timing = WallTiming::load(&dir).unwrap().unwrap();
    assert_eq!(timing.rows, rows);
    assert_eq!(timing.machine, machine());
    let md = section("12.7", Some(&timing), &[]);
    for needle in [
        "commit `0123456789ab` on AMD EPYC, 2 cores, 2026-12-01 20:57:14 UTC",
        "](timing/TIMING.md)",
        "Of its 2 timed configurations, 0 are configurations of this report's benchmark",
        "a factor 3.8",
    ] {
        assert!(md.contains(needle), "{needle} not in {md}");
    }
    // The counts of residual-stopped points and of spreads above 20 % are read from the CSV
    // (`make timing` re-measures it). Negative case: a spread of exactly 20 % is not counted.
    assert!(
        md.contains("(2 at fixed iteration counts, 0 stopped at a residual)"),
        "{md}"
    );
    assert!(
        md.contains("; 0 of these times spread by more than 20 %"),
        "{md}"
    );
    let mut moved = rows.clone();
    moved[0].stopping = "residual 1e-6".into();
    moved[0].wall_spread = 0.2;
    moved[1].wall_spread = 0.3;
    std::fs::write(dir.join(WALL_CSV), rows_csv(&moved)).unwrap();
    let md = section("12.7", Some(&WallTiming::load(&dir).unwrap().unwrap()), &[]);
    assert!(
        md.contains("(1 at fixed iteration counts, 1 stopped at a residual)"),
        "{md}"
    );
    assert!(
        md.contains("; 1 of these times spread by more than 20 %"),
        "{md}"
    );
    let mut bad = rows.clone();
    bad[1].wall_s = -1.0;
    std::fs::write(dir.join(WALL_CSV), rows_csv(&bad)).unwrap();
    let err = WallTiming::load(&dir).unwrap_err().to_string();
    assert!(err.contains("record 2 wall_s"), "{err}");
    std::fs::write(dir.join(WALL_CSV), "scene,solver\nrope,xpbd\n").unwrap();
    assert!(WallTiming::load(&dir).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--quick`: the benchmark part alone, on the soft rope at its two largest time steps; every
/// file it writes reads back strictly with its columns, TIMING.md embeds the figure, has no
/// empty section and no internal issue number, and the figure passes the report's figure check.
#[test]
fn a_quick_run_writes_the_wall_time_files() {
    let dir = std::env::temp_dir().join(format!("timing-quick-{}", std::process::id()));
    let (code, out, err) = timing(&["--quick", "--out", dir.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let stem = stem(Case::ALL[0]);
    assert!(out.contains(&format!("{stem}.svg")), "{out}");
    let header = csv::Reader::from_path(dir.join(WALL_CSV))
        .unwrap()
        .headers()
        .unwrap()
        .clone();
    assert_eq!(
        header.iter().collect::<Vec<_>>(),
        [
            "scene",
            "stiffness_n_per_m",
            "solver",
            "iterations",
            "integrator",
            "stopping",
            "dt_s",
            "wall_s",
            "cpu_s",
            "wall_spread",
            "flagged",
            "flops",
            "physical_rel"
        ]
    );
    let timing = WallTiming::load(&dir).unwrap().unwrap();
    assert!(timing.rows.len() > 40, "{}", timing.rows.len());
    assert!(timing
        .rows
        .iter()
        .all(|r| r.scene == "rope" && r.dt_s >= 0.05));
    assert_eq!(
        timing.machine.cores,
        std::thread::available_parallelism().unwrap().get()
    );
    let md = std::fs::read_to_string(dir.join("TIMING.md")).unwrap();
    for needle in [
        format!("]({stem}.svg)"),
        "Kendall τ (flops, wall)".into(),
        "**A flop is not a flop.**".into(),
    ] {
        assert!(md.contains(&needle), "{needle} not in {md}");
    }
    assert!(
        !md.contains("NaN") && !md.to_lowercase().contains("issue"),
        "{md}"
    );
    let lines: Vec<&str> = md.lines().filter(|l| !l.trim().is_empty()).collect();
    for pair in lines.windows(2) {
        assert!(
            !(pair[0].starts_with('#') && pair[1].starts_with('#')),
            "an empty section: {pair:?}"
        );
    }
    assert!(
        !lines.last().unwrap().starts_with('#'),
        "an empty last section"
    );
    // The figure is cut at the exact motion's floor, which the binary computed from the case's
    // truth, as here.
    let truth = CaseTruth::compute(Case::ALL[0]).unwrap();
    let f = figure(
        &timing.rows,
        Case::ALL[0],
        Some(truth.halving_gap / truth.amplitude),
    )
    .unwrap();
    assert_eq!(
        std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap(),
        f.svg
    );
    assert_eq!(
        figure_check::problems(f.stem, &f.layout, &f.svg),
        Vec::<String>::new()
    );
    assert!(
        !dir.join("scaling.csv").exists(),
        "--quick runs no scaling study"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// `shared/docs/reliability-cases.md` [13]: `--out` settled before the measurements,
// the files written atomically and all or none, never through a symbolic link.

use sandbox::{exits_2_or_succeeds, in_mount_namespace, quoted, run_within};
use std::path::Path;
use std::time::Duration;

/// A quick run takes about a second.
const QUICK_RUN: Duration = Duration::from_secs(60);

/// What `timing` prints while it measures: absent when it refused before measuring.
const MEASURING: &str = "benchmark errors";

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("timing-i27-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// [13] A read-only `--out` (a read-only bind mount, in a private mount namespace) is refused
/// before anything is measured (exit 2).
#[test]
fn a_read_only_out_is_refused_before_measuring() {
    let dir = scratch("read-only");
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let script = format!(
        "mount --bind {out} {out} && mount -o remount,bind,ro {out} && exec {timing} --quick \
         --out {out}",
        out = quoted(&out),
        timing = quoted(Path::new(env!("CARGO_BIN_EXE_timing"))),
    );
    let Some(mut command) = in_mount_namespace(&script) else {
        return;
    };
    let output = run_within(&mut command, QUICK_RUN, "timing on a read-only --out");
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{err}");
    assert!(err.contains("--out") && err.contains("out"), "{err}");
    assert!(!err.contains(MEASURING), "it measured first: {err}");
}

/// [13] A full disk (a 12 KiB tmpfs) fails the run (exit 1, an I/O failure, not bad input)
/// and leaves the previous output whole: no file replaced, none truncated, nothing beside them.
#[test]
fn a_full_disk_leaves_the_previous_output_whole() {
    let dir = scratch("full-disk");
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let script = format!(
        "mount -t tmpfs -o size=12k none {out} && echo old > {out}/TIMING.md && \
         echo old > {out}/benchmark_wall.csv && {timing} --quick --out {out}; \
         echo \"status=$?\"; for f in {out}/* {out}/.[!.]*; do [ -e \"$f\" ] && \
         echo \"== $(basename \"$f\"): $(cat \"$f\")\"; done",
        out = quoted(&out),
        timing = quoted(Path::new(env!("CARGO_BIN_EXE_timing"))),
    );
    let Some(mut command) = in_mount_namespace(&script) else {
        return;
    };
    let output = run_within(&mut command, QUICK_RUN, "timing on a full disk");
    let (o, err) = (
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr),
    );
    assert!(o.contains("status=1"), "{o}\n{err}");
    assert!(err.contains("No space left on device"), "{err}");
    let listing: Vec<&str> = o.lines().filter(|l| l.starts_with("== ")).collect();
    assert_eq!(
        listing,
        ["== TIMING.md: old", "== benchmark_wall.csv: old"],
        "{o}"
    );
}

/// [13] A symbolic link named `TIMING.md` inside `--out` is refused before the measurements
/// (exit 2) and the file it points to is kept.
#[test]
fn a_symlinked_output_file_is_refused_and_its_target_kept() {
    let dir = scratch("symlink");
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(dir.join("notes.txt"), "my notes").unwrap();
    std::os::unix::fs::symlink("../notes.txt", out.join("TIMING.md")).unwrap();
    let output = run_within(
        Command::new(env!("CARGO_BIN_EXE_timing")).args([
            "--quick",
            "--out",
            out.to_str().unwrap(),
        ]),
        QUICK_RUN,
        "timing with a symlinked TIMING.md",
    );
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{err}");
    assert!(
        err.contains("TIMING.md") && err.contains("symbolic link"),
        "{err}"
    );
    assert!(!err.contains(MEASURING), "it measured first: {err}");
    assert_eq!(
        std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
        "my notes"
    );
    assert!(std::fs::symlink_metadata(out.join("TIMING.md"))
        .unwrap()
        .file_type()
        .is_symlink());
}

/// `timing --point` at its largest side and one past it, under a 4 GiB address-space limit: exit
/// 2 or success, never a signal (`tests/option_bounds.rs` does the same for `mss`'s options).
/// `--max-side` is not run at its maximum (320): that is the whole scaling study, minutes long,
/// and allocates no more than `--point ... 320`.
#[test]
fn the_point_option_at_its_maximum_exits_2_or_succeeds_under_4_gib() {
    let i64_max = i64::MAX.to_string();
    let timing = env!("CARGO_BIN_EXE_timing");
    exits_2_or_succeeds(timing, &["--point", "pbd", "320"]);
    exits_2_or_succeeds(timing, &["--point", "pbd", &i64_max]);
}

// Issue 48: `timing` against a concurrent report run, and options that mean what they say.

/// [4] `timing --out DIR` takes the lock `report` takes for the report directory holding DIR
/// (`report/timing` → `.report.lock`): with it held, timing is refused at once (exit 2) and
/// writes nothing, where it measured and wrote beside a report run replacing the directory.
/// In a directory of the user's own (no manifest) it locks DIR beside it, not the parent's
/// parent (where it once failed for want of permission).
#[test]
fn timing_waits_for_no_report_run_and_writes_nothing_while_one_holds_the_lock() {
    use rustix::fs::{flock, FlockOperation};
    let base = std::env::temp_dir().join(format!("timing-lock-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    std::fs::create_dir_all(base.join("report")).unwrap();
    // A report directory: it holds a report's manifest.
    std::fs::write(base.join("report/MANIFEST"), "").unwrap();
    let lock = std::fs::File::create(base.join(".report.lock")).unwrap();
    flock(&lock, FlockOperation::NonBlockingLockExclusive).unwrap();
    let out = base.join("report/timing");
    let (code, _, err) = timing(&["--quick", "--out", out.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(".report.lock"), "{err}");
    assert!(
        !out.exists(),
        "timing wrote {} under the lock",
        out.display()
    );
    drop(lock);
    // A directory of the user's own: its lock beside it, none in its parent's parent.
    std::fs::create_dir_all(base.join("mine")).unwrap();
    let mine = base.join("mine/t");
    let (code, _, err) = timing(&["--quick", "--out", mine.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(base.join("mine/.t.lock").exists());
    assert!(!base.join(".mine.lock").exists());
    std::fs::remove_dir_all(&base).unwrap();
}

/// [4] `--point` prints its row and writes no file, so `--out` beside it is refused (it was
/// ignored), and `--max-side`, the scaling study's largest sheet, is refused with `--quick`,
/// which runs no study (it was ignored too); `--help` says the benchmark runs whole whatever
/// `--max-side` is.
#[test]
fn point_and_quick_refuse_the_options_they_would_ignore() {
    let (code, _, err) = timing(&["--point", "fast_mass_spring", "10", "--out", "x"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--out") && err.contains("--point"), "{err}");
    let dir = std::env::temp_dir().join(format!("timing-quick-side-{}", std::process::id()));
    let (code, _, err) = timing(&[
        "--quick",
        "--max-side",
        "10",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--max-side") && err.contains("--quick"),
        "{err}"
    );
    assert!(!dir.exists());
    let (_, help, _) = timing(&["--help"]);
    assert!(
        help.split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
            .contains("the benchmark runs whole whatever it is"),
        "{help}"
    );
}

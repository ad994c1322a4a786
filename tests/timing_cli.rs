//! `make timing`'s binary: bad input is named before anything runs, and one point is measured
//! in its own process and printed as one row (the scaling study itself takes a minute: run by
//! `make timing`, not here). Its work-precision part in wall time: the selections against the
//! report's own in flops, on synthetic rows and on a part of the sweep, and the files of a
//! quick run (no time is asserted).

use mass_spring_solvers::registry::SolverId;
use mass_spring_solvers::report::work_precision_wall::*;
use mass_spring_solvers::work_precision::{
    self as wp, cheapest_by, most_accurate_within_by, pareto_front_by, sweep_of, sweep_points,
    Case, ErrorKind, Point, WallTime,
};
use std::process::Command;

mod figure_check;
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

/// A row of `case`: the configuration of `id` at `dt_s` with the given costs and error.
fn row(case: Case, id: SolverId, dt_s: f64, wall: f64, flops: f64, error: f64) -> Timed {
    let point: Point = sweep_points(case)
        .into_iter()
        .find(|p| p.spec.id == id && p.dt_s == dt_s)
        .expect("the sweep has the configuration");
    let time = WallTime {
        min: wall,
        max: wall,
        repeats: 5,
    };
    Timed {
        point,
        flops,
        physical_error: error,
        wall: time,
        cpu: time,
        batch: 1,
        iterations_mean: point.spec.iterations as f64,
    }
}

/// The cheapest by each cost is the minimum of that cost among the configurations that reach
/// the level; the front keeps only improvements; where the two costs pick different solvers the
/// section says so.
#[test]
fn the_wall_time_selections_are_the_minimum_of_their_cost() {
    let case = Case::ALL[0];
    let (xpbd, liu) = (SolverId::Xpbd, SolverId::FastMassSpring);
    let rows = vec![
        row(case, xpbd, 0.01, 5e-3, 500.0, 0.05),
        row(case, xpbd, 0.02, 3e-3, 300.0, 0.08),
        row(case, xpbd, 0.05, 1e-3, 100.0, 0.5),
        row(case, xpbd, 0.005, 9e-3, 900.0, 0.005),
        // Liu reaches 0.08 m dearer in flops than XPBD, cheaper in wall time.
        row(case, liu, 0.01, 2e-3, 400.0, 0.07),
        row(Case::ALL[1], xpbd, 0.1, 1e-9, 1.0, 1e-9),
    ];
    let pick = |id, cost, level| cheapest(&rows, case, id, cost, level).map(|r| r.point.dt_s);
    assert_eq!(pick(xpbd, Cost::Wall, 0.1), Some(0.02));
    assert_eq!(pick(xpbd, Cost::Wall, 0.06), Some(0.01));
    assert_eq!(pick(xpbd, Cost::Wall, 0.01), Some(0.005));
    assert_eq!(pick(xpbd, Cost::Wall, 1e-3), None);
    let ids = |r: Vec<(SolverId, f64)>| r.into_iter().map(|x| x.0).collect::<Vec<_>>();
    assert_eq!(ids(ranking(&rows, case, Cost::Wall, 0.08)), [liu, xpbd]);
    assert_eq!(ids(ranking(&rows, case, Cost::Flops, 0.08)), [xpbd, liu]);
    assert_eq!(ids(ranking(&rows, case, Cost::Flops, 0.01)), [xpbd]);
    let front: Vec<f64> = pareto_front_by(rows_of(&rows, case, xpbd), Timed::wall_s, Timed::error)
        .iter()
        .map(|r| r.wall_s())
        .collect();
    assert_eq!(front, [1e-3, 3e-3, 5e-3, 9e-3]);
    let best = |budget| most_accurate_within(&rows, case, Cost::Wall, budget).map(|r| r.point);
    assert_eq!(best(2.5e-3), Some(rows[4].point));
    assert_eq!(best(1e-4), None);
    assert_eq!(
        most_frequent_wall_winner(&rows, case),
        Some((vec![xpbd], 3, 3))
    );
    let md = case_section(&rows, case);
    assert!(
        md.contains(
            "≤ 0.1 m: 2 of 12 solvers reach it; the cheapest in wall time is `fast_mass_spring`"
        ),
        "{md}"
    );
    assert!(md.contains("they differ"), "{md}");
    // Liu's best, 0.07 m, is the error both reach: Liu cheaper in both costs there.
    assert_eq!(common_level(&rows, case), Some(0.07));
    assert!(
        md.contains("| `fast_mass_spring` | 0.002000 | 1 | 400.0 | 1 | dt = 0.01 s, 1 it. |"),
        "{md}"
    );
    assert!(md.contains("≤ 0.01 m: 1 of 12 solvers reach it"), "{md}");
    // Tuples: what the selections need is a cost and an error.
    let pairs = [
        (3.0, Some(0.1)),
        (1.0, None),
        (2.0, Some(0.1)),
        (4.0, Some(0.01)),
    ];
    let cost = |p: &(f64, Option<f64>)| p.0;
    let error = |p: &(f64, Option<f64>)| p.1;
    assert_eq!(cheapest_by(&pairs, cost, error, 0.1), Some(&pairs[2]));
    assert_eq!(
        most_accurate_within_by(&pairs, cost, error, 3.0),
        Some(&pairs[2])
    );
    assert_eq!(pareto_front_by(&pairs, cost, error), [&pairs[2], &pairs[3]]);
}

/// On a part of the real sweep, the selections by flops are the report's own
/// ([`wp::cheapest`], [`wp::pareto_front`]), at levels between the errors reached; the figure
/// of every solver passes the report's figure check.
#[test]
fn the_flops_selections_are_the_reports() {
    let case = Case::ALL[0];
    let points: Vec<Point> = sweep_points(case)
        .into_iter()
        .filter(|p| case.dts()[..3].contains(&p.dt_s))
        .collect();
    let (_, results) = sweep_of(&points, &|_, _| {}).unwrap();
    // Wall time falling with flops, so that the two costs disagree everywhere they can.
    let rows: Vec<Timed> = results
        .iter()
        .filter_map(|r| {
            let e = r.error(ErrorKind::Physical)?;
            let mut t = row(
                case,
                r.point.spec.id,
                r.point.dt_s,
                1.0 / r.flops,
                r.flops,
                e,
            );
            t.point = r.point;
            Some(t)
        })
        .collect();
    let mut errors: Vec<f64> = rows.iter().map(|r| r.physical_error).collect();
    errors.sort_by(f64::total_cmp);
    let mut compared = 0;
    for id in wp::sweep_solvers() {
        for level in [errors[errors.len() / 4], errors[errors.len() / 2]] {
            let ours = cheapest(&rows, case, id, Cost::Flops, level).map(|r| r.point);
            let theirs =
                wp::cheapest(&results, case, id, ErrorKind::Physical, level).map(|r| r.point);
            assert_eq!(ours, theirs, "{id} at {level} m");
            compared += usize::from(ours.is_some());
        }
        let ours: Vec<Point> = pareto_front_by(rows_of(&rows, case, id), |r| r.flops, Timed::error)
            .iter()
            .map(|r| r.point)
            .collect();
        let theirs: Vec<Point> = wp::pareto_front(&results, case, id, ErrorKind::Physical)
            .iter()
            .map(|r| r.point)
            .collect();
        assert_eq!(ours, theirs, "{id}");
    }
    assert!(compared >= 10, "{compared} levels reached");
    let f = figure(&rows, case).unwrap();
    assert_eq!(f.stem, "work_precision_rope_k1e3");
    assert_eq!(
        figure_check::problems(f.stem, &f.layout, &f.svg),
        Vec::<String>::new()
    );
}

/// `--quick`: the work-precision part alone, on the first case at its two largest time steps;
/// TIMING.md links the figure, the figure's CSV has its columns and each solver's front falls
/// in error as its wall time grows.
#[test]
fn a_quick_run_writes_the_wall_time_figure_and_tables() {
    let dir = std::env::temp_dir().join(format!("timing-quick-{}", std::process::id()));
    let (code, out, err) = timing(&["--quick", "--out", dir.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("work_precision_rope_k1e3.svg"), "{out}");
    let md = std::fs::read_to_string(dir.join("TIMING.md")).unwrap();
    for needle in [
        "](work_precision_rope_k1e3.svg)",
        "| solver | ≤ 0.1 m, wall | ≤ 0.1 m, flops |",
        "**The most accuracy per unit of wall time** on the rope, k = 1e3 N/m",
        "configurations' batch means spread by more than 20 %",
    ] {
        assert!(md.contains(needle), "{needle} not in {md}");
    }
    assert!(!md.contains("NaN"), "{md}");
    let svg = std::fs::read_to_string(dir.join("work_precision_rope_k1e3.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("wall seconds per simulated second"));
    let csv = std::fs::read_to_string(dir.join("work_precision_rope_k1e3.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(FIGURE_CSV_HEADER));
    let mut last: Option<(String, f64, f64)> = None;
    let mut solvers = 0;
    for line in lines {
        let c: Vec<&str> = line.split(',').collect();
        assert_eq!(c.len(), 10, "{line}");
        let (wall, error): (f64, f64) = (c[4].parse().unwrap(), c[9].parse().unwrap());
        assert!(
            c[1].is_empty() || c[1].parse::<f64>().unwrap() > 0.0,
            "{line}"
        );
        for i in [2, 3, 5, 6, 7, 8] {
            assert!(c[i].parse::<f64>().unwrap() >= 0.0, "{line}");
        }
        assert!(wall > 0.0 && error > 0.0, "{line}");
        match &last {
            Some((id, w, e)) if id == c[0] => assert!(wall >= *w && error < *e, "{line}"),
            _ => solvers += 1,
        }
        last = Some((c[0].to_string(), wall, error));
    }
    assert_eq!(solvers, wp::sweep_solvers().len());
    let wall_csv = std::fs::read_to_string(dir.join("work_precision_wall.csv")).unwrap();
    assert_eq!(wall_csv.lines().next(), Some(wp::WALL_CSV_HEADER));
    assert!(
        !dir.join("scaling.csv").exists(),
        "--quick runs no scaling study"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// Issue 27, `shared/docs/reliability-cases.md` [13]: `--out` settled before the measurements,
// the files written atomically and all or none, never through a symbolic link.

use sandbox::{in_mount_namespace, quoted, run_within};
use std::path::Path;
use std::time::Duration;

/// A quick run takes about a second.
const QUICK_RUN: Duration = Duration::from_secs(60);

/// What `timing` prints while it measures: absent when it refused before measuring.
const MEASURING: &str = "work-precision errors";

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
         echo old > {out}/work_precision_wall.csv && {timing} --quick --out {out}; \
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
        ["== TIMING.md: old", "== work_precision_wall.csv: old"],
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

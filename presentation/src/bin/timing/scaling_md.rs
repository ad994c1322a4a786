//! What TIMING.md and `scaling.svg` show of the sheet's scaling study ([`crate::scaling`]):
//! the points, the slopes, the figure, the bound of an iteration and the targets.

use crate::measure::{seconds, BATCH_SECONDS, REPEATS};
use crate::scaling::{
    solvers, Point, Scaling, BYTES_PER_FACTOR_ENTRY, DT, ITERATIONS, NEWTON_ITERATIONS, SIDES,
    STIFFNESS,
};
use mass_spring_report::benchmark::families::FAMILIES;
use mass_spring_report::benchmark::rows_csv;
use mass_spring_report::plot::{self, Axis, Chart, Panel, Series};
use mass_spring_report::style::{colour, family_marker, solver_line};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::solvers::registry::SolverId;
use std::fmt::Write as _;

/// Least-squares slope of log y against log x.
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|(x, y)| (x.ln(), y.ln())).collect();
    let k = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / k, b + y / k));
    let (sxy, sxx) = logs.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    Some(sxy / sxx)
}

/// Points from n = 40 up fit the slopes: the smallest sheets are dominated by fixed costs.
const FIT_FROM_SIDE: usize = 40;
/// `scaling.svg`: CPU time per node of an iteration (top row) and of the set-up (bottom row)
/// against the nodes, log-log, one small panel per family of solvers as in the report's
/// work-precision figures ([`FAMILIES`]), each solver in its colour, line and marker there. A
/// flat series is time in proportion to the nodes; a rising one, faster than the nodes.
pub fn figure(study: &Scaling) -> Result<String> {
    let measured = solvers();
    let mut rows: [Vec<Panel>; 2] = [Vec::new(), Vec::new()];
    for (family, ids) in FAMILIES {
        let mut iteration = Panel::new(
            Axis::log("nodes"),
            Axis::log("CPU time per iteration per node (s)"),
        );
        let mut setup = Panel::new(
            Axis::log("nodes"),
            Axis::log("set-up CPU time per node (s)"),
        );
        iteration.heading = short_family(family).into();
        setup.heading = short_family(family).into();
        for &id in ids {
            if !measured.iter().any(|s| s.id == id) {
                continue;
            }
            let mine: Vec<&Point> = study
                .points
                .iter()
                .filter(|p| p.solver == id.id())
                .collect();
            if mine.is_empty() {
                continue;
            }
            let styled = |label: &str, per_node: fn(&Point) -> f64| {
                let points = mine
                    .iter()
                    .map(|p| (p.nodes as f64, per_node(p) / p.nodes as f64))
                    .collect();
                Series::line(label, points, colour(id, 0))
                    .with_line(solver_line(id))
                    .with_marker(family_marker(id), true)
            };
            // One legend per family, under the set-up panels.
            iteration.series.push(styled("", |p| p.iteration_cpu_s));
            setup
                .series
                .push(styled(id.display_name(), |p| p.setup_cpu_s));
        }
        rows[0].push(iteration);
        rows[1].push(setup);
    }
    // Each row on one range of whole decades, so that the families compare across a row.
    for row in &mut rows {
        let values = row
            .iter()
            .flat_map(|p| p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1)));
        let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), y| {
            (lo.min(y), hi.max(y))
        });
        if lo.is_finite() && lo > 0.0 {
            let decades = (
                10f64.powf(lo.log10().floor()),
                10f64.powf(hi.log10().ceil()),
            );
            for panel in row.iter_mut() {
                panel.y.range = Some(decades);
            }
        }
    }
    let [iteration, setup] = rows;
    let panels: Vec<Panel> = iteration.into_iter().chain(setup).collect();
    let mut chart = Chart::new(plot::FULL_WIDTH_MM, 190.0, panels);
    chart.columns = FAMILIES.len();
    Ok(plot::layout(&chart)?.svg())
}

/// A family's name short enough for a third of the page.
fn short_family(family: &str) -> &str {
    match family {
        "accelerated Projective Dynamics" => "accelerated PD",
        "substeps and vertex descent" => "substeps and VBD",
        other => other,
    }
}

/// TIMING.md's sections of the scaling study: the points, the slopes, the figure, the bound of
/// an iteration and the targets.
pub fn scaling_md(study: &Scaling, figure: usize) -> String {
    let points = &study.points;
    let mut md = String::new();
    let w = &mut md;
    let _ = writeln!(w, "## Scaling on the sheet\n");
    let _ = writeln!(
        w,
        "The sheet of `docs/sheet-scene.md` at k = {STIFFNESS:e} N/m, Δt = {DT} s, for n = {} \
         nodes per side; {ITERATIONS} iterations per step for every iterative solver, \
         {NEWTON_ITERATIONS} Newton iterations for Backward Euler; every point in its own \
         process. Times are per call, the least of repeated batch means (each batch at least \
         {:.0} ms), in the thread's CPU time (the machine is shared: wall times, in \
         [`scaling.csv`](scaling.csv), are inflated by the load); the spread is the largest \
         wall-time batch mean over the least. One core: no solver runs in parallel. Figure \
         {figure} draws the times against the nodes.\n",
        SIDES.map(|n| n.to_string()).join(", "),
        BATCH_SECONDS * 1e3
    );
    let _ = writeln!(
        w,
        "| solver | n | nodes | springs | factor nnz | set-up | local | global | iteration | step | spread | peak memory |"
    );
    let _ = writeln!(
        w,
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for p in points {
        let name = SolverId::from_id(&p.solver).map_or("?", |s| s.display_name());
        let _ = writeln!(
            w,
            "| {name} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} | {} MiB |",
            p.n,
            p.nodes,
            p.springs,
            p.factor_nnz.map_or("–".into(), |v| v.to_string()),
            seconds(p.setup_cpu_s),
            p.local_cpu_s.map_or("–".into(), seconds),
            p.global_cpu_s.map_or("–".into(), seconds),
            seconds(p.iteration_cpu_s),
            seconds(p.step_cpu_s),
            p.spread(),
            p.peak_bytes >> 20
        );
    }
    let _ = writeln!(
        w,
        "\nFactor non-zeros: faer's simplicial Cholesky of the n²×n² matrix (one factor, the three \
         coordinates solved together as three right-hand sides by `SparseCholesky::solve_three`) \
         after its default fill-reducing ordering (approximate minimum degree); up to n = 15 the \
         matrix's half-bandwidth n + 1 is at most 16 and the banded LDLᵀ factors it instead. \
         Backward Euler's is the 3n²×3n² Newton matrix, simplicial or supernodal as faer \
         chooses. Set-up: building the solver (matrix, symbolic analysis, factorisation); \
         Backward Euler refactors in every Newton iteration, inside its step.\n"
    );
    let _ = writeln!(w, "### Slopes\n");
    let _ = writeln!(
        w,
        "![Figure {figure}](scaling.svg)\n\n*Figure {figure}. CPU time per node of an iteration \
         (top) and of the set-up (bottom) against the nodes of the sheet, one panel per family \
         of solvers as in the report's work-precision figures: a flat series is time in \
         proportion to the nodes, a rising one grows faster (its slope is the table's less \
         1).* Least-squares slopes of log CPU time against log nodes, n ≥ {FIT_FROM_SIDE}:\n"
    );
    let _ = writeln!(w, "| solver | per iteration | set-up | step |");
    let _ = writeln!(w, "|---|---:|---:|---:|");
    for solver in &solvers() {
        let fit = |f: fn(&Point) -> f64| {
            let xy: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.solver == solver.id.id() && p.n >= FIT_FROM_SIDE)
                .map(|p| (p.nodes as f64, f(p)))
                .collect();
            slope(&xy).map_or("–".into(), |s| format!("{s:.2}"))
        };
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} |",
            solver.id.display_name(),
            fit(|p| p.iteration_cpu_s),
            fit(|p| p.setup_cpu_s),
            fit(|p| p.step_cpu_s)
        );
    }
    md += &bound_md(study);
    md += &targets_md(study);
    md
}

/// The bound of a Liu and an ADMM iteration against their measured time, size by size.
fn bound_md(study: &Scaling) -> String {
    let mut md = String::new();
    let w = &mut md;
    let _ = writeln!(w, "\n### The bound of an iteration\n");
    let _ = writeln!(
        w,
        "Global step: the two triangular solves stream the factor once each, the three \
         coordinates in one pass: 2 × {BYTES_PER_FACTOR_ENTRY} × nnz bytes (a value and a 32-bit \
         row per entry), at the read bandwidth measured on a buffer of that size \
         ([`bandwidth.csv`](bandwidth.csv): eight-lane sums, best of {REPEATS}); and each entry \
         of each pass multiplies a node's four lanes (x, y, z and a padding lane, one AVX2 vector \
         where the CPU has it) and adds them, {:.2} ns per entry measured (eight independent \
         sums over an in-cache array, no fused multiply-add): the global floor is the longer of \
         the two. Local step: a square root and a division per spring, {:.2} ns per spring \
         measured (`l0 / q.sqrt()` over an in-cache array). The bound is the sum of the two \
         floors; the ratio is the measured CPU time over it. What the floors leave out: each \
         entry's load of a node at an index that wanders over the right-hand sides in the \
         fill-reducing order (a gather the out-of-order core overlaps only in part), and the \
         right-hand side's assembly: Liu's in its local step (the same pass over the springs, \
         its nodes kept in the solve's order), ADMM-PD's in its global step with the \
         permutations in and out of that order. The iteration and the local step are timed, \
         the global step is their difference. The column \"ns per entry\" is the measured \
         global step over 2 × nnz.\n",
        study.multiply_add * 1e9,
        study.sqrt_div * 1e9
    );
    let _ = writeln!(
        w,
        "| n | factor MiB | read bandwidth | global floor | local floor | bound | Liu iteration | ratio | ADMM iteration | ratio | Liu global, ns per entry |"
    );
    let _ = writeln!(
        w,
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for b in &study.bandwidth {
        let Some(liu) = study.point(SolverId::FastMassSpring, b.n) else {
            continue;
        };
        let Some((global, local)) = study.bound(liu) else {
            continue;
        };
        let total = global + local;
        let cell = |id| {
            study.point(id, b.n).map_or(("–".into(), "–".into()), |p| {
                (
                    seconds(p.iteration_cpu_s),
                    format!("{:.1}", p.iteration_cpu_s / total),
                )
            })
        };
        let (l, lr) = cell(SolverId::FastMassSpring);
        let (a, ar) = cell(SolverId::AdmmPd);
        let _ = writeln!(
            w,
            "| {} | {:.2} | {:.1} GB/s | {} | {} | {} | {l} | {lr} | {a} | {ar} | {:.2} |",
            b.n,
            b.factor_bytes as f64 / (1 << 20) as f64,
            b.read_bandwidth_bytes_per_s / 1e9,
            seconds(global),
            seconds(local),
            seconds(total),
            liu.global_cpu_s.unwrap_or(f64::NAN) * 1e9 / (2.0 * liu.factor_nnz.unwrap_or(0) as f64)
        );
    }
    md
}

/// The study's targets: a Liu or ADMM iteration on the 100 × 100 sheet within
/// max(0.5 ms, 1.5 × its bound), a step of 320 × 320 under 1 s and 2 GB.
fn targets_md(study: &Scaling) -> String {
    let mut md = String::new();
    let w = &mut md;
    let _ = writeln!(
        w,
        "\n### Targets\n\nSet when the study was planned: a Liu or ADMM iteration on the 100 × 100 \
         sheet within max(0.5 ms, 1.5 × its bound); a step of {ITERATIONS} iterations on the \
         320 × 320 sheet (102,400 nodes) under 1 s of CPU and 2 GB.\n"
    );
    for id in [SolverId::FastMassSpring, SolverId::AdmmPd] {
        let name = id.display_name();
        if let Some(p) = study.point(id, 100) {
            let bound = study.bound(p).map_or(f64::NAN, |(g, l)| g + l);
            let limit = (0.5e-3_f64).max(1.5 * bound);
            let _ = writeln!(
                w,
                "- {name}, 100 × 100: one iteration {} CPU (local {}, global {}); bound {}; \
                 target ≤ {}: {}.",
                seconds(p.iteration_cpu_s),
                p.local_cpu_s.map_or("–".into(), seconds),
                p.global_cpu_s.map_or("–".into(), seconds),
                seconds(bound),
                seconds(limit),
                if p.iteration_cpu_s <= limit {
                    "met"
                } else {
                    "missed"
                }
            );
        }
        if let Some(p) = study.point(id, 320) {
            let _ = writeln!(
                w,
                "- {name}, 320 × 320: a step {} CPU ({} wall), peak memory {} MiB: {}.",
                seconds(p.step_cpu_s),
                seconds(p.step_s),
                p.peak_bytes >> 20,
                if p.step_cpu_s < 1.0 && p.peak_bytes < 2_000_000_000 {
                    "met"
                } else {
                    "missed"
                }
            );
        }
    }
    if let Some(p) = study.point(SolverId::BackwardEuler, 320) {
        let _ = writeln!(
            w,
            "- Backward Euler, 320 × 320: a step of {NEWTON_ITERATIONS} Newton iterations {} CPU, \
             peak memory {} MiB (measured, not targeted).",
            seconds(p.step_cpu_s),
            p.peak_bytes >> 20
        );
    }
    md
}

/// The files of the scaling study: `scaling.csv`, `bandwidth.csv` and `scaling.svg`.
pub fn files(study: &Scaling) -> Result<Vec<(String, String)>> {
    Ok(vec![
        ("scaling.csv".into(), rows_csv(&study.points)),
        ("bandwidth.csv".into(), rows_csv(&study.bandwidth)),
        ("scaling.svg".into(), figure(study)?),
    ])
}

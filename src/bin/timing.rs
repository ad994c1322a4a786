//! `make timing`: how each solver's cost grows with the sheet (issue 13 step 4,
//! `docs/sheet-scene.md`, "The family for scaling").
//!
//! For n = 10 to 320 nodes per side at k = 1e6 N/m and every solver of [`solvers`] (the registry's): the set-up
//! (building the solver: for Liu 2013 and ADMM-PD the matrix, its symbolic analysis and its
//! factorisation), the time per iteration (local and global step apart for Liu and ADMM), a
//! whole step, the non-zeros of the factor and the process's peak memory. Each point runs in a
//! child process (this binary with `--point SOLVER N`) so that its peak memory (`VmHWM`) is its
//! own. Every time is the minimum over repeats, with the spread (largest over smallest) beside
//! it, in wall time and in the thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`): the machine is
//! shared, and the CPU time is the figure to judge by.
//!
//! The bound of an iteration: the global step streams the factor twice (forward and backward
//! substitution, the three coordinates in one pass), $`2 \cdot 8\,\mathrm{nnz}`$ bytes of values at
//! least, against the read bandwidth measured here on a buffer of the factor's size; the local
//! step does a square root and a division per spring, against their measured throughput.
//!
//! Then the configurations of the report's work-precision chapter (issue 14,
//! [`mass_spring_solvers::work_precision`]): run once in parallel for their errors, then each
//! timed over its window on this thread, the least of [`WALL_REPEATS`] batch means (each batch
//! at least [`BATCH_SECONDS`]) per simulated second, against its counted flops; the diagrams,
//! the cheapest configuration per error level and the most accurate within wall-time budgets
//! ([`mass_spring_solvers::report::work_precision_wall`]).
//!
//! Writes `report/timing/` (or `--out DIR`): `TIMING.md`, `scaling.csv`, `bandwidth.csv`,
//! `scaling.svg`, `work_precision_wall.csv`, `work_precision_<case>.svg` and `.csv`, with the
//! machine, the toolchain and the commit. Every output file is checked and opened before the
//! measurements ([`OutputFile`]: a symbolic link among them is refused, a directory this user
//! may not write too) and replaced atomically after them, all or none: a full disk leaves the
//! previous files whole. Exit status 2 for bad input (found before anything is measured), 1
//! for a failure after. Outside the byte-identical report: times differ from
//! run to run. `--quick` skips the scaling study and times the work-precision configurations
//! of the first case at its two largest time steps only (a second; for the tests).

use clap::Parser;
use mass_spring_solvers::admm::AdmmPd;
use mass_spring_solvers::backward_euler::BackwardEuler;
use mass_spring_solvers::beyond::kendall_tau;
use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::fast_mass_spring::FastMassSpring;
use mass_spring_solvers::linear::{SymmetricMatrix, BANDED_MAX_BANDWIDTH};
use mass_spring_solvers::output_file::{Links, OutputFile};
use mass_spring_solvers::registry::{Builder, SolverId, SolverSpec};
use mass_spring_solvers::report::figures::{colour, solver_line};
use mass_spring_solvers::report::plot::{self, Axis, Chart, LegendPlace, Marker, Panel, Series};
use mass_spring_solvers::report::work_precision::stem;
use mass_spring_solvers::report::work_precision_wall::{
    self as wall_figures, case_section, rows_of, Timed,
};
use mass_spring_solvers::scene::SheetParams;
use mass_spring_solvers::work_precision::{
    sample_trajectory, sweep_of, sweep_points, sweep_solvers, wall_csv, Case, ErrorKind,
    Point as Configuration, PointResult, WallTime, WALL_REPEATS, WALL_SPREAD_FLAG, WINDOW_S,
};
use mass_spring_solvers::{MassSpringSystem, State, TimeStepper};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

/// Nodes per side of the family (100 to 102,400 nodes), with the 100 × 100 target.
const SIDES: [usize; 7] = [10, 20, 40, 80, 100, 160, 320];
/// Stiffness of every spring, N/m (`docs/sheet-scene.md`: k = 1e3 overstretches the finest sheets).
const STIFFNESS: f64 = 1e6;
/// Time step, s (the thesis's middle one; an iteration's cost does not depend on it).
const DT: f64 = 0.01;
/// Iterations of a step of Liu, ADMM, XPBD and PBD (the target: a step of 10).
const ITERATIONS: usize = 10;
/// Newton iterations of a Backward Euler step (the reference's 5).
const NEWTON_ITERATIONS: usize = 5;
/// Each timed batch runs at least this long, s, so that the clock's resolution is negligible.
const BATCH_SECONDS: f64 = 0.02;
/// Timed batches per measurement (the minimum is reported, the spread beside it).
const REPEATS: usize = 5;
/// Fewer batches for a measurement whose single run is longer than this, s.
const LONG_SECONDS: f64 = 0.5;

/// One solver of the study: how to build it, and whether its iterations split into a local and
/// a global step.
struct Solver {
    id: SolverId,
    kind: Kind,
}

enum Kind {
    /// Local/global iterations with one prefactored n×n matrix: Liu 2013 and ADMM-PD.
    Projective(fn(&MassSpringSystem) -> Result<Box<dyn LocalGlobal>>),
    /// Any other solver of the registry: one step of [`ITERATIONS`].
    Iterative(SolverSpec),
    /// Backward Euler: a step of [`NEWTON_ITERATIONS`] factorisations of the 3n×3n matrix.
    Newton,
}

/// Liu's and ADMM's iterations split in two, for timing each half.
trait LocalGlobal: TimeStepper {
    fn local(&mut self);
    fn global(&mut self);
}

impl LocalGlobal for FastMassSpring {
    fn local(&mut self) {
        self.local_step();
    }
    fn global(&mut self) {
        self.global_step();
    }
}

impl LocalGlobal for AdmmPd {
    fn local(&mut self) {
        self.local_step();
    }
    fn global(&mut self) {
        self.global_step();
    }
}

/// Every solver of the registry that runs springs and gravity with iterations (the damped
/// Backward Euler aside: Backward Euler's cost plus a damping term), in registry order.
/// Chebyshev takes a given spectral radius, 0.99: its estimate runs the plain iteration up to
/// 2000 times, which would dominate its set-up at every size.
fn solvers() -> Vec<Solver> {
    SolverId::ALL
        .into_iter()
        .filter(|&id| {
            let info = id.info();
            matches!(info.builder, Builder::Springs(_))
                && info.iteration.is_some()
                && id != SolverId::DampedBackwardEuler
        })
        .map(|id| Solver {
            id,
            kind: match id {
                SolverId::FastMassSpring => {
                    Kind::Projective(|s| Ok(Box::new(FastMassSpring::new(s, DT, ITERATIONS)?)))
                }
                SolverId::AdmmPd => {
                    Kind::Projective(|s| Ok(Box::new(AdmmPd::new(s, DT, ITERATIONS)?)))
                }
                SolverId::BackwardEuler => Kind::Newton,
                _ => {
                    let mut spec = SolverSpec::new(id, ITERATIONS);
                    spec.params.spectral_radius = Some(CHEBYSHEV_SPECTRAL_RADIUS);
                    Kind::Iterative(spec)
                }
            },
        })
        .collect()
}

/// The spectral radius Chebyshev is given here (see [`solvers`]).
const CHEBYSHEV_SPECTRAL_RADIUS: f64 = 0.99;

#[derive(Parser)]
#[command(about = "The sheet's scaling study: writes report/timing/ (TIMING.md, CSVs, figure)")]
struct Args {
    /// Output directory (default: report/timing of the crate).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Largest n to run (nodes per side), for a quick look.
    #[arg(long, default_value_t = 320)]
    max_side: usize,
    /// A quick look (and the tests): no scaling study, and the work-precision part on the
    /// first case at its two largest time steps only, in batches of 1 ms.
    #[arg(long)]
    quick: bool,
    /// Internal: measure one point (solver id, n) and print it as one line.
    #[arg(long, num_args = 2, value_names = ["SOLVER", "N"])]
    point: Option<Vec<String>>,
}

/// A time: the minimum over repeats and the spread, in wall and thread CPU seconds.
#[derive(Debug, Clone, Copy, Default)]
struct Time {
    wall: f64,
    cpu: f64,
    /// Largest over smallest wall time of the repeats.
    spread: f64,
    /// Largest over smallest CPU time of the repeats.
    cpu_spread: f64,
    repeats: usize,
    /// Calls per timed batch.
    batch: usize,
}

/// The CPU time of the calling thread, s (`CLOCK_THREAD_CPUTIME_ID`).
fn thread_cpu() -> f64 {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// Times `f`: batches of enough calls to last [`BATCH_SECONDS`], [`REPEATS`] of them (one
/// for a call longer than [`LONG_SECONDS`], three for one over a tenth of it); per call.
fn time(f: impl FnMut() -> Result<()>) -> Result<Time> {
    time_batches(f, BATCH_SECONDS, |once| {
        if once > LONG_SECONDS {
            1
        } else if once > 0.1 * LONG_SECONDS {
            3
        } else {
            REPEATS
        }
    })
}

/// Times `f` per call: one call first, then `repeats(its seconds)` batches of enough calls to
/// last `batch_seconds` (a scheduler's interruption spreads over a batch instead of
/// dominating one short call); the least batch mean, and the spreads of the batch means.
fn time_batches(
    mut f: impl FnMut() -> Result<()>,
    batch_seconds: f64,
    repeats: impl Fn(f64) -> usize,
) -> Result<Time> {
    let t = Instant::now();
    f()?;
    let once = t.elapsed().as_secs_f64();
    let batch = ((batch_seconds / once.max(1e-9)).ceil() as usize).clamp(1, 1 << 20);
    let repeats = repeats(once);
    let (mut walls, mut cpus) = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        let (c, t) = (thread_cpu(), Instant::now());
        for _ in 0..batch {
            f()?;
        }
        walls.push(t.elapsed().as_secs_f64() / batch as f64);
        cpus.push((thread_cpu() - c) / batch as f64);
    }
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    Ok(Time {
        wall: min(&walls),
        cpu: min(&cpus),
        spread: max(&walls) / min(&walls),
        cpu_spread: max(&cpus) / min(&cpus),
        repeats,
        batch,
    })
}

/// The process's peak resident memory so far, bytes (`VmHWM`).
fn peak_memory() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("VmHWM:"))?.to_string();
            line.split_whitespace().nth(1)?.parse::<u64>().ok()
        })
        .map_or(0, |kib| kib * 1024)
}

/// Non-zeros of the sparse Cholesky factor of a matrix with the pattern of `a`, as this crate
/// factors it ([`mass_spring_solvers::linear::SparseCholesky`]): faer's default fill-reducing
/// ordering, the simplicial factor for Liu's and ADMM's matrix (`simplicial`), faer's choice for
/// Backward Euler's (a supernodal factor's explicit zeros included: what a solve streams).
fn factor_nonzeros(a: &SymmetricMatrix, simplicial: bool) -> Result<usize> {
    use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, CholeskySymbolicParams};
    use faer::sparse::linalg::SupernodalThreshold;
    use faer::sparse::SymbolicSparseColMatRef;
    let mut col_ptr = vec![0];
    let mut row_idx = Vec::new();
    for i in 0..a.dim() {
        row_idx.extend(a.row_slots(i).map(|(_, j)| j));
        col_ptr.push(row_idx.len());
    }
    let pattern = SymbolicSparseColMatRef::new_checked(a.dim(), a.dim(), &col_ptr, None, &row_idx);
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: if simplicial {
            SupernodalThreshold::FORCE_SIMPLICIAL
        } else {
            SupernodalThreshold::default()
        },
        ..Default::default()
    };
    let symbolic =
        factorize_symbolic_cholesky(pattern, faer::Side::Lower, Default::default(), params)
            .map_err(|e| Error::Input(format!("symbolic analysis failed: {e:?}")))?;
    Ok(symbolic.len_val())
}

/// One measured point.
#[derive(Debug, Clone, Default)]
struct Point {
    solver: String,
    n: usize,
    nodes: usize,
    springs: usize,
    setup: Time,
    /// Local and global step of one iteration (Liu, ADMM).
    local: Option<Time>,
    global: Option<Time>,
    /// One iteration: local + global, or a step over its iterations.
    iteration: Time,
    step: Time,
    factor_nnz: Option<usize>,
    peak_bytes: u64,
}

fn measure(solver: &Solver, n: usize) -> Result<Point> {
    let system = SheetParams::spec(n, STIFFNESS).build()?;
    let mut point = Point {
        solver: solver.id.id().into(),
        n,
        nodes: system.len(),
        springs: system.springs().len(),
        ..Point::default()
    };
    let pattern = |block| {
        let edges: Vec<_> = system.springs().iter().map(|s| (s.a, s.b)).collect();
        SymmetricMatrix::from_node_graph(system.len(), block, &edges)
    };
    let initial = system.initial_state();
    match &solver.kind {
        Kind::Projective(build) => {
            point.setup = time(|| build(&system).map(drop))?;
            let mut s = build(&system)?;
            let mut state = initial.clone();
            s.step(&mut state)?;
            point.step = time(|| {
                let mut state = initial.clone();
                s.step(&mut state)
            })?;
            point.local = Some(time(|| {
                s.local();
                Ok(())
            })?);
            point.global = Some(time(|| {
                s.global();
                Ok(())
            })?);
            let (l, g) = (point.local.unwrap(), point.global.unwrap());
            point.iteration = Time {
                wall: l.wall + g.wall,
                cpu: l.cpu + g.cpu,
                spread: l.spread.max(g.spread),
                cpu_spread: l.cpu_spread.max(g.cpu_spread),
                repeats: l.repeats.min(g.repeats),
                batch: l.batch.min(g.batch),
            };
            let a = pattern(1);
            point.factor_nnz = Some(match a.bandwidth() {
                // The banded LDLᵀ: n + p rows of p + 1 values.
                p if p <= BANDED_MAX_BANDWIDTH => (a.dim() + p) * (p + 1),
                _ => factor_nonzeros(&a, true)?,
            });
        }
        Kind::Iterative(spec) => {
            let build = || spec.build_send(&system, DT);
            point.setup = time(|| build().map(drop))?;
            let mut s = build()?;
            point.step = time(|| {
                let mut state = initial.clone();
                s.step(&mut state)
            })?;
            point.iteration = per_iteration(point.step, ITERATIONS);
        }
        Kind::Newton => {
            point.setup = time(|| BackwardEuler::new(&system, DT, NEWTON_ITERATIONS).map(drop))?;
            let mut s = BackwardEuler::new(&system, DT, NEWTON_ITERATIONS)?;
            point.step = time(|| {
                let mut state: State = initial.clone();
                s.step(&mut state)
            })?;
            point.iteration = per_iteration(point.step, NEWTON_ITERATIONS);
            point.factor_nnz = Some(factor_nonzeros(&pattern(3), false)?);
        }
    }
    point.peak_bytes = peak_memory();
    Ok(point)
}

fn per_iteration(step: Time, iterations: usize) -> Time {
    Time {
        wall: step.wall / iterations as f64,
        cpu: step.cpu / iterations as f64,
        ..step
    }
}

/// The fields of a point, one `key=value` per field, in [`COLUMNS`] order.
const COLUMNS: &str = "solver,n,nodes,springs,factor_nnz,setup_s,setup_cpu_s,setup_spread,\
local_s,local_cpu_s,local_spread,global_s,global_cpu_s,global_spread,iteration_s,\
iteration_cpu_s,step_s,step_cpu_s,step_spread,step_repeats,peak_bytes";

fn csv_row(p: &Point) -> String {
    let opt =
        |t: Option<Time>, f: fn(&Time) -> f64| t.map_or(String::new(), |t| format!("{:e}", f(&t)));
    format!(
        "{},{},{},{},{},{:e},{:e},{:.3},{},{},{},{},{},{},{:e},{:e},{:e},{:e},{:.3},{},{}",
        p.solver,
        p.n,
        p.nodes,
        p.springs,
        p.factor_nnz.map_or(String::new(), |v| v.to_string()),
        p.setup.wall,
        p.setup.cpu,
        p.setup.spread,
        opt(p.local, |t| t.wall),
        opt(p.local, |t| t.cpu),
        opt(p.local, |t| t.spread),
        opt(p.global, |t| t.wall),
        opt(p.global, |t| t.cpu),
        opt(p.global, |t| t.spread),
        p.iteration.wall,
        p.iteration.cpu,
        p.step.wall,
        p.step.cpu,
        p.step.spread,
        p.step.repeats,
        p.peak_bytes
    )
}

fn parse_row(line: &str) -> Option<Point> {
    let f: Vec<&str> = line.trim().split(',').collect();
    if f.len() != COLUMNS.split(',').count() {
        return None;
    }
    let num = |i: usize| f[i].parse::<f64>().ok();
    let time = |w: usize, c: usize, s: Option<usize>| {
        Some(Time {
            wall: num(w)?,
            cpu: num(c)?,
            spread: s.and_then(num).unwrap_or(f64::NAN),
            cpu_spread: f64::NAN,
            repeats: 0,
            batch: 0,
        })
    };
    Some(Point {
        solver: f[0].into(),
        n: f[1].parse().ok()?,
        nodes: f[2].parse().ok()?,
        springs: f[3].parse().ok()?,
        factor_nnz: f[4].parse().ok(),
        setup: time(5, 6, Some(7))?,
        local: time(8, 9, Some(10)),
        global: time(11, 12, Some(13)),
        iteration: time(14, 15, None)?,
        step: Time {
            repeats: f[19].parse().ok()?,
            ..time(16, 17, Some(18))?
        },
        peak_bytes: f[20].parse().ok()?,
    })
}

/// Read bandwidth of a buffer of `bytes`, B/s: the best of [`REPEATS`] batches of sums over it
/// in eight independent lanes (vectorised), each batch at least [`BATCH_SECONDS`].
fn read_bandwidth(bytes: usize) -> f64 {
    let buffer: Vec<f64> = (0..(bytes / 8).max(64)).map(|i| (i % 7) as f64).collect();
    let sum = |v: &[f64]| {
        let mut lanes = [0.0; 8];
        for chunk in v.chunks_exact(8) {
            for (l, x) in lanes.iter_mut().zip(chunk) {
                *l += x;
            }
        }
        lanes.iter().sum::<f64>()
    };
    let mut best = f64::INFINITY;
    let mut sink = 0.0;
    let once = {
        let t = Instant::now();
        sink += sum(&buffer);
        t.elapsed().as_secs_f64()
    };
    let batch = ((BATCH_SECONDS / once.max(1e-9)).ceil() as usize).clamp(1, 1 << 20);
    for _ in 0..REPEATS {
        let c = thread_cpu();
        for _ in 0..batch {
            sink += std::hint::black_box(sum(std::hint::black_box(&buffer)));
        }
        best = best.min((thread_cpu() - c) / batch as f64);
    }
    std::hint::black_box(sink);
    (buffer.len() * 8) as f64 / best
}

/// Throughput of the local step's arithmetic, s per spring: $`l_0/\sqrt{q}`$ over an in-cache
/// array, the square root and division that [`mass_spring_solvers::projective::project_on_spheres`]
/// does per spring (CPU time).
fn sqrt_div_seconds() -> f64 {
    let q: Vec<f64> = (0..4096).map(|i| 1.0 + i as f64 * 1e-3).collect();
    let mut out = vec![0.0; q.len()];
    let batch = 2000;
    let mut best = f64::INFINITY;
    for _ in 0..REPEATS {
        let c = thread_cpu();
        for _ in 0..batch {
            for (o, q) in out.iter_mut().zip(std::hint::black_box(&q)) {
                *o = 1.5 / q.sqrt();
            }
            std::hint::black_box(&mut out);
        }
        best = best.min((thread_cpu() - c) / (batch * q.len()) as f64);
    }
    best
}

fn git(args: &[&str], root: &Path) -> String {
    Command::new("git")
        .args(args)
        .current_dir(root)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into())
}

fn machine() -> (String, usize) {
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = info
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map_or("unknown".into(), |m| m.trim().to_string());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    (model, cores)
}

fn rustc_version() -> String {
    Command::new(std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into()))
        .arg("-V")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

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

fn figure(points: &[Point]) -> Result<String> {
    let mut iteration = Panel::new(Axis::log("nodes"), Axis::log("CPU time per iteration (s)"));
    let mut setup = Panel::new(Axis::log("nodes"), Axis::log("set-up CPU time (s)"));
    iteration.legend = LegendPlace::Below;
    setup.legend = LegendPlace::Below;
    let markers = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
        Marker::Circle,
    ];
    for (k, solver) in solvers().iter().enumerate() {
        let mine: Vec<&Point> = points
            .iter()
            .filter(|p| p.solver == solver.id.id())
            .collect();
        if mine.is_empty() {
            continue;
        }
        for (panel, value) in [
            (
                &mut iteration,
                (|p: &Point| p.iteration.cpu) as fn(&Point) -> f64,
            ),
            (&mut setup, |p: &Point| p.setup.cpu),
        ] {
            let xy: Vec<(f64, f64)> = mine.iter().map(|p| (p.nodes as f64, value(p))).collect();
            let fit: Vec<(f64, f64)> = mine
                .iter()
                .filter(|p| p.n >= FIT_FROM_SIDE)
                .map(|p| (p.nodes as f64, value(p)))
                .collect();
            let label = match slope(&fit) {
                Some(s) => format!("{} (slope {s:.2})", solver.id.abbreviation()),
                None => solver.id.abbreviation().to_string(),
            };
            panel.series.push(
                Series::line(label, xy, colour(solver.id, 0))
                    .with_line(solver_line(solver.id))
                    .with_marker(markers[k % markers.len()], true),
            );
        }
    }
    iteration.heading = "per iteration".into();
    setup.heading = "set-up".into();
    let chart = Chart::new(plot::FULL_WIDTH_MM, 95.0, vec![iteration, setup]);
    Ok(plot::layout(&chart)?.svg())
}

fn seconds(t: f64) -> String {
    if !t.is_finite() {
        "–".into()
    } else if t >= 1.0 {
        format!("{t:.2} s")
    } else if t >= 1e-3 {
        format!("{:.3} ms", t * 1e3)
    } else {
        format!("{:.2} µs", t * 1e6)
    }
}

fn run_child(exe: &Path, solver: &Solver, n: usize) -> Result<Point> {
    let out = Command::new(exe)
        .args(["--point", solver.id.id(), &n.to_string()])
        .output()
        .map_err(|e| Error::Input(format!("cannot run {}: {e}", exe.display())))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        return Err(Error::Input(format!(
            "{} at n = {n} failed: {}",
            solver.id.abbreviation(),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    stdout.lines().find_map(parse_row).ok_or_else(|| {
        Error::Input(format!(
            "{} at n = {n}: no result in {stdout:?}",
            solver.id.abbreviation()
        ))
    })
}

/// Why `timing` stops: bad input, found before anything is measured (exit 2), or a failure of
/// the measurements or of writing their files (exit 1).
enum Failure {
    Input(Error),
    Run(Error),
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Run(e)
    }
}

/// The largest n of the study, and of `--point`'s N.
const MAX_SIDE: usize = SIDES[SIDES.len() - 1];

/// The work-precision configurations to time, and the least length of a timed batch, s:
/// `--quick`, the first case at its two largest time steps in batches of 1 ms.
fn configurations(quick: bool) -> (Vec<Configuration>, f64) {
    if quick {
        let case = Case::ALL[0];
        let dts = &case.dts()[..2];
        let points = sweep_points(case)
            .into_iter()
            .filter(|p| dts.contains(&p.dt_s))
            .collect::<Vec<_>>();
        (points, 1e-3)
    } else {
        // Most configurations run their window in under a millisecond to a few, where one
        // interruption by the scheduler would be the measurement: batches, as the scaling's.
        let points = Case::ALL.into_iter().flat_map(sweep_points).collect();
        (points, BATCH_SECONDS)
    }
}

/// Opens every file of the output directory before the measurements (see the module
/// documentation), creating the directory if it is missing.
fn open_outputs(out: &Path, names: &[String]) -> Result<Vec<(String, OutputFile)>> {
    std::fs::create_dir_all(out)
        .map_err(|e| Error::Input(format!("cannot create {}: {e}", out.display())))?;
    names
        .iter()
        .map(|name| {
            Ok((
                name.clone(),
                OutputFile::open("--out", &out.join(name), Links::Refuse)?,
            ))
        })
        .collect()
}

fn run(args: Args) -> std::result::Result<String, Failure> {
    if let Some(point) = args.point {
        let all = solvers();
        let solver = all.iter().find(|s| s.id.id() == point[0]).ok_or_else(|| {
            let ids: Vec<&str> = all.iter().map(|s| s.id.id()).collect();
            Failure::Input(Error::invalid("--point SOLVER", &point[0], &ids.join(", ")))
        })?;
        let n: usize = point[1]
            .parse()
            .ok()
            .filter(|n| (3..=MAX_SIDE).contains(n))
            .ok_or_else(|| {
                Failure::Input(Error::invalid(
                    "--point N",
                    &point[1],
                    &format!("an integer from 3 to {MAX_SIDE}, the study's sizes"),
                ))
            })?;
        return Ok(csv_row(&measure(solver, n)?));
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = args.out.unwrap_or_else(|| root.join("report/timing"));
    let sides: Vec<usize> = SIDES.into_iter().filter(|&n| n <= args.max_side).collect();
    if sides.is_empty() {
        return Err(Failure::Input(Error::invalid(
            "--max-side",
            args.max_side,
            "an integer >= 10",
        )));
    }
    let (configurations, batch_seconds) = configurations(args.quick);
    let mut names = vec![
        "TIMING.md".to_string(),
        "work_precision_wall.csv".to_string(),
    ];
    for case in Case::ALL {
        if configurations.iter().any(|p| p.case == case) {
            names.push(format!("{}.svg", stem(case)));
            names.push(format!("{}.csv", stem(case)));
        }
    }
    if !args.quick {
        names.extend(["scaling.csv", "bandwidth.csv", "scaling.svg"].map(String::from));
    }
    let mut outputs = open_outputs(&out, &names).map_err(Failure::Input)?;
    let started = Instant::now();
    let load_before = load_average();
    let scaling = if args.quick {
        None
    } else {
        Some(scaling_study(&sides)?)
    };
    let (timed, diverged) = work_precision_wall(&configurations, batch_seconds)?;
    let load_after = load_average();
    let (model, cores) = machine();
    let commit = git(&["rev-parse", "HEAD"], &root);
    // Its own output aside: a run replaces report/timing/.
    let status = [
        "status",
        "--porcelain",
        "--untracked-files=no",
        "--",
        ".",
        ":!report/timing",
    ];
    let dirty = !git(&status, &root).is_empty();
    let context = Context {
        model,
        cores,
        toolchain: rustc_version(),
        commit: if dirty {
            format!("{commit} (with uncommitted changes)")
        } else {
            commit
        },
        load: format!("{load_before} before, {load_after} after"),
        seconds: started.elapsed().as_secs_f64(),
    };

    let mut files: Vec<(String, String)> = Vec::new();
    let md = match &scaling {
        Some(study) => timing_md(study, &context),
        None => format!(
            "# A quick look (`timing --quick`): no scaling study, one case\n\n{}",
            context_md(&context)
        ),
    };
    files.push((
        "TIMING.md".into(),
        md + &work_precision_md(&timed, &diverged, batch_seconds),
    ));
    let keys: Vec<(Configuration, f64, WallTime)> = timed
        .iter()
        .map(|r| (r.point, r.iterations_mean, r.wall))
        .collect();
    files.push(("work_precision_wall.csv".into(), wall_csv(&keys)));
    for case in Case::ALL {
        if timed.iter().any(|r| r.point.case == case) {
            let f = wall_figures::figure(&timed, case)?;
            files.push((format!("{}.svg", f.stem), f.svg));
            files.push((format!("{}.csv", f.stem), f.csv));
        }
    }
    if let Some(study) = &scaling {
        let mut csv = format!("{COLUMNS}\n");
        for p in &study.points {
            writeln!(csv, "{}", csv_row(p)).expect("String");
        }
        let mut bw_csv = String::from("n,factor_bytes,read_bandwidth_bytes_per_s\n");
        for (n, bytes, bw) in &study.bandwidth {
            writeln!(bw_csv, "{n},{bytes},{bw:e}").expect("String");
        }
        files.push(("scaling.csv".into(), csv));
        files.push(("bandwidth.csv".into(), bw_csv));
        files.push(("scaling.svg".into(), figure(&study.points)?));
    }
    // A file opened for a case none of whose configurations finished is not written: its
    // previous version stays.
    let mut written = Vec::new();
    for (name, text) in &files {
        let at = outputs.iter().position(|(n, _)| n == name).ok_or_else(|| {
            Error::Input(format!("{name} was not opened before the measurements"))
        })?;
        let (_, mut file) = outputs.swap_remove(at);
        file.writer()
            .write_all(text.as_bytes())
            .map_err(|e| Error::Input(format!("--out {}: {e}", out.join(name).display())))?;
        written.push(file);
    }
    OutputFile::finish_all(written)?;
    let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
    Ok(format!(
        "wrote {} to {} in {:.0} s",
        names.join(", "),
        out.display(),
        started.elapsed().as_secs_f64()
    ))
}

/// The sheet's scaling study: every point of `sides` × [`solvers`] in its own process, the
/// read bandwidth at each factor's size and the local step's arithmetic.
struct Scaling {
    points: Vec<Point>,
    bandwidth: Vec<(usize, usize, f64)>,
    sqrt_div: f64,
}

fn scaling_study(sides: &[usize]) -> Result<Scaling> {
    let exe = std::env::current_exe().map_err(|e| Error::Input(e.to_string()))?;
    let mut points = Vec::new();
    for &n in sides {
        for solver in &solvers() {
            let t = Instant::now();
            let p = run_child(&exe, solver, n)?;
            eprintln!(
                "timing: n = {n:>3} {:<15} iteration {:>10} (CPU), step {:>10}, peak {:>5} MiB  [{:.1} s]",
                solver.id.abbreviation(),
                seconds(p.iteration.cpu),
                seconds(p.step.cpu),
                p.peak_bytes >> 20,
                t.elapsed().as_secs_f64()
            );
            points.push(p);
        }
    }
    let sqrt_div = sqrt_div_seconds();
    let mut bandwidth = Vec::new();
    for p in points.iter().filter(|p| p.solver == "liu") {
        let bytes = BYTES_PER_FACTOR_ENTRY * p.factor_nnz.unwrap_or(0);
        bandwidth.push((p.n, bytes, read_bandwidth(bytes)));
    }
    eprintln!("timing: bandwidth and arithmetic measured");
    Ok(Scaling {
        points,
        bandwidth,
        sqrt_div,
    })
}

/// The work-precision configurations `points`: run once in parallel for their errors
/// ([`sweep_of`], as the report runs them), then each that finished its window timed on this
/// thread, [`WALL_REPEATS`] batches of at least `batch_seconds`, with progress. Returns the
/// timed configurations and those that did not finish.
fn work_precision_wall(
    points: &[Configuration],
    batch_seconds: f64,
) -> Result<(Vec<Timed>, Vec<PointResult>)> {
    let started = Instant::now();
    let (_, results) = sweep_of(points, &|done, total| {
        if done % 100 == 0 || done == total {
            eprintln!(
                "timing: work-precision errors {done}/{total}  [{:.0} s]",
                started.elapsed().as_secs_f64()
            );
        }
    })?;
    let (finished, diverged): (Vec<PointResult>, Vec<PointResult>) =
        results.into_iter().partition(|r| r.errors.is_ok());
    let started = Instant::now();
    let mut rows = Vec::with_capacity(finished.len());
    for (i, r) in finished.iter().enumerate() {
        let p = &r.point;
        let system = p.case.scene.system(p.case.stiffness)?;
        let run = || -> Result<()> {
            let mut solver = p.spec.build_send(&system, p.dt_s)?;
            std::hint::black_box(sample_trajectory(solver.as_mut(), system.initial_state())?);
            Ok(())
        };
        let t = time_batches(run, batch_seconds, |_| WALL_REPEATS)?;
        let per_simulated_second = |least: f64, spread: f64| WallTime {
            min: least / WINDOW_S,
            max: least * spread / WINDOW_S,
            repeats: t.repeats,
        };
        rows.push(Timed {
            point: *p,
            flops: r.flops,
            physical_error: r
                .error(ErrorKind::Physical)
                .expect("a finished run has its errors"),
            wall: per_simulated_second(t.wall, t.spread),
            cpu: per_simulated_second(t.cpu, t.cpu_spread),
            batch: t.batch,
            iterations_mean: r.iterations_mean(),
        });
        if (i + 1) % 50 == 0 || i + 1 == finished.len() {
            eprintln!(
                "timing: work-precision timed {}/{} configurations  [{:.0} s]",
                i + 1,
                finished.len(),
                started.elapsed().as_secs_f64()
            );
        }
    }
    Ok((rows, diverged))
}

/// TIMING.md's work-precision section: how the configurations were timed and how many spread,
/// per case each solver's configurations summed in counted flops and in wall time with the two
/// rankings, then per case ([`case_section`]) the work-precision figure in wall time, the
/// cheapest configuration at each error level and the most accurate within each budget.
fn work_precision_md(rows: &[Timed], diverged: &[PointResult], batch_seconds: f64) -> String {
    let mut md = String::new();
    let w = &mut md;
    let flagged: Vec<&Timed> = rows.iter().filter(|r| r.wall.flagged()).collect();
    let cpu_flagged = rows.iter().filter(|r| r.cpu.flagged()).count();
    let batched = rows.iter().filter(|r| r.batch > 1).count();
    let cases: Vec<Case> = Case::ALL
        .into_iter()
        .filter(|c| rows.iter().any(|r| r.point.case == *c))
        .collect();
    let _ = writeln!(
        w,
        "\n## Work-precision in wall-clock time (issue 14)\n\n\
         The configurations of the report's work-precision chapter (every solver, time step, \
         iteration count and tolerance on each case), run once in parallel for their errors (as the \
         report runs them); {} did not finish the window and are not timed. Each of the {} \
         that did is timed on this thread: one run, then {WALL_REPEATS} batches of as many \
         runs of the window (solver built and run, the errors not measured) as last at least \
         {:.0} ms ({batched} configurations needed more than one run per batch); the least \
         batch mean per simulated second is its wall time (`work_precision_wall.csv`, beside \
         the floating-point operations the report counts). {} configurations' batch means \
         spread by more than {:.0} % in wall time (flagged, listed at the end), {cpu_flagged} \
         in the thread's CPU time (the machine is shared: a batch that waited for the core \
         spreads the wall time, not the CPU time).\n",
        diverged.len(),
        rows.len(),
        batch_seconds * 1e3,
        flagged.len(),
        WALL_SPREAD_FLAG * 100.0
    );
    for &case in &cases {
        let totals: Vec<(SolverId, f64, f64)> = sweep_solvers()
            .into_iter()
            .map(|id| {
                rows_of(rows, case, id).fold((id, 0.0, 0.0), |(id, flops, wall), r| {
                    (id, flops + r.flops, wall + r.wall_s())
                })
            })
            .collect();
        let rank = |key: fn(&(SolverId, f64, f64)) -> f64| {
            let mut sorted = totals.clone();
            sorted.sort_by(|a, b| key(a).total_cmp(&key(b)));
            sorted.into_iter().map(|t| t.0).collect::<Vec<_>>()
        };
        let by_flops = rank(|t| t.1);
        let by_wall = rank(|t| t.2);
        let _ = writeln!(
            w,
            "**{}**: every timed configuration of each solver summed, ranked cheapest first \
             (Kendall τ between the two rankings: {}).\n",
            case.label(),
            kendall_tau(&by_flops, &by_wall).map_or("–".into(), |t| format!("{t:.2}"))
        );
        let _ = writeln!(
            w,
            "| solver | flops | rank by flops | wall s per simulated s | rank by wall | ns per flop |"
        );
        let _ = writeln!(w, "|---|---:|---:|---:|---:|---:|");
        for (id, flops, wall) in &totals {
            let position = |list: &[SolverId]| list.iter().position(|x| x == id).unwrap_or(0) + 1;
            let _ = writeln!(
                w,
                "| `{id}` | {flops:.3e} | {} | {wall:.3e} | {} | {:.2} |",
                position(&by_flops),
                position(&by_wall),
                wall * WINDOW_S / flops * 1e9
            );
        }
        let _ = writeln!(w);
    }
    let _ = writeln!(
        w,
        "## Work-precision diagrams and the cheapest configurations in wall time\n\n\
         Costs in wall seconds per simulated second (s/s, one core; 1 is real time) and in the \
         report's counted flops over the {} s window; errors are the report's physical error \
         (the per-node distance summed, at the worst sample of the window).\n",
        WINDOW_S
    );
    for &case in &cases {
        md += &case_section(rows, case);
    }
    let w = &mut md;
    if !flagged.is_empty() {
        let _ = writeln!(
            w,
            "Flagged (wall-time spread of the batch means above {:.0} %):\n",
            WALL_SPREAD_FLAG * 100.0
        );
        for r in flagged {
            let _ = writeln!(
                w,
                "- `{}` {} it., dt = {} s, {}: spread {:.0} % (CPU time {:.0} %; runs per batch: {})",
                r.point.spec.id,
                r.point.spec.iterations,
                r.point.dt_s,
                r.point.case.label(),
                r.wall.spread() * 100.0,
                r.cpu.spread() * 100.0,
                r.batch
            );
        }
    }
    md
}

struct Context {
    model: String,
    cores: usize,
    toolchain: String,
    commit: String,
    load: String,
    seconds: f64,
}

/// Bytes a triangular solve reads per stored entry of a simplicial factor: its value and its
/// 32-bit row (`SparseCholesky::solve_three`).
const BYTES_PER_FACTOR_ENTRY: usize = 12;

/// The bound of one Liu/ADMM iteration at point `p`: the factor streamed twice at the
/// bandwidth measured for its size, plus a square root and a division per spring.
fn bound(p: &Point, bandwidth: &[(usize, usize, f64)], sqrt_div: f64) -> Option<(f64, f64)> {
    let (_, bytes, bw) = bandwidth.iter().find(|(n, _, _)| *n == p.n)?;
    Some((2.0 * *bytes as f64 / bw, p.springs as f64 * sqrt_div))
}

/// The machine, the toolchain, the commit, the load and the run time.
fn context_md(c: &Context) -> String {
    format!(
        "- machine: {}, {} cores available\n- toolchain: {}\n- commit: {}\n\
         - load average (1, 5, 15 min): {}\n- run time: {:.0} s\n\n",
        c.model, c.cores, c.toolchain, c.commit, c.load, c.seconds
    )
}

fn timing_md(study: &Scaling, c: &Context) -> String {
    let Scaling {
        points,
        bandwidth,
        sqrt_div,
    } = study;
    let (bandwidth, sqrt_div) = (bandwidth.as_slice(), *sqrt_div);
    let mut md = String::new();
    let w = &mut md;
    let _ = writeln!(w, "# Scaling on the sheet (`make timing`)\n");
    let _ = writeln!(
        w,
        "The sheet of `docs/sheet-scene.md` at k = {STIFFNESS:e} N/m, Δt = {DT} s, for n = {} \
         nodes per side; {ITERATIONS} iterations per step for Liu 2013, ADMM-PD, XPBD and PBD, \
         {NEWTON_ITERATIONS} Newton iterations for Backward Euler. Written by `src/bin/timing.rs`; \
         every point in its own process.\n",
        SIDES.map(|n| n.to_string()).join(", ")
    );
    w.push_str(&context_md(c));
    let _ = writeln!(
        w,
        "Times are per call, the minimum over repeated batches (each at least {:.0} ms), in the \
         thread's CPU time (the machine is shared: wall times, in `scaling.csv`, are inflated by \
         the load); the spread is the largest wall time over the smallest. One core: no \
         solver runs in parallel.\n",
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
        let name = solvers()
            .into_iter()
            .find(|s| s.id.id() == p.solver)
            .map_or("?", |s| s.id.abbreviation());
        let _ = writeln!(
            w,
            "| {name} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} | {} MiB |",
            p.n,
            p.nodes,
            p.springs,
            p.factor_nnz.map_or("–".into(), |v| v.to_string()),
            seconds(p.setup.cpu),
            p.local.map_or("–".into(), |t| seconds(t.cpu)),
            p.global.map_or("–".into(), |t| seconds(t.cpu)),
            seconds(p.iteration.cpu),
            seconds(p.step.cpu),
            p.step.spread.max(p.iteration.spread),
            p.peak_bytes >> 20
        );
    }
    let _ = writeln!(
        w,
        "\nFactor non-zeros: faer's simplicial Cholesky of the n²×n² matrix (one factor, the three \
         coordinates solved together as three right-hand sides by `SparseCholesky::solve_three`) \
         after its default fill-reducing ordering (approximate minimum degree); up to n = 15 the \
         matrix's half-bandwidth n + 1 is at most 16 and the banded LDLᵀ factors it instead. \
         Backward Euler's is the 3n²×3n² Newton matrix, simplicial or supernodal as faer chooses. Set-up: building the solver (matrix, \
         symbolic analysis, factorisation); Backward Euler refactors in every Newton iteration, \
         inside its step.\n"
    );
    let _ = writeln!(w, "## Slopes\n");
    let _ = writeln!(
        w,
        "Least-squares slopes of log CPU time against log nodes, n ≥ {FIT_FROM_SIDE} \
         (`scaling.svg`):\n"
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
            solver.id.abbreviation(),
            fit(|p| p.iteration.cpu),
            fit(|p| p.setup.cpu),
            fit(|p| p.step.cpu)
        );
    }
    let _ = writeln!(w, "\n## The bound of an iteration\n");
    let _ = writeln!(
        w,
        "Global step: the two triangular solves stream the factor once each, the three \
         coordinates in one pass: 2 × 12 × nnz bytes (a value and a 32-bit row per entry), at the \
         read bandwidth measured on a buffer of that size (`bandwidth.csv`: eight-lane sums, best \
         of {REPEATS}). Local step: a square root and a division per spring, {:.2} ns per spring \
         measured (`l0 / q.sqrt()` over an in-cache array). The bound is their sum; the ratio is \
         the measured CPU time over it. The factor fits in the caches up to n = 160, so the \
         bandwidth is the caches' and the bound is not what limits: each entry of the factor is \
         a load of three coordinates at an index that wanders over the right-hand sides in the \
         fill-reducing order, three multiplications and three additions into partial sums \
         (scalar: the x86-64 baseline has no fused multiply-add and the build targets no more). \
         The forward substitution scatters each column of the factor into the rows below; the \
         backward one gathers each column into four partial sums per coordinate (`gather_three` \
         in `src/linear.rs`; with one running sum the additions chain: 0.70 ms against 0.65 ms at \
         n = 100). Gathering in the forward substitution too, from a copy of the factor by rows, \
         measured 0.61 ms at n = 100 but 3.0 ms against 2.0 ms at n = 160, its two copies of the \
         factor outgrowing the cache; faer's own solve took 1.6 ms at n = 100. The column \
         \"ns per entry\" is the measured global step over 2 × nnz.\n",
        sqrt_div * 1e9
    );
    let _ = writeln!(
        w,
        "| n | factor MiB | read bandwidth | global floor | local floor | bound | Liu iteration | ratio | ADMM iteration | ratio | Liu global, ns per entry |"
    );
    let _ = writeln!(
        w,
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for (n, bytes, bw) in bandwidth {
        let get = |id: &str| points.iter().find(|p| p.solver == id && p.n == *n);
        let Some(liu) = get("liu") else { continue };
        let Some((global, local)) = bound(liu, bandwidth, sqrt_div) else {
            continue;
        };
        let total = global + local;
        let cell = |id: &str| {
            get(id).map_or(("–".into(), "–".into()), |p| {
                (
                    seconds(p.iteration.cpu),
                    format!("{:.1}", p.iteration.cpu / total),
                )
            })
        };
        let (l, lr) = cell("liu");
        let (a, ar) = cell("admm");
        let _ = writeln!(
            w,
            "| {n} | {:.2} | {:.1} GB/s | {} | {} | {} | {l} | {lr} | {a} | {ar} | {:.2} |",
            *bytes as f64 / (1 << 20) as f64,
            bw / 1e9,
            seconds(global),
            seconds(local),
            seconds(total),
            liu.global.map_or(f64::NAN, |g| g.cpu) * 1e9
                / (2.0 * liu.factor_nnz.unwrap_or(0) as f64)
        );
    }
    let _ = writeln!(w, "\n## Targets (issue 13)\n");
    for (id, name) in [("liu", "Liu 2013"), ("admm", "ADMM-PD")] {
        if let Some(p) = points.iter().find(|p| p.solver == id && p.n == 100) {
            let bound = bound(p, bandwidth, sqrt_div).map_or(f64::NAN, |(g, l)| g + l);
            let limit = (0.5e-3_f64).max(1.5 * bound);
            let _ = writeln!(
                w,
                "- {name}, 100 × 100: one iteration {} CPU (local {}, global {}); bound {}; \
                 target ≤ max(0.5 ms, 1.5 × bound) = {}: {}.",
                seconds(p.iteration.cpu),
                p.local.map_or("–".into(), |t| seconds(t.cpu)),
                p.global.map_or("–".into(), |t| seconds(t.cpu)),
                seconds(bound),
                seconds(limit),
                if p.iteration.cpu <= limit {
                    "met"
                } else {
                    "missed"
                }
            );
        }
        if let Some(p) = points.iter().find(|p| p.solver == id && p.n == 320) {
            let _ = writeln!(
                w,
                "- {name}, n = 320 (102,400 nodes): a step of {ITERATIONS} iterations {} CPU \
                 ({} wall), peak memory {} MiB; target < 1 s and < 2 GB: {}.",
                seconds(p.step.cpu),
                seconds(p.step.wall),
                p.peak_bytes >> 20,
                if p.step.cpu < 1.0 && p.peak_bytes < 2_000_000_000 {
                    "met"
                } else {
                    "missed"
                }
            );
        }
    }
    if let Some(p) = points.iter().find(|p| p.solver == "be" && p.n == 320) {
        let _ = writeln!(
            w,
            "- Backward Euler, n = 320: a step of {NEWTON_ITERATIONS} Newton iterations {} CPU, \
             peak memory {} MiB (measured, not targeted).",
            seconds(p.step.cpu),
            p.peak_bytes >> 20
        );
    }
    md
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(message) => {
            println!("{message}");
            ExitCode::SUCCESS
        }
        Err(Failure::Input(e)) => {
            eprintln!("timing: {e}");
            ExitCode::from(2)
        }
        Err(Failure::Run(e)) => {
            eprintln!("timing: {e}");
            ExitCode::FAILURE
        }
    }
}

//! The sheet's scaling study (`docs/sheet-scene.md`, "The family for scaling"): for n = 10 to
//! 320 nodes per side at k = 1e6 N/m and every solver of [`solvers`] (the registry's), the
//! set-up (building the solver: for Liu 2013 and ADMM-PD the matrix, its symbolic analysis and
//! its factorisation), the time per iteration (for Liu and ADMM the iteration and its local
//! step timed, the global step their difference; Liu's local step assembles the global step's
//! right-hand side too, in the same pass over the springs),
//! a whole step, the non-zeros of the factor and the process's peak memory. Each point runs in
//! a child process (this binary with `--point SOLVER N`) so that its peak memory (`VmHWM`) is
//! its own.
//!
//! The bound of an iteration: the global step streams the factor twice (forward and backward
//! substitution, the three coordinates in one pass), $`2 \cdot 12\,\mathrm{nnz}`$ bytes at
//! least, against the read bandwidth measured here on a buffer of the factor's size, and does a
//! multiplication and an addition of a node's four lanes per entry and pass, $`2\,\mathrm{nnz}`$
//! of them against their measured throughput: the longer of the two; the local step does a
//! square root and a division per spring, against their measured throughput.

use crate::measure::{seconds, thread_cpu, time_batches, Time, BATCH_SECONDS, REPEATS};
use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::model::linear::{SymmetricMatrix, BANDED_MAX_BANDWIDTH};
use mass_spring_solvers::model::scene::SheetParams;
use mass_spring_solvers::platform::floors;
use mass_spring_solvers::solvers::admm::AdmmPd;
use mass_spring_solvers::solvers::backward_euler::BackwardEuler;
use mass_spring_solvers::solvers::fast_mass_spring::FastMassSpring;
use mass_spring_solvers::solvers::registry::{Builder, SolverId, SolverSpec};
use mass_spring_solvers::{MassSpringSystem, State, TimeStepper};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Nodes per side of the family (100 to 102,400 nodes), with the 100 × 100 sheet of the targets.
pub const SIDES: [usize; 7] = [10, 20, 40, 80, 100, 160, 320];
/// Stiffness of every spring, N/m (`docs/sheet-scene.md`: k = 1e3 overstretches the finest sheets).
pub const STIFFNESS: f64 = 1e6;
/// Time step, s (the thesis's middle one; an iteration's cost does not depend on it).
pub const DT: f64 = 0.01;
/// Iterations of a step of Liu, ADMM, XPBD and PBD (the targets' step of 10).
pub const ITERATIONS: usize = 10;
/// Newton iterations of a Backward Euler step (the reference's 5).
pub const NEWTON_ITERATIONS: usize = 5;
/// Fewer batches for a measurement whose single run is longer than this, s.
const LONG_SECONDS: f64 = 0.5;

/// One solver of the study: how to build it, and whether its iterations split into a local and
/// a global step.
pub struct Solver {
    pub id: SolverId,
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
pub fn solvers() -> Vec<Solver> {
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

/// for a call longer than [`LONG_SECONDS`], three for one over a tenth of it); per call.
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
/// factors it ([`mass_spring_solvers::model::linear::SparseCholesky`]): faer's default fill-reducing
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

/// One measured point, a row of `scaling.csv`: times per call in wall and thread CPU seconds,
/// each the least batch mean, with the spread (largest over least batch mean) beside it.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Point {
    pub solver: String,
    pub n: usize,
    pub nodes: usize,
    pub springs: usize,
    /// Non-zeros of the factor (Liu, ADMM, Backward Euler).
    pub factor_nnz: Option<usize>,
    pub setup_s: f64,
    pub setup_cpu_s: f64,
    pub setup_spread: f64,
    /// The local and the global step of one iteration (Liu, ADMM).
    pub local_s: Option<f64>,
    pub local_cpu_s: Option<f64>,
    pub local_spread: Option<f64>,
    pub global_s: Option<f64>,
    pub global_cpu_s: Option<f64>,
    pub global_spread: Option<f64>,
    /// One iteration: local + global, or a step over its iterations.
    pub iteration_s: f64,
    pub iteration_cpu_s: f64,
    pub step_s: f64,
    pub step_cpu_s: f64,
    pub step_spread: f64,
    pub step_repeats: usize,
    pub peak_bytes: u64,
}

impl Point {
    /// The largest spread of its step and iteration's parts.
    pub fn spread(&self) -> f64 {
        [self.local_spread, self.global_spread]
            .into_iter()
            .flatten()
            .fold(self.step_spread, f64::max)
    }
}

/// A step of `solver` from `initial`, timed. The state is reset by two slice copies (a
/// `memcpy` each), not cloned: this crate is built unoptimised (`Cargo.toml`), and a clone's
/// element-by-element code took 3-5 µs of a 50 µs step of XPBD on the 10 × 10 sheet.
fn step_time<S: TimeStepper + ?Sized>(solver: &mut S, initial: &State) -> Result<Time> {
    let mut state = initial.clone();
    time(|| {
        state.x.copy_from_slice(&initial.x);
        state.v.copy_from_slice(&initial.v);
        solver.step(&mut state)
    })
}

/// Measures one point in this process.
pub fn measure(solver: &Solver, n: usize) -> Result<Point> {
    let system = SheetParams::spec(n, STIFFNESS).build()?;
    let pattern = |block| {
        let edges: Vec<_> = system.springs().iter().map(|s| (s.a, s.b)).collect();
        SymmetricMatrix::from_node_graph(system.len(), block, &edges)
    };
    let initial = system.initial_state();
    let (setup, step, parts, factor_nnz, iterations) = match &solver.kind {
        Kind::Projective(build) => {
            let setup = time(|| build(&system).map(drop))?;
            let mut s = build(&system)?;
            let mut state = initial.clone();
            s.step(&mut state)?;
            let step = step_time(s.as_mut(), &initial)?;
            // The iteration timed whole and its local step alone; the global step is the
            // difference. Liu's global step alone would solve the last solution again (its
            // solve overwrites the right-hand side its local step assembled) and grow it by up
            // to 1/m a call.
            let iteration = time(|| {
                s.local();
                s.global();
                Ok(())
            })?;
            let local = time(|| {
                s.local();
                Ok(())
            })?;
            let global = iteration.beyond(&local);
            let a = pattern(1);
            let nnz = match a.bandwidth() {
                // The banded LDLᵀ: n + p rows of p + 1 values.
                p if p <= BANDED_MAX_BANDWIDTH => (a.dim() + p) * (p + 1),
                _ => factor_nonzeros(&a, true)?,
            };
            (setup, step, Some((local, global)), Some(nnz), ITERATIONS)
        }
        Kind::Iterative(spec) => {
            let build = || spec.build_send(&system, DT);
            let setup = time(|| build().map(drop))?;
            let step = step_time(build()?.as_mut(), &initial)?;
            (setup, step, None, None, ITERATIONS)
        }
        Kind::Newton => {
            let build = || BackwardEuler::new(&system, DT, NEWTON_ITERATIONS);
            let setup = time(|| build().map(drop))?;
            let step = step_time(&mut build()?, &initial)?;
            let nnz = factor_nonzeros(&pattern(3), false)?;
            (setup, step, None, Some(nnz), NEWTON_ITERATIONS)
        }
    };
    let (iteration_s, iteration_cpu_s) = match parts {
        Some((l, g)) => (l.wall + g.wall, l.cpu + g.cpu),
        None => (step.wall / iterations as f64, step.cpu / iterations as f64),
    };
    let part =
        |f: fn(&Time) -> f64, which: usize| parts.map(|p| f(if which == 0 { &p.0 } else { &p.1 }));
    Ok(Point {
        solver: solver.id.id().into(),
        n,
        nodes: system.len(),
        springs: system.springs().len(),
        factor_nnz,
        setup_s: setup.wall,
        setup_cpu_s: setup.cpu,
        setup_spread: setup.spread,
        local_s: part(|t| t.wall, 0),
        local_cpu_s: part(|t| t.cpu, 0),
        local_spread: part(|t| t.spread, 0),
        global_s: part(|t| t.wall, 1),
        global_cpu_s: part(|t| t.cpu, 1),
        global_spread: part(|t| t.spread, 1),
        iteration_s,
        iteration_cpu_s,
        step_s: step.wall,
        step_cpu_s: step.cpu,
        step_spread: step.spread,
        step_repeats: step.repeats,
        peak_bytes: peak_memory(),
    })
}

/// A point as the one line `--point` prints: its CSV record, no header.
pub fn point_line(p: &Point) -> String {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.serialize(p).expect("a point serialises");
    String::from_utf8(w.into_inner().expect("in memory"))
        .expect("UTF-8")
        .trim_end()
        .to_string()
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
            solver.id.display_name(),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(stdout.as_bytes())
        .deserialize::<Point>()
        .next()
        .and_then(|r| r.ok())
        .ok_or_else(|| {
            Error::Input(format!(
                "{} at n = {n}: no result in {stdout:?}",
                solver.id.display_name()
            ))
        })
}

/// The read bandwidth at one factor's size, a row of `bandwidth.csv`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Bandwidth {
    pub n: usize,
    pub factor_bytes: usize,
    pub read_bandwidth_bytes_per_s: f64,
}

/// The sheet's scaling study: every point of `sides` × [`solvers`] in its own process, the
/// read bandwidth at each of Liu's factor's sizes and the local step's arithmetic.
pub struct Scaling {
    pub points: Vec<Point>,
    pub bandwidth: Vec<Bandwidth>,
    /// A square root and a division, s per spring.
    pub sqrt_div: f64,
    /// A multiplication and an addition of four lanes, s per entry of the factor and pass.
    pub multiply_add: f64,
}

/// Bytes a triangular solve reads per stored entry of a simplicial factor: its value and its
/// 32-bit row (`SparseCholesky::solve_three`).
pub const BYTES_PER_FACTOR_ENTRY: usize = 12;

pub fn scaling_study(sides: &[usize]) -> Result<Scaling> {
    let exe = std::env::current_exe().map_err(|e| Error::Input(e.to_string()))?;
    let mut points = Vec::new();
    for &n in sides {
        for solver in &solvers() {
            let t = Instant::now();
            let p = run_child(&exe, solver, n)?;
            eprintln!(
                "timing: n = {n:>3} {:<15} iteration {:>10} (CPU), step {:>10}, peak {:>5} MiB  [{:.1} s]",
                solver.id.display_name(),
                seconds(p.iteration_cpu_s),
                seconds(p.step_cpu_s),
                p.peak_bytes >> 20,
                t.elapsed().as_secs_f64()
            );
            points.push(p);
        }
    }
    let sqrt_div = floors::sqrt_div_seconds(thread_cpu, REPEATS);
    let multiply_add = floors::multiply_add_seconds(thread_cpu, REPEATS);
    let bandwidth = points
        .iter()
        .filter(|p| p.solver == SolverId::FastMassSpring.id())
        .map(|p| {
            let bytes = BYTES_PER_FACTOR_ENTRY * p.factor_nnz.unwrap_or(0);
            Bandwidth {
                n: p.n,
                factor_bytes: bytes,
                read_bandwidth_bytes_per_s: floors::read_bandwidth(
                    bytes,
                    thread_cpu,
                    REPEATS,
                    BATCH_SECONDS,
                ),
            }
        })
        .collect();
    eprintln!("timing: bandwidth and arithmetic measured");
    Ok(Scaling {
        points,
        bandwidth,
        sqrt_div,
        multiply_add,
    })
}

impl Scaling {
    pub fn point(&self, id: SolverId, n: usize) -> Option<&Point> {
        self.points.iter().find(|p| p.solver == id.id() && p.n == n)
    }

    /// The bound of one Liu/ADMM iteration at `p`'s size, s: the global step's floor, the
    /// longer of the factor streamed twice at the bandwidth measured for its size and the
    /// multiplication and addition of each entry in both passes, and the local step's, a
    /// square root and a division per spring.
    pub fn bound(&self, p: &Point) -> Option<(f64, f64)> {
        let b = self.bandwidth.iter().find(|b| b.n == p.n)?;
        let streamed = 2.0 * b.factor_bytes as f64 / b.read_bandwidth_bytes_per_s;
        let entries = 2.0 * (b.factor_bytes / BYTES_PER_FACTOR_ENTRY) as f64;
        Some((
            streamed.max(entries * self.multiply_add),
            p.springs as f64 * self.sqrt_div,
        ))
    }
}

//! Cost of one step of each solver on the thesis rope at the thesis's iteration counts, and of
//! Liu's and ADMM's iterations on a 100×100 hanging cloth (`make bench`).
//!
//! The rope runs at dt = 1e-3 s and k = 1e3 N/m, the setting of the longest published runs
//! (about 488 000 steps each), from a moving state. On the cloth, the global solve goes
//! through faer's sparse Cholesky; `cloth_global_solve` measures its three coordinates solved
//! together (as the solvers do) against one at a time.
//!
//! The `floor_*` benchmarks measure what no implementation of an iteration on the rope can
//! avoid, on this machine: the nine springs' square roots and divisions, independent in Liu's
//! and ADMM's local step (a throughput bound) and one after another in XPBD's Gauss-Seidel
//! sweep (a latency bound), and the rope's prefactored global solve (Liu, ADMM). A solver's
//! step with m iterations divided by m, against its floor, says how much is left to gain.

use mass_spring_solvers::integrators::time_stepper::TimeStepper;
use mass_spring_solvers::model::boundary::{fixed_unknowns, ConstrainedSystem};
use mass_spring_solvers::model::linear::{BandedLdlt, SymmetricMatrix};
use mass_spring_solvers::model::scene::{thesis_rope, SheetParams, SHEET_NODES_PER_SIDE};
use mass_spring_solvers::particles::scenes::ClothParams;
use mass_spring_solvers::solvers::admm::AdmmPd;
use mass_spring_solvers::solvers::backward_euler::BackwardEuler;
use mass_spring_solvers::solvers::batch::admm::AdmmLanes;
use mass_spring_solvers::solvers::batch::liu::LiuLanes;
use mass_spring_solvers::solvers::batch::xpbd::XpbdLanes;
use mass_spring_solvers::solvers::batch::{LaneSolver, WIDTH};
use mass_spring_solvers::solvers::fast_mass_spring::FastMassSpring;
use mass_spring_solvers::solvers::projective::{system_matrix, to_columns, GlobalSolve};
use mass_spring_solvers::solvers::registry::{Builder, SolverId, SolverSpec};
use mass_spring_solvers::solvers::xpbd::Xpbd;
use mass_spring_solvers::{MassSpringSystem, State, Vec3};
use std::hint::black_box;

fn main() {
    divan::main();
}

/// Time step of the benchmarks, s.
const DT: f64 = 1e-3;

/// The thesis rope at k = 1e3 N/m and a moving state of it (200 reference steps from rest).
fn rope() -> (MassSpringSystem, State) {
    let system = thesis_rope(1e3).unwrap();
    let mut be = BackwardEuler::reference(&system).unwrap();
    let mut state = system.initial_state();
    for _ in 0..200 {
        be.step(&mut state).unwrap();
    }
    (system, state)
}

/// One step of `solver` from `start`; the copy of the start state is made outside the timing.
fn bench_step(bencher: divan::Bencher, mut solver: Box<dyn TimeStepper + Send>, start: &State) {
    bencher
        .with_inputs(|| start.clone())
        .bench_local_refs(|state| solver.step(state).unwrap());
}

/// A solver of the registry at an iteration count.
#[derive(Debug, Clone, Copy)]
struct RopeCase(SolverSpec);

impl std::fmt::Display for RopeCase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.0.id, self.0.iterations)
    }
}

/// Every solver of springs and gravity in the registry (the tutorial's integrators run a
/// particle system and are measured by the report's tutorial chapter): Backward Euler at the
/// reference's 5 Newton iterations, every other solver at 1 iteration and at the thesis's
/// iteration counts (Tables 2-7; XPBD's and ADMM's 20 and 50 for the solvers it lacks).
fn rope_cases() -> Vec<RopeCase> {
    SolverId::ALL
        .into_iter()
        .filter(|id| matches!(id.info().builder, Builder::Springs(_)))
        .flat_map(|id| {
            let counts: &[usize] = match id {
                SolverId::BackwardEuler => &[5],
                SolverId::FastMassSpring => &[1, 30, 70],
                _ => &[1, 20, 50],
            };
            counts
                .iter()
                .map(move |&m| RopeCase(SolverSpec::new(id, m)))
        })
        .collect()
}

/// One step of each solver on the rope. Per iteration: (step of m − step of 1)/(m − 1).
#[divan::bench(args = rope_cases())]
fn rope_step(bencher: divan::Bencher, case: RopeCase) {
    let (system, start) = rope();
    let solver = case.0.build_send(&system, DT).unwrap();
    bench_step(bencher, solver, &start);
}

/// One step of [`WIDTH`] runs of `solver` in `lanes`, each from `start`: per run, a
/// [`WIDTH`]th of it. Per iteration: as `rope_step`'s.
fn bench_lanes<L: LaneSolver + Clone>(
    bencher: divan::Bencher,
    mut lanes: L,
    solver: &L::Run,
    start: &State,
) {
    for lane in 0..WIDTH {
        lanes.load(lane, solver, start);
    }
    bencher
        .with_inputs(|| lanes.clone())
        .bench_local_refs(|lanes| lanes.step());
}

/// Four XPBD runs of the rope in the lanes of a batch (`batch::xpbd`), from a moving state.
#[divan::bench(args = [1, 20, 50])]
fn rope_step_xpbd_lanes(bencher: divan::Bencher, iterations: usize) {
    let (system, start) = rope();
    let solver = Xpbd::new(&system, DT, iterations).unwrap();
    bench_lanes(bencher, XpbdLanes::new(&solver).unwrap(), &solver, &start);
}

/// Four Liu 2013 runs of the rope in the lanes of a batch (`batch::liu`).
#[divan::bench(args = [1, 30, 70])]
fn rope_step_liu_lanes(bencher: divan::Bencher, iterations: usize) {
    let (system, start) = rope();
    let solver = FastMassSpring::new(&system, DT, iterations).unwrap();
    bench_lanes(bencher, LiuLanes::new(&solver).unwrap(), &solver, &start);
}

/// Four ADMM-PD runs of the rope in the lanes of a batch (`batch::admm`).
#[divan::bench(args = [1, 20, 50])]
fn rope_step_admm_lanes(bencher: divan::Bencher, iterations: usize) {
    let (system, start) = rope();
    let solver = AdmmPd::new(&system, DT, iterations).unwrap();
    bench_lanes(bencher, AdmmLanes::new(&solver).unwrap(), &solver, &start);
}

/// A 100×100 cloth hanging from its two top corners (10 000 nodes, 29 601 springs), moving:
/// 20 steps of Liu with 10 iterations from rest. Its springs are undamped: the thesis's
/// solvers refuse spring damping, which only the particle system models.
fn cloth() -> (MassSpringSystem, State) {
    let system = ClothParams {
        nx: 100,
        ny: 100,
        damping: 0.0,
        ..ClothParams::default()
    }
    .hanging()
    .unwrap();
    let mut solver = FastMassSpring::new(&system, DT, 10).unwrap();
    let mut state = system.initial_state();
    for _ in 0..20 {
        solver.step(&mut state).unwrap();
    }
    (system, state)
}

/// Liu on the cloth: a step with 1 and with 2 iterations; their difference is one iteration
/// (a local step over the springs and one sparse solve), the rest the step's own O(n) work.
#[divan::bench(args = [1, 2], sample_count = 30)]
fn cloth_liu(bencher: divan::Bencher, iterations: usize) {
    let (system, start) = cloth();
    let solver = FastMassSpring::new(&system, DT, iterations).unwrap();
    bench_step(bencher, Box::new(solver), &start);
}

/// ADMM-PD on the cloth, as [`cloth_liu`].
#[divan::bench(args = [1, 2], sample_count = 30)]
fn cloth_admm(bencher: divan::Bencher, iterations: usize) {
    let (system, start) = cloth();
    let solver = AdmmPd::new(&system, DT, iterations).unwrap();
    bench_step(bencher, Box::new(solver), &start);
}

/// The cloth's prefactored global solve (Eqs 43-47 and faer's sparse Cholesky) for the three
/// coordinates: together (one solve with three right-hand sides) or one at a time.
#[divan::bench(args = ["together", "one at a time"], sample_count = 30)]
fn cloth_global_solve(bencher: divan::Bencher, how: &str) {
    let (system, state) = cloth();
    let n = system.len();
    let k: Vec<f64> = system.springs().iter().map(|s| s.stiffness).collect();
    let mut a = system_matrix(&system, DT, &k).unwrap();
    let fixed_nodes = system.nodes().iter().enumerate().filter(|(_, n)| n.fixed);
    let fixed = fixed_unknowns(fixed_nodes.map(|(i, _)| i), 1);
    let solve = ConstrainedSystem::new(&mut a, &fixed).unwrap();
    let columns: Vec<f64> = (0..3)
        .flat_map(|c| state.x.iter().map(move |p| p[c]))
        .collect();
    let together = how == "together";
    bencher
        .with_inputs(|| columns.clone())
        .bench_local_refs(|b| {
            if together {
                solve.solve(b, &columns, 3);
            } else {
                for (b, x_bar) in b.chunks_exact_mut(n).zip(columns.chunks_exact(n)) {
                    solve.solve(b, x_bar, 1);
                }
            }
        });
}

/// The springs' vectors $`x_a - x_b`$ of the moving rope.
fn spring_vectors(system: &MassSpringSystem, state: &State) -> Vec<Vec3> {
    system
        .springs()
        .iter()
        .map(|s| state.x[s.a] - state.x[s.b])
        .collect()
}

/// Floor of a Jacobi local step (Liu, ADMM): $`l_0/|d_i|`$ for the nine springs, independent of
/// one another, so their square roots and divisions overlap.
#[divan::bench]
fn floor_local_step_arithmetic(bencher: divan::Bencher) {
    let (system, state) = rope();
    let d = spring_vectors(&system, &state);
    let l0: Vec<f64> = system.springs().iter().map(|s| s.rest_length).collect();
    let mut scale = vec![0.0; d.len()];
    bencher.bench_local(|| {
        for ((r, d), &l0) in scale.iter_mut().zip(black_box(&d)).zip(&l0) {
            *r = l0 / d.norm_squared().sqrt();
        }
        black_box(&scale);
    });
}

/// Floor of a Gauss-Seidel sweep (XPBD): each spring's square root and division wait for the
/// previous spring's correction, which moves the node they share.
#[divan::bench]
fn floor_gauss_seidel_chain(bencher: divan::Bencher) {
    let (system, state) = rope();
    let d = spring_vectors(&system, &state);
    let l0: Vec<f64> = system.springs().iter().map(|s| s.rest_length).collect();
    bencher.bench_local(|| {
        let mut carried = 0.0;
        for (d, &l0) in black_box(&d).iter().zip(&l0) {
            // The previous spring's correction enters this spring's length (as zero, which the
            // compiler cannot fold away).
            let length = (d.norm_squared() + carried).sqrt();
            carried = (length - l0) / length * 0.0;
        }
        black_box(carried)
    });
}

/// The rope's prefactored global solve of Liu (Eq 29) for the three coordinates, the floor of
/// a Liu or ADMM iteration together with [`floor_local_step_arithmetic`].
#[divan::bench]
fn floor_rope_global_solve(bencher: divan::Bencher) {
    let (system, state) = rope();
    let k: Vec<f64> = system.springs().iter().map(|s| s.stiffness).collect();
    let solve = GlobalSolve::new(&system, DT, &k).unwrap();
    let mut x_n = vec![0.0; 3 * system.len()];
    to_columns(&state.x, &mut x_n);
    bencher
        .with_inputs(|| x_n.clone())
        .bench_local_refs(|b| solve.solve(b, &x_n));
}

/// The banded matrix of Backward Euler's Newton step (three unknowns per node) on the rope
/// (30 unknowns, half-bandwidth 5) or the 10×10 sheet of the benchmark (300, 35), made
/// positive definite by a dominant diagonal: what [`BandedLdlt`] factors and solves per
/// Newton iteration.
fn banded_matrix(scene: &str) -> SymmetricMatrix {
    let system = match scene {
        "rope" => thesis_rope(1e3).unwrap(),
        _ => SheetParams::spec(SHEET_NODES_PER_SIDE, 1e3)
            .build()
            .unwrap(),
    };
    let edges: Vec<_> = system.springs().iter().map(|s| (s.a, s.b)).collect();
    let mut a = SymmetricMatrix::from_node_graph(system.len(), 3, &edges);
    for &(i, j) in &edges {
        for r in 0..3 {
            for c in 0..3 {
                let v = if r == c { 2.0 } else { 0.25 };
                a.add(3 * i + r, 3 * i + c, v);
                a.add(3 * j + r, 3 * j + c, v);
                a.add(3 * i + r, 3 * j + c, -v / 2.0);
                a.add(3 * j + r, 3 * i + c, -v / 2.0);
            }
        }
    }
    for i in 0..a.dim() {
        a.add(i, i, 1.0);
    }
    a
}

/// The banded $`LDL^\top`$ refactored with new values (Backward Euler's Newton iteration).
#[divan::bench(args = ["rope", "sheet"])]
fn banded_refactor(bencher: divan::Bencher, scene: &str) {
    let a = banded_matrix(scene);
    let mut f = BandedLdlt::new(&a).unwrap();
    bencher.bench_local(|| f.refactor(black_box(&a)).unwrap());
}

/// Its substitutions for one right-hand side.
#[divan::bench(args = ["rope", "sheet"])]
fn banded_solve(bencher: divan::Bencher, scene: &str) {
    let a = banded_matrix(scene);
    let f = BandedLdlt::new(&a).unwrap();
    let b: Vec<f64> = (0..a.dim()).map(|i| (i as f64 * 0.37).sin()).collect();
    bencher
        .with_inputs(|| b.clone())
        .bench_local_refs(|b| f.solve_in_place(b, 1));
}

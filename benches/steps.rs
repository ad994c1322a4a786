//! Cost of one step of each solver on the thesis rope (`make bench`).

use mass_spring_solvers::backward_euler::BackwardEuler;
use mass_spring_solvers::scene::thesis_rope;
use mass_spring_solvers::solver::TimeStepper;
use mass_spring_solvers::State;

fn main() {
    divan::main();
}

/// A moving state of the rope, so the Newton iterations do real work.
fn moving(system: &mass_spring_solvers::MassSpringSystem) -> State {
    let mut be = BackwardEuler::reference(system).unwrap();
    let mut state = system.initial_state();
    for _ in 0..200 {
        be.step(&mut state).unwrap();
    }
    state
}

/// One Backward Euler step of the thesis rope (dt = 1e-3), by Newton iterations per step.
#[divan::bench(args = [1, 5])]
fn backward_euler_step(bencher: divan::Bencher, newton_iterations: usize) {
    let system = thesis_rope(1e6).unwrap();
    let start = moving(&system);
    let mut be = BackwardEuler::new(&system, 1e-3, newton_iterations).unwrap();
    bencher.bench_local(|| {
        let mut state = start.clone();
        be.step(divan::black_box(&mut state)).unwrap();
        state
    });
}

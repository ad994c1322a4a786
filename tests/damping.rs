//! Rayleigh damping after Brown et al. 2018 (`src/integrators/damping.rs`, `src/solvers/damped_admm.rs`, the damped
//! Backward Euler of `src/solvers/backward_euler.rs`) against independent oracles: rigid motion, the
//! modal damping ratio of the linearised rope, and the damped converged step; plus the oracle's
//! own honesty (a stalled line search is an error) and the rejection of `Spring::damping` by the
//! thesis's solvers.

use mass_spring_solvers::integrators::damping::{rayleigh_force, spring_hessian, RayleighDamping};
use mass_spring_solvers::model::scene::{thesis_rope, RopeParams};
use mass_spring_solvers::solvers::admm::AdmmPd;
use mass_spring_solvers::solvers::backward_euler::{BackwardEuler, ConvergedStepOptions};
use mass_spring_solvers::solvers::converged_stage::{converged_step, damped_converged_step};
use mass_spring_solvers::solvers::damped_admm::DampedAdmm;
use mass_spring_solvers::solvers::fast_mass_spring::FastMassSpring;
use mass_spring_solvers::solvers::pbd::Pbd;
use mass_spring_solvers::solvers::xpbd::Xpbd;
use mass_spring_solvers::studies::beyond::{gap, Start};
use mass_spring_solvers::{Error, MassSpringSystem, Node, Spring, State, TimeStepper, Vec3};
use nalgebra::{DMatrix, Rotation3};

/// The shared moving state: 10 converged Backward Euler steps of dt = 1e-2 from the thesis
/// rope's start.
fn step10(system: &MassSpringSystem) -> State {
    Start::Step10.state(system).unwrap()
}

fn one_step(solver: &mut dyn TimeStepper, state: &State) -> State {
    let mut next = state.clone();
    solver.step(&mut next).unwrap();
    next
}

fn field_of(e: Error) -> String {
    match e {
        Error::InvalidParameter { field, .. } => field,
        other => panic!("expected an invalid parameter, got {other}"),
    }
}

/// The damping of the tests below: both terms matter at the rope's frequencies.
const DAMPING: RayleighDamping = RayleighDamping {
    alpha: 0.5,
    beta: 2e-3,
};

#[test]
fn bad_damping_is_rejected_with_its_name() {
    let rope = thesis_rope(1e3).unwrap();
    for (damping, field) in [
        (
            RayleighDamping {
                alpha: -1.0,
                beta: 0.0,
            },
            "alpha",
        ),
        (
            RayleighDamping {
                alpha: f64::NAN,
                beta: 0.0,
            },
            "alpha",
        ),
        (
            RayleighDamping {
                alpha: 0.0,
                beta: -1e-3,
            },
            "beta",
        ),
        (
            RayleighDamping {
                alpha: 0.0,
                beta: f64::INFINITY,
            },
            "beta",
        ),
    ] {
        assert_eq!(field_of(damping.validate().unwrap_err()), field);
        let admm = DampedAdmm::new(&rope, 1e-2, 10, damping).unwrap_err();
        assert_eq!(field_of(admm), field);
        let be = BackwardEuler::damped(&rope, 1e-2, 5, damping).unwrap_err();
        assert_eq!(field_of(be), field);
        let state = rope.initial_state();
        let oracle = damped_converged_step(&rope, &state, 1e-2, damping, Default::default());
        assert_eq!(field_of(oracle.unwrap_err()), field);
    }
    assert_eq!(
        field_of(DampedAdmm::new(&rope, 1e-2, 0, DAMPING).unwrap_err()),
        "iterations"
    );
    // Finite but overflowing the global matrix's weights.
    let huge = RayleighDamping {
        alpha: 0.0,
        beta: 1e305,
    };
    assert_eq!(
        field_of(DampedAdmm::new(&rope, 1e-2, 10, huge).unwrap_err()),
        "beta"
    );
    assert_eq!(RayleighDamping::default(), RayleighDamping::NONE);
}

/// `Spring::damping` is the tutorial's: every thesis solver rejects it by name instead of
/// ignoring it.
#[test]
fn spring_damping_is_rejected_by_the_thesis_solvers() {
    let rope = thesis_rope(1e3).unwrap();
    let mut springs = rope.springs().to_vec();
    springs[3].damping = 0.5;
    let damped = MassSpringSystem::new(rope.nodes().to_vec(), springs, rope.gravity()).unwrap();
    let state = damped.initial_state();
    let errors = [
        BackwardEuler::new(&damped, 1e-2, 5).map(|_| ()),
        converged_step(&damped, &state, 1e-2, Default::default()).map(|_| ()),
        AdmmPd::new(&damped, 1e-2, 5).map(|_| ()),
        DampedAdmm::new(&damped, 1e-2, 5, DAMPING).map(|_| ()),
        FastMassSpring::new(&damped, 1e-2, 5).map(|_| ()),
        Xpbd::new(&damped, 1e-2, 5).map(|_| ()),
        Pbd::new(&damped, 1e-2, 5, 1.0).map(|_| ()),
    ];
    for e in errors {
        assert_eq!(field_of(e.unwrap_err()), "springs[3].damping");
    }
}

/// A free rope (no fixed node, no gravity) of 10 nodes on a zigzag, every spring at its rest
/// length; `stretch` scales the rest lengths down (1: unstressed).
fn free_zigzag(stretch: f64) -> MassSpringSystem {
    let nodes = (0..10)
        .map(|i| Node {
            mass: 1.0 + 0.1 * i as f64,
            position: Vec3::new(i as f64 * 0.8, 0.6 * (i % 2) as f64, 0.05 * (i * i) as f64),
            velocity: Vec3::zeros(),
            fixed: false,
        })
        .collect::<Vec<_>>();
    let springs = (0..9)
        .map(|i| Spring {
            a: i,
            b: i + 1,
            rest_length: (nodes[i].position - nodes[i + 1].position).norm() / stretch,
            stiffness: 1e3,
            damping: 0.0,
        })
        .collect();
    MassSpringSystem::new(nodes, springs, Vec3::zeros()).unwrap()
}

/// (a) The stiffness-proportional force $`-\beta K(x)v`$ of a rigid motion (translation and
/// rotation) of a free, unstressed rope is zero with $`K(x)`$ the tangent stiffness at the
/// current, rotated positions (the paper's $`K`$); with the stiffness of the unrotated rope it
/// is not, nor on a stretched rope. The mass-proportional force is $`-\alpha M v`$ by design.
#[test]
fn damping_force_vanishes_for_rigid_motion_of_an_unstressed_rope() {
    let beta_only = RayleighDamping {
        alpha: 0.0,
        beta: 0.1,
    };
    let rotation = Rotation3::from_euler_angles(0.3, -1.1, 0.7);
    let (u, omega) = (Vec3::new(0.4, -2.0, 1.5), Vec3::new(1.3, 0.2, -0.9));
    let centre = Vec3::new(2.0, 1.0, -0.5);
    let rigid = |system: &MassSpringSystem| {
        let x: Vec<Vec3> = system
            .nodes()
            .iter()
            .map(|n| rotation * n.position)
            .collect();
        let v: Vec<Vec3> = x.iter().map(|x| u + omega.cross(&(x - centre))).collect();
        (x, v)
    };
    let largest = |f: &[Vec3]| f.iter().map(|f| f.norm()).fold(0.0, f64::max);
    let unstressed = free_zigzag(1.0);
    let (x, v) = rigid(&unstressed);
    // The scale: β·k·|v| ≈ 0.1 · 1e3 · 10 = 1e3 N.
    let f = rayleigh_force(&unstressed, beta_only, &x, &v);
    assert!(
        largest(&f) < 1e-9,
        "rigid motion damped: {:e} N",
        largest(&f)
    );

    // The stiffness of the unrotated rope does not turn with it: it damps the rotation.
    let x_ref: Vec<Vec3> = unstressed.nodes().iter().map(|n| n.position).collect();
    let mut f_ref = vec![Vec3::zeros(); x.len()];
    for (i, s) in unstressed.springs().iter().enumerate() {
        let f_a = -beta_only.beta * (spring_hessian(&unstressed, &x_ref, i) * (v[s.a] - v[s.b]));
        f_ref[s.a] += f_a;
        f_ref[s.b] -= f_a;
    }
    assert!(largest(&f_ref) > 10.0, "{:e} N", largest(&f_ref));

    // A stretched rope's tangent stiffness has a transverse part: rotation is damped.
    let stretched = free_zigzag(1.1);
    let (x, v) = rigid(&stretched);
    let f = rayleigh_force(&stretched, beta_only, &x, &v);
    assert!(largest(&f) > 10.0, "{:e} N", largest(&f));

    // Mass-proportional: −αMv, rigid motion included.
    let alpha_only = RayleighDamping {
        alpha: 0.7,
        beta: 0.0,
    };
    let (x, v) = rigid(&unstressed);
    let f = rayleigh_force(&unstressed, alpha_only, &x, &v);
    for ((f, v), node) in f.iter().zip(&v).zip(unstressed.nodes()) {
        assert!((f + 0.7 * node.mass * v).norm() < 1e-12);
    }
}

/// The taut rope without gravity: the thesis rope's nodes and anchors with rest length 0.9 m,
/// so the straight rope is its equilibrium, under tension 0.1 k.
fn taut_rope(stiffness: f64) -> MassSpringSystem {
    RopeParams {
        rest_length: 0.9,
        gravity: 0.0,
        ..RopeParams::thesis(stiffness)
    }
    .build()
    .unwrap()
}

/// The lowest mode of $`K\phi = \omega^2 M\phi`$ on the free coordinates ($`M = I`$ here: 1 kg
/// nodes), with $`K = -dF/dx`$ at the straight equilibrium: $`(\omega, \phi)`$, $`\phi`$ of unit
/// $`M`$-norm as 3n coordinates (0 on the anchors).
fn lowest_mode(system: &MassSpringSystem) -> (f64, Vec<f64>) {
    let x = system.initial_state().x;
    let k = -system.force_jacobian_dense(&x);
    let free: Vec<usize> = (0..3 * system.len())
        .filter(|r| !system.nodes()[r / 3].fixed)
        .collect();
    let k_free = DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let eigen = k_free.symmetric_eigen();
    let (lowest, &omega2) = eigen
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .unwrap();
    let mut phi = vec![0.0; 3 * system.len()];
    for (i, &r) in free.iter().enumerate() {
        phi[r] = eigen.eigenvectors[(i, lowest)];
    }
    (omega2.sqrt(), phi)
}

/// (b) The lowest mode of the damped taut rope, released from a small displacement along it,
/// decays at the Rayleigh rate $`\zeta\omega`$, $`\zeta = \alpha/(2\omega) + \beta\omega/2`$.
///
/// k = 1e3 N/m: $`\omega`$ = 3.47 rad/s (transverse, tension 100 N). α = 0.3 1/s and
/// β = 0.02 s give ζ = 0.043 + 0.035 = 0.078; Backward Euler's own damping at dt = 2e-4 s is
/// $`\zeta_{num} \approx \omega\,dt/2`$ = 3.5e-4, 0.45 % of it. The modal energy
/// $`E = \frac12(\dot q^2 + \omega^2 q^2)`$ of a damped oscillator falls by exactly
/// $`e^{-2\zeta\omega T_d}`$ over a damped period $`T_d`$, whatever the phase.
#[test]
fn lowest_mode_decays_at_the_rayleigh_rate() {
    let system = taut_rope(1e3);
    let (omega, phi) = lowest_mode(&system);
    let damping = RayleighDamping {
        alpha: 0.3,
        beta: 0.02,
    };
    let zeta = damping.modal_ratio(omega);
    let dt = 2e-4;
    let amplitude = 1e-4;
    let mut state = system.initial_state();
    let equilibrium = state.x.clone();
    for (i, x) in state.x.iter_mut().enumerate() {
        *x += amplitude * Vec3::new(phi[3 * i], phi[3 * i + 1], phi[3 * i + 2]);
    }
    let modal_energy = |s: &State| {
        let (mut q, mut q_dot) = (0.0, 0.0);
        for (i, (x, v)) in s.x.iter().zip(&s.v).enumerate() {
            let p = Vec3::new(phi[3 * i], phi[3 * i + 1], phi[3 * i + 2]);
            q += p.dot(&(x - equilibrium[i]));
            q_dot += p.dot(v);
        }
        0.5 * (q_dot * q_dot + omega * omega * q * q)
    };
    let damped_period = 2.0 * std::f64::consts::PI / (omega * (1.0 - zeta * zeta).sqrt());
    let steps = (damped_period / dt).round() as usize;
    let e0 = modal_energy(&state);
    let mut solver = BackwardEuler::damped(&system, dt, 2, damping).unwrap();
    for _ in 0..steps {
        solver.step(&mut state).unwrap();
    }
    let rate = -(modal_energy(&state) / e0).ln() / (2.0 * steps as f64 * dt);
    let expected = zeta * omega;
    println!(
        "omega {omega:.4} rad/s, zeta {zeta:.4}: decay rate {rate:.5} 1/s, Rayleigh {expected:.5} \
         1/s (integrator's own about {:.1e} 1/s)",
        omega * omega * dt / 2.0
    );
    assert!((omega - 3.4730).abs() < 1e-3, "omega {omega}");
    assert!(
        (rate - expected).abs() < 0.01 * expected,
        "decay rate {rate} 1/s, Rayleigh {expected} 1/s"
    );
    // What is left is Backward Euler's own damping, about ω²dt/2 on a rate this small.
    let with_integrator = expected + omega * omega * dt / 2.0;
    assert!(
        (rate - with_integrator).abs() < 1e-3 * expected,
        "decay rate {rate} 1/s, Rayleigh and integrator {with_integrator} 1/s"
    );
}

/// (c) Damped ADMM-PD reaches the damped converged step (its fixed point) to below 1e-9 m.
#[test]
fn damped_admm_reaches_the_damped_converged_step() {
    for k in [1e3, 1e6] {
        let rope = thesis_rope(k).unwrap();
        for (start, state) in [("rest", rope.initial_state()), ("step10", step10(&rope))] {
            for (dt, iterations) in [(1e-3, 300), (1e-2, 6000)] {
                let oracle =
                    damped_converged_step(&rope, &state, dt, DAMPING, Default::default()).unwrap();
                let undamped = converged_step(&rope, &state, dt, Default::default()).unwrap();
                let mut admm = DampedAdmm::new(&rope, dt, iterations, DAMPING).unwrap();
                let next = one_step(&mut admm, &state);
                let g = gap(&next, &oracle);
                println!(
                    "k {k:e} {start} dt {dt:e}: {iterations} iterations, gap {g:.1e} m \
                     (damping moves the step {:.1e} m)",
                    gap(&undamped, &oracle)
                );
                assert!(g < 1e-9, "k {k:e} {start} dt {dt:e}: gap {g:e} m");
                // The undamped step would fail the comparison: the damping is seen.
                assert!(gap(&undamped, &oracle) > 2e-9);
            }
        }
    }
}

/// The damped Backward Euler of fixed Newton iterations (the velocity residual of Eqs 8-9 with
/// the damping force, an independent formulation) reaches the damped converged step (the
/// minimiser of the damped potential).
#[test]
fn damped_newton_reaches_the_damped_converged_step() {
    for k in [1e3, 1e6] {
        let rope = thesis_rope(k).unwrap();
        let state = step10(&rope);
        for dt in [1e-3, 1e-2] {
            let oracle =
                damped_converged_step(&rope, &state, dt, DAMPING, Default::default()).unwrap();
            let mut be = BackwardEuler::damped(&rope, dt, 20, DAMPING).unwrap();
            let g = gap(&one_step(&mut be, &state), &oracle);
            println!("k {k:e} dt {dt:e}: gap {g:.1e} m");
            assert!(g < 1e-12, "k {k:e} dt {dt:e}: gap {g:e} m");
        }
    }
}

/// (d) With α = β = 0 the damped solvers are the undamped ones, bit for bit.
#[test]
fn without_damping_the_damped_solvers_are_the_undamped_ones() {
    for k in [1e3, 1e6] {
        let rope = thesis_rope(k).unwrap();
        let state = step10(&rope);
        for dt in [1e-3, 1e-2] {
            let admm = one_step(&mut AdmmPd::new(&rope, dt, 20).unwrap(), &state);
            let damped = one_step(
                &mut DampedAdmm::new(&rope, dt, 20, RayleighDamping::NONE).unwrap(),
                &state,
            );
            assert_eq!(admm, damped);
            let be = one_step(&mut BackwardEuler::new(&rope, dt, 5).unwrap(), &state);
            let damped = one_step(
                &mut BackwardEuler::damped(&rope, dt, 5, RayleighDamping::NONE).unwrap(),
                &state,
            );
            assert_eq!(be, damped);
        }
    }
}

/// The oracle does not report convergence when it has none. An absurd rope (k = 1e18 N/m on
/// 1 mg nodes, 1 km from the origin, dt = 100 s) makes the Newton step too ill-conditioned to
/// descend: the line search stalls at Newton iteration 45, which is an error naming the line
/// search and the iteration (taking the stalled step, as the oracle did before, ends in a
/// reported convergence). A tolerance below round-off is an error too (the iteration limit).
#[test]
fn the_oracle_reports_a_stalled_line_search() {
    let absurd = RopeParams {
        stiffness: 1e18,
        node_mass: 1e-6,
        anchor_left: Vec3::new(1e3, 0.0, 0.0),
        anchor_right: Vec3::new(1e3 + 9.0, 0.0, 0.0),
        ..RopeParams::thesis(1e18)
    }
    .build()
    .unwrap();
    let mut state = absurd.initial_state();
    state.v[4] = Vec3::new(0.0, 3.0, 1.0);
    match converged_step(&absurd, &state, 100.0, ConvergedStepOptions::default()) {
        Err(Error::NotConverged { what, detail }) => {
            println!("{what}: {detail}");
            assert!(detail.contains("line search stalled at Newton iteration"));
        }
        other => panic!("a stalled line search reported {other:?}"),
    }

    let rope = thesis_rope(1e6).unwrap();
    let below_round_off = ConvergedStepOptions {
        tolerance: 1e-20,
        ..Default::default()
    };
    let err = converged_step(&rope, &step10(&rope), 1e-2, below_round_off).unwrap_err();
    assert!(matches!(err, Error::NotConverged { .. }), "{err}");
}

/// The measurement (run with `--ignored --nocapture`): at dt = 1e-2, k = 1e6, from
/// `step10`, the iterations m each solver needs for a gap below 1e-6 m to its converged step,
/// each m a fresh solver taking one step.
#[test]
#[ignore]
fn iterations_to_one_micrometre() {
    let rope = thesis_rope(1e6).unwrap();
    let state = step10(&rope);
    let dt = 1e-2;
    let first_below = |oracle: &State, build: &dyn Fn(usize) -> Box<dyn TimeStepper>| {
        (1..=20_000).find(|&m| gap(&one_step(build(m).as_mut(), &state), oracle) < 1e-6)
    };
    let undamped = converged_step(&rope, &state, dt, Default::default()).unwrap();
    let damped = damped_converged_step(&rope, &state, dt, DAMPING, Default::default()).unwrap();
    let admm = first_below(&undamped, &|m| Box::new(AdmmPd::new(&rope, dt, m).unwrap()));
    let none = first_below(&undamped, &|m| {
        Box::new(DampedAdmm::new(&rope, dt, m, RayleighDamping::NONE).unwrap())
    });
    let with = first_below(&damped, &|m| {
        Box::new(DampedAdmm::new(&rope, dt, m, DAMPING).unwrap())
    });
    let damping = DAMPING;
    println!("ADMM-PD {admm:?}, damped ADMM (0, 0) {none:?}, damped ADMM {damping:?} {with:?}");
}

//! The optimization integrators of issue 23 (`src/integrators/optimization_integrator.rs`) and their
//! dissipation functions (`src/integrators/dissipation.rs`), each claim recomputed and each test shown
//! failing on a plausible wrong hypothesis:
//! - the global orders (1 for Backward Euler, 2 for the others) against the exact motion; a
//!   TR-BDF2 whose trapezoid forgets its explicit half is first order and fails;
//! - the numerical damping of the rope's lowest mode: the second-order schemes damp at least
//!   ten times less than Backward Euler; that TR-BDF2 does not;
//! - every minimizing solver, run to convergence on each stage, reaches the Newton-solved
//!   stage; a solver handed Backward Euler's problem instead of the stage's misses it;
//! - Rayleigh damping in TR-BDF2 follows the damped oscillator at order 2; with the damping
//!   in the implicit half only it is first order;
//! - a mass under power-law drag stops at the closed-form time and distance at the
//!   integrator's order (Backward Euler's first order fails the second-order check);
//! - the implicit midpoint keeps a free rope's angular momentum to round-off under the
//!   momentum-conserving Rayleigh damping and loses it under the classical one (and under
//!   Backward Euler, whose own damping takes it).

use mass_spring_solvers::integrators::damping::RayleighDamping;
use mass_spring_solvers::integrators::dissipation::{Dissipation, PowerLawDrag, RayleighForm};
use mass_spring_solvers::integrators::optimization_integrator::{
    tr_bdf2_coefficients, Integrated, MinimizingSolver, OptimizationIntegrator, StageProblem, GAMMA,
};
use mass_spring_solvers::integrators::stopping::Convergence;
use mass_spring_solvers::integrators::time_stepper::TimeStepper;
use mass_spring_solvers::model::scene::thesis_rope;
use mass_spring_solvers::model::system::{MassSpringSystem, Node, Spring, State, Vec3};
use mass_spring_solvers::solvers::converged_stage::ConvergedNewton;
use mass_spring_solvers::solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::studies::beyond::{Start, CONVERGENCE_DAMPING};
use mass_spring_solvers::studies::integrator_study::{
    exact_amplitude_rate, exact_stages, fitted_slope, largest_distance, lowest_mode,
    minimizing_solvers, order_reference, DampingStudy, OrderStudy, DAMPING_DT, DAMPING_STIFFNESS,
    ORDER_STIFFNESS,
};
use mass_spring_solvers::Result;
use std::process::Command;
use std::sync::{Arc, Mutex};

const ALL: [OptimizationIntegrator; 4] = OptimizationIntegrator::ALL;

/// The wrong hypothesis of the negative cases: TR-BDF2 whose trapezoidal stage omits its
/// explicit half ($`u_0 = v_n`$, without $`\tau M^{-1}(F(x_n) + f_d)`$), the stages solved to
/// round-off.
struct ImplicitOnlyTrBdf2 {
    oracle: ConvergedNewton,
    h: f64,
}

impl TimeStepper for ImplicitOnlyTrBdf2 {
    fn name(&self) -> String {
        "TR-BDF2 without the trapezoid's explicit half".into()
    }
    fn dt(&self) -> f64 {
        self.h
    }
    fn system(&self) -> &MassSpringSystem {
        self.oracle.system()
    }
    fn step(&mut self, state: &mut State) -> Result<()> {
        let tau = GAMMA * self.h / 2.0;
        let fixed: Vec<bool> = self.system().nodes().iter().map(|n| n.fixed).collect();
        let mut stage = state.clone();
        for (i, fixed) in fixed.iter().enumerate() {
            if !fixed {
                stage.x[i] += tau * state.v[i];
            }
        }
        let problem = |slot| StageProblem {
            tau,
            step: self.h,
            slot,
            frozen: None,
        };
        self.oracle.solve(&problem(0), &mut stage)?;
        let (a, b, _) = tr_bdf2_coefficients();
        for (i, fixed) in fixed.iter().enumerate() {
            if !fixed {
                stage.x[i] = a * stage.x[i] - b * state.x[i];
                stage.v[i] = a * stage.v[i] - b * state.v[i];
            }
        }
        self.oracle.solve(&problem(1), &mut stage)?;
        *state = stage;
        Ok(())
    }
}

fn implicit_only(system: &MassSpringSystem, h: f64, d: Dissipation) -> Box<dyn TimeStepper> {
    Box::new(ImplicitOnlyTrBdf2 {
        oracle: ConvergedNewton::new(system, h, d).unwrap(),
        h,
    })
}

#[test]
fn tr_bdf2_shares_one_stage_step_and_its_coefficients_are_consistent() {
    let (a, b, w) = tr_bdf2_coefficients();
    assert!((a - b - 1.0).abs() < 1e-15);
    // w = γ/2 for γ = 2 - √2: both stages have c = γ²/4, one factorisation.
    assert!((w - GAMMA / 2.0).abs() < 1e-15, "{w} {}", GAMMA / 2.0);
    assert_eq!(OptimizationIntegrator::TrBdf2.stage_steps(1e-2).len(), 1);
    assert_eq!(OptimizationIntegrator::Bdf2.stage_steps(1e-2).len(), 2);
    let c = StageProblem {
        tau: GAMMA * 1e-2 / 2.0,
        step: 1e-2,
        slot: 0,
        frozen: None,
    }
    .weight();
    assert!((c - GAMMA * GAMMA / 4.0).abs() < 1e-15);
}

/// Orders 1 ± 0.1 and 2 ± 0.1 (positions at t = 1 s of the k = 1e3 rope, dt 4e-3 to 5e-4);
/// the exact motion's own error (RK4 at 1/100 against 1/200 of its limit) is far below the
/// smallest error fitted.
#[test]
fn the_integrators_are_of_orders_one_and_two() {
    let exact = order_reference().unwrap();
    // RK4 at half the exact motion's step, to t = 1 s.
    let finer = {
        let system = mass_spring_solvers::studies::beyond::GridScene::Rope
            .system(ORDER_STIFFNESS)
            .unwrap();
        let limit = mass_spring_solvers::studies::work_precision::rk4_stability_limit(&system);
        let per_sample = (0.1 / (0.005 * limit)).ceil();
        let mut rk4 = mass_spring_solvers::solvers::registry::SolverSpec::new(
            mass_spring_solvers::solvers::registry::SolverId::Rk4,
            1,
        )
        .build(&system, 0.1 / per_sample)
        .unwrap();
        let mut state = system.initial_state();
        for _ in 0..(10 * per_sample as u64) {
            rk4.step(&mut state).unwrap();
        }
        state.x
    };
    let reference_error = largest_distance(&exact, &finer);
    for integrator in ALL {
        let study = OrderStudy::compute(integrator, &exact).unwrap();
        let expected = integrator.order() as f64;
        assert!(
            (study.order - expected).abs() <= 0.1,
            "{integrator}: {} {:?}",
            study.order,
            study.errors
        );
        let smallest = study.errors.iter().map(|e| e.1).fold(f64::MAX, f64::min);
        assert!(reference_error < 1e-3 * smallest, "{reference_error:e}");
    }
    // Negative: without the trapezoid's explicit half, TR-BDF2 is first order.
    let wrong = OrderStudy::of(OptimizationIntegrator::TrBdf2, &exact, &|system, dt| {
        Ok(implicit_only(system, dt, Dissipation::NONE))
    })
    .unwrap();
    assert!((wrong.order - 2.0).abs() > 0.1, "{}", wrong.order);
}

/// The lowest mode of the k = 1e6 rope at dt = 0.01 s: Backward Euler damps it, each
/// second-order scheme at least ten times less; the midpoint not at all (symplectic).
#[test]
fn second_order_schemes_damp_ten_times_less_than_backward_euler() {
    let mode = lowest_mode(DAMPING_STIFFNESS).unwrap();
    // The mode is the thesis rope's slow swing (T/2 of Table 1: 0.206 s).
    assert!((std::f64::consts::PI / mode.omega - 0.206).abs() < 0.01);
    let exact = exact_amplitude_rate(&mode).unwrap();
    let per_period = |i| DampingStudy::compute(i, &mode, exact).unwrap().per_period;
    let be = per_period(OptimizationIntegrator::BackwardEuler);
    assert!(be > 0.3, "{be}");
    for integrator in &ALL[1..] {
        let d = per_period(*integrator);
        assert!(d.abs() * 10.0 <= be, "{integrator}: {d} against {be}");
    }
    assert!(per_period(OptimizationIntegrator::ImplicitMidpoint).abs() < 1e-4);
    // Negative: the first-order TR-BDF2 damps as much as Backward Euler, within ten times.
    let system = thesis_rope(DAMPING_STIFFNESS).unwrap();
    let mut wrong = implicit_only(&system, DAMPING_DT, Dissipation::NONE);
    let d = DampingStudy::of(OptimizationIntegrator::TrBdf2, &mode, exact, wrong.as_mut())
        .unwrap()
        .per_period;
    assert!(d * 10.0 > be, "{d} against {be}");
}

/// A minimizing solver and the Newton oracle on the same stage problems: the oracle's solution
/// goes on, the solver's gap to it is kept.
struct Versus {
    solver: Box<dyn MinimizingSolver + Send>,
    oracle: ConvergedNewton,
    /// Hand the solver Backward Euler's problem of the whole step instead (the negative case).
    ignore_stage: bool,
    /// The largest gap so far, shared with the test (the integrator owns the solver).
    gap: Arc<Mutex<f64>>,
}

impl TimeStepper for Versus {
    fn name(&self) -> String {
        self.solver.name()
    }
    fn dt(&self) -> f64 {
        self.solver.dt()
    }
    fn system(&self) -> &MassSpringSystem {
        self.oracle.system()
    }
    fn convergence(&mut self) -> Option<&mut Convergence> {
        self.solver.convergence()
    }
    fn step(&mut self, state: &mut State) -> Result<()> {
        self.solve(&StageProblem::backward_euler(self.dt()), state)
    }
}

impl MinimizingSolver for Versus {
    fn solve(&mut self, problem: &StageProblem, stage: &mut State) -> Result<()> {
        let mut theirs = stage.clone();
        let handed = if self.ignore_stage {
            StageProblem::backward_euler(problem.step)
        } else {
            *problem
        };
        self.solver.solve(&handed, &mut theirs)?;
        self.oracle.solve(problem, stage)?;
        let gap = largest_distance(&theirs.x, &stage.x);
        let mut largest = self.gap.lock().unwrap();
        *largest = largest.max(gap);
        Ok(())
    }
    fn dissipation(&self) -> Option<&Dissipation> {
        self.oracle.dissipation()
    }
}

/// `spec`'s largest gap to the Newton-solved stages over two steps of `integrator` from a
/// moving state.
fn stage_gap(
    spec: &SolverSpec,
    system: &MassSpringSystem,
    dt: f64,
    integrator: OptimizationIntegrator,
    ignore_stage: bool,
) -> f64 {
    let gap = Arc::new(Mutex::new(0.0));
    let versus = Versus {
        solver: spec.build_stage_solver(system, dt).unwrap(),
        oracle: ConvergedNewton::new(system, dt, spec.params.dissipation()).unwrap(),
        ignore_stage,
        gap: Arc::clone(&gap),
    };
    let mut stepper = Integrated::new(Box::new(versus), integrator).unwrap();
    let mut state = Start::Step10.state(system).unwrap();
    for _ in 0..2 {
        stepper.step(&mut state).unwrap();
    }
    let largest = *gap.lock().unwrap();
    largest
}

/// Every minimizing solver, each stage run to convergence, reaches the Newton-solved stage to
/// 1e-9 m at dt = 1e-2 and 1e-3 s on the rope at both stiffnesses under every integrator (the
/// damped ones with the convergence study's Rayleigh damping, against the damped stage).
#[test]
fn every_minimizing_solver_reaches_the_newton_solved_stage() {
    for k in [1e3, 1e6] {
        let system = thesis_rope(k).unwrap();
        for dt in [1e-2, 1e-3] {
            for id in minimizing_solvers() {
                let mut spec = SolverSpec::new(id, 40_000).to_tolerance(1e-13).unwrap();
                if matches!(id, SolverId::DampedBackwardEuler | SolverId::DampedAdmm) {
                    spec.params.damping = CONVERGENCE_DAMPING;
                }
                for integrator in ALL {
                    let gap = stage_gap(&spec, &system, dt, integrator, false);
                    assert!(gap <= 1e-9, "{id} {integrator} k {k} dt {dt}: {gap:e}");
                }
            }
        }
    }
    // Negative: a solver handed Backward Euler's problem of the step instead of the stage's.
    let system = thesis_rope(1e3).unwrap();
    let spec = SolverSpec::new(SolverId::Vbd, 400)
        .to_tolerance(1e-13)
        .unwrap();
    let gap = stage_gap(
        &spec,
        &system,
        1e-2,
        OptimizationIntegrator::ImplicitMidpoint,
        true,
    );
    assert!(gap > 1e-6, "{gap:e}");
}

/// The dissipation functions in the solvers that take them (Newton and damped ADMM-PD) reach
/// the Newton-solved damped stage under TR-BDF2 and Backward Euler: classical and
/// momentum-conserving Rayleigh damping and power-law drag.
#[test]
fn damped_admm_and_newton_reach_the_damped_newton_stage() {
    let dissipations = [
        Dissipation::rayleigh(CONVERGENCE_DAMPING),
        Dissipation {
            form: RayleighForm::MomentumConserving,
            ..Dissipation::rayleigh(CONVERGENCE_DAMPING)
        },
        Dissipation {
            drag: PowerLawDrag {
                coefficient: 2.0,
                exponent: 0.5,
            },
            ..Dissipation::NONE
        },
    ];
    for k in [1e3, 1e6] {
        let system = thesis_rope(k).unwrap();
        for d in dissipations {
            for id in [SolverId::DampedBackwardEuler, SolverId::DampedAdmm] {
                let mut spec = SolverSpec::new(id, 40_000).to_tolerance(1e-13).unwrap();
                spec.params.damping = d.rayleigh;
                spec.params.rayleigh_form = d.form;
                spec.params.drag = d.drag;
                for integrator in [
                    OptimizationIntegrator::BackwardEuler,
                    OptimizationIntegrator::TrBdf2,
                ] {
                    let gap = stage_gap(&spec, &system, 1e-2, integrator, false);
                    assert!(gap <= 1e-9, "{id} {d:?} {integrator} k {k}: {gap:e}");
                }
            }
        }
    }
}

/// One mass on a spring to a fixed anchor, along the spring, no gravity: $`m\ddot x = -kx -
/// (\alpha m + \beta k)\dot x`$, whose closed form is the damped oscillator's.
fn oscillator(k: f64, displacement: f64) -> MassSpringSystem {
    let node = |x: f64, fixed| Node {
        mass: 1.0,
        position: Vec3::new(x, 0.0, 0.0),
        velocity: Vec3::zeros(),
        fixed,
    };
    MassSpringSystem::new(
        vec![node(0.0, true), node(1.0 + displacement, false)],
        vec![Spring {
            a: 0,
            b: 1,
            rest_length: 1.0,
            stiffness: k,
            damping: 0.0,
        }],
        Vec3::zeros(),
    )
    .unwrap()
}

/// Rayleigh damping in TR-BDF2 against the damped oscillator's closed form (k = 100 N/m,
/// m = 1 kg, alpha = 0.5 1/s, beta = 1e-3 s: zeta = 0.035), at t = 2 s over dt 0.02 to
/// 0.0025 s: order 2 ± 0.1, and the finest error below 1e-3 of the amplitude. Negative: the
/// damping in the implicit half only is first order.
#[test]
fn rayleigh_damping_in_tr_bdf2_follows_the_damped_oscillator() {
    let (k, a0, t) = (100.0, 0.1, 2.0);
    let damping = RayleighDamping {
        alpha: 0.5,
        beta: 1e-3,
    };
    let c = damping.alpha + damping.beta * k;
    let omega = k.sqrt();
    let zeta = c / (2.0 * omega);
    let omega_d = omega * (1.0 - zeta * zeta).sqrt();
    let exact = a0
        * (-zeta * omega * t).exp()
        * ((omega_d * t).cos() + zeta * omega / omega_d * (omega_d * t).sin());
    let system = oscillator(k, a0);
    let d = Dissipation::rayleigh(damping);
    let errors = |build: &dyn Fn(f64) -> Box<dyn TimeStepper>| -> Vec<(f64, f64)> {
        [0.02, 0.01, 0.005, 0.0025]
            .iter()
            .map(|&dt| {
                let mut s = build(dt);
                let mut state = system.initial_state();
                for _ in 0..(t / dt).round() as usize {
                    s.step(&mut state).unwrap();
                }
                (dt, (state.x[1].x - 1.0 - exact).abs())
            })
            .collect()
    };
    let tr = errors(&|dt| {
        Box::new(exact_stages(&system, dt, OptimizationIntegrator::TrBdf2, d).unwrap())
    });
    assert!((fitted_slope(&tr) - 2.0).abs() <= 0.1, "{tr:?}");
    assert!(tr[3].1 < 1e-3 * a0, "{tr:?}");
    // The registry's damped Backward Euler solver under TR-BDF2 is the same scheme.
    let mut spec = SolverSpec::new(SolverId::DampedBackwardEuler, 50)
        .to_tolerance(1e-13)
        .unwrap();
    spec.params.damping = damping;
    spec.params.integrator = OptimizationIntegrator::TrBdf2;
    let newton = errors(&|dt| spec.build(&system, dt).unwrap());
    for (a, b) in newton.iter().zip(&tr) {
        assert!((a.1 - b.1).abs() < 1e-9, "{newton:?} {tr:?}");
    }
    let wrong = errors(&|dt| implicit_only(&system, dt, d));
    assert!((fitted_slope(&wrong) - 2.0).abs() > 0.1, "{wrong:?}");
}

/// The time in `[t0, t1]` at which the cubic Hermite interpolant of the speeds `v0`, `v1`
/// with their rates `a0`, `a1` falls to `level` (bisection; the speed decreases).
fn hermite_crossing(
    t0: f64,
    t1: f64,
    (v0, a0): (f64, f64),
    (v1, a1): (f64, f64),
    level: f64,
) -> f64 {
    let h = t1 - t0;
    let at = |t: f64| {
        let s = (t - t0) / h;
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * v0
            + (s3 - 2.0 * s2 + s) * h * a0
            + (-2.0 * s3 + 3.0 * s2) * v1
            + (s3 - s2) * h * a1
    };
    let (mut lo, mut hi) = (t0, t1);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if at(mid) > level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// A free mass of 1 kg at 1 m/s under drag c = 1 N·(s/m)^p, p = 2/3, no gravity: it stops after
/// $`t^* = 3`$ s and $`d^* = 0.75`$ m. The distance travelled (at $`2t^*`$, at rest to
/// round-off) and the time its speed falls to 1e-3 of the start's (closed form
/// $`t^*(1 - 10^{-3(1-p)}) = 0.9\,t^*`$; between steps, the cubic Hermite interpolant of the
/// speeds and their rates $`-c v^p/m`$) converge at the integrator's order, 1 ± 0.1 for
/// Backward Euler and 2 ± 0.1 for TR-BDF2, and Backward Euler fails the second-order check.
#[test]
fn power_law_drag_stops_at_the_closed_form_time_and_distance() {
    let drag = PowerLawDrag {
        coefficient: 1.0,
        exponent: 2.0 / 3.0,
    };
    let (t_star, d_star) = drag.stop(1.0, 1.0);
    assert!((t_star - 3.0).abs() < 1e-12 && (d_star - 0.75).abs() < 1e-12);
    let level: f64 = 1e-3;
    let t_level = t_star * (1.0 - level.powf(1.0 - drag.exponent));
    let system = MassSpringSystem::new(
        vec![Node {
            mass: 1.0,
            position: Vec3::zeros(),
            velocity: Vec3::new(1.0, 0.0, 0.0),
            fixed: false,
        }],
        Vec::new(),
        Vec3::zeros(),
    )
    .unwrap();
    let d = Dissipation {
        drag,
        ..Dissipation::NONE
    };
    let rate = |v: f64| -drag.coefficient * v.powf(drag.exponent);
    let slopes = |integrator| {
        let (mut distance, mut time) = (Vec::new(), Vec::new());
        for dt in [0.04, 0.02, 0.01, 0.005] {
            let mut s = exact_stages(&system, dt, integrator, d).unwrap();
            let mut state = system.initial_state();
            let (mut before, mut crossed) = ((0.0, 1.0), None);
            for j in 1..=(2.0 * t_star / dt).round() as usize {
                s.step(&mut state).unwrap();
                let (t, speed) = (j as f64 * dt, state.v[0].norm());
                if crossed.is_none() && speed < level {
                    let (t0, v0) = before;
                    crossed = Some(hermite_crossing(
                        t0,
                        t,
                        (v0, rate(v0)),
                        (speed, rate(speed)),
                        level,
                    ));
                }
                before = (t, speed);
            }
            assert!(state.v[0].norm() < 1e-9, "{integrator} {dt}: not stopped");
            distance.push((dt, (state.x[0].x - d_star).abs()));
            time.push((dt, (crossed.unwrap() - t_level).abs()));
        }
        (fitted_slope(&distance), fitted_slope(&time), distance, time)
    };
    for integrator in [
        OptimizationIntegrator::BackwardEuler,
        OptimizationIntegrator::TrBdf2,
    ] {
        let (d, t, distance, time) = slopes(integrator);
        let order = integrator.order() as f64;
        assert!((d - order).abs() <= 0.1, "{integrator} {distance:?}");
        assert!((t - order).abs() <= 0.1, "{integrator} {time:?}");
    }
    let (d, t, ..) = slopes(OptimizationIntegrator::BackwardEuler);
    assert!((d - 2.0).abs() > 0.1 && (t - 2.0).abs() > 0.1);
}

/// A free, unstressed rope (10 nodes of 1 kg, 1 m springs of 1e3 N/m, no gravity, no fixed
/// node) rotating rigidly at 1 rad/s about its centre: its angular momentum after 300 steps
/// of 0.01 s under the implicit midpoint rule with the momentum-conserving Rayleigh damping
/// (alpha 0.5 1/s, beta 1e-3 s) is kept to 1e-12 (relative), while the damping dissipates the
/// stretching the rotation causes; classical Rayleigh damping loses more than half of it, and
/// Backward Euler loses some of it even with the momentum-conserving form.
#[test]
fn the_midpoint_keeps_angular_momentum_under_momentum_conserving_damping() {
    let n = 10;
    let nodes: Vec<Node> = (0..n)
        .map(|i| {
            let x = i as f64 - 4.5;
            Node {
                mass: 1.0,
                position: Vec3::new(x, 0.0, 0.0),
                velocity: Vec3::new(0.0, x, 0.0),
                fixed: false,
            }
        })
        .collect();
    let springs = (0..n - 1)
        .map(|i| Spring {
            a: i,
            b: i + 1,
            rest_length: 1.0,
            stiffness: 1e3,
            damping: 0.0,
        })
        .collect();
    let system = MassSpringSystem::new(nodes, springs, Vec3::zeros()).unwrap();
    let angular = |s: &State| -> f64 { s.x.iter().zip(&s.v).map(|(x, v)| x.cross(v).z).sum() };
    let energy = |s: &State| s.kinetic_energy(&system) + system.potential_energy(&s.x);
    let run = |integrator, form| {
        let d = Dissipation {
            form,
            ..Dissipation::rayleigh(RayleighDamping {
                alpha: 0.5,
                beta: 1e-3,
            })
        };
        let mut s = exact_stages(&system, 1e-2, integrator, d).unwrap();
        let mut state = system.initial_state();
        let (l0, e0) = (angular(&state), energy(&state));
        let mut worst = 0.0_f64;
        for _ in 0..300 {
            s.step(&mut state).unwrap();
            worst = worst.max(((angular(&state) - l0) / l0).abs());
        }
        (worst, e0 - energy(&state))
    };
    let midpoint = OptimizationIntegrator::ImplicitMidpoint;
    let (kept, dissipated) = run(midpoint, RayleighForm::MomentumConserving);
    assert!(kept < 1e-12, "{kept:e}");
    assert!(dissipated > 1e-2, "{dissipated:e} J");
    let (lost, _) = run(midpoint, RayleighForm::Classical);
    assert!(lost > 0.5, "{lost:e}");
    let (lost, _) = run(
        OptimizationIntegrator::BackwardEuler,
        RayleighForm::MomentumConserving,
    );
    assert!(lost > 1e-3, "{lost:e}");
}

fn mss(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_mss"))
        .args(args)
        .output()
        .unwrap()
}

/// `mss --integrator` takes every integrator with every minimizing solver and says it; with
/// PBD, the XPBD family or a tutorial integrator it exits 2 naming both.
#[test]
fn mss_takes_every_integrator_with_every_minimizing_solver() {
    for id in minimizing_solvers() {
        for integrator in ALL {
            let out = mss(&[
                "--solver",
                id.id(),
                "--integrator",
                integrator.key(),
                "--dt",
                "1e-2",
                "--iterations",
                "10",
                "--max-time",
                "0.2",
                "--json",
            ]);
            assert!(out.status.success(), "{id} {integrator}: {out:?}");
            let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            assert_eq!(json["integrator"], integrator.key(), "{id}");
        }
    }
    for id in [
        SolverId::Pbd,
        SolverId::Xpbd,
        SolverId::XpbdSubsteps,
        SolverId::ExplicitEuler,
        SolverId::Rk4,
    ] {
        assert!(!id.is_minimizing());
        let out = mss(&["--solver", id.id(), "--integrator", "tr-bdf2"]);
        assert_eq!(out.status.code(), Some(2), "{id}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(id.id()) && err.contains("tr-bdf2") && err.contains("--integrator"),
            "{err}"
        );
    }
    let out = mss(&["--solver", "vbd", "--integrator", "rk4"]);
    assert_eq!(out.status.code(), Some(2));
}

/// The registry's Backward Euler under [`Integrated`] is the solver's own step bit for bit (the
/// thesis's tables run through it), and a BDF2 run restarts with TR-BDF2 from a state it did
/// not produce.
#[test]
fn backward_euler_is_the_solvers_own_step_and_bdf2_restarts() {
    let system = thesis_rope(1e6).unwrap();
    for id in minimizing_solvers() {
        let spec = SolverSpec::new(id, 7);
        let mut registry = spec.build(&system, 1e-2).unwrap();
        let mut own = spec.build_stage_solver(&system, 1e-2).unwrap();
        let (mut a, mut b) = (system.initial_state(), system.initial_state());
        for _ in 0..5 {
            registry.step(&mut a).unwrap();
            own.step(&mut b).unwrap();
        }
        assert_eq!(a, b, "{id}");
    }
    let mut bdf2 = exact_stages(
        &system,
        1e-2,
        OptimizationIntegrator::Bdf2,
        Dissipation::NONE,
    )
    .unwrap();
    let mut tr = exact_stages(
        &system,
        1e-2,
        OptimizationIntegrator::TrBdf2,
        Dissipation::NONE,
    )
    .unwrap();
    let start = Start::Step10.state(&system).unwrap();
    let (mut a, mut b) = (start.clone(), start.clone());
    bdf2.step(&mut a).unwrap();
    tr.step(&mut b).unwrap();
    assert_eq!(a, b, "the first BDF2 step is a TR-BDF2 step");
    let second = a.clone();
    bdf2.step(&mut a).unwrap();
    tr.step(&mut b).unwrap();
    assert!(largest_distance(&a.x, &b.x) > 0.0, "then BDF2 steps");
    // From a state it did not produce, BDF2 starts again with TR-BDF2.
    let (mut c, mut e) = (start.clone(), start);
    bdf2.step(&mut c).unwrap();
    let mut fresh_tr = exact_stages(
        &system,
        1e-2,
        OptimizationIntegrator::TrBdf2,
        Dissipation::NONE,
    )
    .unwrap();
    fresh_tr.step(&mut e).unwrap();
    assert_eq!(c, e);
    assert_eq!(c, second);
}

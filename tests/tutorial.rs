//! The tutorial's particle system (seed 004) against independent oracles: closed-form
//! oscillators for the convergence orders, the eigenvalues of the linearised thesis rope for
//! the stability limits, and elementary mechanics for the ground, the drag and momentum.

use mass_spring_solvers::model::metrics::StoppingRule;
use mass_spring_solvers::model::scene::thesis_rope;
use mass_spring_solvers::particles::scenes::{ClothDropParams, ClothParams, PendulumParams};
use mass_spring_solvers::particles::{
    DampedSprings, Drag, Gravity, Ground, Integrator, ParticleStepper, ParticleSystem, Particles,
};
use mass_spring_solvers::solvers::backward_euler::{BackwardEuler, ConvergedStepOptions};
use mass_spring_solvers::solvers::converged_stage::converged_step;
use mass_spring_solvers::{
    simulate, Error, MassSpringSystem, Node, RunOptions, Spring, State, TimeStepper, Vec3,
};
use nalgebra::{DMatrix, DVector};
use std::sync::OnceLock;

// ---------------------------------------------------------------------------------------------
// Convergence orders against the closed-form (damped) harmonic oscillator
// ---------------------------------------------------------------------------------------------

const MASS: f64 = 1.0;
const K: f64 = 100.0;
const REST: f64 = 1.0;
const U0: f64 = 0.1;
const V0: f64 = 0.5;
const FINAL_TIME: f64 = 1.0;

/// One free particle on a spring to an anchor at the origin, along x, no gravity: its
/// stretch obeys $m\ddot u = -k u - k_d \dot u$ exactly (the spring never leaves the x axis).
fn single_spring(k_d: f64) -> MassSpringSystem {
    let node = |x: f64, v: f64, fixed| Node {
        mass: MASS,
        position: Vec3::new(x, 0.0, 0.0),
        velocity: Vec3::new(v, 0.0, 0.0),
        fixed,
    };
    let spring = Spring {
        a: 0,
        b: 1,
        rest_length: REST,
        stiffness: K,
        damping: k_d,
    };
    MassSpringSystem::new(
        vec![node(0.0, 0.0, true), node(REST + U0, V0, false)],
        vec![spring],
        Vec3::zeros(),
    )
    .unwrap()
}

/// Closed form of $\ddot u + 2\zeta\omega\dot u + \omega^2 u = 0$ (underdamped):
/// $(u(t), \dot u(t))$.
fn oscillator(k_d: f64, t: f64) -> (f64, f64) {
    let omega = (K / MASS).sqrt();
    let zeta = k_d / (2.0 * MASS * omega);
    let omega_d = omega * (1.0 - zeta * zeta).sqrt();
    let decay = (-zeta * omega * t).exp();
    let (s, c) = (omega_d * t).sin_cos();
    let u = decay * (U0 * c + (V0 + zeta * omega * U0) / omega_d * s);
    let v = decay * (V0 * c - (omega * omega * U0 + zeta * omega * V0) / omega_d * s);
    (u, v)
}

/// Error in the phase plane, $\sqrt{e_u^2 + (e_v/\omega)^2}$, at `FINAL_TIME` (so that a
/// zero crossing of one component cannot fake a small error).
fn final_error(stepper: &mut dyn TimeStepper, k_d: f64) -> f64 {
    let mut state = stepper.system().initial_state();
    let steps = (FINAL_TIME / stepper.dt()).round() as usize;
    assert!((steps as f64 * stepper.dt() - FINAL_TIME).abs() < 1e-12);
    for _ in 0..steps {
        stepper.step(&mut state).unwrap();
    }
    let (u, v) = oscillator(k_d, FINAL_TIME);
    let omega = (K / MASS).sqrt();
    let e_u = state.x[1].x - REST - u;
    let e_v = state.v[1].x - v;
    assert!(state.x[1].y == 0.0 && state.x[1].z == 0.0);
    (e_u * e_u + (e_v / omega).powi(2)).sqrt()
}

/// Least-squares slope of log(error) against log(dt), and the slopes between neighbours.
fn observed_order(dts: &[f64], errors: &[f64]) -> (f64, Vec<f64>) {
    let lx: Vec<f64> = dts.iter().map(|d| d.ln()).collect();
    let ly: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let n = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    let pairs = lx
        .windows(2)
        .zip(ly.windows(2))
        .map(|(x, y)| (y[1] - y[0]) / (x[1] - x[0]))
        .collect();
    (sxy / sxx, pairs)
}

fn assert_order(
    label: &str,
    expected: f64,
    dts: &[f64],
    make: impl Fn(f64) -> Box<dyn TimeStepper>,
    k_d: f64,
) {
    let errors: Vec<f64> = dts
        .iter()
        .map(|&dt| final_error(make(dt).as_mut(), k_d))
        .collect();
    let (slope, pairs) = observed_order(dts, &errors);
    println!("{label}: errors {errors:.3?}, pairwise slopes {pairs:.4?}, fitted slope {slope:.4}");
    for p in &pairs {
        assert!(
            (p - expected).abs() <= 0.1,
            "{label}: pairwise slope {p} not within 0.1 of {expected} (errors {errors:?})"
        );
    }
    assert!((slope - expected).abs() <= 0.1, "{label}: slope {slope}");
}

fn halvings(coarsest: f64, count: usize) -> Vec<f64> {
    (0..count).map(|j| coarsest / 2f64.powi(j as i32)).collect()
}

fn tutorial_stepper(system: MassSpringSystem, integrator: Integrator, dt: f64) -> ParticleStepper {
    ParticleStepper::new(ParticleSystem::from_system(system), integrator, dt).unwrap()
}

const DAMPING: f64 = 2.0; // zeta = 0.1

#[test]
fn explicit_euler_is_first_order() {
    // The tutorial says "Euler es un Runge-Kutta de orden 2": the measured order is 1.
    assert_order(
        "explicit Euler",
        1.0,
        &halvings(1e-3, 5),
        |dt| {
            Box::new(tutorial_stepper(
                single_spring(DAMPING),
                Integrator::ExplicitEuler,
                dt,
            ))
        },
        DAMPING,
    );
}

#[test]
fn symplectic_euler_is_first_order() {
    assert_order(
        "symplectic Euler",
        1.0,
        &halvings(1e-3, 5),
        |dt| {
            Box::new(tutorial_stepper(
                single_spring(DAMPING),
                Integrator::SymplecticEuler,
                dt,
            ))
        },
        DAMPING,
    );
}

#[test]
fn rk4_is_fourth_order_on_a_damped_spring() {
    assert_order(
        "RK4",
        4.0,
        &halvings(2e-2, 5),
        |dt| {
            Box::new(tutorial_stepper(
                single_spring(DAMPING),
                Integrator::Rk4,
                dt,
            ))
        },
        DAMPING,
    );
}

#[test]
fn backward_euler_is_first_order_on_an_undamped_spring() {
    // Backward Euler's force model has no spring damping: the undamped oscillator.
    assert_order(
        "Backward Euler",
        1.0,
        &halvings(1e-3, 5),
        |dt| Box::new(BackwardEuler::new(&single_spring(0.0), dt, 10).unwrap()),
        0.0,
    );
}

// ---------------------------------------------------------------------------------------------
// Stability on the thesis rope at its static equilibrium
// ---------------------------------------------------------------------------------------------

const ROPE_K: f64 = 1e3;

struct Linearised {
    system: MassSpringSystem,
    equilibrium: State,
    /// Largest angular frequency of the linearised free DOFs, rad/s.
    omega_max: f64,
    /// Its mode as a displacement per node, normalised so that $u^\top M u = 1$.
    mode: Vec<Vec3>,
}

/// The thesis rope at rest: Backward Euler steps of 10 s from rest, restarted at rest each time,
/// descend the potential until the position stops changing; then the eigen-decomposition of
/// $M^{-1/2} K M^{-1/2}$, $K = -dF/dx$ (Eq 4 blocks) on the free DOFs.
fn linearised_rope() -> &'static Linearised {
    static CELL: OnceLock<Linearised> = OnceLock::new();
    CELL.get_or_init(|| {
        let system = thesis_rope(ROPE_K).unwrap();
        let mut state = system.initial_state();
        for _ in 0..200 {
            let next =
                converged_step(&system, &state, 10.0, ConvergedStepOptions::default()).unwrap();
            let moved = next
                .x
                .iter()
                .zip(&state.x)
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f64::max);
            state = State {
                v: vec![Vec3::zeros(); next.x.len()],
                x: next.x,
            };
            if moved < 1e-13 {
                break;
            }
        }
        let mut f = vec![Vec3::zeros(); system.len()];
        system.forces(&state.x, &mut f);
        let residual = f.iter().map(|f| f.norm()).fold(0.0, f64::max);
        assert!(residual < 1e-8, "equilibrium force residual {residual} N");

        let free: Vec<usize> = (0..system.len())
            .filter(|&i| !system.nodes()[i].fixed)
            .collect();
        // K = -dF/dx restricted to the free unknowns.
        let dofs: Vec<usize> = free
            .iter()
            .flat_map(|&i| (0..3).map(move |c| 3 * i + c))
            .collect();
        let n = dofs.len();
        let jacobian = system.force_jacobian_dense(&state.x);
        let k = DMatrix::from_fn(n, n, |r, c| -jacobian[(dofs[r], dofs[c])]);
        let inv_sqrt_m = DVector::from_fn(n, |r, _| 1.0 / system.nodes()[free[r / 3]].mass.sqrt());
        let scaled = DMatrix::from_fn(n, n, |r, c| inv_sqrt_m[r] * k[(r, c)] * inv_sqrt_m[c]);
        let eigen = scaled.symmetric_eigen();
        let (top, lambda_max) =
            eigen
                .eigenvalues
                .iter()
                .copied()
                .enumerate()
                .fold(
                    (0, f64::MIN),
                    |best, (i, l)| if l > best.1 { (i, l) } else { best },
                );
        assert!(
            eigen.eigenvalues.iter().all(|&l| l > 0.0),
            "K is positive definite at rest"
        );
        let column = eigen.eigenvectors.column(top);
        let mut mode = vec![Vec3::zeros(); system.len()];
        for (r, value) in column.iter().enumerate() {
            mode[free[r / 3]][r % 3] = value * inv_sqrt_m[r];
        }
        Linearised {
            system,
            equilibrium: state,
            omega_max: lambda_max.sqrt(),
            mode,
        }
    })
}

impl Linearised {
    /// The equilibrium displaced by `amplitude` (m·√kg) along the top mode, at rest.
    fn perturbed(&self, amplitude: f64) -> State {
        let mut state = self.equilibrium.clone();
        for (x, u) in state.x.iter_mut().zip(&self.mode) {
            *x += amplitude * u;
        }
        state
    }

    /// The top mode's amplitude in the phase plane, $\sqrt{q^2 + (\dot q/\omega)^2}$ with
    /// $q = u^\top M (x - x_{eq})$.
    fn modal_amplitude(&self, state: &State) -> f64 {
        let project = |d: &dyn Fn(usize) -> Vec3| -> f64 {
            (0..self.system.len())
                .map(|i| self.system.nodes()[i].mass * self.mode[i].dot(&d(i)))
                .sum()
        };
        let q = project(&|i| state.x[i] - self.equilibrium.x[i]);
        let q_dot = project(&|i| state.v[i]);
        (q * q + (q_dot / self.omega_max).powi(2)).sqrt()
    }

    fn stepper(&self, integrator: Integrator, dt: f64) -> ParticleStepper {
        tutorial_stepper(self.system.clone(), integrator, dt)
    }
}

/// Runs `steps` steps through `simulate` with a stopping rule that never fires.
fn run_for(stepper: &mut ParticleStepper, state: State, steps: u64) -> Result<State, Error> {
    let options = RunOptions {
        stop: StoppingRule {
            threshold: f64::MIN_POSITIVE,
            max_time: steps as f64 * stepper.dt(),
            exempt_first_peak: false,
        },
        ..RunOptions::default()
    };
    simulate(stepper, state, &options).map(|run| {
        assert_eq!(run.steps, steps);
        run.final_state
    })
}

/// Asserts that `result` is a divergence reported with its step and time, not a NaN state.
fn assert_diverged(label: &str, result: Result<State, Error>, dt: f64) -> u64 {
    match result {
        Err(Error::Diverged {
            step, time, reason, ..
        }) => {
            assert!(step > 0);
            assert!(
                (time - step as f64 * dt).abs() <= 1e-9 * time,
                "{label}: time {time} at step {step}"
            );
            println!("{label}: diverged at step {step} (t = {time:.6} s): {reason}");
            step
        }
        other => panic!("{label}: expected Error::Diverged, got {other:?}"),
    }
}

const PERTURBATION: f64 = 1e-6;
const STABLE_STEPS: u64 = 20_000;

/// Growth per step of the top mode's amplitude in its linear regime, measured between steps
/// `from` and `to` of a run started 1e-9 along the mode (after `from` steps only the dominant
/// eigenvector of the step's 2×2 map is left).
fn linear_growth(integrator: Integrator, dt: f64, from: usize, to: usize) -> f64 {
    let rope = linearised_rope();
    let mut stepper = rope.stepper(integrator, dt);
    let mut state = rope.perturbed(1e-9);
    let mut a_from = 0.0;
    for n in 1..=to {
        stepper.step(&mut state).unwrap();
        if n == from {
            a_from = rope.modal_amplitude(&state);
        }
    }
    (rope.modal_amplitude(&state) / a_from).powf(1.0 / (to - from) as f64)
}

/// Stable just below `limit`/ω_max: the top mode stays bounded over many steps. Unstable just
/// above: the mode grows per step by the linear theory's factor, `amplification(ω_max·dt)`.
/// Returns the dt at the limit.
fn assert_stability_limit(
    integrator: Integrator,
    limit: f64,
    amplification: impl Fn(f64) -> f64,
) -> f64 {
    let rope = linearised_rope();
    let dt_limit = limit / rope.omega_max;
    println!(
        "{integrator}: omega_max = {:.6} rad/s, limit {limit:.6}/omega_max = {dt_limit:.6e} s",
        rope.omega_max
    );

    let below = 0.98 * dt_limit;
    let mut stepper = rope.stepper(integrator, below);
    let start = rope.perturbed(PERTURBATION);
    let a0 = rope.modal_amplitude(&start);
    let end = run_for(&mut stepper, start, STABLE_STEPS).unwrap();
    let growth = rope.modal_amplitude(&end) / a0;
    let drift = end
        .x
        .iter()
        .zip(&rope.equilibrium.x)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    println!("{integrator} at 0.98x: top-mode amplitude x{growth:.3e} after {STABLE_STEPS} steps, max |x - x_eq| = {drift:.3e} m");
    // Symplectic Euler's invariant ellipse q² + p² - a·q·p (p = q'/ω, a = ωh) lets the
    // amplitude swing up to 1/√(1 - a/2) = 7.1 times its start at a = 1.96; RK4 contracts.
    assert!(
        growth < 10.0,
        "{integrator} at 0.98x the limit: mode grew x{growth}"
    );
    assert!(drift < 100.0 * PERTURBATION);

    let measured = linear_growth(integrator, 1.02 * dt_limit, 10, 40);
    let expected = amplification(1.02 * limit);
    println!("{integrator} at 1.02x: top-mode growth per step {measured:.6} (linear theory {expected:.6})");
    assert!(expected > 1.1, "{expected}");
    assert!(
        (measured - expected).abs() < 1e-3 * expected,
        "{measured} vs {expected}"
    );
    dt_limit
}

#[test]
fn symplectic_euler_is_stable_below_two_over_omega_max() {
    // Symplectic Euler on $\ddot q = -\omega^2 q$: $\lambda^2 - (2 - a^2)\lambda + 1 = 0$ with
    // $a = \omega h$; |λ| = 1 while $a \le 2$, beyond it a real root below -1.
    let dt_limit = assert_stability_limit(Integrator::SymplecticEuler, 2.0, |a| {
        let b = a * a - 2.0;
        (b + (b * b - 4.0).sqrt()) / 2.0
    });
    // Just above the limit the run blows up, and the run loop says when.
    let rope = linearised_rope();
    let dt = 1.02 * dt_limit;
    let mut stepper = rope.stepper(Integrator::SymplecticEuler, dt);
    let step = assert_diverged(
        "symplectic Euler at 1.02x",
        run_for(&mut stepper, rope.perturbed(PERTURBATION), STABLE_STEPS),
        dt,
    );
    assert!(step < STABLE_STEPS);
}

/// RK4's stability function $R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24$ on the imaginary axis:
/// $|R(iy)| = \sqrt{1 - y^6/72 + y^8/576}$.
fn rk4_amplification(y: f64) -> f64 {
    (1.0 - y.powi(6) / 72.0 + y.powi(8) / 576.0).sqrt()
}

#[test]
fn rk4_is_stable_below_two_sqrt_two_over_omega_max() {
    // The undamped rope's first-order system has eigenvalues ±iω, so the limit is where RK4's
    // stability region meets the imaginary axis: $|R(iy)| \le 1 \iff y^8/576 \le y^6/72 \iff
    // y \le 2\sqrt2 \approx 2.828$. The other figure, 2.785, is where the region meets the
    // negative real axis ($R(-2.785) \approx 1$): it bounds pure decay (drag, overdamped modes),
    // not oscillation, so it is not the limit here.
    let y = 2.0 * 2f64.sqrt();
    assert!((rk4_amplification(y) - 1.0).abs() < 1e-12);
    assert!(rk4_amplification(0.999 * y) < 1.0 && rk4_amplification(1.001 * y) > 1.0);
    let r = |z: f64| 1.0 + z + z * z / 2.0 + z.powi(3) / 6.0 + z.powi(4) / 24.0;
    assert!(r(-2.785).abs() < 1.0 && r(-2.786).abs() > 1.0);
    let dt_limit = assert_stability_limit(Integrator::Rk4, y, rk4_amplification);

    // At 1.02x the top mode grows by 1.15 per step, but the growth saturates: once the rope
    // flails, slack springs lower its effective frequencies into RK4's dissipative region
    // (|R(iy)| < 1 below 2√2), and the kinetic energy stays near 1e2 J, far from the run
    // loop's divergence threshold. A little further above the limit it no longer saturates.
    let rope = linearised_rope();
    let mut stepper = rope.stepper(Integrator::Rk4, 1.02 * dt_limit);
    let mut state = rope.perturbed(PERTURBATION);
    let start_energy =
        rope.system.potential_energy(&state.x) - rope.system.potential_energy(&rope.equilibrium.x);
    let mut peak = 0.0_f64;
    for _ in 0..4000 {
        stepper.step(&mut state).unwrap();
        peak = peak.max(state.kinetic_energy(&rope.system));
    }
    println!("RK4 at 1.02x: perturbation energy {start_energy:.2e} J grows to kinetic-energy peaks of {peak:.3e} J in 4000 steps, then saturates");
    assert!(
        peak > 1e9 * start_energy,
        "the perturbation grew by orders of magnitude"
    );
    let dt = 1.1 * dt_limit;
    let mut stepper = rope.stepper(Integrator::Rk4, dt);
    let step = assert_diverged(
        "RK4 at 1.1x",
        run_for(&mut stepper, rope.perturbed(PERTURBATION), STABLE_STEPS),
        dt,
    );
    assert!(step < STABLE_STEPS);
}

#[test]
fn explicit_euler_grows_at_every_dt() {
    // Explicit Euler on $\ddot q = -\omega^2 q$ maps $(q, \dot q/\omega)$ by a rotation scaled by
    // $\sqrt{1 + \omega^2h^2}$: the amplitude grows at every step, whatever h.
    let rope = linearised_rope();
    for fraction in [0.01, 0.1, 0.5, 1.0, 2.0] {
        let dt = fraction / rope.omega_max;
        let steps = (3.0 / (1.0 + fraction * fraction).ln().max(1e-12))
            .ceil()
            .min(1e5) as u64;
        let start = rope.perturbed(1e-8);
        let a0 = rope.modal_amplitude(&start);
        let mut stepper = rope.stepper(Integrator::ExplicitEuler, dt);
        let end = run_for(&mut stepper, start, steps).unwrap();
        let measured = (rope.modal_amplitude(&end) / a0).powf(1.0 / steps as f64);
        let expected = (1.0 + fraction * fraction).sqrt();
        println!(
            "explicit Euler, omega_max dt = {fraction}: growth per step {measured:.9} (expected {expected:.9}) over {steps} steps"
        );
        assert!(
            (measured - expected).abs() <= 1e-6 * (expected - 1.0).max(1e-3),
            "growth {measured} vs {expected}"
        );
    }
    // And it eventually blows up, reported by the run loop, even well inside symplectic Euler's limit.
    let dt = 0.5 / rope.omega_max;
    let mut stepper = rope.stepper(Integrator::ExplicitEuler, dt);
    assert_diverged(
        "explicit Euler at 0.5/omega_max",
        run_for(&mut stepper, rope.perturbed(PERTURBATION), 100_000),
        dt,
    );
}

// ---------------------------------------------------------------------------------------------
// Tutorial physics
// ---------------------------------------------------------------------------------------------

fn single_particle(height: f64, gravity: f64) -> MassSpringSystem {
    MassSpringSystem::new(
        vec![Node {
            mass: 2.0,
            position: Vec3::new(0.0, height, 0.0),
            velocity: Vec3::zeros(),
            fixed: false,
        }],
        vec![],
        Vec3::new(0.0, -gravity, 0.0),
    )
    .unwrap()
}

#[test]
fn a_dropped_particle_rebounds_to_e_squared_h() {
    let (h, g): (f64, f64) = (1.0, 9.81);
    let v_impact = (2.0 * g * h).sqrt();
    for e in [0.0, 0.5, 0.8, 1.0] {
        for integrator in Integrator::ALL {
            for dt in [1e-3, 1e-4] {
                let particles = ParticleSystem::from_system(single_particle(h, g))
                    .with_ground(Ground::new(0.0, e).unwrap());
                let mut stepper = ParticleStepper::new(particles, integrator, dt).unwrap();
                let mut state = stepper.system().initial_state();
                let mut bounced = false;
                let mut apex: f64 = 0.0;
                let t_end = (2.0 * h / g).sqrt() * (1.0 + e) + 0.05;
                for _ in 0..(t_end / dt) as usize {
                    stepper.step(&mut state).unwrap();
                    assert!(state.x[0].y >= 0.0, "below the floor");
                    if state.x[0].y == 0.0 {
                        bounced = true;
                    }
                    if bounced {
                        apex = apex.max(state.x[0].y);
                    }
                }
                assert!(bounced);
                let error = (apex - e * e * h).abs();
                println!("{integrator}, e = {e}, dt = {dt:e}: rebound {apex:.6} m (e²h = {:.6} m), error {error:.2e} m = {:.2} v_impact·dt", e * e * h, error / (v_impact * dt));
                // Two first-order errors. Contact is seen up to one step late, at a depth
                // d <= v·dt, and the particle leaves with the speed gained down to -d: up to
                // e²·v·dt more height. Explicit Euler also gains v·dt/2 of height on the way
                // down and e·v·dt/2 on the way up (x lags the exact velocity): at e = 1 the
                // worst case is 2·v·dt; symplectic Euler and RK4 stay well inside it.
                assert!(
                    error <= 2.5 * v_impact * dt,
                    "{integrator} e={e} dt={dt}: {apex} vs {}",
                    e * e * h
                );
            }
        }
    }
}

#[test]
fn drag_alone_reaches_the_terminal_velocity() {
    let (g, k_f, mass) = (9.81, 4.0, 2.0);
    let terminal = mass * g / k_f;
    let tau = mass / k_f;
    for integrator in Integrator::ALL {
        let dt = 1e-3;
        let particles = ParticleSystem::from_system(single_particle(0.0, g))
            .with_force(Box::new(Drag {
                k_f,
                particles: Particles::All,
            }))
            .unwrap();
        let mut stepper = ParticleStepper::new(particles, integrator, dt).unwrap();
        let mut state = stepper.system().initial_state();
        // The transient: v(t) = -v_t (1 - e^{-t/τ}), checked at t = τ.
        let n_tau = (tau / dt).round() as usize;
        for _ in 0..n_tau {
            stepper.step(&mut state).unwrap();
        }
        let closed = -terminal * (1.0 - (-1f64).exp());
        let tolerance = if integrator == Integrator::Rk4 {
            1e-12
        } else {
            terminal * dt / tau
        };
        assert!(
            (state.v[0].y - closed).abs() < tolerance,
            "{integrator}: v(τ) = {} vs {closed}",
            state.v[0].y
        );
        for _ in 0..(40.0 * tau / dt) as usize {
            stepper.step(&mut state).unwrap();
        }
        println!(
            "{integrator}: terminal velocity {:.12} m/s (m g / k_f = {terminal})",
            -state.v[0].y
        );
        assert!((state.v[0].y + terminal).abs() < 1e-9 * terminal);
        assert!(state.v[0].x == 0.0 && state.v[0].z == 0.0);
    }
}

/// A cloth in free space (no gravity, no anchors), stretched and spun with a pseudo-random
/// velocity field.
fn moving_cloth() -> (MassSpringSystem, State) {
    let params = ClothParams {
        nx: 6,
        ny: 5,
        gravity: 0.0,
        ..ClothParams::default()
    };
    let system = params.horizontal(1.0).unwrap();
    let mut state = system.initial_state();
    for (i, (x, v)) in state.x.iter_mut().zip(&mut state.v).enumerate() {
        let s = i as f64;
        *x += 0.02 * Vec3::new((1.3 * s).sin(), (2.1 * s).cos(), (0.7 * s).sin());
        *v = Vec3::new((0.9 * s).cos(), (1.7 * s).sin(), 0.3 + (0.4 * s).cos());
    }
    (system, state)
}

#[test]
fn the_cloth_conserves_linear_momentum_without_gravity_and_anchors() {
    for integrator in Integrator::ALL {
        let (system, start) = moving_cloth();
        // dt well inside every method's stability limit (explicit Euler included).
        let mut stepper = tutorial_stepper(system, integrator, 1e-4);
        let p0 = stepper.particles().momentum(&start);
        let mut state = start.clone();
        for _ in 0..5000 {
            stepper.step(&mut state).unwrap();
        }
        let p = stepper.particles().momentum(&state);
        let moved = state
            .x
            .iter()
            .zip(&start.x)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        println!("{integrator}: |P - P0| = {:.2e} kg·m/s (|P0| = {:.3}), particles moved up to {moved:.3} m", (p - p0).norm(), p0.norm());
        assert!(moved > 0.3, "the springs did work");
        assert!(
            (p - p0).norm() <= 1e-13 * p0.norm().max(1.0),
            "{integrator}: {p} vs {p0}"
        );
    }
}

#[test]
fn anchored_particles_never_move() {
    let system = ClothParams::default().hanging().unwrap();
    let pinned: Vec<usize> = (0..system.len())
        .filter(|&i| system.nodes()[i].fixed)
        .collect();
    assert_eq!(pinned.len(), 2);
    let start = system.initial_state();
    let mut steppers: Vec<Box<dyn TimeStepper>> = Integrator::ALL
        .into_iter()
        .map(|i| Box::new(tutorial_stepper(system.clone(), i, 1e-4)) as Box<dyn TimeStepper>)
        .collect();
    // The thesis's Backward Euler rejects spring damping: it runs the same cloth undamped.
    let undamped = ClothParams {
        damping: 0.0,
        ..ClothParams::default()
    }
    .hanging()
    .unwrap();
    assert_eq!(undamped.initial_state(), start);
    steppers.push(Box::new(BackwardEuler::new(&undamped, 1e-3, 3).unwrap()));
    for stepper in &mut steppers {
        let mut state = start.clone();
        for _ in 0..(1.0 / stepper.dt()).round() as usize {
            stepper.step(&mut state).unwrap();
            for &i in &pinned {
                assert_eq!(state.x[i], start.x[i], "{}", stepper.name());
            }
        }
        let lowest = state.x.iter().map(|x| x.y).fold(f64::INFINITY, f64::min);
        assert!(
            lowest < -1.0,
            "{}: the cloth fell ({lowest})",
            stepper.name()
        );
    }
}

#[test]
fn several_gravities_act_on_their_own_particles() {
    // Two free particles, one pulled down, the other sideways; g in the system only sets the
    // divergence guard's scale.
    let node = |x: f64| Node {
        mass: 3.0,
        position: Vec3::new(x, 0.0, 0.0),
        velocity: Vec3::zeros(),
        fixed: false,
    };
    let system = MassSpringSystem::new(
        vec![node(0.0), node(5.0)],
        vec![],
        Vec3::new(0.0, -9.81, 0.0),
    )
    .unwrap();
    let down = Gravity {
        g: Vec3::new(0.0, -9.81, 0.0),
        particles: Particles::Only(vec![0]),
    };
    let side = Gravity {
        g: Vec3::new(2.0, 0.0, 0.0),
        particles: Particles::Only(vec![1]),
    };
    let particles = ParticleSystem::new(system, vec![Box::new(down), Box::new(side)]).unwrap();
    let mut stepper = ParticleStepper::new(particles, Integrator::Rk4, 1e-2).unwrap();
    let mut state = stepper.system().initial_state();
    for _ in 0..100 {
        stepper.step(&mut state).unwrap();
    }
    // RK4 integrates constant accelerations exactly: x = x0 + g t²/2 at t = 1 s.
    assert!((state.x[0] - Vec3::new(0.0, -9.81 / 2.0, 0.0)).norm() < 1e-12);
    assert!((state.x[1] - Vec3::new(6.0, 0.0, 0.0)).norm() < 1e-12);
}

#[test]
fn undamped_particle_forces_equal_the_thesis_forces() {
    let system = ClothParams {
        nx: 6,
        ny: 5,
        damping: 0.0,
        ..ClothParams::default()
    }
    .hanging()
    .unwrap();
    let (_, moving) = moving_cloth();
    let state = State {
        x: system
            .initial_state()
            .x
            .iter()
            .zip(&moving.x)
            .map(|(a, b)| a + 0.01 * b)
            .collect(),
        v: moving.v.clone(),
    };
    let mut thesis = vec![Vec3::zeros(); system.len()];
    system.forces(&state.x, &mut thesis);
    let particles = ParticleSystem::from_system(system.clone());
    let mut f = vec![Vec3::zeros(); system.len()];
    particles.accumulate_forces(&state, &mut f);
    for (i, node) in system.nodes().iter().enumerate() {
        if !node.fixed {
            assert!((f[i] - thesis[i]).norm() < 1e-12, "particle {i}");
        }
    }
}

#[test]
fn the_damped_spring_resists_the_approach_speed() {
    // Two particles approaching along x at relative speed 2 m/s, spring at rest length: only
    // the damping acts, f_a = -k_d (l'·l̂) l̂.
    let system = MassSpringSystem::new(
        vec![
            Node {
                mass: 1.0,
                position: Vec3::new(1.0, 0.0, 0.0),
                velocity: Vec3::new(-1.0, 0.0, 0.0),
                fixed: false,
            },
            Node {
                mass: 1.0,
                position: Vec3::zeros(),
                velocity: Vec3::new(1.0, 0.5, 0.0),
                fixed: false,
            },
        ],
        vec![Spring {
            a: 0,
            b: 1,
            rest_length: 1.0,
            stiffness: 50.0,
            damping: 3.0,
        }],
        Vec3::zeros(),
    )
    .unwrap();
    let particles = ParticleSystem::new(system.clone(), vec![Box::new(DampedSprings)]).unwrap();
    let mut f = vec![Vec3::zeros(); 2];
    particles.accumulate_forces(&system.initial_state(), &mut f);
    // l = x_a - x_b = +x, l' = v_a - v_b = (-2, -0.5, 0): l'·l̂ = -2, f_a = +6 x̂.
    assert!((f[0] - Vec3::new(6.0, 0.0, 0.0)).norm() < 1e-15);
    assert_eq!(f[1], -f[0]);
}

#[test]
fn the_tutorial_cloth_falls_ten_metres_and_lands() {
    let params = ClothDropParams::tutorial();
    for integrator in [Integrator::SymplecticEuler, Integrator::Rk4] {
        let particles = params.build().unwrap();
        let mut stepper = ParticleStepper::new(particles, integrator, 1e-3).unwrap();
        let mut state = stepper.system().initial_state();
        let mut landed = None;
        for n in 1..=4000 {
            stepper.step(&mut state).unwrap();
            assert!(state.x.iter().all(|x| x.y >= 0.0));
            if landed.is_none() && state.x.iter().any(|x| x.y == 0.0) {
                landed = Some(n as f64 * 1e-3);
            }
        }
        let t = landed.expect("the cloth reached the floor");
        // Free fall from 10 m takes √(2h/g) = 1.428 s; the light drag delays it slightly.
        println!("{integrator}: cloth lands at t = {t:.3} s");
        assert!((t - (2.0 * 10.0 / 9.81f64).sqrt()).abs() < 0.01);
        let top = state.x.iter().map(|x| x.y).fold(0.0, f64::max);
        let speed = state.v.iter().map(|v| v.norm()).fold(0.0, f64::max);
        println!("{integrator}: 2.6 s after landing, highest particle {top:.2e} m, fastest {speed:.2e} m/s");
        assert!(top < 0.05, "the cloth lies on the floor");
    }
}

#[test]
fn the_tutorial_pendulum_bounces_and_loses_energy() {
    let particles = PendulumParams::tutorial().build().unwrap();
    let mut stepper = ParticleStepper::new(particles, Integrator::SymplecticEuler, 1e-3).unwrap();
    let system = stepper.system().clone();
    let energy = |s: &State| s.kinetic_energy(&system) + system.potential_energy(&s.x);
    let mut state = system.initial_state();
    let e0 = energy(&state);
    let mut contacts = 0;
    let mut energy_before_contact = None;
    for _ in 0..5000 {
        let was_touching = state.x.iter().any(|x| x.y == 0.0);
        let before = energy(&state);
        stepper.step(&mut state).unwrap();
        assert!(state.x.iter().all(|x| x.y >= 0.0));
        assert_eq!(
            state.x[0],
            system.nodes()[0].position,
            "the pivot is anchored"
        );
        if !was_touching && state.x.iter().any(|x| x.y == 0.0) {
            contacts += 1;
            energy_before_contact.get_or_insert(before);
        }
    }
    let e_end = energy(&state);
    println!("pendulum: {contacts} contacts, energy {e0:.3} J -> {:.3} J before the first contact -> {e_end:.3} J after 5 s", energy_before_contact.unwrap());
    assert!(contacts >= 2, "it bounces");
    assert!(e_end < energy_before_contact.unwrap() && e_end < e0);
}

#[test]
fn bad_parameters_are_rejected_with_their_field() {
    let field = |r: Result<(), Error>| match r {
        Err(Error::InvalidParameter { field, .. }) => field,
        other => panic!("expected InvalidParameter, got {other:?}"),
    };
    let system = single_spring(0.0);
    let with = |f: Box<dyn mass_spring_solvers::particles::Force>| {
        ParticleSystem::from_system(system.clone())
            .with_force(f)
            .map(|_| ())
    };
    assert_eq!(
        field(with(Box::new(Drag {
            k_f: -1.0,
            particles: Particles::All
        }))),
        "drag.k_f"
    );
    assert_eq!(
        field(with(Box::new(Drag {
            k_f: 1.0,
            particles: Particles::Only(vec![0, 7])
        }))),
        "drag.particles[1]"
    );
    assert_eq!(
        field(with(Box::new(Gravity {
            g: Vec3::new(0.0, f64::NAN, 0.0),
            particles: Particles::All
        }))),
        "gravity.g[1]"
    );
    assert_eq!(
        field(with(Box::new(Gravity {
            g: Vec3::zeros(),
            particles: Particles::Only(vec![])
        }))),
        "gravity.particles"
    );
    assert_eq!(
        field(Ground::new(0.0, 1.5).map(|_| ())),
        "ground.restitution"
    );
    assert_eq!(
        field(Ground::new(0.0, -0.1).map(|_| ())),
        "ground.restitution"
    );
    assert_eq!(
        field(Ground::new(f64::INFINITY, 0.5).map(|_| ())),
        "ground.height"
    );
    let particles = || ParticleSystem::from_system(system.clone());
    assert_eq!(
        field(ParticleStepper::new(particles(), Integrator::Rk4, 0.0).map(|_| ())),
        "dt"
    );
    assert_eq!(
        field(ParticleStepper::new(particles(), Integrator::Rk4, f64::NAN).map(|_| ())),
        "dt"
    );
    assert_eq!(
        field("heun".parse::<Integrator>().map(|_| ())),
        "integrator"
    );
    assert_eq!("rk4".parse::<Integrator>().unwrap(), Integrator::Rk4);
    let cloth = ClothParams::default();
    for (params, name) in [
        (
            ClothParams {
                nx: 1,
                ..cloth.clone()
            },
            "cloth.nx",
        ),
        (
            ClothParams {
                ny: 0,
                ..cloth.clone()
            },
            "cloth.ny",
        ),
        (
            ClothParams {
                spacing: 0.0,
                ..cloth.clone()
            },
            "cloth.spacing",
        ),
        (
            ClothParams {
                particle_mass: -1.0,
                ..cloth.clone()
            },
            "cloth.particle_mass",
        ),
        (
            ClothParams {
                stiffness: 0.0,
                ..cloth.clone()
            },
            "cloth.stiffness",
        ),
        (
            ClothParams {
                damping: -1.0,
                ..cloth.clone()
            },
            "cloth.damping",
        ),
        (
            ClothParams {
                gravity: f64::NAN,
                ..cloth.clone()
            },
            "cloth.gravity",
        ),
    ] {
        assert_eq!(field(params.hanging().map(|_| ())), name);
        assert_eq!(field(params.horizontal(1.0).map(|_| ())), name);
    }
    assert_eq!(
        field(cloth.horizontal(f64::NAN).map(|_| ())),
        "cloth.height"
    );
    let drop = ClothDropParams::tutorial();
    assert_eq!(
        field(
            ClothDropParams {
                height: 0.0,
                ..drop.clone()
            }
            .build()
            .map(|_| ())
        ),
        "cloth_drop.height"
    );
    assert_eq!(
        field(
            ClothDropParams {
                drag: -1.0,
                ..drop.clone()
            }
            .build()
            .map(|_| ())
        ),
        "cloth_drop.drag"
    );
    assert_eq!(
        field(
            ClothDropParams {
                restitution: 2.0,
                ..drop
            }
            .build()
            .map(|_| ())
        ),
        "ground.restitution"
    );
    let pendulum = PendulumParams::tutorial();
    assert_eq!(
        field(
            PendulumParams {
                particles: 0,
                ..pendulum.clone()
            }
            .build()
            .map(|_| ())
        ),
        "pendulum.particles"
    );
    assert_eq!(
        field(
            PendulumParams {
                drag: -0.1,
                ..pendulum.clone()
            }
            .build()
            .map(|_| ())
        ),
        "pendulum.drag"
    );
    assert_eq!(
        field(
            PendulumParams {
                pivot_height: 0.0,
                ..pendulum
            }
            .build()
            .map(|_| ())
        ),
        "pendulum.pivot_height"
    );
}

#[test]
fn the_cloth_is_a_triangle_mesh() {
    let params = ClothParams {
        nx: 4,
        ny: 3,
        ..ClothParams::default()
    };
    let system = params.hanging().unwrap();
    // Edges of a triangulated 3 × 2 quad grid: 3·3 + 4·2 + 3·2 = 23.
    assert_eq!(system.springs().len(), 23);
    assert_eq!(system.len(), 12);
    let x = system.initial_state().x;
    for s in system.springs() {
        assert!(
            ((x[s.a] - x[s.b]).norm() - s.rest_length).abs() < 1e-15,
            "rest length = initial length"
        );
    }
    let fixed: Vec<usize> = (0..12).filter(|&i| system.nodes()[i].fixed).collect();
    assert_eq!(fixed, vec![params.index(0, 0), params.index(3, 0)]);
    assert_eq!(
        x[params.index(3, 0)],
        Vec3::new(3.0 * params.spacing, 0.0, 0.0)
    );
    assert!(
        x[params.index(0, 2)].y < 0.0,
        "rows hang below the pinned top row"
    );
}

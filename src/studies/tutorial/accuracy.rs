//! The tutorial's accuracy studies: the test oscillator, the integrators' convergence orders and
//! stability limits, and their energy over many periods, each against its closed form.

use crate::error::Result;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, Node, Spring, State, Vec3};
use crate::particles::{AdaptiveStepper, Integrator, ParticleStepper, ParticleSystem};
use crate::solvers::registry::{SolverId, SolverSpec};

// ---------------------------------------------------------------------------------------------
// The test oscillator
// ---------------------------------------------------------------------------------------------

/// One free particle of mass $`m`$ on a spring of stiffness $`k`$ and damping $`k_d`$ to an anchor
/// at the origin, along x, without gravity: its stretch $`u`$ obeys $`m\ddot u = -k u - k_d\dot u`$
/// exactly while $`|u|`$ stays below the rest length (the spring never leaves the x axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator {
    pub mass: f64,
    pub stiffness: f64,
    pub damping: f64,
    pub rest_length: f64,
    /// Initial stretch, m, and velocity, m/s.
    pub u0: f64,
    pub v0: f64,
}

impl Oscillator {
    /// $`m`$ = 1 kg, $`k`$ = 100 N/m ($`\omega`$ = 10 rad/s), damping ratio `zeta`, $`u_0`$ = 0.1 m,
    /// $`v_0`$ = 0.5 m/s.
    pub fn standard(zeta: f64) -> Self {
        Self {
            mass: 1.0,
            stiffness: 100.0,
            damping: 2.0 * zeta * 10.0,
            rest_length: 1.0,
            u0: 0.1,
            v0: 0.5,
        }
    }

    /// Undamped angular frequency $`\omega = \sqrt{k/m}`$, rad/s.
    pub fn omega(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// The particle (index 1) and its anchor (index 0).
    pub fn system(&self) -> MassSpringSystem {
        let node = |x: f64, v: f64, fixed| Node {
            mass: self.mass,
            position: Vec3::new(x, 0.0, 0.0),
            velocity: Vec3::new(v, 0.0, 0.0),
            fixed,
        };
        MassSpringSystem::new(
            vec![
                node(0.0, 0.0, true),
                node(self.rest_length + self.u0, self.v0, false),
            ],
            vec![Spring {
                a: 0,
                b: 1,
                rest_length: self.rest_length,
                stiffness: self.stiffness,
                damping: self.damping,
            }],
            Vec3::zeros(),
        )
        .expect("the oscillator's parameters are valid")
    }

    /// Closed form of the underdamped oscillator, $`(u(t), \dot u(t))`$.
    pub fn exact(&self, t: f64) -> (f64, f64) {
        let omega = self.omega();
        let zeta = self.damping / (2.0 * self.mass * omega);
        let omega_d = omega * (1.0 - zeta * zeta).sqrt();
        let decay = (-zeta * omega * t).exp();
        let (s, c) = (omega_d * t).sin_cos();
        let u = decay * (self.u0 * c + (self.v0 + zeta * omega * self.u0) / omega_d * s);
        let v = decay
            * (self.v0 * c - (omega * omega * self.u0 + zeta * omega * self.v0) / omega_d * s);
        (u, v)
    }

    /// Distance in the phase plane from the closed form at `t`,
    /// $`\sqrt{e_u^2 + (e_v/\omega)^2}`$ (a zero crossing of one component cannot fake a small
    /// error).
    pub fn error(&self, state: &State, t: f64) -> f64 {
        let (u, v) = self.exact(t);
        let e_u = state.x[1].x - self.rest_length - u;
        let e_v = state.v[1].x - v;
        (e_u * e_u + (e_v / self.omega()).powi(2)).sqrt()
    }
}

/// A method of the convergence study: a registry solver as the study runs it (the thesis's
/// Backward Euler with 10 Newton iterations; rk45's fifth-order solution with a fixed step).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Method(pub SolverId);

impl Method {
    pub const ALL: [Method; 5] = [
        Method(SolverId::ExplicitEuler),
        Method(SolverId::SymplecticEuler),
        Method(SolverId::Rk4),
        Method(SolverId::BackwardEuler),
        Method(SolverId::Rk45),
    ];

    /// The order of the global error at a fixed time, from the method's theory.
    pub fn expected_order(self) -> u32 {
        match self.0.integrator() {
            Some(i) => i.order(),
            None if self.0 == SolverId::Rk45 => 5,
            None => 1,
        }
    }

    /// The registry identifier, for CSV files.
    pub fn id(self) -> &'static str {
        self.0.id()
    }

    /// Backward Euler in this crate is the thesis's, which models undamped springs only.
    pub fn models_damping(self) -> bool {
        self.0 != SolverId::BackwardEuler
    }

    /// Runs the oscillator from 0 to `duration` with `steps` fixed steps; the final state.
    pub fn run(self, oscillator: &Oscillator, duration: f64, steps: usize) -> Result<State> {
        let h = duration / steps as f64;
        let system = oscillator.system();
        let mut state = system.initial_state();
        if self.0 == SolverId::Rk45 {
            let mut s = AdaptiveStepper::new(ParticleSystem::from_system(system), h, 1.0)?;
            for _ in 0..steps {
                s.fixed_step(&mut state, h);
            }
            return Ok(state);
        }
        let iterations = if self.0 == SolverId::BackwardEuler {
            10
        } else {
            1
        };
        let mut s = SolverSpec::new(self.0, iterations).build(&system, h)?;
        for _ in 0..steps {
            s.step(&mut state)?;
        }
        Ok(state)
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0.integrator() {
            Some(i) => write!(f, "{i}"),
            None if self.0 == SolverId::Rk45 => f.write_str("Dormand-Prince 5 (fixed h)"),
            None => f.write_str("Backward Euler"),
        }
    }
}

/// Least-squares slope of $`\ln y`$ against $`\ln x`$.
pub fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

// ---------------------------------------------------------------------------------------------
// 1. Convergence orders
// ---------------------------------------------------------------------------------------------

/// Damping ratio of the convergence study's oscillator.
pub const CONVERGENCE_ZETA: f64 = 0.1;
/// The time at which the global error is measured, s.
pub const CONVERGENCE_TIME: f64 = 1.0;

/// The global error of one method against h.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvergenceSeries {
    pub method: Method,
    /// Damping ratio of the oscillator it ran.
    pub zeta: f64,
    /// (h, error at [`CONVERGENCE_TIME`]) from the largest h down.
    pub points: Vec<(f64, f64)>,
    /// Least-squares slope of log error against log h.
    pub slope: f64,
}

/// Step counts of each method: five halvings in its asymptotic range (above roundoff).
fn convergence_steps(method: Method) -> Vec<usize> {
    let coarsest = match method {
        Method(SolverId::Rk4) => 50,
        Method(SolverId::Rk45) => 20,
        _ => 1000,
    };
    (0..5).map(|j| coarsest << j).collect()
}

/// Study 1: the global error at t = 1 s against h for every [`Method`], on the damped
/// oscillator ($`\zeta`$ = 0.1; undamped for Backward Euler, whose springs have no damping).
pub fn convergence() -> Result<Vec<ConvergenceSeries>> {
    Method::ALL
        .into_iter()
        .map(|method| {
            let zeta = if method.models_damping() {
                CONVERGENCE_ZETA
            } else {
                0.0
            };
            let oscillator = Oscillator::standard(zeta);
            let points = convergence_steps(method)
                .into_iter()
                .map(|steps| {
                    let state = method.run(&oscillator, CONVERGENCE_TIME, steps)?;
                    Ok((
                        CONVERGENCE_TIME / steps as f64,
                        oscillator.error(&state, CONVERGENCE_TIME),
                    ))
                })
                .collect::<Result<Vec<_>>>()?;
            Ok(ConvergenceSeries {
                method,
                zeta,
                slope: log_log_slope(&points),
                points,
            })
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// 2. Stability
// ---------------------------------------------------------------------------------------------

/// A one-step map whose spectral radius exceeds 1 by more than this is unstable (the
/// amplification matrix is measured to about 1e-13).
pub const GROWTH_THRESHOLD: f64 = 1e-10;
/// Halvings of the bisection interval.
pub const BISECTION_STEPS: u32 = 60;
/// Bisection interval of $`h\omega`$.
pub const STABILITY_SEARCH: (f64, f64) = (0.0, 4.0);

/// Spectral radius of the one-step map of `integrator` at $`h\omega`$ = `h_omega` on the
/// undamped oscillator, from the 2×2 amplification matrix measured by stepping from two
/// perturbations of the rest state (the map is affine and the rest state a fixed point).
pub fn spectral_radius(integrator: Integrator, h_omega: f64) -> Result<f64> {
    let oscillator = Oscillator {
        u0: 0.0,
        v0: 0.0,
        ..Oscillator::standard(0.0)
    };
    let omega = oscillator.omega();
    let system = oscillator.system();
    let mut stepper = ParticleStepper::new(
        ParticleSystem::from_system(system.clone()),
        integrator,
        h_omega / omega,
    )?;
    let epsilon = 1e-3;
    let rest = system.initial_state();
    // Columns: the images of (u, v/ω) = (ε, 0) and (0, ε), in the same scaled coordinates.
    let mut m = [[0.0; 2]; 2];
    for (column, (du, dv)) in [(epsilon, 0.0), (0.0, epsilon * omega)]
        .into_iter()
        .enumerate()
    {
        let mut state = rest.clone();
        state.x[1].x += du;
        state.v[1].x += dv;
        stepper.step(&mut state)?;
        m[0][column] = (state.x[1].x - rest.x[1].x) / epsilon;
        m[1][column] = state.v[1].x / omega / epsilon;
    }
    let trace = m[0][0] + m[1][1];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let discriminant = 0.25 * trace * trace - det;
    Ok(if discriminant < 0.0 {
        det.sqrt()
    } else {
        0.5 * trace.abs() + discriminant.sqrt()
    })
}

/// The largest stable $`h\omega`$ of each integrator.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityLimit {
    pub integrator: Integrator,
    /// Measured by bisection on the spectral radius.
    pub measured: f64,
    /// From the amplification factor: 0, 2, $`2\sqrt2`$.
    pub expected: f64,
}

/// The closed-form limit: explicit Euler's factor $`\sqrt{1 + h^2\omega^2}`$ exceeds 1 for every
/// $`h > 0`$; symplectic Euler's eigenvalues leave the unit circle at $`h\omega = 2`$; RK4's factor
/// $`|R(iy)|^2 = 1 - y^6/72 + y^8/576`$ exceeds 1 beyond $`y = 2\sqrt2`$.
pub fn expected_limit(integrator: Integrator) -> f64 {
    match integrator {
        Integrator::ExplicitEuler => 0.0,
        Integrator::SymplecticEuler => 2.0,
        Integrator::Rk4 => 2.0 * 2f64.sqrt(),
    }
}

/// Study 2a: bisection ([`BISECTION_STEPS`] halvings) of the largest stable $`h\omega`$.
pub fn stability_limits() -> Result<Vec<StabilityLimit>> {
    Integrator::ALL
        .into_iter()
        .map(|integrator| {
            let (mut lo, mut hi) = STABILITY_SEARCH;
            for _ in 0..BISECTION_STEPS {
                let mid = 0.5 * (lo + hi);
                if spectral_radius(integrator, mid)? > 1.0 + GROWTH_THRESHOLD {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            Ok(StabilityLimit {
                integrator,
                measured: lo,
                expected: expected_limit(integrator),
            })
        })
        .collect()
}

/// The energy of the undamped oscillator against time at one $`h\omega`$.
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyRun {
    pub integrator: Integrator,
    pub h_omega: f64,
    /// (time in periods $`t\omega/2\pi`$, $`E/E_0`$), up to [`ENERGY_PERIODS`] or until
    /// $`E/E_0`$ exceeds [`ENERGY_CAP`].
    pub points: Vec<(f64, f64)>,
}

pub const ENERGY_PERIODS: f64 = 20.0;
pub const ENERGY_CAP: f64 = 1e8;
/// Rest length of the energy runs' spring, m.
pub const ENERGY_REST_LENGTH: f64 = 1e6;

/// The $`h\omega`$ just below and just above each integrator's limit (explicit Euler, stable
/// nowhere, at 0.1 and 0.2).
pub fn energy_h_omegas(integrator: Integrator) -> [f64; 2] {
    match integrator {
        Integrator::ExplicitEuler => [0.1, 0.2],
        _ => {
            let l = expected_limit(integrator);
            [0.98 * l, 1.02 * l]
        }
    }
}

/// Study 2b: energy against time just below and above each limit.
pub fn energy_runs() -> Result<Vec<EnergyRun>> {
    // The spring is linear while the stretch stays below its rest length: a long spring keeps
    // a growth to ENERGY_CAP (an amplitude 1e4 times the initial one) linear.
    let oscillator = Oscillator {
        rest_length: ENERGY_REST_LENGTH,
        ..Oscillator::standard(0.0)
    };
    let omega = oscillator.omega();
    let energy = |s: &State| {
        let u = s.x[1].x - oscillator.rest_length;
        0.5 * oscillator.mass * s.v[1].x.powi(2) + 0.5 * oscillator.stiffness * u * u
    };
    let mut runs = Vec::new();
    for integrator in Integrator::ALL {
        for h_omega in energy_h_omegas(integrator) {
            let h = h_omega / omega;
            let system = oscillator.system();
            let mut state = system.initial_state();
            let e0 = energy(&state);
            let mut stepper =
                ParticleStepper::new(ParticleSystem::from_system(system), integrator, h)?;
            let steps = (ENERGY_PERIODS * std::f64::consts::TAU / omega / h).ceil() as usize;
            let mut points = vec![(0.0, 1.0)];
            for n in 1..=steps {
                stepper.step(&mut state)?;
                let ratio = energy(&state) / e0;
                points.push((n as f64 * h * omega / std::f64::consts::TAU, ratio));
                if ratio > ENERGY_CAP {
                    break;
                }
            }
            runs.push(EnergyRun {
                integrator,
                h_omega,
                points,
            });
        }
    }
    Ok(runs)
}

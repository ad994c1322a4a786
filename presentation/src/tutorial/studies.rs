//! The numerical studies of the tutorial's chapter, each against a closed form or a stated
//! bound: convergence orders, stability limits, forces, collisions and the adaptive integrator.
//! Every function runs the crate's own integrators; nothing here is a published number.

use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::time_stepper::TimeStepper;
use mass_spring_solvers::model::system::{MassSpringSystem, Node, Spring, State, Vec3};
use mass_spring_solvers::particles::scenes::{ClothDropParams, PendulumParams};
use mass_spring_solvers::particles::{
    AdaptiveStats, AdaptiveStepper, DampedSprings, Drag, Gravity, Ground, Integrator,
    ParticleStepper, ParticleSystem, Particles,
};
use mass_spring_solvers::solvers::registry::{SolverId, SolverSpec};

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

// ---------------------------------------------------------------------------------------------
// 3. Forces
// ---------------------------------------------------------------------------------------------

/// A particle of mass `mass` at `position`, at rest unless `velocity` says otherwise.
fn particle(mass: f64, position: Vec3, velocity: Vec3) -> Node {
    Node {
        mass,
        position,
        velocity,
        fixed: false,
    }
}

/// Parameters of the drag study: $`m`$, $`g`$, $`k_f`$.
pub const DRAG: (f64, f64, f64) = (2.0, 9.81, 4.0);
/// Time step of the force studies (RK4), s.
pub const FORCE_DT: f64 = 1e-3;

/// A particle falling from rest under gravity and drag $`f = -k_f v`$.
#[derive(Debug, Clone, PartialEq)]
pub struct DragFall {
    /// (t, downward speed ours, closed form $`\frac{mg}{k_f}(1 - e^{-k_f t/m})`$), every 0.05 s.
    pub samples: Vec<(f64, f64, f64)>,
    /// Largest |ours − closed form| over the whole run, m/s.
    pub max_error: f64,
    /// Speed at $`t = 20\,m/k_f`$ and the terminal velocity $`mg/k_f`$, m/s.
    pub final_speed: f64,
    pub terminal: f64,
}

/// Study 3a, with RK4 at [`FORCE_DT`].
pub fn drag_fall() -> Result<DragFall> {
    let (m, g, k_f) = DRAG;
    let system = MassSpringSystem::new(
        vec![particle(m, Vec3::new(0.0, 0.0, 0.0), Vec3::zeros())],
        vec![],
        Vec3::new(0.0, -g, 0.0),
    )?;
    let particles = ParticleSystem::from_system(system).with_force(Box::new(Drag {
        k_f,
        particles: Particles::All,
    }))?;
    let mut stepper = ParticleStepper::new(particles, Integrator::Rk4, FORCE_DT)?;
    let mut state = stepper.system().initial_state();
    let (terminal, tau) = (m * g / k_f, m / k_f);
    let closed = |t: f64| terminal * (1.0 - (-t / tau).exp());
    let steps = (20.0 * tau / FORCE_DT).round() as usize;
    let every = (0.05 / FORCE_DT).round() as usize;
    let mut samples = vec![(0.0, 0.0, 0.0)];
    let mut max_error: f64 = 0.0;
    for n in 1..=steps {
        stepper.step(&mut state)?;
        let t = n as f64 * FORCE_DT;
        let speed = -state.v[0].y;
        max_error = max_error.max((speed - closed(t)).abs());
        if n % every == 0 && t <= 5.0 * tau + 1e-9 {
            samples.push((t, speed, closed(t)));
        }
    }
    Ok(DragFall {
        samples,
        max_error,
        final_speed: -state.v[0].y,
        terminal,
    })
}

/// Parameters of the two-particle spring: masses, $`k_s`$, $`k_d`$, rest length, initial stretch.
pub const PAIR: SpringPair = SpringPair {
    mass_a: 1.0,
    mass_b: 3.0,
    stiffness: 100.0,
    damping: 1.0,
    rest_length: 1.0,
    stretch: 0.2,
};

/// Two free particles joined by the tutorial's damped spring, released at rest stretched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringPair {
    pub mass_a: f64,
    pub mass_b: f64,
    pub stiffness: f64,
    pub damping: f64,
    pub rest_length: f64,
    pub stretch: f64,
}

impl SpringPair {
    /// Reduced mass $`\mu = m_a m_b/(m_a + m_b)`$: the stretch obeys
    /// $`\mu\ddot u = -k_s u - k_d\dot u`$.
    pub fn reduced_mass(&self) -> f64 {
        self.mass_a * self.mass_b / (self.mass_a + self.mass_b)
    }

    /// Decay rate $`k_d/(2\mu)`$, 1/s.
    pub fn decay_rate(&self) -> f64 {
        self.damping / (2.0 * self.reduced_mass())
    }

    /// Damped angular frequency $`\sqrt{k_s/\mu - (k_d/2\mu)^2}`$, rad/s.
    pub fn damped_frequency(&self) -> f64 {
        (self.stiffness / self.reduced_mass() - self.decay_rate().powi(2)).sqrt()
    }

    /// The closed-form stretch at `t`.
    pub fn stretch_at(&self, t: f64) -> f64 {
        let (a, w) = (self.decay_rate(), self.damped_frequency());
        self.stretch * (-a * t).exp() * ((w * t).cos() + a / w * (w * t).sin())
    }
}

/// The pair simulated, with what was measured from its peaks.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringPairRun {
    pub pair: SpringPair,
    /// (t, stretch ours, stretch closed form), every 10 steps.
    pub samples: Vec<(f64, f64, f64)>,
    /// Largest |stretch − closed form|, m.
    pub max_error: f64,
    /// Decay rate fitted to the stretch's maxima (least squares of ln u), 1/s.
    pub measured_decay: f64,
    /// $`2\pi`$ over the mean spacing of the maxima, rad/s.
    pub measured_frequency: f64,
    /// Largest |total momentum|, kg·m/s (0 for internal forces).
    pub max_momentum: f64,
}

/// Parabolic interpolation of a local maximum from three equally spaced samples: the offset
/// of the vertex from the middle one, in samples, and its value.
fn parabola_vertex(y0: f64, y1: f64, y2: f64) -> (f64, f64) {
    let denominator = y0 - 2.0 * y1 + y2;
    let offset = 0.5 * (y0 - y2) / denominator;
    (offset, y1 - 0.25 * (y0 - y2) * offset)
}

/// Time step and length of the spring-pair run (RK4), s.
pub const PAIR_DT: f64 = 1e-4;
pub const PAIR_TIME: f64 = 5.0;

/// Study 3b: the pair with RK4 at [`PAIR_DT`] for [`PAIR_TIME`].
pub fn spring_pair() -> Result<SpringPairRun> {
    let p = PAIR;
    let dt = PAIR_DT;
    let system = MassSpringSystem::new(
        vec![
            particle(p.mass_a, Vec3::zeros(), Vec3::zeros()),
            particle(
                p.mass_b,
                Vec3::new(p.rest_length + p.stretch, 0.0, 0.0),
                Vec3::zeros(),
            ),
        ],
        vec![Spring {
            a: 0,
            b: 1,
            rest_length: p.rest_length,
            stiffness: p.stiffness,
            damping: p.damping,
        }],
        Vec3::zeros(),
    )?;
    let particles = ParticleSystem::new(system, vec![Box::new(DampedSprings)])?;
    let mut stepper = ParticleStepper::new(particles, Integrator::Rk4, dt)?;
    let mut state = stepper.system().initial_state();
    let stretch = |s: &State| (s.x[1] - s.x[0]).norm() - p.rest_length;
    let steps = (PAIR_TIME / dt).round() as usize;
    let mut series = vec![stretch(&state)];
    let mut samples = vec![(0.0, stretch(&state), p.stretch)];
    let (mut max_error, mut max_momentum): (f64, f64) = (0.0, 0.0);
    for n in 1..=steps {
        stepper.step(&mut state)?;
        let (t, u) = (n as f64 * dt, stretch(&state));
        series.push(u);
        max_error = max_error.max((u - p.stretch_at(t)).abs());
        max_momentum = max_momentum.max(stepper.particles().momentum(&state).norm());
        if n % 10 == 0 {
            samples.push((t, u, p.stretch_at(t)));
        }
    }
    // Interior maxima of the stretch, located to sub-step accuracy.
    let maxima: Vec<(f64, f64)> = series
        .windows(3)
        .enumerate()
        .filter(|(_, w)| w[1] > w[0] && w[1] >= w[2] && w[1] > 0.0)
        .map(|(i, w)| {
            let (offset, value) = parabola_vertex(w[0], w[1], w[2]);
            ((i as f64 + 1.0 + offset) * dt, value)
        })
        .collect();
    let n = maxima.len() as f64;
    let (mt, ml) = (
        maxima.iter().map(|m| m.0).sum::<f64>() / n,
        maxima.iter().map(|m| m.1.ln()).sum::<f64>() / n,
    );
    let stt: f64 = maxima.iter().map(|m| (m.0 - mt).powi(2)).sum();
    let stl: f64 = maxima.iter().map(|m| (m.0 - mt) * (m.1.ln() - ml)).sum();
    let spacing = (maxima[maxima.len() - 1].0 - maxima[0].0) / (n - 1.0);
    Ok(SpringPairRun {
        pair: p,
        samples,
        max_error,
        measured_decay: -stl / stt,
        measured_frequency: std::f64::consts::TAU / spacing,
        max_momentum,
    })
}

/// One particle of the several-gravities study.
#[derive(Debug, Clone, PartialEq)]
pub struct GravityParticle {
    /// The gravities acting on it, by name.
    pub gravities: Vec<&'static str>,
    pub start: Vec3,
    pub velocity: Vec3,
    /// Position at [`GRAVITIES_TIME`], ours and $`x_0 + v_0 t + \frac12 \sum g\,t^2`$.
    pub ours: Vec3,
    pub closed: Vec3,
}

pub const GRAVITIES_TIME: f64 = 2.0;

/// The gravities of the study: name, acceleration, the particles it acts on.
pub fn gravity_objects() -> Vec<(&'static str, Vec3, Vec<usize>)> {
    vec![
        (
            "Earth (0, −9.81, 0)",
            Vec3::new(0.0, -9.81, 0.0),
            vec![0, 1],
        ),
        ("Moon (0, −1.62, 0)", Vec3::new(0.0, -1.62, 0.0), vec![2]),
        ("sideways (2, 0, 0)", Vec3::new(2.0, 0.0, 0.0), vec![1, 3]),
    ]
}

/// Study 3c: four particles in one system, three gravity objects on different sets (particle
/// 1 under two of them, particle 3 under one sideways only), RK4 at [`FORCE_DT`] for 2 s.
pub fn several_gravities() -> Result<Vec<GravityParticle>> {
    let starts = [
        (Vec3::new(0.0, 10.0, 0.0), Vec3::zeros()),
        (Vec3::new(1.0, 10.0, 0.0), Vec3::new(0.0, 3.0, 0.0)),
        (Vec3::new(2.0, 10.0, 0.0), Vec3::new(0.5, 0.0, 0.0)),
        (Vec3::new(3.0, 10.0, 0.0), Vec3::zeros()),
    ];
    let system = MassSpringSystem::new(
        starts.iter().map(|&(x, v)| particle(1.0, x, v)).collect(),
        vec![],
        Vec3::zeros(),
    )?;
    let objects = gravity_objects();
    let forces = objects
        .iter()
        .map(|(_, g, set)| {
            Box::new(Gravity {
                g: *g,
                particles: Particles::Only(set.clone()),
            }) as Box<dyn mass_spring_solvers::particles::Force>
        })
        .collect();
    let mut stepper = ParticleStepper::new(
        ParticleSystem::new(system, forces)?,
        Integrator::Rk4,
        FORCE_DT,
    )?;
    let mut state = stepper.system().initial_state();
    for _ in 0..(GRAVITIES_TIME / FORCE_DT).round() as usize {
        stepper.step(&mut state)?;
    }
    let t = GRAVITIES_TIME;
    Ok(starts
        .iter()
        .enumerate()
        .map(|(i, &(x0, v0))| {
            let acting: Vec<_> = objects.iter().filter(|o| o.2.contains(&i)).collect();
            let g: Vec3 = acting.iter().map(|o| o.1).sum();
            GravityParticle {
                gravities: acting.iter().map(|o| o.0).collect(),
                start: x0,
                velocity: v0,
                ours: state.x[i],
                closed: x0 + v0 * t + 0.5 * g * t * t,
            }
        })
        .collect())
}

// ---------------------------------------------------------------------------------------------
// 4. Collisions
// ---------------------------------------------------------------------------------------------

/// Drop height, m, restitution and gravity of the bounce study.
pub const DROP: (f64, f64, f64) = (1.0, 0.5, 9.81);
/// Bounces measured.
pub const BOUNCES: usize = 4;

/// How a run is integrated: a fixed-step tutorial integrator or the adaptive pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scheme {
    Fixed(Integrator, f64),
    /// Dormand-Prince 5(4) with this tolerance.
    Adaptive(f64),
}

impl std::fmt::Display for Scheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Scheme::Fixed(i, h) => write!(f, "{i}, h = {h:e} s"),
            Scheme::Adaptive(tol) => write!(f, "Dormand-Prince 5(4), tolerance {tol:e}"),
        }
    }
}

/// A particle system advanced under a [`Scheme`], one sample interval at a time (fixed steps
/// are repeated `interval / h` times per sample).
#[allow(
    clippy::large_enum_variant,
    reason = "one sampler per run, never in a collection"
)]
enum Sampler {
    Fixed(ParticleStepper, usize),
    Adaptive(AdaptiveStepper),
}

impl Sampler {
    fn new(particles: ParticleSystem, scheme: Scheme, interval: f64) -> Result<Self> {
        Ok(match scheme {
            Scheme::Fixed(integrator, h) => Sampler::Fixed(
                ParticleStepper::new(particles, integrator, h)?,
                (interval / h).round() as usize,
            ),
            Scheme::Adaptive(tolerance) => {
                Sampler::Adaptive(AdaptiveStepper::new(particles, interval, tolerance)?)
            }
        })
    }

    fn system(&self) -> &MassSpringSystem {
        match self {
            Sampler::Fixed(s, _) => s.system(),
            Sampler::Adaptive(s) => s.system(),
        }
    }

    fn advance(&mut self, state: &mut State) -> Result<()> {
        match self {
            Sampler::Fixed(s, substeps) => (0..*substeps).try_for_each(|_| s.step(state)),
            Sampler::Adaptive(s) => s.step(state),
        }
    }

    fn stats(&self) -> Option<AdaptiveStats> {
        match self {
            Sampler::Fixed(..) => None,
            Sampler::Adaptive(s) => Some(s.stats()),
        }
    }

    /// Mechanical energy: kinetic, gravitational and elastic, J.
    fn energy(&self, state: &State) -> f64 {
        state.kinetic_energy(self.system()) + self.system().potential_energy(&state.x)
    }
}

/// A single particle of mass 1 kg dropped from rest at `height` onto a floor of restitution
/// `e`, under gravity `g`.
pub fn dropped_particle(height: f64, e: f64, g: f64) -> Result<ParticleSystem> {
    let system = MassSpringSystem::new(
        vec![particle(1.0, Vec3::new(0.0, height, 0.0), Vec3::zeros())],
        vec![],
        Vec3::new(0.0, -g, 0.0),
    )?;
    Ok(ParticleSystem::from_system(system).with_ground(Ground::new(0.0, e)?))
}

/// The energy kept at each bounce of the dropped particle under one scheme.
#[derive(Debug, Clone, PartialEq)]
pub struct BounceRun {
    pub scheme: Scheme,
    /// $`E_n / E_{n-1}`$ for bounces $`n = 1..`$[`BOUNCES`] ($`E_0 = mgh`$), against $`e^2`$.
    pub kept: Vec<f64>,
    /// (t, E) every sample.
    pub energy: Vec<(f64, f64)>,
}

/// The schemes of the bounce study.
pub fn bounce_schemes() -> [Scheme; 4] {
    [
        Scheme::Fixed(Integrator::SymplecticEuler, 1e-4),
        Scheme::Fixed(Integrator::Rk4, 1e-4),
        Scheme::Fixed(Integrator::Rk4, 1e-3),
        Scheme::Adaptive(1e-8),
    ]
}

/// Study 4a: the energy after each bounce, sampled every 1e-4 s (1e-3 s for RK4 at 1e-3 s);
/// a bounce is a sample whose upward velocity follows a downward one.
pub fn bounces() -> Result<Vec<BounceRun>> {
    let (height, e, g) = DROP;
    // Bounce n happens at t = sqrt(2h/g)·(1 + 2e + ... + 2e^(n-1)); run a little past it.
    let fall = (2.0 * height / g).sqrt();
    let duration = fall * (1.0 + 2.0 * (1..BOUNCES).map(|n| e.powi(n as i32)).sum::<f64>()) + 0.1;
    bounce_schemes()
        .into_iter()
        .map(|scheme| {
            let interval = match scheme {
                Scheme::Fixed(_, h) => h,
                Scheme::Adaptive(_) => 1e-4,
            };
            let mut sampler = Sampler::new(dropped_particle(height, e, g)?, scheme, interval)?;
            let mut state = sampler.system().initial_state();
            let mut previous = sampler.energy(&state);
            let mut energy = vec![(0.0, previous)];
            let mut kept = Vec::new();
            for n in 1..=(duration / interval).round() as usize {
                let falling = state.v[0].y < 0.0;
                sampler.advance(&mut state)?;
                let now = sampler.energy(&state);
                energy.push((n as f64 * interval, now));
                if falling && state.v[0].y >= 0.0 && kept.len() < BOUNCES {
                    kept.push(now / previous);
                    previous = now;
                }
            }
            Ok(BounceRun {
                scheme,
                kept,
                energy,
            })
        })
        .collect()
}

/// The tutorial's pendulum run: frames and energy.
#[derive(Debug, Clone, PartialEq)]
pub struct PendulumRun {
    pub params: PendulumParams,
    pub integrator: Integrator,
    pub dt: f64,
    /// (t, positions) at [`PENDULUM_FRAMES`].
    pub frames: Vec<(f64, Vec<Vec3>)>,
    /// (t, mechanical energy J), every [`PENDULUM_SAMPLE`] s.
    pub energy: Vec<(f64, f64)>,
    /// The steps in which the floor acted: (t, first particle on the floor, mechanical energy
    /// at the start and at the end of the step, J).
    pub contacts: Vec<(f64, usize, f64, f64)>,
}

/// Sampling interval of the pendulum's energy, s.
pub const PENDULUM_SAMPLE: f64 = 0.005;
/// The tutorial's six frames, s.
pub const PENDULUM_FRAMES: [f64; 6] = [0.0, 0.5, 0.7, 0.9, 1.1, 1.5];
/// Length of the pendulum run, s.
pub const PENDULUM_TIME: f64 = 4.0;

/// Study 4b: the pendulum with RK4 at 1e-4 s. A step in which the floor acted is one that
/// leaves a free particle exactly on the floor (where the response puts it).
pub fn pendulum() -> Result<PendulumRun> {
    let params = PendulumParams::tutorial();
    let (integrator, dt) = (Integrator::Rk4, 1e-4);
    let particles = params.build()?;
    let floor = particles.ground().map_or(0.0, |g| g.height());
    let mut stepper = ParticleStepper::new(particles, integrator, dt)?;
    let system = stepper.system().clone();
    let energy_of = |s: &State| s.kinetic_energy(&system) + system.potential_energy(&s.x);
    let mut state = system.initial_state();
    let mut frames = Vec::new();
    let mut energy = Vec::new();
    let mut contacts = Vec::new();
    let every = (PENDULUM_SAMPLE / dt).round() as usize;
    for n in 0..=(PENDULUM_TIME / dt).round() as usize {
        let t = n as f64 * dt;
        if n > 0 {
            let before = energy_of(&state);
            stepper.step(&mut state)?;
            let on_floor = system
                .nodes()
                .iter()
                .zip(&state.x)
                .position(|(node, x)| !node.fixed && x.y == floor);
            if let Some(i) = on_floor {
                contacts.push((t, i, before, energy_of(&state)));
            }
        }
        if PENDULUM_FRAMES.iter().any(|f| (f - t).abs() < 0.5 * dt) {
            frames.push((t, state.x.clone()));
        }
        if n % every == 0 {
            energy.push((t, energy_of(&state)));
        }
    }
    Ok(PendulumRun {
        params,
        integrator,
        dt,
        frames,
        energy,
        contacts,
    })
}

/// The tutorial's cloth dropped from 10 m.
#[derive(Debug, Clone, PartialEq)]
pub struct ClothDropRun {
    pub params: ClothDropParams,
    pub dt: f64,
    /// The cloth's springs (for drawing the frames).
    pub springs: Vec<(usize, usize)>,
    /// (t, positions) at [`CLOTH_FRAMES`] and at the first contact.
    pub frames: Vec<(f64, Vec<Vec3>)>,
    /// The centre of mass's height at every step, simulated and in closed form: (t, m).
    pub centre: Vec<(f64, f64)>,
    pub closed_centre: Vec<(f64, f64)>,
    /// First time a particle reached the floor, s, and the closed form of the drag fall.
    pub first_contact: f64,
    pub closed_contact: f64,
    /// Largest |height of the centre of mass − closed form| before the first contact, m.
    pub max_centre_error: f64,
    /// Lowest particle over the run (never below the floor), m.
    pub lowest: f64,
    /// Highest particle and kinetic energy at the end, m and J.
    pub final_highest: f64,
    pub final_kinetic: f64,
}

pub const CLOTH_FRAMES: [f64; 4] = [0.0, 0.7, 1.2, 2.5];
pub const CLOTH_TIME: f64 = 2.5;

/// Study 4c: the cloth drop with RK4 at 1e-3 s. The springs and the floor aside, every
/// particle feels gravity and the same linear drag, and the springs' forces cancel in the sum,
/// so until the first contact the centre of mass falls exactly as one particle with drag:
/// $`y_c(t) = y_0 - v_t\,(t - \tau(1 - e^{-t/\tau}))`$, $`\tau = m/k_f`$, $`v_t = g\tau`$.
pub fn cloth_drop() -> Result<ClothDropRun> {
    let params = ClothDropParams::tutorial();
    let dt = 1e-3;
    let particles = params.build()?;
    let springs = particles
        .system()
        .springs()
        .iter()
        .map(|s| (s.a, s.b))
        .collect();
    let mut stepper = ParticleStepper::new(particles, Integrator::Rk4, dt)?;
    let mut state = stepper.system().initial_state();
    let n = state.x.len() as f64;
    let tau = params.cloth.particle_mass / params.drag;
    let v_t = params.cloth.gravity * tau;
    let closed = |t: f64| params.height - v_t * (t - tau * (1.0 - (-t / tau).exp()));
    // The closed form reaches the floor when y_c = 0 (bisection on the monotone fall).
    let (mut lo, mut hi) = (0.0, 10.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if closed(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let mut frames = vec![(0.0, state.x.clone())];
    let centre_of = |x: &[Vec3]| x.iter().map(|p| p.y).sum::<f64>() / n;
    let mut centre = vec![(0.0, centre_of(&state.x))];
    let mut first_contact = None;
    let (mut max_centre_error, mut lowest): (f64, f64) = (0.0, f64::INFINITY);
    for step in 1..=(CLOTH_TIME / dt).round() as usize {
        stepper.step(&mut state)?;
        let t = step as f64 * dt;
        let low = state.x.iter().map(|x| x.y).fold(f64::INFINITY, f64::min);
        lowest = lowest.min(low);
        centre.push((t, centre_of(&state.x)));
        if first_contact.is_none() {
            if low <= 0.0 {
                first_contact = Some(t);
                frames.push((t, state.x.clone()));
            } else {
                max_centre_error = max_centre_error.max((centre_of(&state.x) - closed(t)).abs());
            }
        }
        if CLOTH_FRAMES[1..].iter().any(|f| (f - t).abs() < 0.5 * dt) {
            frames.push((t, state.x.clone()));
        }
    }
    frames.sort_by(|a, b| a.0.total_cmp(&b.0));
    let closed_centre = centre
        .iter()
        .map(|&(t, _)| (t, closed(t)))
        .take_while(|&(_, y)| y >= 0.0)
        .collect();
    Ok(ClothDropRun {
        params,
        dt,
        springs,
        frames,
        centre,
        closed_centre,
        first_contact: first_contact.unwrap_or(f64::NAN),
        closed_contact: lo,
        max_centre_error,
        lowest,
        final_highest: state
            .x
            .iter()
            .map(|x| x.y)
            .fold(f64::NEG_INFINITY, f64::max),
        final_kinetic: state.kinetic_energy(stepper.system()),
    })
}

// ---------------------------------------------------------------------------------------------
// 5. The adaptive integrator
// ---------------------------------------------------------------------------------------------

/// The tolerances of the adaptive study.
pub const TOLERANCES: [f64; 6] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];
/// The reference run's tolerance.
pub const REFERENCE_TOLERANCE: f64 = 1e-11;
/// Length of the adaptive runs on the pendulum, s.
pub const ADAPTIVE_TIME: f64 = 2.0;
/// Length of the adaptive runs on the dropped particle, s: after its third bounce, before the
/// bounces accumulate (at $`3\sqrt{2h/g}`$ = 1.35 s for $`e`$ = 0.5).
pub const DROP_TIME: f64 = 1.0;

/// One adaptive run at one tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct AdaptiveRun {
    pub tolerance: f64,
    pub stats: AdaptiveStats,
    /// Pendulum: largest |x − x_ref| over the particles at [`ADAPTIVE_TIME`], m (against the
    /// run at [`REFERENCE_TOLERANCE`]). Dropped particle: |y − y_exact| at [`DROP_TIME`], m,
    /// against the closed-form bouncing trajectory.
    pub error: f64,
}

/// The adaptive integrator on the pendulum and on the dropped particle.
#[derive(Debug, Clone, PartialEq)]
pub struct AdaptiveStudy {
    pub pendulum: Vec<AdaptiveRun>,
    pub reference: AdaptiveStats,
    /// RK4 with a fixed step on the pendulum, for comparison: h, evaluations, error.
    pub rk4: Vec<(f64, u64, f64)>,
    pub drop: Vec<AdaptiveRun>,
}

/// The pendulum's state at [`ADAPTIVE_TIME`] under `scheme`, and the adaptive statistics.
fn pendulum_at_end(scheme: Scheme) -> Result<(State, Option<AdaptiveStats>)> {
    let mut sampler = Sampler::new(PendulumParams::tutorial().build()?, scheme, ADAPTIVE_TIME)?;
    let mut state = sampler.system().initial_state();
    sampler.advance(&mut state)?;
    Ok((state, sampler.stats()))
}

/// Largest distance between the particles of two states, m.
fn distance(a: &State, b: &State) -> f64 {
    a.x.iter()
        .zip(&b.x)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// The exact height and vertical velocity at `t` of a particle dropped from rest at `height`
/// onto a floor of restitution `e`: parabolas joined at the bounces, $`v \leftarrow -e\,v`$.
pub fn bouncing_exact(height: f64, e: f64, g: f64, t: f64) -> (f64, f64) {
    let (mut now, mut y, mut v) = (0.0, height, 0.0);
    loop {
        let hit = (v + (v * v + 2.0 * g * y).sqrt()) / g;
        if now + hit > t || hit <= 0.0 {
            let s = t - now;
            return (y + v * s - 0.5 * g * s * s, v - g * s);
        }
        now += hit;
        v = -e * (v - g * hit);
        y = 0.0;
    }
}

/// Study 5.
pub fn adaptive() -> Result<AdaptiveStudy> {
    let (reference, reference_stats) = pendulum_at_end(Scheme::Adaptive(REFERENCE_TOLERANCE))?;
    let pendulum = TOLERANCES
        .iter()
        .map(|&tolerance| {
            let (state, stats) = pendulum_at_end(Scheme::Adaptive(tolerance))?;
            Ok(AdaptiveRun {
                tolerance,
                stats: stats.unwrap_or_default(),
                error: distance(&state, &reference),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let rk4 = [1e-3, 1e-4]
        .into_iter()
        .map(|h| {
            let (state, _) = pendulum_at_end(Scheme::Fixed(Integrator::Rk4, h))?;
            Ok((
                h,
                4 * (ADAPTIVE_TIME / h).round() as u64,
                distance(&state, &reference),
            ))
        })
        .collect::<Result<Vec<_>>>()?;
    let (height, e, g) = DROP;
    let drop = TOLERANCES
        .iter()
        .map(|&tolerance| {
            let mut stepper =
                AdaptiveStepper::new(dropped_particle(height, e, g)?, DROP_TIME, tolerance)?;
            let mut state = stepper.system().initial_state();
            stepper.step(&mut state)?;
            let (y, _) = bouncing_exact(height, e, g, DROP_TIME);
            Ok(AdaptiveRun {
                tolerance,
                stats: stepper.stats(),
                error: (state.x[0].y - y).abs(),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(AdaptiveStudy {
        pendulum,
        reference: reference_stats.unwrap_or_default(),
        rk4,
        drop,
    })
}

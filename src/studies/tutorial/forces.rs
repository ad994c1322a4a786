//! The tutorial's forces checked against their closed forms: drag, a pair of damped springs and
//! several gravity objects.

use crate::error::Result;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, Node, Spring, State, Vec3};
use crate::particles::{
    DampedSprings, Drag, Gravity, Integrator, ParticleStepper, ParticleSystem, Particles,
};

// ---------------------------------------------------------------------------------------------
// 3. Forces
// ---------------------------------------------------------------------------------------------

/// A particle of mass `mass` at `position`, at rest unless `velocity` says otherwise.
pub(super) fn particle(mass: f64, position: Vec3, velocity: Vec3) -> Node {
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
            }) as Box<dyn crate::particles::Force>
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

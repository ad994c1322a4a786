//! The tutorial's collisions (a particle bouncing on the ground under four schemes, the
//! pendulum and the cloth dropped on the floor) and its adaptive integrator against exact
//! motions and a tight-tolerance reference.

use super::forces::particle;
use crate::error::Result;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::particles::scenes::{ClothDropParams, PendulumParams};
use crate::particles::{
    AdaptiveStats, AdaptiveStepper, Ground, Integrator, ParticleStepper, ParticleSystem,
};

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

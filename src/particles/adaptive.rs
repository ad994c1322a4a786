//! Beyond the tutorial, which promises "otro artículo" on adaptive step size: the embedded
//! Runge-Kutta pair of Dormand and Prince, 5(4), with error control.
//!
//! Each attempted step of size $`h`$ evaluates seven stages and gives a fifth-order solution
//! $`y_5`$ (which is propagated) and a fourth-order one $`y_4`$; their difference estimates the
//! local error of $`y_4`$, a safe bound for $`y_5`$. The step is accepted when
//! $`\max_i |y_{5,i} - y_{4,i}| / (T\,(1 + \max(|y_i|, |y_{5,i}|))) \le 1`$ over every position
//! (m) and velocity (m/s) component, with $`T`$ the tolerance, and the next step is
//! $`h \cdot \min(5, \max(0.2, 0.9\,\mathrm{err}^{-1/5}))`$. The last stage is the derivative at
//! $`y_5`$, reused as the first stage of the next step ("first same as last") unless a contact
//! changed the state.
//!
//! **Bounces are handled by step rejection**, not by event location. The floor is not part of
//! the differential equation, so the error estimate cannot see it: instead, an accepted step
//! that leaves a free particle more than $`T\,(1 + |y_{floor}|)`$ metres below the floor is
//! rejected and retried with half the step. The step that is finally accepted ends at most
//! that depth past the contact, where the floor's response is applied as in the fixed-step
//! integrators ([`super::Ground::resolve`]). The contact time is so located to within
//! $`T/|v_y|`$ and the rebound height to within about $`T\,(1 + e^2)`$; a particle resting on the
//! floor limits the step to about $`\sqrt{2T/g}`$.

use super::integrators::axpy;
use super::ParticleSystem;
use crate::error::{require_positive, Error, Result};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};

/// Stages of the Dormand-Prince pair (the forces do not depend on time, so the nodes $`c_i`$ of
/// the tableau are not needed).
const STAGES: usize = 7;

/// Coefficients $`a_{ij}`$ of the Dormand-Prince tableau, row $`i`$ (stage $`i + 1`$); the last row
/// is the fifth-order weights $`b_j`$.
const A: [[f64; 6]; 6] = [
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];

/// $`b_j - b^*_j`$: fifth-order minus fourth-order weights, the error estimate's coefficients.
const ERROR_WEIGHTS: [f64; STAGES] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Step-size controller: safety factor and bounds of the change per step.
pub const SAFETY: f64 = 0.9;
pub const MAX_GROWTH: f64 = 5.0;
pub const MAX_SHRINK: f64 = 0.2;

/// What the adaptive integrator did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AdaptiveStats {
    /// Steps accepted.
    pub accepted: u64,
    /// Steps rejected by the error estimate.
    pub rejected_error: u64,
    /// Steps rejected because a particle ended too far below the floor.
    pub rejected_contact: u64,
    /// Evaluations of the forces (derivative of the state).
    pub evaluations: u64,
    /// Smallest and largest accepted step, s (0 before the first step).
    pub smallest_step: f64,
    pub largest_step: f64,
}

/// A particle system advanced by Dormand-Prince 5(4) with error tolerance `tolerance`. As a
/// [`TimeStepper`], each call of `step` advances by the output interval `dt` with as many
/// adaptive steps as the tolerance needs, the last one shortened to land on the interval's end.
#[derive(Debug)]
pub struct AdaptiveStepper {
    particles: ParticleSystem,
    interval: f64,
    tolerance: f64,
    /// The next step size to attempt.
    h: f64,
    f: Vec<Vec3>,
    k: [State; STAGES],
    /// True when `k[0]` is the derivative at the current state.
    first_stage_current: bool,
    stage: State,
    trial: State,
    stats: AdaptiveStats,
    /// The most steps (accepted or rejected) the stepper may attempt: a work budget.
    attempt_limit: Option<u64>,
}

impl AdaptiveStepper {
    /// A stepper for `particles` sampled every `interval` s (> 0) with error tolerance
    /// `tolerance` (> 0, relative to 1 + |component|, in m and m/s).
    pub fn new(particles: ParticleSystem, interval: f64, tolerance: f64) -> Result<Self> {
        require_positive("dt", interval)?;
        require_positive("tolerance", tolerance)?;
        let n = particles.system().len();
        let zeros = State::zeros(n);
        Ok(Self {
            particles,
            interval,
            tolerance,
            h: interval,
            f: vec![Vec3::zeros(); n],
            k: std::array::from_fn(|_| zeros.clone()),
            first_stage_current: false,
            stage: zeros.clone(),
            trial: zeros,
            stats: AdaptiveStats::default(),
            attempt_limit: None,
        })
    }

    /// This stepper failing, when it would attempt more than `limit` steps in all, with an error
    /// saying when (a work budget: the caller's estimate of the steps can be passed at will
    /// by a tolerance the scene makes expensive); `None`: no limit.
    pub fn with_attempt_limit(mut self, limit: Option<u64>) -> Self {
        self.attempt_limit = limit;
        self
    }

    /// The particle system being advanced.
    pub fn particles(&self) -> &ParticleSystem {
        &self.particles
    }

    /// The error tolerance.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Counts of steps, rejections and force evaluations so far.
    pub fn stats(&self) -> AdaptiveStats {
        self.stats
    }

    fn derivative(&mut self, stage: usize, at_trial: bool) {
        let y = if at_trial { &self.trial } else { &self.stage };
        self.particles
            .derivative(y, &mut self.f, &mut self.k[stage]);
        self.stats.evaluations += 1;
    }

    /// One Dormand-Prince step of size `h` from `y` into `self.trial`; returns the scaled error
    /// estimate (accept when <= 1; NaN when the state is not finite).
    fn attempt(&mut self, y: &State, h: f64) -> f64 {
        if !self.first_stage_current {
            self.stage.clone_from(y);
            self.derivative(0, false);
            self.first_stage_current = true;
        }
        for (s, row) in A.iter().enumerate() {
            self.stage.clone_from(y);
            for (a, k) in row.iter().zip(&self.k).take(s + 1) {
                if *a != 0.0 {
                    axpy(&mut self.stage, h * a, k);
                }
            }
            if s + 1 == A.len() {
                // The last row is the fifth-order solution; its derivative is stage 7.
                self.trial.clone_from(&self.stage);
                self.derivative(s + 1, true);
            } else {
                self.derivative(s + 1, false);
            }
        }
        if !self.trial.is_finite() {
            return f64::NAN;
        }
        // The error estimate h·Σ (b_j - b*_j) k_j, in the stage buffer (free again).
        let error = &mut self.stage;
        error.x.fill(Vec3::zeros());
        error.v.fill(Vec3::zeros());
        for (w, k) in ERROR_WEIGHTS.iter().zip(&self.k) {
            if *w != 0.0 {
                axpy(error, h * w, k);
            }
        }
        let tolerance = self.tolerance;
        let scaled = |e: &[Vec3], old: &[Vec3], new: &[Vec3]| {
            e.iter()
                .zip(old)
                .zip(new)
                .flat_map(|((e, o), n)| {
                    (0..3)
                        .map(move |c| e[c].abs() / (tolerance * (1.0 + o[c].abs().max(n[c].abs()))))
                })
                .fold(0.0, f64::max)
        };
        scaled(&error.x, &y.x, &self.trial.x).max(scaled(&error.v, &y.v, &self.trial.v))
    }

    /// How far the deepest free particle of `state` is below the floor, m (0 if none).
    fn penetration(&self, state: &State) -> f64 {
        let Some(ground) = self.particles.ground() else {
            return 0.0;
        };
        self.particles
            .system()
            .nodes()
            .iter()
            .zip(&state.x)
            .filter(|(node, _)| !node.fixed)
            .map(|(_, x)| ground.height() - x.y)
            .fold(0.0, f64::max)
    }

    /// One Dormand-Prince step of exactly `h` (no error control), then the floor's response:
    /// the pair's fifth-order method as a fixed-step integrator.
    pub fn fixed_step(&mut self, state: &mut State, h: f64) {
        self.attempt(state, h);
        self.accept(state, h);
    }

    /// Takes `self.trial` as the new state and resolves contacts.
    fn accept(&mut self, state: &mut State, h: f64) {
        std::mem::swap(state, &mut self.trial);
        self.k.swap(0, STAGES - 1);
        if self.penetration(state) > 0.0 {
            self.particles.resolve_contacts(state);
            self.first_stage_current = false;
        }
        let s = &mut self.stats;
        s.accepted += 1;
        s.largest_step = s.largest_step.max(h);
        s.smallest_step = if s.accepted == 1 {
            h
        } else {
            s.smallest_step.min(h)
        };
    }

    /// Advances `state` by `duration` s with error control.
    pub fn advance(&mut self, state: &mut State, duration: f64) -> Result<()> {
        let depth_allowed =
            self.tolerance * (1.0 + self.particles.ground().map_or(0.0, |g| g.height().abs()));
        let mut remaining = duration;
        while remaining > 1e-12 * duration {
            let clipped = self.h >= remaining;
            let h = self.h.min(remaining);
            if h <= 1e-14 * duration.max(1.0) {
                return Err(Error::NotConverged {
                    what: "Dormand-Prince 5(4)".into(),
                    detail: format!(
                        "the step size fell to {h:e} s at tolerance {:e}",
                        self.tolerance
                    ),
                });
            }
            if let Some(limit) = self.attempt_limit {
                let s = &self.stats;
                if s.accepted + s.rejected_error + s.rejected_contact >= limit {
                    return Err(Error::Input(format!(
                        "the adaptive steps reached their work budget of {limit} attempted \
                         steps (accepted {}, rejected {}, the last of {h:e} s)",
                        s.accepted,
                        s.rejected_error + s.rejected_contact
                    )));
                }
            }
            let err = self.attempt(state, h);
            // A NaN estimate (a non-finite state) is rejected like a too-large one.
            if err.is_nan() || err > 1.0 {
                self.stats.rejected_error += 1;
                let factor = if err.is_finite() {
                    (SAFETY * err.powf(-0.2)).max(MAX_SHRINK)
                } else {
                    MAX_SHRINK
                };
                self.h = h * factor;
                continue;
            }
            if self.penetration(&self.trial) > depth_allowed {
                self.stats.rejected_contact += 1;
                self.h = 0.5 * h;
                continue;
            }
            self.accept(state, h);
            remaining = if clipped { 0.0 } else { remaining - h };
            let proposal = h * (SAFETY * err.powf(-0.2)).clamp(MAX_SHRINK, MAX_GROWTH);
            // A step shortened to land on the interval's end says little about the next one.
            if !clipped {
                self.h = proposal;
            }
        }
        Ok(())
    }
}

impl TimeStepper for AdaptiveStepper {
    fn name(&self) -> String {
        format!(
            "Dormand-Prince 5(4), tolerance {:e} (particle system)",
            self.tolerance
        )
    }

    fn dt(&self) -> f64 {
        self.interval
    }

    fn system(&self) -> &MassSpringSystem {
        self.particles.system()
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.advance(state, self.interval)
    }
}

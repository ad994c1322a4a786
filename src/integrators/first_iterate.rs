//! Where a step's iteration starts: the one notion of a *first iterate* that every solver
//! iterating on the incremental potential (Eq 20) shares, so that comparisons can start every
//! solver from the same point.
//!
//! A step from $`(x_n, v_n)`$ minimises $`g(x) = \frac{1}{2h^2}|x - x_n - h v_n|_M^2 + E(x)`$
//! (gravity in $`E`$) by iterating from some $`x^0`$. The papers start from different points,
//! which Chen et al. 2024 (§3.7) list as the four initial guesses (a)-(d), named here as there:
//! - (a) [`FirstIterate::Previous`], $`x^0 = x_n`$: Backward Euler's Newton start ($`v_0 = 0`$)
//!   and this crate's reading of the thesis's Algorithm 3 (Liu 2013), which leaves the start
//!   open;
//! - (b) [`FirstIterate::Inertial`], "inertia", $`x^0 = x_n + h v_n`$: Liu 2013's $`y`$, the
//!   other reading of Algorithm 3 (section 6 of the report);
//! - (c) [`FirstIterate::InertialPrediction`], "inertia and acceleration",
//!   $`x^0 = y = x_n + h v_n + h^2 M^{-1} f_{ext}`$, the inertial prediction: the thesis's
//!   Algorithm 4 (ADMM's $`\tilde x`$), Wang 2015's Algorithm 1, Peng et al. 2018's and Zhang et
//!   al. 2019's reference code, Liu et al. 2017's L-BFGS, and PBD and XPBD by construction. The
//!   report's comparisons of convergence (section 10) start every solver here;
//! - (d) [`FirstIterate::Adaptive`], $`x^0 = x_n + h v_n + h^2\tilde a`$ with the previous
//!   step's acceleration ([Chen 2024, Eq. 17], [`adaptive_scale`]), VBD's recommendation.
//!
//! Fixed nodes start where they are. [`StepStart`] computes the first iterate of each step and
//! keeps the one thing the adaptive guess carries across steps, the velocity at the start of
//! the previous step; with the other three a step depends on its state only.
//!
//! Under an optimization integrator ([`crate::integrators::optimization_integrator`]) a step is one or more
//! stage problems, each a Backward Euler step of length $`\tau`$ from a pseudo-state
//! $`(x_a, u_0)`$: the rules apply to it unchanged, as predictions of the stage's velocity,
//! (a) $`u = 0`$ ($`x^0 = x_a`$, the stage's anchor: $`x_n`$ under Backward Euler and the
//! midpoint), (b) $`u = u_0`$, (c) $`u = u_0 + \tau M^{-1}f_{ext}`$, the stage's inertial
//! prediction $`\hat y`$, and (d) the adaptive one, whose acceleration is measured between the
//! same stage of consecutive steps, a step $`h`$ apart. Under Backward Euler,
//! $`(x_a, u_0, \tau) = (x_n, v_n, h)`$ and every rule is as above.

use crate::error::{Error, Result};
use crate::integrators::optimization_integrator::StageProblem;
use crate::model::lanes::Lane;
use crate::model::system::{MassSpringSystem, State, Vec3};
use nalgebra::Vector3;

pub use super::prediction::{inertial_prediction_from, predicted, pull};

/// The first iterate of a step (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum FirstIterate {
    /// (a) $`x^0 = x_n`$, the previous positions.
    #[default]
    Previous,
    /// (b) "inertia", $`x^0 = x_n + h v_n`$ (Liu 2013's $`y`$).
    Inertial,
    /// (c) "inertia and acceleration", the inertial prediction
    /// $`x^0 = x_n + h v_n + h^2 M^{-1} f_{ext}`$.
    InertialPrediction,
    /// (d) adaptive, $`x^0 = x_n + h v_n + h^2 \hat\alpha\,a_{ext}`$ (Chen 2024, Eq. 17).
    Adaptive,
}

impl FirstIterate {
    /// Every rule, in the order (a)-(d).
    pub const ALL: [FirstIterate; 4] = [
        FirstIterate::Previous,
        FirstIterate::Inertial,
        FirstIterate::InertialPrediction,
        FirstIterate::Adaptive,
    ];

    /// The name on the command line and in the registry: Chen et al. 2024's names.
    pub fn key(self) -> &'static str {
        match self {
            FirstIterate::Previous => "previous-position",
            FirstIterate::Inertial => "inertia",
            FirstIterate::InertialPrediction => "inertia-and-acceleration",
            FirstIterate::Adaptive => "adaptive",
        }
    }

    /// The formula, for prose.
    pub fn formula(self) -> &'static str {
        match self {
            FirstIterate::Previous => "(a) x_n",
            FirstIterate::Inertial => "(b) x_n + h v_n",
            FirstIterate::InertialPrediction => "(c) y = x_n + h v_n + h² M⁻¹ f_ext",
            FirstIterate::Adaptive => "(d) x_n + h v_n + h² α̂ a_ext (adaptive)",
        }
    }
}

impl std::fmt::Display for FirstIterate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.key())
    }
}

impl std::str::FromStr for FirstIterate {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        FirstIterate::ALL
            .into_iter()
            .find(|f| f.key() == s)
            .ok_or_else(|| {
                Error::invalid(
                    "first_iterate",
                    s,
                    "one of previous-position, inertia, inertia-and-acceleration, adaptive",
                )
            })
    }
}

/// (b) "inertia", $`x_n + h v_n`$ of one node, for any lane type ([`crate::model::lanes`]).
#[inline]
pub fn inertia<T: Lane>(x: Vector3<T>, v: Vector3<T>, h: T) -> Vector3<T> {
    x + v * h
}

/// The inertial prediction of node `i`, $`x_n + h v_n + h^2 M^{-1} f_{ext}`$ (a fixed node
/// stays at $`x_n`$): ADMM-PD's $`\tilde x`$ ([`crate::solvers::admm::AdmmIterate::predict`]),
/// so that ADMM starting here is the thesis's Algorithm 4 bit for bit.
pub fn inertial_prediction(system: &MassSpringSystem, state: &State, dt: f64, i: usize) -> Vec3 {
    inertial_prediction_from(system, &state.x, &state.v, dt, i)
}

/// [Chen 2024, Eq. 17] The scale $`\hat\alpha \in [0, 1]`$ of $`a_{ext}`$ in the adaptive
/// guess: the component of the previous step's acceleration $`a^t`$ along $`a_{ext}`$, over
/// $`|a_{ext}|`$, clamped; 1 without an external acceleration to project on.
pub fn adaptive_scale(a_t: Vec3, a_ext: Vec3) -> f64 {
    if a_ext.norm() > 0.0 {
        (a_t.dot(&a_ext) / a_ext.norm_squared()).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The first iterate of each stage under a [`FirstIterate`] rule, with the adaptive guess's
/// history.
#[derive(Debug, Clone, PartialEq)]
pub struct StepStart {
    rule: FirstIterate,
    /// $`v^{t-1}`$: the velocity of each stage slot's previous pseudo-state (adaptive guess
    /// only).
    previous_velocity: Vec<Option<Vec<Vec3>>>,
    /// The last first iterate, one entry per node.
    x: Vec<Vec3>,
}

impl StepStart {
    /// Stages starting at `rule`, with no history.
    pub fn new(rule: FirstIterate) -> Self {
        Self {
            rule,
            previous_velocity: Vec::new(),
            x: Vec::new(),
        }
    }

    /// The rule.
    pub fn rule(&self) -> FirstIterate {
        self.rule
    }

    /// The first iterate of `problem` from the pseudo-state `stage` (a step of `dt` from a
    /// state under Backward Euler), one entry per node. The adaptive guess of a stage without
    /// history is the inertial prediction (TinyVBD's first frame), and it records `stage.v`
    /// for the same stage of the next step.
    pub fn first_iterate(
        &mut self,
        system: &MassSpringSystem,
        stage: &State,
        problem: &StageProblem,
    ) -> &[Vec3] {
        let (dt, slot) = (problem.tau, problem.slot);
        let a_ext = system.gravity();
        if self.previous_velocity.len() <= slot {
            self.previous_velocity.resize(slot + 1, None);
        }
        self.x.resize(stage.x.len(), Vec3::zeros());
        for (i, x) in self.x.iter_mut().enumerate() {
            let node = &system.nodes()[i];
            *x = match self.rule {
                _ if node.fixed => stage.x[i],
                FirstIterate::Previous => stage.x[i],
                FirstIterate::Inertial => inertia(stage.x[i], stage.v[i], dt),
                FirstIterate::InertialPrediction => inertial_prediction(system, stage, dt, i),
                FirstIterate::Adaptive => match &self.previous_velocity[slot] {
                    Some(previous) => {
                        let a_t = (stage.v[i] - previous[i]) / problem.step;
                        let a_tilde = adaptive_scale(a_t, a_ext) * a_ext;
                        stage.x[i] + dt * stage.v[i] + dt * dt * a_tilde
                    }
                    None => inertial_prediction(system, stage, dt, i),
                },
            };
        }
        if self.rule == FirstIterate::Adaptive {
            self.previous_velocity[slot] = Some(stage.v.clone());
        }
        &self.x
    }
}

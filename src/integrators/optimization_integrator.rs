//! Optimization integrators (issue 23): the time integrator apart from the solver that
//! minimises, so that every minimizing solver runs under Backward Euler, implicit midpoint,
//! BDF2 and TR-BDF2.
//!
//! Every implicit solver here minimises thesis Eq 20. Backward Euler fixes the prediction and
//! the weight of the elastic energy in it; other implicit schemes give other predictions and
//! weights, and so the same minimisation (Brown, Overby, Forootaninia & Narain 2018 call these
//! *optimization integrators*). An integrator turns a state into one or more **stage
//! problems**,
//! ```math
//! \min_x\ \tfrac12\lVert x - \hat y\rVert_M^2 + c\,h^2\,U(x) + c\,h^2\,\tau\,\mathcal D\!\left(x_D, \frac{x - x_a}{\tau}\right),
//! \qquad \hat y = x_a + \tau u_0 + \tau^2 M^{-1} f_{ext},\qquad \tau = \sqrt c\,h,
//! ```
//! with $`U`$ the springs' energy, every explicit force (gravity, the explicit half of a
//! trapezoid) folded into $`\hat y`$, and the dissipation $`\mathcal D`$ of
//! [`crate::integrators::dissipation`] at the stage's velocity $`u(x) = (x - x_a)/\tau`$, its position
//! argument frozen at $`x_D`$. In every scheme below $`c h^2 = \tau^2`$: a stage is a Backward
//! Euler step of length $`\tau`$ from the *pseudo-state* $`(x_a, u_0)`$ (the anchor $`x_a`$,
//! where the stage's velocity is zero, and the velocity prediction $`u_0`$), whose minimiser
//! $`x^*`$ and velocity $`u^* = (x^* - x_a)/\tau`$ the integrator turns into the next state.
//! A [`MinimizingSolver`] solves that problem ([`MinimizingSolver::solve`]) and never knows the
//! integrator; [`Integrated`] is the integrator around one. Backward Euler's stage is the state
//! itself, $`(x_a, u_0) = (x_n, v_n)`$ with $`\tau = h`$ ($`\hat y = x_n + h v_n + h^2 M^{-1}
//! f_{ext}`$, $`c = 1`$), on which each solver does the arithmetic of its printed algorithm, so
//! the thesis's solvers and tables are unchanged bit for bit. A solver prepares its
//! prefactored matrices once per distinct $`\tau`$ ([`MinimizingSolver::prepare`],
//! [`PerStageStep`]). The stage's first iterate is where [`crate::integrators::first_iterate`]'s rule puts
//! it on the pseudo-state: the stage's inertial prediction $`\hat y`$ for (c).
//!
//! Brown et al. 2018's body is not available here (`docs/papers.md`: abstract only): the
//! stage problems below are derived from the standard coefficients of each scheme, applied to
//! $`\dot x = v`$, $`M\dot v = F(x) + f_d(x, v)`$, $`F = -\nabla U + f_{ext}`$, and checked by
//! the tests of `tests/optimization_integrators.rs` (orders, damping, stages).
//!
//! **Backward Euler** (order 1): $`x_a = x_n`$, $`u_0 = v_n`$, $`\tau = h`$; then
//! $`x_{n+1} = x^*`$, $`v_{n+1} = u^*`$.
//!
//! **Implicit midpoint** (order 2, symplectic): with $`z = (x_n + x_{n+1})/2`$,
//! $`x_{n+1} - x_n = h\,\bar v`$ and $`M(v_{n+1} - v_n) = h\,(F(z) + f_d(\bar v))`$,
//! $`\bar v = (v_n + v_{n+1})/2`$, the midpoint minimises
//! $`\frac12\lVert z - (x_n + \frac h2 v_n + \frac{h^2}{4}M^{-1}f_{ext})\rVert_M^2 + \frac{h^2}{4}U(z)`$:
//! $`x_a = x_n`$, $`u_0 = v_n`$, $`\tau = h/2`$, $`c = 1/4`$, $`u^* = \bar v`$; then
//! $`x_{n+1} = 2z - x_n`$ and $`v_{n+1} = 2u^* - v_n = 4(z - x_n)/h - v_n`$.
//!
//! **BDF2** (order 2): $`x_{n+1} - \frac43 x_n + \frac13 x_{n-1} = \frac{2h}{3}v_{n+1}`$ and
//! the same for $`v`$ with $`M^{-1}(F + f_d)`$ at $`n+1`$ give $`x_a = \frac43 x_n - \frac13
//! x_{n-1}`$, $`u_0 = \frac13(4v_n - v_{n-1})`$, $`\tau = \frac{2h}{3}`$, $`c = 4/9`$:
//! $`\hat y = \frac43 x_n - \frac13 x_{n-1} + \frac{2h}{9}(4v_n - v_{n-1}) + \frac49 h^2 M^{-1}
//! f_{ext}`$, and $`v_{n+1} = u^* = \frac{3}{2h}(x_{n+1} - \frac43 x_n + \frac13 x_{n-1})`$.
//! BDF2 needs a previous state: its first step (and any step from a state it did not produce)
//! is one TR-BDF2 step.
//!
//! **TR-BDF2** (order 2, L-stable; Bank et al. 1985's two stages) with
//! $`\gamma = 2 - \sqrt2`$ ([`GAMMA`]). Stage 1, the trapezoidal rule to $`t_n + \gamma h`$:
//! $`x_\gamma = x_n + \frac{\gamma h}{2}(v_n + v_\gamma)`$,
//! $`M(v_\gamma - v_n) = \frac{\gamma h}{2}(F(x_n) + f_d(x_n, v_n) + F(x_\gamma) + f_d(v_\gamma))`$,
//! so $`\tau = \gamma h/2`$, $`c_1 = \gamma^2/4`$, $`x_a = x_n + \tau v_n`$ and
//! $`u_0 = v_n + \tau M^{-1}(F(x_n) + f_d(x_n, v_n))`$ with $`F`$ the full force, gravity in it
//! (so $`\hat y_1 = x_n + \gamma h v_n + \frac{(\gamma h)^2}{4}M^{-1}(F(x_n) + f_{ext})`$ without
//! dissipation), and $`u^* = v_\gamma = 2(x_\gamma - x_n)/(\gamma h) - v_n`$. Stage 2, BDF2
//! over $`x_n, x_\gamma, x_{n+1}`$: with $`a = \frac{1}{\gamma(2-\gamma)}`$,
//! $`b = \frac{(1-\gamma)^2}{\gamma(2-\gamma)}`$ ($`a - b = 1`$) and
//! $`w = \frac{1-\gamma}{2-\gamma}`$, $`x_{n+1} = a x_\gamma - b x_n + w h\,v_{n+1}`$ and the same
//! for $`v`$: $`x_a = a x_\gamma - b x_n`$, $`u_0 = a v_\gamma - b v_n`$, $`\tau = w h`$,
//! $`c_2 = w^2`$, $`\hat y_2 = a x_\gamma - b x_n + w h(a v_\gamma - b v_n) + w^2h^2M^{-1}f_{ext}`$,
//! $`v_{n+1} = u^* = (x_{n+1} - a x_\gamma + b x_n)/(wh)`$. For this $`\gamma`$,
//! $`w = \gamma/2`$ exactly, so $`c_1 = c_2`$ and one factorisation serves both stages; the
//! code takes $`\tau_2 = \tau_1`$ (tested: the two formulas agree to round-off).
//!
//! The dissipation's position argument (where Rayleigh damping's stiffness is frozen, as in
//! [`crate::integrators::damping`]) is the stage's start: $`x_n`$ for Backward Euler, the midpoint, BDF2
//! and TR-BDF2's first stage, $`x_\gamma`$ for its second. Frozen there, the stiffness-
//! proportional term is exact for a linear spring and first order in the change of the
//! stiffness over a step otherwise. Fixed nodes keep $`x_a = x_n`$, $`u_0 = 0`$ exactly.

use crate::error::{Error, Result};
use crate::integrators::dissipation::Dissipation;
use crate::integrators::stopping::Convergence;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};

/// TR-BDF2's $`\gamma = 2 - \sqrt2`$ (module doc).
pub const GAMMA: f64 = 2.0 - std::f64::consts::SQRT_2;

/// An optimization integrator (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub enum OptimizationIntegrator {
    /// Order 1: the thesis's scheme.
    #[default]
    BackwardEuler,
    /// Order 2, symplectic: a minimisation over the midpoint, $`c = 1/4`$.
    ImplicitMidpoint,
    /// Order 2, two steps, $`c = 4/9`$; started by one TR-BDF2 step.
    Bdf2,
    /// Order 2: a trapezoidal stage to $`t + \gamma h`$, then a BDF2 stage, $`c = \gamma^2/4`$.
    TrBdf2,
}

impl OptimizationIntegrator {
    /// Every integrator.
    pub const ALL: [OptimizationIntegrator; 4] = [
        OptimizationIntegrator::BackwardEuler,
        OptimizationIntegrator::ImplicitMidpoint,
        OptimizationIntegrator::Bdf2,
        OptimizationIntegrator::TrBdf2,
    ];

    /// The name on the command line, in the registry and in CSV files.
    pub fn key(self) -> &'static str {
        match self {
            OptimizationIntegrator::BackwardEuler => "backward-euler",
            OptimizationIntegrator::ImplicitMidpoint => "implicit-midpoint",
            OptimizationIntegrator::Bdf2 => "bdf2",
            OptimizationIntegrator::TrBdf2 => "tr-bdf2",
        }
    }

    /// The name in prose.
    pub fn label(self) -> &'static str {
        match self {
            OptimizationIntegrator::BackwardEuler => "Backward Euler",
            OptimizationIntegrator::ImplicitMidpoint => "implicit midpoint",
            OptimizationIntegrator::Bdf2 => "BDF2",
            OptimizationIntegrator::TrBdf2 => "TR-BDF2",
        }
    }

    /// The global order of accuracy.
    pub fn order(self) -> u32 {
        match self {
            OptimizationIntegrator::BackwardEuler => 1,
            _ => 2,
        }
    }

    /// The distinct stage steps $`\tau = \sqrt c\,h`$ of a step `h`: one prefactored matrix each.
    pub fn stage_steps(self, h: f64) -> Vec<f64> {
        match self {
            OptimizationIntegrator::BackwardEuler => vec![h],
            OptimizationIntegrator::ImplicitMidpoint => vec![h / 2.0],
            OptimizationIntegrator::Bdf2 => vec![2.0 * h / 3.0, tr_bdf2_tau(h)],
            OptimizationIntegrator::TrBdf2 => vec![tr_bdf2_tau(h)],
        }
    }
}

impl std::fmt::Display for OptimizationIntegrator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.key())
    }
}

impl std::str::FromStr for OptimizationIntegrator {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        OptimizationIntegrator::ALL
            .into_iter()
            .find(|i| i.key() == s)
            .ok_or_else(|| {
                Error::invalid(
                    "integrator",
                    s,
                    "one of backward-euler, implicit-midpoint, bdf2, tr-bdf2",
                )
            })
    }
}

/// TR-BDF2's stage step $`\tau = \gamma h/2`$ (both stages).
fn tr_bdf2_tau(h: f64) -> f64 {
    GAMMA * h / 2.0
}

/// TR-BDF2's second-stage coefficients $`(a, b, w)`$ of the module doc.
pub fn tr_bdf2_coefficients() -> (f64, f64, f64) {
    let g = GAMMA;
    let a = 1.0 / (g * (2.0 - g));
    let b = (1.0 - g) * (1.0 - g) / (g * (2.0 - g));
    (a, b, (1.0 - g) / (2.0 - g))
}

/// The arithmetic of a stage's pseudo-state and of a step's end on one coordinate (`f64`, the
/// continuum's flat unknowns) or one node (`Vec3`, the springs'): one formula for both models.
pub trait Coordinate:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<f64, Output = Self>
    + std::ops::Div<f64, Output = Self>
{
}

impl<T> Coordinate for T where
    T: Copy
        + std::ops::Add<Output = T>
        + std::ops::Sub<Output = T>
        + std::ops::Mul<f64, Output = T>
        + std::ops::Div<f64, Output = T>
{
}

/// Implicit midpoint's end of a step (module doc): $`x_{n+1} = 2z - x_n`$ from the midpoint
/// $`z`$, and likewise $`v_{n+1} = 2u^* - v_n`$.
pub fn midpoint_end<T: Coordinate>(mid: T, start: T) -> T {
    mid * 2.0 - start
}

/// BDF2's pseudo-state (module doc): $`x_a = \frac13(4x_n - x_{n-1})`$, and likewise
/// $`u_0`$ from the velocities.
pub fn bdf2_pseudo<T: Coordinate>(now: T, before: T) -> T {
    (now * 4.0 - before) / 3.0
}

/// TR-BDF2's first, trapezoidal stage (module doc): $`x_a = x_n + \tau v_n`$,
/// $`u_0 = v_n + \tau M^{-1}F`$, `force` the full force (gravity and the dissipation in it).
pub fn trapezoid_pseudo<T: Coordinate>(x: T, v: T, force: T, tau: f64, mass: f64) -> (T, T) {
    (x + v * tau, v + force * (tau / mass))
}

/// TR-BDF2's second, BDF2 stage (module doc): $`x_a = a\,x_\gamma - b\,x_n`$, and likewise
/// $`u_0`$, with `(a, b)` of [`tr_bdf2_coefficients`].
pub fn tr_bdf2_pseudo<T: Coordinate>(gamma: T, start: T, (a, b): (f64, f64)) -> T {
    gamma * a - start * b
}

/// One stage problem (module doc), apart from its pseudo-state $`(x_a, u_0)`$, which the
/// solver is handed as a [`State`] and replaces by the solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageProblem<'a> {
    /// $`\tau = \sqrt c\,h`$, s: the weight of the elastic energy is $`\tau^2`$.
    pub tau: f64,
    /// The time step $`h`$, s: the time from this stage to the same stage of the next step.
    pub step: f64,
    /// Which stage of the step (0, or 1 for TR-BDF2's second), for what a solver carries from
    /// one step's stage to the next step's (the adaptive first iterate).
    pub slot: usize,
    /// Where the dissipation's position argument is frozen, $`x_D`$; `None`: at the anchor
    /// $`x_a`$ (Backward Euler, the midpoint).
    pub frozen: Option<&'a [Vec3]>,
}

impl StageProblem<'static> {
    /// Backward Euler's only stage for a step `h`: $`\tau = h`$, the state itself.
    pub fn backward_euler(h: f64) -> Self {
        Self {
            tau: h,
            step: h,
            slot: 0,
            frozen: None,
        }
    }
}

impl StageProblem<'_> {
    /// $`c = (\tau/h)^2`$.
    pub fn weight(&self) -> f64 {
        (self.tau / self.step).powi(2)
    }

    /// $`x_D`$: the frozen positions, or the anchor `stage.x`.
    pub fn frozen_positions<'b>(&'b self, stage: &'b State) -> &'b [Vec3] {
        self.frozen.unwrap_or(&stage.x)
    }
}

/// A solver of stage problems: every solver iterating on thesis Eq 20.
pub trait MinimizingSolver: TimeStepper {
    /// Solves `problem` from the pseudo-state `stage` $`= (x_a, u_0)`$ and leaves in it the
    /// solution $`(x^*, u^*)`$, $`u^* = (x^* - x_a)/\tau`$ in the solver's own arithmetic. Fixed
    /// nodes stay at $`x_a`$.
    fn solve(&mut self, problem: &StageProblem, stage: &mut State) -> Result<()>;

    /// Builds what the solver prefactors for a stage step `tau`, so that a run fails before it
    /// starts rather than at its first stage of that step; [`Self::solve`] builds it otherwise.
    fn prepare(&mut self, _tau: f64) -> Result<()> {
        Ok(())
    }

    /// The dissipation in the solver's objective, whose explicit half a trapezoidal stage
    /// folds into its prediction.
    fn dissipation(&self) -> Option<&Dissipation> {
        None
    }
}

/// What a solver prepares per stage step $`\tau`$ (a factorisation, a spectral radius), built
/// once per distinct $`\tau`$, with the one the current stage uses.
#[derive(Debug, Clone)]
pub struct PerStageStep<T> {
    entries: Vec<(f64, T)>,
    current: usize,
}

impl<T> PerStageStep<T> {
    /// The entry of the solver's own step `tau`.
    pub fn new(tau: f64, value: T) -> Self {
        Self {
            entries: vec![(tau, value)],
            current: 0,
        }
    }

    /// Makes the entry of `tau` current, building it with `build` if it is new.
    pub fn select(&mut self, tau: f64, build: impl FnOnce(f64) -> Result<T>) -> Result<&mut T> {
        match self.entries.iter().position(|(t, _)| *t == tau) {
            Some(i) => self.current = i,
            None => {
                self.entries.push((tau, build(tau)?));
                self.current = self.entries.len() - 1;
            }
        }
        Ok(&mut self.entries[self.current].1)
    }

    /// The entry of the solver's own step (the one [`Self::new`] took).
    pub fn own(&self) -> &T {
        &self.entries[0].1
    }

    /// The current entry.
    pub fn current(&self) -> &T {
        &self.entries[self.current].1
    }

    /// The current entry, mutable.
    pub fn current_mut(&mut self) -> &mut T {
        &mut self.entries[self.current].1
    }
}

/// Sets the pseudo-state `stage` of a stage from `state` $`= (x_n, v_n)`$: `free(i, m_i,
/// stage)` gives $`(x_a, u_0)`$ of free node `i` (from the stage's previous contents, for a
/// stage that follows another); a fixed node keeps $`x_a = x_n`$, $`u_0 = 0`$ exactly.
fn set_pseudo_state(
    system: &MassSpringSystem,
    state: &State,
    stage: &mut State,
    free: impl Fn(usize, f64, &State) -> (Vec3, Vec3),
) {
    for (i, node) in system.nodes().iter().enumerate() {
        let (x, v) = if node.fixed {
            (state.x[i], Vec3::zeros())
        } else {
            free(i, node.mass, stage)
        };
        stage.x[i] = x;
        stage.v[i] = v;
    }
}

/// A minimizing solver under an integrator: the [`TimeStepper`] that builds each step's stage
/// problems and turns their solutions into the next state (module doc).
pub struct Integrated {
    solver: Box<dyn MinimizingSolver + Send>,
    integrator: OptimizationIntegrator,
    h: f64,
    /// BDF2: the state before the last step, and the state the last step produced (a step from
    /// any other state starts the two-step scheme again).
    history: Option<(State, State)>,
    /// The pseudo-state of the current stage.
    stage: State,
    /// A stage's frozen dissipation positions, when they are not the step's start.
    frozen: Vec<Vec3>,
    /// Scratch: the explicit force of a trapezoidal stage.
    forces: Vec<Vec3>,
}

impl std::fmt::Debug for Integrated {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Integrated")
            .field("solver", &self.solver.name())
            .field("integrator", &self.integrator)
            .finish()
    }
}

impl Integrated {
    /// `solver` under `integrator`, its matrices prepared for every stage step.
    pub fn new(
        mut solver: Box<dyn MinimizingSolver + Send>,
        integrator: OptimizationIntegrator,
    ) -> Result<Self> {
        let h = solver.dt();
        for tau in integrator.stage_steps(h) {
            solver.prepare(tau)?;
        }
        let n = solver.system().len();
        Ok(Self {
            solver,
            integrator,
            h,
            history: None,
            stage: State::zeros(n),
            frozen: vec![Vec3::zeros(); n],
            forces: vec![Vec3::zeros(); n],
        })
    }

    /// The integrator.
    pub fn integrator(&self) -> OptimizationIntegrator {
        self.integrator
    }

    /// The implicit midpoint step (module doc).
    fn midpoint(&mut self, state: &mut State) -> Result<()> {
        let problem = StageProblem {
            tau: self.h / 2.0,
            step: self.h,
            slot: 0,
            frozen: None,
        };
        self.stage.clone_from(state);
        self.solver.solve(&problem, &mut self.stage)?;
        let (z, u) = (&self.stage.x, &self.stage.v);
        for (i, node) in self.solver.system().nodes().iter().enumerate() {
            if !node.fixed {
                state.x[i] = midpoint_end(z[i], state.x[i]);
                state.v[i] = midpoint_end(u[i], state.v[i]);
            }
        }
        Ok(())
    }

    /// The BDF2 stage from $`x_n`$ (`state`) and $`x_{n-1}`$ (`previous`), module doc.
    fn bdf2(&mut self, state: &mut State, previous: &State) -> Result<()> {
        let problem = StageProblem {
            tau: 2.0 * self.h / 3.0,
            step: self.h,
            slot: 0,
            frozen: Some(&state.x),
        };
        set_pseudo_state(self.solver.system(), state, &mut self.stage, |i, _, _| {
            (
                bdf2_pseudo(state.x[i], previous.x[i]),
                bdf2_pseudo(state.v[i], previous.v[i]),
            )
        });
        self.solver.solve(&problem, &mut self.stage)?;
        state.clone_from(&self.stage);
        Ok(())
    }

    /// The TR-BDF2 step: the trapezoidal stage, then the BDF2 stage (module doc).
    fn tr_bdf2(&mut self, state: &mut State) -> Result<()> {
        let tau = tr_bdf2_tau(self.h);
        let system = self.solver.system();
        system.forces(&state.x, &mut self.forces);
        if let Some(d) = self.solver.dissipation() {
            d.add_force(system, &state.x, &state.v, &mut self.forces);
        }
        let forces = &self.forces;
        set_pseudo_state(system, state, &mut self.stage, |i, mass, _| {
            trapezoid_pseudo(state.x[i], state.v[i], forces[i], tau, mass)
        });
        let trapezoid = StageProblem {
            tau,
            step: self.h,
            slot: 0,
            frozen: Some(&state.x),
        };
        self.solver.solve(&trapezoid, &mut self.stage)?;
        // Stage 2 from (x_n, v_n) and (x_γ, v_γ); its dissipation frozen at x_γ.
        let (a, b, _) = tr_bdf2_coefficients();
        let ab = (a, b);
        self.frozen.copy_from_slice(&self.stage.x);
        set_pseudo_state(
            self.solver.system(),
            state,
            &mut self.stage,
            |i, _, gamma| {
                (
                    tr_bdf2_pseudo(gamma.x[i], state.x[i], ab),
                    tr_bdf2_pseudo(gamma.v[i], state.v[i], ab),
                )
            },
        );
        let bdf2 = StageProblem {
            tau,
            step: self.h,
            slot: 1,
            frozen: Some(&self.frozen),
        };
        self.solver.solve(&bdf2, &mut self.stage)?;
        state.clone_from(&self.stage);
        Ok(())
    }
}

impl TimeStepper for Integrated {
    fn name(&self) -> String {
        match self.integrator {
            OptimizationIntegrator::BackwardEuler => self.solver.name(),
            other => format!("{} under {}", self.solver.name(), other.label()),
        }
    }

    fn dt(&self) -> f64 {
        self.h
    }

    fn system(&self) -> &MassSpringSystem {
        self.solver.system()
    }

    fn convergence(&mut self) -> Option<&mut Convergence> {
        self.solver.convergence()
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        match self.integrator {
            OptimizationIntegrator::BackwardEuler => self
                .solver
                .solve(&StageProblem::backward_euler(self.h), state),
            OptimizationIntegrator::ImplicitMidpoint => self.midpoint(state),
            OptimizationIntegrator::TrBdf2 => self.tr_bdf2(state),
            OptimizationIntegrator::Bdf2 => {
                let n = state.x.len();
                let continued = self.history.as_ref().is_some_and(|(_, last)| last == state);
                let (mut previous, mut last) = self
                    .history
                    .take()
                    .unwrap_or_else(|| (State::zeros(n), State::zeros(n)));
                if continued {
                    self.bdf2(state, &previous)?;
                    // x_n, the state the last step produced, is the next step's x_{n-1}.
                    std::mem::swap(&mut previous, &mut last);
                } else {
                    previous.clone_from(state);
                    self.tr_bdf2(state)?;
                }
                last.clone_from(state);
                self.history = Some((previous, last));
                Ok(())
            }
        }
    }
}

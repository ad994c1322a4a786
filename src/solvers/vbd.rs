//! Vertex Block Descent (Anka He Chen, Ziheng Liu, Yin Yang & Cem Yuksel 2024, "Vertex Block
//! Descent", ACM TOG 43(4), SIGGRAPH 2024; reference code AnkaChan/Gaia and AnkaChan/TinyVBD).
//!
//! VBD minimises the same variational form of implicit Euler as the thesis's Eq 20,
//! ```math
//! x^{t+1} = \arg\min_x G(x),\qquad G(x) = \frac{1}{2h^2}\lVert x - y\rVert_M^2 + E(x),\qquad
//! y = x^t + h v^t + h^2 a_{ext},
//! ```
//! (the paper's §3.1; gravity is the external acceleration, so $`E`$ holds the springs only, which
//! is Eq 20 up to a constant), by block coordinate descent with one block per vertex
//! (Gauss-Seidel over vertices). Vertex $`i`$ sees only the part of $`G`$ that depends on it,
//! $`G_i(x) = \frac{m_i}{2h^2}\lVert x_i - y_i\rVert^2 + \sum_{j\in\mathcal F_i} E_j(x)`$, and
//! takes one Newton step on it (the paper's §3.2):
//! ```math
//! \begin{aligned}
//! H_i\,\Delta x_i &= f_i,\\
//! f_i &= -\frac{m_i}{h^2}(x_i - y_i)
//!   - \sum_{j\in\mathcal F_i}\frac{\partial E_j}{\partial x_i},\\
//! H_i &= \frac{m_i}{h^2}I
//!   + \sum_{j\in\mathcal F_i}\frac{\partial^2 E_j}{\partial x_i\,\partial x_i},
//! \end{aligned}
//! ```
//! with $`-\partial E_j/\partial x_i`$ the spring force of thesis Eq 3 and
//! $`\partial^2E_j/\partial x_i^2 = -\,\partial F/\partial x`$ of thesis Eq 4 ([`vertex_step`]).
//! Vertices that share no spring do not interact, so the vertices of one colour of a graph
//! colouring can move in parallel; the paper's Algorithm 1 sweeps the colours in order. The rope
//! is 2-colourable (odd and even free nodes); [`greedy_colouring`] colours any spring graph.
//! Running the vertices of a colour one after the other gives bit for bit what the parallel
//! update gives, since none reads another's position.
//!
//! # Initial guess (the paper's §3.7)
//! The step starts from one of the paper's four guesses, which are the crate's shared
//! [`FirstIterate`] rules ([`crate::integrators::first_iterate`]), named as the paper names them: (a)
//! `previous-position` $`x^t`$; (b) `inertia` $`x^t + hv^t`$; (c) `inertia-and-acceleration`
//! $`y = x^t + hv^t + h^2a_{ext}`$; (d) `adaptive`, the paper's recommendation and the default,
//! $`x^t + hv^t + h^2\tilde a`$ with $`\tilde a = \hat\alpha\,a_{ext}`$ (Eq. 17), where
//! $`\hat\alpha`$ is the component of the previous step's acceleration $`a^t = (v^t - v^{t-1})/h`$
//! along $`a_{ext}`$, divided by $`|a_{ext}|`$ and clamped to [0, 1].
//!
//! The adaptive guess needs $`v^{t-1}`$, the velocity at the start of the previous step: it is
//! the one thing [`Vbd`] carries from one step to the next (the paper's method does, and only
//! with this guess does a step depend on more than the state). The first step of a solver has
//! no history and takes $`\hat\alpha = 1`$, the guess (c), as TinyVBD does; the convergence
//! curves measured with a fresh solver per point are therefore those of (c).
//!
//! # Indefinite local Hessians
//! A compressed spring ($`l < l_0`$) makes its Hessian block indefinite across its axis, and
//! $`H_i`$ may then not be positive definite. The paper (§3.2) inverts the exact $`H_i`$
//! regardless, the step then being toward the extremum of the local quadratic model rather than
//! a descent direction, and it considers and rejects a positive-semidefinite projection as too
//! costly for so rare an event; it skips a vertex for the iteration only when
//! $`|\det H_i| \le \varepsilon`$, for a small $`\varepsilon`$ it does not state. That is the
//! default here ([`LocalHessian::Exact`]), with
//! $`\varepsilon = 10^{-10}\,(m_i/h^2)^3`$ ([`DETERMINANT_THRESHOLD`], relative to the
//! determinant of the inertia term alone, so that it does not depend on the units); the skipped
//! vertices are counted in the iteration log ([`crate::integrators::stopping::IterationLog::skipped`]).
//! [`LocalHessian::Projected`], this crate's variant, rebuilds a non-positive-definite $`H_i`$
//! with every spring's transverse term $`1 - l_0/l`$ clamped at 0
//! ([`spring::force_jacobian_definite`], the projection the converged Backward Euler step uses),
//! which keeps $`H_i \succeq \frac{m_i}{h^2}I`$: every vertex moves along a descent direction of
//! $`G_i`$ and none is skipped. Where the exact $`H_i`$ is positive definite both rules take the
//! paper's step. TinyVBD (the authors' strand code) solves the exact $`H_i`$ by a QR
//! decomposition, with neither a skip nor a projection.
//!
//! What is left out: the paper's collisions and friction (the rope has none), its damping term,
//! and its Chebyshev acceleration of the iterations (Eqs. 18-19; TinyVBD's active set-up has it
//! off, `useAcceleration = false`, with $`\rho`$ = 0.05 in the version read, and the Chebyshev
//! semi-iterative method is [`crate::solvers::chebyshev`]'s subject).
//!
//! Under an optimization integrator ([`crate::integrators::optimization_integrator`]) each stage is the same
//! sweep with $`h`$ the stage's $`\tau`$ and $`(x^t, v^t)`$ its pseudo-state, $`y`$ its
//! inertial prediction $`\hat y`$.
//!
//! # Measured on the thesis rope (`tests/newer_solvers.rs`)
//! At dt = 1e-2, k = 1e6, one step from a moving state (10 converged steps from rest), VBD needs
//! 9 sweeps for a gap of 1e-6 m to the converged Backward Euler step and 53 for 1e-9 m (L-BFGS:
//! 92 and 188). On the rope each vertex's 3×3 Newton step carries the spring's exact transverse
//! stiffness, which Projective Dynamics' Laplacian overstates by the inverse strain. Along
//! 100 steps of VBD runs from rest (both stiffnesses, dt = 1e-3 and 1e-2, 5 sweeps) all 16000
//! vertex steps had a positive definite exact $`H_i`$ and each lowered the incremental
//! potential; the projection is reached from a compressed start (rest length 1.2 m).

use crate::error::{require_positive, Error, Result};
use crate::integrators::first_iterate::{inertial_prediction, FirstIterate, StepStart};
use crate::integrators::optimization_integrator::{MinimizingSolver, StageProblem};
use crate::integrators::stopping::Convergence;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::spring;
use crate::model::system::{MassSpringSystem, State, Vec3};
use nalgebra::Matrix3;

/// $`\varepsilon / (m_i/h^2)^3`$: a vertex whose exact $`|\det H_i|`$ is at most this times the
/// cube of its inertia term is skipped for the iteration (the paper's §3.2 rule; the value is
/// ours, the paper gives none).
pub const DETERMINANT_THRESHOLD: f64 = 1e-10;

/// How a vertex's Newton step treats its local Hessian $`H_i`$ (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LocalHessian {
    /// The paper's: the exact $`H_i`$, inverted whatever its definiteness; the vertex skipped
    /// when $`|\det H_i| \le \varepsilon`$.
    #[default]
    Exact,
    /// This crate's variant: a non-positive-definite $`H_i`$ rebuilt with each spring's
    /// transverse term clamped at 0.
    Projected,
}

impl LocalHessian {
    /// Both rules.
    pub const ALL: [LocalHessian; 2] = [LocalHessian::Exact, LocalHessian::Projected];

    /// The name on the command line.
    pub fn key(self) -> &'static str {
        match self {
            LocalHessian::Exact => "exact",
            LocalHessian::Projected => "projected",
        }
    }
}

impl std::str::FromStr for LocalHessian {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        LocalHessian::ALL
            .into_iter()
            .find(|h| h.key() == s)
            .ok_or_else(|| Error::invalid("hessian", s, "exact or projected"))
    }
}

/// The parameters of Chen et al. 2024.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VbdParams {
    /// The initial guess of each step (the paper's §3.7, (a)-(d)).
    pub first_iterate: FirstIterate,
    /// The local Hessian rule.
    pub hessian: LocalHessian,
}

impl Default for VbdParams {
    /// The paper's recommendation: the adaptive initial guess (d), and the exact Hessian.
    fn default() -> Self {
        Self {
            first_iterate: FirstIterate::Adaptive,
            hessian: LocalHessian::Exact,
        }
    }
}

impl VbdParams {
    /// Every combination is valid; kept so that every solver's parameters validate alike.
    pub fn validate(&self) -> Result<()> {
        Ok(())
    }
}

/// A colouring of the free nodes of `system`'s spring graph in which no two nodes of a colour
/// share a spring: each free node, in index order, takes the smallest colour none of its
/// already coloured neighbours has. Fixed nodes never move and are left out. Returns the nodes
/// of each colour, in index order.
pub fn greedy_colouring(system: &MassSpringSystem) -> Vec<Vec<usize>> {
    let n = system.len();
    let mut neighbours = vec![Vec::new(); n];
    for s in system.springs() {
        neighbours[s.a].push(s.b);
        neighbours[s.b].push(s.a);
    }
    let mut colour: Vec<Option<usize>> = vec![None; n];
    let mut colours: Vec<Vec<usize>> = Vec::new();
    for i in (0..n).filter(|&i| !system.nodes()[i].fixed) {
        let taken: Vec<usize> = neighbours[i].iter().filter_map(|&j| colour[j]).collect();
        let c = (0..).find(|c| !taken.contains(c)).expect("a free colour");
        colour[i] = Some(c);
        if c == colours.len() {
            colours.push(Vec::new());
        }
        colours[c].push(i);
    }
    colours
}

/// The outcome of one vertex's Newton step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexUpdate {
    /// $`\Delta x_i`$, m (zero for a skipped vertex).
    pub delta_x: Vec3,
    /// True when the exact rule skipped the vertex ($`|\det H_i| \le \varepsilon`$).
    pub skipped: bool,
}

/// [Chen 2024, Eqs. 8-9] The local system of vertex `i` over the springs `adjacent` to it: the
/// force $`f_i = -\frac{m_i}{h^2}(x_i - y_i) + \sum_j F_j`$ and the exact Hessian
/// $`H_i = \frac{m_i}{h^2}I - \sum_j \partial F_j/\partial x_i`$ (thesis Eqs 3-4), or with
/// `jacobian` = [`spring::force_jacobian_definite`] the projected one. `y` is the paper's
/// inertia $`x^t + hv^t + h^2a_{ext}`$.
pub fn local_system(
    system: &MassSpringSystem,
    adjacent: &[usize],
    x: &[Vec3],
    y: &[Vec3],
    i: usize,
    dt: f64,
    jacobian: fn(&Vec3, &Vec3, f64, f64) -> Matrix3<f64>,
) -> (Matrix3<f64>, Vec3) {
    let inertia = system.nodes()[i].mass / (dt * dt);
    let mut f = -inertia * (x[i] - y[i]);
    let mut h = inertia * Matrix3::identity();
    for &j in adjacent {
        let s = &system.springs()[j];
        let force = spring::force(&x[s.a], &x[s.b], s.rest_length, s.stiffness);
        f += if s.a == i { force } else { -force };
        h -= jacobian(&x[s.a], &x[s.b], s.rest_length, s.stiffness);
    }
    (h, f)
}

/// [Chen 2024, Eq. 7] One vertex's Newton step on $`G_i`$, $`H_i\Delta x_i = f_i`$
/// ([`local_system`]), under the rule `hessian`: the exact $`H_i`$ inverted, or the vertex
/// skipped when $`|\det H_i| \le \varepsilon`$ ([`DETERMINANT_THRESHOLD`]); or the projected
/// $`H_i`$ where the exact one is not positive definite.
pub fn vertex_step(
    system: &MassSpringSystem,
    adjacent: &[usize],
    x: &[Vec3],
    y: &[Vec3],
    i: usize,
    dt: f64,
    hessian: LocalHessian,
) -> VertexUpdate {
    let (h, f) = local_system(system, adjacent, x, y, i, dt, spring::force_jacobian);
    let moved = |delta_x| VertexUpdate {
        delta_x,
        skipped: false,
    };
    match hessian {
        LocalHessian::Exact => {
            let inertia = system.nodes()[i].mass / (dt * dt);
            let threshold = DETERMINANT_THRESHOLD * inertia.powi(3);
            match h.try_inverse() {
                Some(inverse) if h.determinant().abs() > threshold => moved(inverse * f),
                _ => VertexUpdate {
                    delta_x: Vec3::zeros(),
                    skipped: true,
                },
            }
        }
        LocalHessian::Projected => match h.cholesky() {
            Some(h) => moved(h.solve(&f)),
            None => moved(
                local_system(
                    system,
                    adjacent,
                    x,
                    y,
                    i,
                    dt,
                    spring::force_jacobian_definite,
                )
                .0
                .cholesky()
                .expect("m/h² I plus positive semidefinite blocks")
                .solve(&f),
            ),
        },
    }
}

/// Vertex Block Descent with `iterations` sweeps over the colours per step.
#[derive(Debug, Clone)]
pub struct Vbd {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    params: VbdParams,
    colours: Vec<Vec<usize>>,
    /// The springs of each node, $`\mathcal F_i`$.
    adjacent: Vec<Vec<usize>>,
    /// The initial guess, with the adaptive guess's history.
    start: StepStart,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
}

impl Vbd {
    /// VBD for `system` with time step `dt` (s, > 0), `iterations` (>= 1) colour sweeps per
    /// step and the paper's `params`.
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        params: VbdParams,
    ) -> Result<Self> {
        params.validate()?;
        require_positive("dt", dt)?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let mut adjacent = vec![Vec::new(); system.len()];
        for (j, s) in system.springs().iter().enumerate() {
            adjacent[s.a].push(j);
            adjacent[s.b].push(j);
        }
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            params,
            colours: greedy_colouring(system),
            adjacent,
            start: StepStart::new(params.first_iterate),
            convergence: Convergence::default(),
        })
    }

    /// The colours, each a list of nodes.
    pub fn colours(&self) -> &[Vec<usize>] {
        &self.colours
    }

    /// The springs of each node.
    pub fn adjacent(&self) -> &[Vec<usize>] {
        &self.adjacent
    }
}

impl TimeStepper for Vbd {
    fn name(&self) -> String {
        format!(
            "VBD ({}, {} initialization, {} Hessian)",
            self.convergence
                .iterations_label(self.iterations, "iterations"),
            self.params.first_iterate.key(),
            self.params.hessian.key()
        )
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    fn convergence(&mut self) -> Option<&mut Convergence> {
        Some(&mut self.convergence)
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.solve(&StageProblem::backward_euler(self.dt), state)
    }
}

impl MinimizingSolver for Vbd {
    /// [Chen 2024, Alg. 1] The inertia $`y`$, the initial guess, `iterations` sweeps over the
    /// colours with one Newton step per vertex, then $`v^{t+1} = (x - x^t)/h`$ (Eq. 6).
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        let h = problem.tau;
        let y: Vec<Vec3> = (0..state.x.len())
            .map(|i| inertial_prediction(&self.system, state, h, i))
            .collect();
        let mut x = self
            .start
            .first_iterate(&self.system, state, problem)
            .to_vec();
        self.convergence
            .begin_stage(&self.system, state, problem.tau, x.iter().copied());
        let mut skipped = 0;
        // Stopping early only in the tolerance mode.
        for _ in 0..self.iterations {
            for colour in &self.colours {
                for &i in colour {
                    let update = vertex_step(
                        &self.system,
                        &self.adjacent[i],
                        &x,
                        &y,
                        i,
                        h,
                        self.params.hessian,
                    );
                    x[i] += update.delta_x;
                    skipped += u64::from(update.skipped);
                }
            }
            if self.convergence.converged(x.iter().copied()) {
                break;
            }
        }
        self.convergence.skipped(skipped);
        self.convergence.end_step(0);
        if !x.iter().all(|p| p.iter().all(|c| c.is_finite())) {
            return Err(Error::NotConverged {
                what: "VBD".into(),
                detail: "a vertex update is no longer finite".into(),
            });
        }
        for ((x_t, v), x) in state.x.iter_mut().zip(state.v.iter_mut()).zip(&x) {
            *v = (x - *x_t) / h;
            *x_t = *x;
        }
        Ok(())
    }
    // endregion: step
}

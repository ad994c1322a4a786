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
//! [`Initialization`]: the previous position $`x^t`$; $`x^t + hv^t`$; the inertia
//! $`y = x^t + hv^t + h^2a_{ext}`$; or the paper's recommended adaptive guess
//! $`x^t + hv^t + h^2\tilde a`$, $`\tilde a = \hat\alpha\,a_{ext}`$, where $`\hat\alpha`$ is the
//! component of the previous step's acceleration $`a^t = (v^t - v^{t-1})/h`$ along
//! $`a_{ext}`$, divided by $`|a_{ext}|`$ and clamped to [0, 1]. It is the default.
//!
//! The adaptive guess needs $`v^{t-1}`$, the velocity at the start of the previous step: it is
//! the one thing [`Vbd`] carries from one step to the next (the paper's method does, and only
//! with this guess does a step depend on more than the state). The first step of a solver has
//! no history and takes $`\hat\alpha = 1`$, the inertia $`y`$, as TinyVBD does; the
//! convergence curves measured with a fresh solver per point are therefore those of the
//! inertia guess.
//!
//! # Indefinite local Hessians
//! A compressed spring ($`l < l_0`$) makes its Hessian block indefinite across its axis, and
//! $`H_i`$ may then not be positive definite; the paper skips a vertex whose $`|\det H_i|`$ is
//! below a threshold. Here, when the exact $`H_i`$ has no Cholesky factorisation, it is rebuilt
//! with every spring's transverse term $`1 - l_0/l`$ clamped at 0
//! ([`spring::force_jacobian_definite`], the projection the converged Backward Euler step
//! uses), which keeps $`H_i \succeq \frac{m_i}{h^2}I`$: every vertex moves along a descent
//! direction of $`G_i`$ and none is skipped. Where the exact $`H_i`$ is positive definite the
//! step is the paper's.
//!
//! What is left out: the paper's collisions and friction (the rope has none), its damping term,
//! and its Chebyshev acceleration of the iterations (§3.8; TinyVBD's active configuration sets
//! its $`\rho`$ to 0, and the Chebyshev semi-iterative method is another module's subject).
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
use crate::solver::TimeStepper;
use crate::spring;
use crate::stopping::Convergence;
use crate::system::{MassSpringSystem, State, Vec3};
use nalgebra::Matrix3;

/// The initial guesses of the paper's §3.7.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Initialization {
    /// $`x = x^t`$.
    PreviousPosition,
    /// $`x = x^t + hv^t`$.
    PreviousVelocity,
    /// $`x = y = x^t + hv^t + h^2a_{ext}`$.
    Inertia,
    /// $`x = x^t + hv^t + h^2\tilde a`$ with the previous step's acceleration (the paper's choice).
    Adaptive,
}

impl Initialization {
    /// Every option, in the paper's order.
    pub const ALL: [Initialization; 4] = [
        Initialization::PreviousPosition,
        Initialization::PreviousVelocity,
        Initialization::Inertia,
        Initialization::Adaptive,
    ];

    /// The name used on the command line.
    pub fn key(self) -> &'static str {
        match self {
            Initialization::PreviousPosition => "previous-position",
            Initialization::PreviousVelocity => "previous-velocity",
            Initialization::Inertia => "inertia",
            Initialization::Adaptive => "adaptive",
        }
    }
}

impl std::str::FromStr for Initialization {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        Initialization::ALL
            .into_iter()
            .find(|i| i.key() == s)
            .ok_or_else(|| {
                Error::invalid(
                    "initialization",
                    s,
                    "one of previous-position, previous-velocity, inertia, adaptive",
                )
            })
    }
}

/// The parameters of Chen et al. 2024.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VbdParams {
    /// The initial guess of each step.
    pub initialization: Initialization,
}

impl Default for VbdParams {
    /// The paper's recommendation: the adaptive initial guess.
    fn default() -> Self {
        Self {
            initialization: Initialization::Adaptive,
        }
    }
}

impl VbdParams {
    /// Every initialization is valid; kept so that every solver's parameters validate alike.
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
    /// $`\Delta x_i = H_i^{-1} f_i`$, m.
    pub delta_x: Vec3,
    /// True when the exact $`H_i`$ was positive definite (the paper's step); false when the
    /// projected $`H_i`$ was used.
    pub exact_hessian: bool,
}

/// [Chen 2024, Alg. 1] One vertex's Newton step on $`G_i`$: $`H_i\Delta x_i = f_i`$ with
/// $`f_i = -\frac{m_i}{h^2}(x_i - y_i) + \sum_j F_j`$ and
/// $`H_i = \frac{m_i}{h^2}I - \sum_j \partial F_j/\partial x_i`$ over the springs `adjacent` to
/// node `i` (thesis Eqs 3-4), projected where the exact $`H_i`$ is not positive definite.
/// `y` is the paper's inertia $`x^t + hv^t + h^2a_{ext}`$.
pub fn vertex_step(
    system: &MassSpringSystem,
    adjacent: &[usize],
    x: &[Vec3],
    y: &[Vec3],
    i: usize,
    dt: f64,
) -> VertexUpdate {
    let inertia = system.nodes()[i].mass / (dt * dt);
    let mut f = -inertia * (x[i] - y[i]);
    for &j in adjacent {
        let s = &system.springs()[j];
        let force = spring::force(&x[s.a], &x[s.b], s.rest_length, s.stiffness);
        f += if s.a == i { force } else { -force };
    }
    let hessian = |jacobian: fn(&Vec3, &Vec3, f64, f64) -> Matrix3<f64>| {
        adjacent
            .iter()
            .fold(inertia * Matrix3::identity(), |h, &j| {
                let s = &system.springs()[j];
                h - jacobian(&x[s.a], &x[s.b], s.rest_length, s.stiffness)
            })
    };
    match hessian(spring::force_jacobian).cholesky() {
        Some(h) => VertexUpdate {
            delta_x: h.solve(&f),
            exact_hessian: true,
        },
        None => VertexUpdate {
            delta_x: hessian(spring::force_jacobian_definite)
                .cholesky()
                .expect("m/h² I plus positive semidefinite blocks")
                .solve(&f),
            exact_hessian: false,
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
    /// $`v^{t-1}`$ for the adaptive guess: the velocity at the start of the previous step.
    previous_velocity: Option<Vec<Vec3>>,
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
            previous_velocity: None,
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

    /// [Chen 2024, Alg. 1] The scale $`\hat\alpha \in [0, 1]`$ of $`a_{ext}`$ in the adaptive
    /// guess of node `i`: $`a^t\cdot\hat a_{ext}/|a_{ext}|`$ clamped, 1 without history.
    fn adaptive_scale(&self, v: &[Vec3], i: usize) -> f64 {
        let a_ext = self.system.gravity();
        match &self.previous_velocity {
            Some(previous) if a_ext.norm() > 0.0 => {
                let a_t = (v[i] - previous[i]) / self.dt;
                (a_t.dot(&a_ext) / a_ext.norm_squared()).clamp(0.0, 1.0)
            }
            _ => 1.0,
        }
    }
}

impl TimeStepper for Vbd {
    fn name(&self) -> String {
        format!(
            "VBD ({}, {} initialization)",
            self.convergence
                .iterations_label(self.iterations, "iterations"),
            self.params.initialization.key()
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

    /// [Chen 2024, Alg. 1] The inertia $`y`$, the initial guess, `iterations` sweeps over the
    /// colours with one Newton step per vertex, then $`v^{t+1} = (x - x^t)/h`$.
    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        let h = self.dt;
        let a_ext = self.system.gravity();
        let free = |i: usize| !self.system.nodes()[i].fixed;
        let y: Vec<Vec3> = (0..state.x.len())
            .map(|i| {
                if free(i) {
                    state.x[i] + h * state.v[i] + h * h * a_ext
                } else {
                    state.x[i]
                }
            })
            .collect();
        let mut x: Vec<Vec3> = (0..state.x.len())
            .map(|i| {
                if !free(i) {
                    return state.x[i];
                }
                match self.params.initialization {
                    Initialization::PreviousPosition => state.x[i],
                    Initialization::PreviousVelocity => state.x[i] + h * state.v[i],
                    Initialization::Inertia => y[i],
                    Initialization::Adaptive => {
                        let a_tilde = self.adaptive_scale(&state.v, i) * a_ext;
                        state.x[i] + h * state.v[i] + h * h * a_tilde
                    }
                }
            })
            .collect();
        self.convergence.begin(x.iter().copied());
        // Stopping early only in the tolerance mode.
        for _ in 0..self.iterations {
            for colour in &self.colours {
                for &i in colour {
                    let update = vertex_step(&self.system, &self.adjacent[i], &x, &y, i, h);
                    x[i] += update.delta_x;
                }
            }
            if self.convergence.converged(x.iter().copied()) {
                break;
            }
        }
        self.convergence.end_step(0);
        if !x.iter().all(|p| p.iter().all(|c| c.is_finite())) {
            return Err(Error::NotConverged {
                what: "VBD".into(),
                detail: "a vertex update is no longer finite".into(),
            });
        }
        self.previous_velocity = Some(state.v.clone());
        for ((x_t, v), x) in state.x.iter_mut().zip(state.v.iter_mut()).zip(&x) {
            *v = (x - *x_t) / h;
            *x_t = *x;
        }
        Ok(())
    }
    // endregion: step
}

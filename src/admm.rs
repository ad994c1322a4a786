//! ADMM ⊇ Projective Dynamics (Overby et al. 2017; thesis §2.3.2 and §3.5, Algorithm 4,
//! Eqs 30-42 and 54-56).
//!
//! Eq (20) split as in Eqs (34)-(39): $`f(x) = \frac{1}{2dt^2}|x - \tilde x|_M^2`$,
//! $`g(z) = U_*(z)`$ (the springs' Hooke energy), constraint $`W(Dx - z) = 0`$ with the reduction
//! matrix $`D`$ (Eq 54) and the weights $`W = \omega I`$, $`\omega_i = \sqrt{k_i}`$ by default (the
//! "usual" choice of §2.3.2, and the one §3.5 assumes). Each step starts from
//! $`x^0 = \tilde x = x_n + dt\,v_n + dt^2 M^{-1} f_{ext}`$ with the scaled dual $`\bar u = 0`$
//! (lines 2.1-2.2), then iterates, in the order of Algorithm 4: the local step $`z`$ (Eq 41,
//! solved by Eqs 55-56 for Hooke's energy), the dual update $`\bar u`$ (Eq 42), and the global
//! step $`x`$ (Eq 40) with $`A = M + dt^2 D^\top W^\top W D`$ factored once per scene and time step
//! ([`crate::projective`], shared with Liu 2013; fixed nodes by Eqs 43-47). The velocity is
//! $`(x - x_n)/dt`$ (line 2.11).
//!
//! Errata implemented in consistent form (see `docs/thesis-errata.md`):
//! - Eq (34): the inertial term is $`(x - \tilde x)^\top M (x - \tilde x)`$, as Eq (35) has it
//!   (printed with $`x^n - x^{n+1}`$).
//! - Eq (36): $`g(z) = U_*(z)`$ (printed $`g(x)`$).
//! - Eq (40), last line: $`D^\top W^\top W`$ (printed $`D^\top W W`$; equal for a diagonal $`W`$).
//!
//! Eq (56)'s simplified form $`z = \frac12(p + D_i x + \bar u_i)`$ holds only for
//! $`\omega_i^2 = k_i`$; the general form is used so that other weights ([`AdmmPd::with_omega`])
//! stay correct.
//!
//! # Labelled variants (forensics of issue 5, never the default)
//!
//! [`AdmmPd::with_variant`] runs the same algorithm with one or more departures described by
//! [`AdmmVariant`]; [`AdmmVariant::FAITHFUL`] is Algorithm 4 as written and gives results
//! bit-identical to [`AdmmPd::new`]. The departures are the candidates for what the thesis's
//! code did at dt = 0.1 and 0.01 s (forensic finding 6 of `docs/thesis-scene.md`):
//! - [`StartPoint`]: the first iterate $`x^0`$ (line 2.1): $`\tilde x`$ (faithful), $`x_n + dt\,v_n`$
//!   (gravity left out of the first iterate only; the right-hand side keeps $`M\tilde x`$), or
//!   $`x_n`$;
//! - `carry_dual`: $`\bar u`$ kept from the previous step instead of reset (line 2.2);
//! - [`Weights`]: $`\omega_i = \sqrt{k_i}`$ (faithful), $`\omega_i = k_i`$, or $`\omega_i^2 = \sqrt{k_i}`$;
//! - [`FixedNodes`]: the three ways of fixing nodes that thesis §3.2 weighs: Eqs 43-47
//!   (faithful, the thesis's choice), overwriting the fixed positions after each solve of the
//!   unconstrained system, or removing the fixed degrees of freedom;
//! - `stale_rhs`: Eq (40)'s right-hand side, with the Eqs 45-47 correction $`b - A u`$, formed
//!   once per step (after the first local step) and left stale in later iterations.

use crate::error::{require_positive, Error, Result};
use crate::linear::{Factorization, SymmetricMatrix};
use crate::projective::{
    finish_step, project_on_sphere, reduction_matrix, system_matrix, to_columns, GlobalSolve,
    SpringIncidence,
};
use crate::solver::TimeStepper;
use crate::system::{MassSpringSystem, State, Vec3};

/// The default weights $`\omega_i = \sqrt{k_i}`$ (§2.3.2, Eqs 37-38: $`A = WD`$, $`B = -W`$).
pub fn default_omega(system: &MassSpringSystem) -> Vec<f64> {
    system
        .springs()
        .iter()
        .map(|s| s.stiffness.sqrt())
        .collect()
}

/// The per-spring weights $`\omega_i`$ of a variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Weights {
    /// $`\omega_i = \sqrt{k_i}`$ (faithful, §2.3.2).
    SqrtStiffness,
    /// Variant: $`\omega_i = k_i`$.
    Stiffness,
    /// Variant: $`\omega_i^2 = \sqrt{k_i}`$.
    FourthRootStiffness,
}

impl Weights {
    /// The weights $`\omega_i`$ for `system`.
    pub fn omega(self, system: &MassSpringSystem) -> Vec<f64> {
        match self {
            Weights::SqrtStiffness => default_omega(system),
            Weights::Stiffness => system.springs().iter().map(|s| s.stiffness).collect(),
            Weights::FourthRootStiffness => system
                .springs()
                .iter()
                .map(|s| s.stiffness.sqrt().sqrt())
                .collect(),
        }
    }
}

/// Where each step's iteration starts (Algorithm 4 line 2.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StartPoint {
    /// $`x^0 = \tilde x = x_n + dt\,v_n + dt^2 M^{-1} f_{ext}`$ (faithful, line 2.1).
    Prediction,
    /// Variant: $`x^0 = x_n + dt\,v_n`$, gravity left out of the first iterate only (the
    /// right-hand side of Eq 40 keeps $`M\tilde x`$).
    Inertial,
    /// Variant: $`x^0 = x_n`$.
    Previous,
}

/// How the fixed nodes enter the global step (the three ways of thesis §3.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FixedNodes {
    /// Eqs 43-47 on the prefactored matrix (faithful, the thesis's choice).
    Imposed,
    /// Variant: the unconstrained $`A`$ is solved with the fixed nodes free, and their positions
    /// are overwritten with $`x_n`$ after each solve.
    Overwritten,
    /// Variant: the fixed degrees of freedom are removed; the free ones solve
    /// $`A_{ff}\,x_f = b_f - A_{fc}\,\bar x_c`$ with a separately factored $`A_{ff}`$.
    Eliminated,
}

/// A labelled departure from Algorithm 4 (see the module documentation); never the default.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AdmmVariant {
    pub start: StartPoint,
    /// Keep $`\bar u`$ from the previous step instead of resetting it (line 2.2).
    pub carry_dual: bool,
    pub weights: Weights,
    pub fixed_nodes: FixedNodes,
    /// Form Eq (40)'s right-hand side once per step and keep it through the iterations.
    pub stale_rhs: bool,
}

impl AdmmVariant {
    /// Algorithm 4 as written.
    pub const FAITHFUL: AdmmVariant = AdmmVariant {
        start: StartPoint::Prediction,
        carry_dual: false,
        weights: Weights::SqrtStiffness,
        fixed_nodes: FixedNodes::Imposed,
        stale_rhs: false,
    };

    /// Whether this is Algorithm 4 as written.
    pub fn is_faithful(&self) -> bool {
        *self == Self::FAITHFUL
    }

    /// The departures from Algorithm 4, comma-separated; empty for the faithful method.
    pub fn label(&self) -> String {
        let mut parts = Vec::new();
        match self.start {
            StartPoint::Prediction => {}
            StartPoint::Inertial => parts.push("x⁰ = x_n + dt·v_n"),
            StartPoint::Previous => parts.push("x⁰ = x_n"),
        }
        if self.carry_dual {
            parts.push("ū carried across steps");
        }
        match self.weights {
            Weights::SqrtStiffness => {}
            Weights::Stiffness => parts.push("ω = k"),
            Weights::FourthRootStiffness => parts.push("ω² = √k"),
        }
        match self.fixed_nodes {
            FixedNodes::Imposed => {}
            FixedNodes::Overwritten => parts.push("fixed nodes overwritten after the solve"),
            FixedNodes::Eliminated => parts.push("fixed DOFs removed"),
        }
        if self.stale_rhs {
            parts.push("right-hand side formed once per step");
        }
        parts.join(", ")
    }
}

impl Default for AdmmVariant {
    fn default() -> Self {
        Self::FAITHFUL
    }
}

/// The prefactored global matrix with the fixed nodes handled as a [`FixedNodes`] says.
#[derive(Debug, Clone)]
enum GlobalMatrix {
    Imposed(GlobalSolve),
    Overwritten {
        factorization: Factorization,
        fixed: Vec<usize>,
    },
    Eliminated {
        /// The free nodes, in order; the reduced unknowns are their indices here.
        free: Vec<usize>,
        /// $`(f, c, A_{fc})`$ for reduced row $`f`$ and fixed node $`c`$.
        coupling: Vec<(usize, usize, f64)>,
        factorization: Factorization,
        reduced: Vec<f64>,
    },
}

impl GlobalMatrix {
    /// $`A = M + dt^2 \sum_i \omega_i^2 D_i^\top D_i`$ for `system`, factored once.
    fn new(system: &MassSpringSystem, dt: f64, omega2: &[f64], how: FixedNodes) -> Result<Self> {
        let fixed: Vec<usize> = (0..system.len())
            .filter(|&i| system.nodes()[i].fixed)
            .collect();
        Ok(match how {
            FixedNodes::Imposed => GlobalMatrix::Imposed(GlobalSolve::new(system, dt, omega2)?),
            FixedNodes::Overwritten => GlobalMatrix::Overwritten {
                factorization: Factorization::new(&system_matrix(system, dt, omega2)?)?,
                fixed,
            },
            FixedNodes::Eliminated => {
                let a = system_matrix(system, dt, omega2)?;
                let free: Vec<usize> = (0..system.len())
                    .filter(|&i| !system.nodes()[i].fixed)
                    .collect();
                let mut reduced_index = vec![None; system.len()];
                for (f, &i) in free.iter().enumerate() {
                    reduced_index[i] = Some(f);
                }
                let edges: Vec<(usize, usize)> = system
                    .springs()
                    .iter()
                    .filter_map(|s| Some((reduced_index[s.a]?, reduced_index[s.b]?)))
                    .collect();
                let mut a_ff = SymmetricMatrix::from_node_graph(free.len(), 1, &edges);
                let mut coupling = Vec::new();
                for (f, &i) in free.iter().enumerate() {
                    for (j, a_ij) in a.row(i) {
                        match reduced_index[j] {
                            Some(g) => a_ff.add(f, g, a_ij),
                            None => coupling.push((f, j, a_ij)),
                        }
                    }
                }
                GlobalMatrix::Eliminated {
                    reduced: vec![0.0; 3 * free.len()],
                    factorization: Factorization::new(&a_ff)?,
                    free,
                    coupling,
                }
            }
        })
    }

    /// Solves $`A x = b`$ for the three coordinates (column-major, `b` overwritten by $`x`$), the
    /// fixed nodes at their values in `x_n`.
    fn solve(&mut self, b: &mut [f64], x_n: &[f64]) {
        match self {
            GlobalMatrix::Imposed(a) => a.solve(b, x_n),
            GlobalMatrix::Overwritten {
                factorization,
                fixed,
            } => {
                let n = b.len() / 3;
                factorization.solve_in_place(b, 3);
                for c in 0..3 {
                    for &j in fixed.iter() {
                        b[c * n + j] = x_n[c * n + j];
                    }
                }
            }
            GlobalMatrix::Eliminated {
                free,
                coupling,
                factorization,
                reduced,
            } => {
                let (n, m) = (b.len() / 3, free.len());
                for c in 0..3 {
                    for (f, &i) in free.iter().enumerate() {
                        reduced[c * m + f] = b[c * n + i];
                    }
                    for &(f, j, a_fj) in coupling.iter() {
                        reduced[c * m + f] -= a_fj * x_n[c * n + j];
                    }
                }
                factorization.solve_in_place(reduced, 3);
                b.copy_from_slice(x_n);
                for c in 0..3 {
                    for (f, &i) in free.iter().enumerate() {
                        b[c * n + i] = reduced[c * m + f];
                    }
                }
            }
        }
    }
}

/// Eq. (56): $`z_i = \dfrac{k\,p_i + \omega_i^2\,(D_i x + \bar u_i)}{\omega_i^2 + k}`$, the
/// minimiser of Eq (41) for Hooke's energy given the projection $`p_i`$ of Eq (55);
/// $`\frac12(p_i + D_i x + \bar u_i)`$ when $`\omega_i^2 = k`$.
#[inline]
pub fn z_update(p: Vec3, q: Vec3, k: f64, omega: f64) -> Vec3 {
    let omega2 = omega * omega;
    (k * p + omega2 * q) / (omega2 + k)
}

/// Eq. (41): $`z_i = \arg\min_{z_i} U_i(z_i) + \frac12|W_i(D_i x - z_i + \bar u_i)|^2`$ for
/// $`U_i(z) = \frac12 k(|z| - l_0)^2`$, with $`q = D_i x + \bar u_i`$: the minimiser lies on $`q`$'s
/// ray, so it is Eq (56) applied to the projection $`p_i = l_0\,q/|q|`$ of Eq (55).
#[inline]
pub fn z_minimisation(q: Vec3, l0: f64, k: f64, omega: f64) -> Vec3 {
    let p = project_on_sphere(q, l0);
    z_update(p, q, k, omega)
}

/// Eq. (42): $`\bar u_i \leftarrow \bar u_i + D_i x - z_i`$.
#[inline]
pub fn dual_update(u_bar: Vec3, d_x: Vec3, z: Vec3) -> Vec3 {
    u_bar + d_x - z
}

/// ADMM-PD with a fixed number of iterations per step.
#[derive(Debug, Clone)]
pub struct AdmmPd {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    /// $`D`$ of Eq (54), stored per spring.
    d: SpringIncidence,
    /// $`\omega_i`$, the diagonal of $`W`$.
    omega: Vec<f64>,
    /// Departures from Algorithm 4 ([`AdmmVariant::FAITHFUL`] for none).
    variant: AdmmVariant,
    /// $`dt^2\,\omega_i^2`$, the factor of $`D_i^\top`$ in Eq (40)'s right-hand side.
    dt2_omega2: Vec<f64>,
    /// $`A = M + dt^2 D^\top W^\top W D`$, factored once (line 1.5).
    a: GlobalMatrix,
    // Per-step buffers (column-major, 3n; one Vec3 per spring), so that a step allocates nothing.
    x_n: Vec<f64>,
    x_tilde: Vec<f64>,
    /// $`M\tilde x`$.
    m_x_tilde: Vec<f64>,
    x: Vec<f64>,
    z: Vec<Vec3>,
    u_bar: Vec<Vec3>,
    /// Eq (40)'s right-hand side of the step's first iteration (`stale_rhs` variant only).
    first_rhs: Vec<f64>,
}

impl AdmmPd {
    /// The faithful solver: $`\omega_i = \sqrt{k_i}`$. Needs every stiffness > 0, `dt` > 0 and
    /// `iterations` >= 1.
    pub fn new(system: &MassSpringSystem, dt: f64, iterations: usize) -> Result<Self> {
        system.require_positive_stiffness()?;
        Self::with_omega(system, dt, iterations, default_omega(system))
    }

    /// The solver with other per-spring weights $`\omega_i`$ (> 0), a variant of the faithful
    /// $`\omega_i = \sqrt{k_i}`$. Algorithm 4, lines 1.1-1.5.
    pub fn with_omega(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        omega: Vec<f64>,
    ) -> Result<Self> {
        Self::build(system, dt, iterations, omega, AdmmVariant::FAITHFUL)
    }

    /// The solver with the labelled departures of `variant` (its weights included);
    /// [`AdmmVariant::FAITHFUL`] gives [`AdmmPd::new`].
    pub fn with_variant(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        variant: AdmmVariant,
    ) -> Result<Self> {
        system.require_positive_stiffness()?;
        Self::build(
            system,
            dt,
            iterations,
            variant.weights.omega(system),
            variant,
        )
    }

    /// Algorithm 4, lines 1.1-1.5, with the weights `omega` (from `variant.weights`, or custom
    /// ones from [`AdmmPd::with_omega`]).
    fn build(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        omega: Vec<f64>,
        variant: AdmmVariant,
    ) -> Result<Self> {
        require_positive("dt", dt)?;
        system.require_positive_stiffness()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        if omega.len() != system.springs().len() {
            return Err(Error::invalid(
                "omega.len()",
                omega.len(),
                &format!("one weight per spring ({})", system.springs().len()),
            ));
        }
        for (j, &w) in omega.iter().enumerate() {
            require_positive(format!("omega[{j}]"), w)?;
        }
        let n = system.len();
        let s = system.springs().len();
        let omega2: Vec<f64> = omega.iter().map(|w| w * w).collect();
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            d: reduction_matrix(system),
            dt2_omega2: omega2.iter().map(|w2| dt * dt * w2).collect(),
            a: GlobalMatrix::new(system, dt, &omega2, variant.fixed_nodes)?,
            variant,
            omega,
            x_n: vec![0.0; 3 * n],
            x_tilde: vec![0.0; 3 * n],
            m_x_tilde: vec![0.0; 3 * n],
            x: vec![0.0; 3 * n],
            z: vec![Vec3::zeros(); s],
            u_bar: vec![Vec3::zeros(); s],
            first_rhs: vec![0.0; if variant.stale_rhs { 3 * n } else { 0 }],
        })
    }

    /// Iterations per step.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// The weights $`\omega_i`$.
    pub fn omega(&self) -> &[f64] {
        &self.omega
    }

    /// Line 2.1: $`\tilde x = x_n + dt\,v_n + dt^2 M^{-1} f_{ext}`$ (Eq 35's $`\tilde x`$), and
    /// $`M\tilde x`$ for Eq (40). Fixed nodes predict their own position: they never move.
    fn predict(&mut self, state: &State) {
        let (n, dt) = (state.x.len(), self.dt);
        for (i, node) in self.system.nodes().iter().enumerate() {
            let x_tilde = if node.fixed {
                state.x[i]
            } else {
                state.x[i] + dt * state.v[i] + dt * dt / node.mass * self.system.external_force(i)
            };
            for c in 0..3 {
                self.x_tilde[c * n + i] = x_tilde[c];
                self.m_x_tilde[c * n + i] = node.mass * x_tilde[c];
            }
        }
    }

    /// Line 2.1's first iterate: $`x^0 = \tilde x`$, or a [`StartPoint`] variant.
    fn start(&mut self, state: &State) {
        match self.variant.start {
            StartPoint::Prediction => self.x.copy_from_slice(&self.x_tilde),
            StartPoint::Previous => self.x.copy_from_slice(&self.x_n),
            StartPoint::Inertial => {
                let n = state.x.len();
                for (i, node) in self.system.nodes().iter().enumerate() {
                    let x0 = if node.fixed {
                        state.x[i]
                    } else {
                        state.x[i] + self.dt * state.v[i]
                    };
                    for c in 0..3 {
                        self.x[c * n + i] = x0[c];
                    }
                }
            }
        }
    }

    /// Lines 2.4-2.7: for every spring, $`z_i`$ (Eq 41 by Eqs 55-56), then $`\bar u_i`$ (Eq 42),
    /// from the current iterate $`x`$.
    fn local_step(&mut self) {
        let springs = self.system.springs();
        for (i, ((z, u_bar), s)) in self
            .z
            .iter_mut()
            .zip(self.u_bar.iter_mut())
            .zip(springs)
            .enumerate()
        {
            let d_x = self.d.apply_row(i, &self.x);
            *z = z_minimisation(d_x + *u_bar, s.rest_length, s.stiffness, self.omega[i]);
            *u_bar = dual_update(*u_bar, d_x, *z);
        }
    }

    /// Eq. (40): $`(M + dt^2 D^\top W^\top W D)\,x = M\tilde x + dt^2 D^\top W^\top W (z - \bar u)`$,
    /// solved with the prefactored $`A`$ for the three coordinates at once; fixed nodes stay at
    /// $`x_n`$. The `stale_rhs` variant reuses the first iteration's right-hand side.
    fn global_step(&mut self, iteration: usize) {
        if self.variant.stale_rhs && iteration > 0 {
            self.x.copy_from_slice(&self.first_rhs);
        } else {
            self.x.copy_from_slice(&self.m_x_tilde);
            for (i, ((z, u_bar), &w)) in self
                .z
                .iter()
                .zip(&self.u_bar)
                .zip(&self.dt2_omega2)
                .enumerate()
            {
                self.d.add_row_transposed(i, w * (z - u_bar), &mut self.x);
            }
            if self.variant.stale_rhs {
                self.first_rhs.copy_from_slice(&self.x);
            }
        }
        self.a.solve(&mut self.x, &self.x_n);
    }
}

impl TimeStepper for AdmmPd {
    fn name(&self) -> String {
        let mut variant = self.variant.label();
        // `with_omega` weights are a variant that `AdmmVariant` does not name.
        if variant.is_empty() && self.omega != default_omega(&self.system) {
            variant = "custom ω".to_string();
        }
        if variant.is_empty() {
            format!("ADMM-PD ({} iterations)", self.iterations)
        } else {
            format!(
                "ADMM-PD ({} iterations, variant: {variant})",
                self.iterations
            )
        }
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    /// Algorithm 4, run-time part.
    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        to_columns(&state.x, &mut self.x_n);
        // 2.1: x̃, and x⁰ = x̃ (a labelled variant may start elsewhere).
        self.predict(state);
        self.start(state);
        // 2.2: ū = 0 every step (unless a variant carries it over).
        if !self.variant.carry_dual {
            self.u_bar.fill(Vec3::zeros());
        }
        // 2.3-2.10
        for iteration in 0..self.iterations {
            self.local_step();
            self.global_step(iteration);
        }
        // 2.11
        finish_step(state, &self.x, self.dt);
        Ok(())
    }
    // endregion: step
}

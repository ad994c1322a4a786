//! Backward Euler solved by Newton-Raphson, the thesis's ground truth (§2.1, Eqs 5-12).
//!
//! Each step solves the implicit equations (8)-(9) for $`v_{n+1}`$. Newton's method on the
//! residual $`r(v) = M(v - v_n) - dt\,F(x_n + dt\,v)`$ linearises the force about the current
//! iterate $`x_k = x_n + dt\,v_k`$ (Eq 10) and solves
//! ```math
//! (M - dt^2 K_k)\,v_{k+1} = M v_n + dt\,F(x_k) + dt\,K_k\,(x_n - x_k),\qquad K_k = \tfrac{dF}{dx}(x_k).
//! ```
//! Starting from $`v_0 = 0`$ ($`x_0 = x_n`$) the first iteration is Eq (12) exactly as printed;
//! the later ones carry the term $`dt\,K_k(x_n - x_k)`$ that the printed equation, re-evaluated
//! at $`x_k`$, drops (erratum: without it the iteration converges to a different, over-damped
//! scheme). The thesis's reference uses dt = 1e-3 and 5 iterations per step.
//!
//! [`converged_step`](crate::solvers::converged_stage::converged_step) is the same step solved to a tolerance, by projected Newton with a line
//! search on the incremental potential of Eq (20): it converges at any $`dt\sqrt{k/m}`$ and is
//! the oracle the other solvers are tested against.

use crate::error::{require_positive, Error, Result};
use crate::integrators::damping::RayleighDamping;
use crate::integrators::dissipation::{Dissipation, StageDissipation};
use crate::integrators::first_iterate::{FirstIterate, StepStart};
use crate::integrators::optimization_integrator::{MinimizingSolver, StageProblem};
use crate::integrators::stopping::{same_bits, Convergence};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::boundary::{fixed_node_unknowns, ConstrainedSystem};
use crate::model::lanes::Lane;
use crate::model::linear::SymmetricMatrix;
use crate::model::spring::{self, SpringArrays};
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::vbd::LocalHessian;
use nalgebra::{Matrix3, Vector3};

/// Newton iterations per step of the thesis's reference (§4.3, Table 1).
pub const REFERENCE_NEWTON_ITERATIONS: usize = 5;
/// Time step of the thesis's reference, s (Table 1).
pub const REFERENCE_DT: f64 = 1e-3;

/// Eqs. (6), (9): $`x(t+dt) = x(t) + v(t+dt)\,dt`$ (per lane in a batch of runs).
pub fn position_update<T: Lane>(x_n: &Vector3<T>, v_next: &Vector3<T>, dt: T) -> Vector3<T> {
    x_n + v_next * dt
}

/// What a Newton iteration of one step reads besides its iterate: the step's start
/// $`(x_n, v_n)`$, the nodes' masses and dt (at `f64` one run's, in lanes one per lane).
#[derive(Debug, Clone, Copy)]
pub struct NewtonStep<'a, T> {
    /// $`x_n`$, per node.
    pub x_n: &'a [Vector3<T>],
    /// $`v_n`$, per node.
    pub v_n: &'a [Vector3<T>],
    /// The nodes' masses, kg.
    pub masses: &'a [T],
    /// The step, s.
    pub dt: T,
}

/// Eq. (4): the force Jacobian of every spring of `springs` at the iterate's positions
/// `x_k`, into `jacobians`.
pub fn spring_jacobians<T: Lane>(
    springs: SpringArrays<T>,
    x_k: &[Vector3<T>],
    jacobians: &mut [Matrix3<T>],
) {
    spring_jacobians_with(springs, x_k, jacobians, spring::force_jacobian_of);
}

/// Eq. (4) for every spring, or another rule for each spring's block (`jacobian`: projected
/// Newton's [`spring::force_jacobian_definite`]): [`spring_jacobians`]'s loop.
#[inline(always)]
pub fn spring_jacobians_with<T: Lane>(
    springs: SpringArrays<T>,
    x_k: &[Vector3<T>],
    jacobians: &mut [Matrix3<T>],
    jacobian: impl Fn(&Vector3<T>, &Vector3<T>, T, T) -> Matrix3<T>,
) {
    let values = springs.rest_lengths.iter().zip(springs.stiffness);
    for (jac, (&(a, b), (&l0, &k))) in jacobians.iter_mut().zip(springs.ends.iter().zip(values)) {
        *jac = jacobian(&x_k[a], &x_k[b], l0, k);
    }
}

/// Eqs. (10), (12): the right-hand side $`M v_n + dt\,F(x_k) + dt\,K_k(x_n - x_k)`$ of a
/// Newton iteration at $`x_k`$ (the springs' `jacobians` $`K_k`$ and the `forces` $`F(x_k)`$
/// given), node-major (unknown $`3i + c`$) into `rhs`.
pub fn newton_rhs<T: Lane>(
    step: &NewtonStep<T>,
    ends: &[(usize, usize)],
    jacobians: &[Matrix3<T>],
    x_k: &[Vector3<T>],
    forces: &[Vector3<T>],
    rhs: &mut [T],
) {
    let (x_n, dt) = (step.x_n, step.dt);
    let nodes = step.masses.iter().zip(step.v_n).zip(forces);
    for (b, ((&mass, v_n), f)) in rhs.chunks_exact_mut(3).zip(nodes) {
        // Scalar times vector, written vector times scalar (the same products) for a lane.
        b.copy_from_slice((v_n * mass + f * dt).as_slice());
    }
    for (jac, &(a, b)) in jacobians.iter().zip(ends) {
        // dt·K_k·(x_n − x_k) = −dt²·K_k·v_k, spring by spring.
        let k_dx = jac * ((x_n[a] - x_k[a]) - (x_n[b] - x_k[b])) * dt;
        for c in 0..3 {
            rhs[3 * a + c] += k_dx[c];
            rhs[3 * b + c] -= k_dx[c];
        }
    }
}

/// Eqs. (7), (8): the residual of $`v(t+dt) = v(t) + M^{-1}F(x(t+dt))\,dt`$ multiplied by $`M`$,
/// with Eq (9) for $`x(t+dt)`$: $`r(v) = M(v - v_n) - dt\,F(x_n + dt\,v)`$. Zero on fixed nodes.
pub fn velocity_residual(
    system: &MassSpringSystem,
    state: &State,
    v: &[Vec3],
    dt: f64,
) -> Vec<Vec3> {
    let x: Vec<Vec3> = state
        .x
        .iter()
        .zip(v)
        .map(|(x, v)| position_update(x, v, dt))
        .collect();
    let mut f = vec![Vec3::zeros(); x.len()];
    system.forces(&x, &mut f);
    system
        .nodes()
        .iter()
        .enumerate()
        .map(|(i, node)| {
            if node.fixed {
                Vec3::zeros()
            } else {
                node.mass * (v[i] - state.v[i]) - dt * f[i]
            }
        })
        .collect()
}

/// The sparse $`3n\times3n`$ matrix $`M - dt^2 K`$ with precomputed value slots for fast assembly.
#[derive(Debug, Clone)]
pub(crate) struct ImplicitMatrix {
    pub(crate) matrix: SymmetricMatrix,
    pub(crate) slots: ImplicitSlots,
}

/// Where each node's and spring's entries of $`M - dt^2 K`$ are in its matrix's values, found
/// once so that an assembly searches nothing: one pattern's, for one run or for runs in lanes.
#[derive(Debug, Clone)]
pub(crate) struct ImplicitSlots {
    /// Slots of the diagonal entries (3 per node).
    diagonal: Vec<usize>,
    /// Slots of each node's 3×3 block, row-major.
    node_blocks: Vec<[usize; 9]>,
    /// Slots of each spring's blocks (a,a), (a,b), (b,a), (b,b), row-major 3×3.
    spring_blocks: Vec<[[usize; 9]; 4]>,
}

impl ImplicitMatrix {
    pub(crate) fn new(system: &MassSpringSystem) -> Self {
        let edges: Vec<_> = system.springs().iter().map(|s| (s.a, s.b)).collect();
        let matrix = SymmetricMatrix::from_node_graph(system.len(), 3, &edges);
        let diagonal = (0..3 * system.len())
            .map(|i| matrix.slot(i, i).expect("diagonal"))
            .collect();
        let block = |p: usize, q: usize| {
            std::array::from_fn(|rc| matrix.slot(3 * p + rc / 3, 3 * q + rc % 3).expect("block"))
        };
        let spring_blocks = system
            .springs()
            .iter()
            .map(|s| {
                [
                    block(s.a, s.a),
                    block(s.a, s.b),
                    block(s.b, s.a),
                    block(s.b, s.b),
                ]
            })
            .collect();
        let node_blocks = (0..system.len()).map(|i| block(i, i)).collect();
        Self {
            matrix,
            slots: ImplicitSlots {
                diagonal,
                node_blocks,
                spring_blocks,
            },
        }
    }

    /// Eq. (12): the left-hand side $`A = M - dt^2\,\frac{dF}{dx}`$, from the springs' force
    /// Jacobians (Eq 4) given per spring; with a dissipation, plus $`h^2`$ times its stage
    /// term's Hessian at `x` ([`StageDissipation`]): with Rayleigh damping
    /// $`\alpha h M + \beta h K(x_n)`$. `definite` projects the momentum-conserving form's
    /// blocks as the springs' are.
    pub(crate) fn assemble(
        &mut self,
        system: &MassSpringSystem,
        dt: f64,
        jacobians: &[Matrix3<f64>],
        dissipation: &StageDissipation,
        x: &[Vec3],
        definite: bool,
    ) {
        let values = self.matrix.values_mut();
        let mass_factor = dissipation.mass_factor();
        let masses = system.nodes().iter().map(|node| node.mass * mass_factor);
        self.slots.set_masses(values, masses);
        if !dissipation.dissipation().is_smooth() {
            for (i, slots) in self.slots.node_blocks.iter().enumerate() {
                let block = dissipation.node_block(system, x, i);
                for (rc, &slot) in slots.iter().enumerate() {
                    values[slot] += block[(rc / 3, rc % 3)];
                }
            }
        }
        let damping_blocks = dissipation.has_spring_blocks();
        self.slots
            .add_springs(values, jacobians, dt * dt, |i, dt2_j| {
                // The damping block enters like a force Jacobian of the opposite sign.
                if damping_blocks {
                    dt2_j - dissipation.spring_block(system, x, i, definite)
                } else {
                    dt2_j
                }
            });
    }
}

impl ImplicitSlots {
    /// Eq. (12)'s $`M`$: `values` zero but the diagonal, node i's three entries its `masses`' i-th.
    pub(crate) fn set_masses<T: Lane>(&self, values: &mut [T], masses: impl Iterator<Item = T>) {
        values.fill(T::splat(0.0));
        for (diagonal, mass) in self.diagonal.chunks_exact(3).zip(masses) {
            for &slot in diagonal {
                values[slot] = mass;
            }
        }
    }

    /// Eq. (12)'s $`-dt^2 K`$ added to `values`, spring by spring from the force Jacobians
    /// (Eq 4): $`dF_a/dx_a = dF_b/dx_b = J`$, $`dF_a/dx_b = dF_b/dx_a = -J`$, each spring's
    /// $`dt^2 J`$ first passed through `adjust` (spring index, block) for a dissipation's term.
    pub(crate) fn add_springs<T: Lane>(
        &self,
        values: &mut [T],
        jacobians: &[Matrix3<T>],
        dt2: T,
        adjust: impl Fn(usize, Matrix3<T>) -> Matrix3<T>,
    ) {
        for (i, ([aa, ab, ba, bb], jac)) in self.spring_blocks.iter().zip(jacobians).enumerate() {
            // Scalar times matrix, written matrix times scalar (the same products) for a lane.
            let jac = adjust(i, jac * dt2);
            for rc in 0..9 {
                let dt2_j = jac[(rc / 3, rc % 3)];
                values[aa[rc]] -= dt2_j;
                values[ab[rc]] += dt2_j;
                values[ba[rc]] += dt2_j;
                values[bb[rc]] -= dt2_j;
            }
        }
    }
}

/// Backward Euler with a fixed number of Newton-Raphson iterations per step (the thesis's
/// reference solver), optionally with a dissipation ([`crate::integrators::dissipation`]); under an
/// optimization integrator, the same Newton iteration on each stage problem.
#[derive(Debug, Clone)]
pub struct BackwardEuler {
    system: MassSpringSystem,
    dt: f64,
    newton_iterations: usize,
    dissipation: StageDissipation,
    implicit: ImplicitMatrix,
    solve: Option<ConstrainedSystem>,
    fixed: Vec<usize>,
    /// The springs' ends, rest lengths and stiffnesses, and the nodes' masses, as arrays.
    ends: Vec<(usize, usize)>,
    rest_lengths: Vec<f64>,
    stiffness: Vec<f64>,
    masses: Vec<f64>,
    jacobians: Vec<Matrix3<f64>>,
    forces: Vec<Vec3>,
    x_k: Vec<Vec3>,
    v_k: Vec<Vec3>,
    rhs: Vec<f64>,
    zeros: Vec<f64>,
    /// Where each step's Newton iteration starts ($`x_0 = x_n`$, $`v_0 = 0`$, by default).
    start: StepStart,
    /// Eq. (4)'s Jacobians as printed (the default), or projected where the matrix they give
    /// is not positive definite ([`LocalHessian::Projected`], a labelled variant).
    hessian: LocalHessian,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
}

impl BackwardEuler {
    /// A solver for `system` with time step `dt` (s, > 0) and `newton_iterations` (>= 1).
    pub fn new(system: &MassSpringSystem, dt: f64, newton_iterations: usize) -> Result<Self> {
        Self::dissipative(system, dt, newton_iterations, Dissipation::NONE)
    }

    /// [Brown 2018, Rayleigh damping] (unverified: no body text or reference code found) The same solver with the damping force
    /// $`-(\alpha M + \beta K(x_n))\,v_{n+1}`$: the residual gains $`h(\alpha M + \beta K(x_n))v`$,
    /// so Eq (12)'s matrix gains $`h(\alpha M + \beta K(x_n))`$ and its right-hand side is unchanged.
    pub fn damped(
        system: &MassSpringSystem,
        dt: f64,
        newton_iterations: usize,
        damping: RayleighDamping,
    ) -> Result<Self> {
        Self::dissipative(
            system,
            dt,
            newton_iterations,
            Dissipation::rayleigh(damping),
        )
    }

    /// [Brown 2018, dissipation functions] (unverified: no body text or reference code found) The same solver on the
    /// objective with `dissipation`'s stage term $`\Psi`$: Newton on the residual
    /// $`r(v) = M(v - u_0) - \tau(F(x) - \nabla\Psi(x))`$, $`x = x_a + \tau v`$, whose matrix gains
    /// $`\tau^2\nabla^2\Psi`$ (Rayleigh: $`\tau(\alpha M + \beta K(x_D))`$, its right-hand side
    /// unchanged; the drag's Hessian smoothed, [`crate::integrators::dissipation`]). With drag, the stage
    /// term is not smooth at rest and each Newton update is backtracked (halved) until the
    /// stage objective does not rise.
    pub fn dissipative(
        system: &MassSpringSystem,
        dt: f64,
        newton_iterations: usize,
        dissipation: Dissipation,
    ) -> Result<Self> {
        require_positive("dt", dt)?;
        dissipation.validate()?;
        system.require_undamped_springs()?;
        if newton_iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let n = system.len();
        Ok(Self {
            system: system.clone(),
            dt,
            newton_iterations,
            dissipation: StageDissipation::new(system, dissipation),
            implicit: ImplicitMatrix::new(system),
            solve: None,
            fixed: fixed_node_unknowns(system, 3),
            ends: system.springs().iter().map(|s| (s.a, s.b)).collect(),
            rest_lengths: system.springs().iter().map(|s| s.rest_length).collect(),
            stiffness: system.springs().iter().map(|s| s.stiffness).collect(),
            masses: system.nodes().iter().map(|node| node.mass).collect(),
            jacobians: vec![Matrix3::zeros(); system.springs().len()],
            forces: vec![Vec3::zeros(); n],
            x_k: vec![Vec3::zeros(); n],
            v_k: vec![Vec3::zeros(); n],
            rhs: vec![0.0; 3 * n],
            zeros: vec![0.0; 3 * n],
            start: StepStart::new(FirstIterate::Previous),
            hessian: LocalHessian::Exact,
            convergence: Convergence::default(),
        })
    }

    /// The same solver with the Hessian rule `hessian`: [`LocalHessian::Exact`], Eq. (4) as
    /// printed (a step whose matrix is not positive definite fails), or
    /// [`LocalHessian::Projected`], this crate's variant, where such a matrix is rebuilt with
    /// each spring's transverse factor clamped at 0 (projected Newton:
    /// [`spring::force_jacobian_definite`]; the fixed point is the same).
    pub fn with_hessian(mut self, hessian: LocalHessian) -> Self {
        self.hessian = hessian;
        self
    }

    /// The same solver starting each step's Newton iteration at `first_iterate`
    /// ([`crate::integrators::first_iterate`]): $`v_0 = (x^0 - x_n)/dt`$. The default, $`x^0 = x_n`$, is
    /// $`v_0 = 0`$, with which the first iteration is Eq (12) as printed.
    pub fn with_first_iterate(mut self, first_iterate: FirstIterate) -> Self {
        self.start = StepStart::new(first_iterate);
        self
    }

    /// The thesis's reference: dt = 1e-3 s, 5 Newton iterations.
    pub fn reference(system: &MassSpringSystem) -> Result<Self> {
        Self::new(system, REFERENCE_DT, REFERENCE_NEWTON_ITERATIONS)
    }

    /// The springs' ends, rest lengths and stiffnesses, as arrays.
    pub fn springs(&self) -> SpringArrays<'_, f64> {
        SpringArrays {
            ends: &self.ends,
            rest_lengths: &self.rest_lengths,
            stiffness: &self.stiffness,
        }
    }

    /// The nodes' masses, kg.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// Newton iterations per step.
    pub fn newton_iterations(&self) -> usize {
        self.newton_iterations
    }

    /// Where each step's Newton iteration starts.
    pub fn first_iterate(&self) -> FirstIterate {
        self.start.rule()
    }

    /// Whether each step runs its full count of iterations ([`crate::integrators::stopping::Stopping::Count`]),
    /// as a batch of runs does ([`crate::solvers::batch`]).
    pub fn counts_iterations(&self) -> bool {
        self.convergence.stopping() == crate::integrators::stopping::Stopping::Count
    }

    /// Eqs. (4), (10), (12): one Newton iteration's linear system at the iterate `x_k`: the
    /// springs' Jacobians (Eq. (4), or `projected` to the negative semidefinite cone,
    /// [`spring::force_jacobian_definite`]), the forces, the right-hand side of Eqs. (10) and
    /// (12) and the matrix $`M - dt^2 K_k`$ factored; an error if it is not positive definite.
    fn linearise(&mut self, state: &State, dt: f64, projected: bool) -> Result<()> {
        let x_k = &self.x_k;
        // The fields, not [`Self::springs`]: the Jacobians are written beside them.
        let springs = SpringArrays {
            ends: &self.ends,
            rest_lengths: &self.rest_lengths,
            stiffness: &self.stiffness,
        };
        if projected {
            spring_jacobians_with(
                springs,
                x_k,
                &mut self.jacobians,
                spring::force_jacobian_definite,
            );
        } else {
            spring_jacobians(springs, x_k, &mut self.jacobians);
        }
        self.system.forces(x_k, &mut self.forces);
        let step = NewtonStep {
            x_n: &state.x,
            v_n: &state.v,
            masses: &self.masses,
            dt,
        };
        newton_rhs(
            &step,
            &self.ends,
            &self.jacobians,
            x_k,
            &self.forces,
            &mut self.rhs,
        );
        self.dissipation
            .add_newton_rhs(&self.system, x_k, &self.v_k, &mut self.rhs);
        self.implicit.assemble(
            &self.system,
            dt,
            &self.jacobians,
            &self.dissipation,
            x_k,
            false,
        );
        match &mut self.solve {
            Some(solve) => solve.refactor(&mut self.implicit.matrix)?,
            None => {
                self.solve = Some(ConstrainedSystem::new(
                    &mut self.implicit.matrix,
                    &self.fixed,
                )?)
            }
        }
        Ok(())
    }

    /// Eqs. (10), (12): one Newton-Raphson iteration, from the iterate $`v_k`$ to $`v_{k+1}`$;
    /// whether $`v_{k+1}`$ is $`v_k`$ bit for bit (a fixed point, [`same_bits`]: the
    /// iteration reads nothing of the solver's but $`v_k`$, the step's state and dt).
    ///
    /// With $`F(x) \approx F(x_k) + K_k (x - x_k)`$ (Eq 10) at $`x = x_n + dt\,v`$,
    /// $`(M - dt^2 K_k)\,v_{k+1} = M v_n + dt\,F(x_k) + dt\,K_k(x_n - x_k)`$. For $`x_k = x_n`$
    /// this is Eq (12) as printed. On a stage problem, $`(x_n, v_n, dt)`$ is the pseudo-state
    /// `state` and $`\tau`$ (`dt`), and a non-quadratic dissipation adds its linearisation to
    /// the right-hand side ([`StageDissipation::add_newton_rhs`]).
    fn newton_iteration(&mut self, state: &State, dt: f64) -> Result<bool> {
        for ((x_k, x_n), v_k) in self.x_k.iter_mut().zip(&state.x).zip(&self.v_k) {
            *x_k = position_update(x_n, v_k, dt);
        }
        // The Hessian as Eq. (4) gives it; under the projected rule, where that is not
        // positive definite (compressed springs' transverse stiffness), projected Newton's.
        if let Err(indefinite) = self.linearise(state, dt, false) {
            if self.hessian == LocalHessian::Exact {
                return Err(indefinite);
            }
            self.linearise(state, dt, true)?;
        }
        // Fixed nodes have v = 0: the x̄ of Eqs 45-47 is zero.
        self.solve
            .as_ref()
            .expect("factored")
            .solve(&mut self.rhs, &self.zeros, 1);

        let next = |i: usize| Vec3::new(self.rhs[3 * i], self.rhs[3 * i + 1], self.rhs[3 * i + 2]);
        if self.dissipation.dissipation().is_smooth() {
            let mut fixed = true;
            for (i, v_k) in self.v_k.iter_mut().enumerate() {
                let v_next = next(i);
                fixed &= same_bits(v_k.iter().copied(), v_next.iter().copied());
                *v_k = v_next;
            }
            return Ok(fixed);
        }
        // The drag's stage term is not smooth at rest: backtrack the update until the stage
        // objective does not rise (full steps once the update is below round-off's reach).
        let objective = |v: &[Vec3]| -> f64 {
            let x: Vec<Vec3> = state
                .x
                .iter()
                .zip(v)
                .map(|(x, v)| position_update(x, v, dt))
                .collect();
            let y = inertia(state, dt);
            incremental_potential(&self.system, &y, &x, dt)
                + self.dissipation.potential(&self.system, &x)
        };
        let update: Vec<Vec3> = (0..self.v_k.len()).map(|i| next(i) - self.v_k[i]).collect();
        let largest = update.iter().fold(0.0_f64, |m, u| m.max(u.amax())) * dt;
        let phi0 = objective(&self.v_k);
        let mut alpha = 1.0;
        let trial = |alpha: f64| -> Vec<Vec3> {
            self.v_k
                .iter()
                .zip(&update)
                .map(|(v, u)| v + alpha * u)
                .collect()
        };
        let mut v = trial(alpha);
        // A NaN objective does not descend either.
        let descends = |phi: f64| phi.partial_cmp(&phi0).is_some_and(|o| o.is_le());
        while largest > 1e-8 && alpha > 1e-12 && !descends(objective(&v)) {
            alpha *= 0.5;
            v = trial(alpha);
        }
        let fixed = same_bits(
            self.v_k.iter().flat_map(|p| p.iter().copied()),
            v.iter().flat_map(|p| p.iter().copied()),
        );
        self.v_k = v;
        Ok(fixed)
    }
}

impl TimeStepper for BackwardEuler {
    fn name(&self) -> String {
        let iterations = self
            .convergence
            .iterations_label(self.newton_iterations, "Newton iterations");
        let RayleighDamping { alpha, beta } = self.dissipation.damping();
        let d = self.dissipation.dissipation();
        if d.is_none() {
            return format!("Backward Euler ({iterations})");
        }
        let mut parts = vec![iterations];
        if !d.rayleigh.is_none() {
            parts.push(format!("alpha {alpha} 1/s, beta {beta} s"));
            if d.form != crate::integrators::dissipation::RayleighForm::Classical {
                parts.push(format!("{} Rayleigh", d.form.key()));
            }
        }
        if d.drag.coefficient > 0.0 {
            parts.push(format!(
                "drag {} |v|^{}",
                d.drag.coefficient, d.drag.exponent
            ));
        }
        format!("Backward Euler ({})", parts.join(", "))
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

impl MinimizingSolver for BackwardEuler {
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        let dt = problem.tau;
        // v_0 = (x⁰ − x_n)/dt; the default x⁰ = x_n gives v_0 = 0 and Eq (12) as printed.
        let x0 = self.start.first_iterate(&self.system, state, problem);
        for ((v, x0), x_n) in self.v_k.iter_mut().zip(x0).zip(&state.x) {
            *v = (x0 - x_n) / dt;
        }
        let frozen = problem.frozen_positions(state);
        self.dissipation.start(&self.system, &state.x, frozen, dt);
        if !self.dissipation.dissipation().is_none() {
            self.convergence.refuse_residual_with_dissipation()?;
        }
        self.convergence
            .begin_stage(&self.system, state, problem.tau, x0.iter().copied());
        // Stopping early only in the tolerance mode, on the positions of Eq (9); at a fixed
        // point the iterations left are not computed ([`same_bits`]: their result is known).
        let mut fixed = false;
        for _ in 0..self.newton_iterations {
            if !fixed {
                fixed = self.newton_iteration(state, dt)?;
            }
            let x_k = state
                .x
                .iter()
                .zip(&self.v_k)
                .map(|(x, v)| position_update(x, v, dt));
            if self.convergence.converged(x_k) {
                break;
            }
        }
        self.convergence.end_step(0);
        for ((x, v), v_next) in state.x.iter_mut().zip(state.v.iter_mut()).zip(&self.v_k) {
            *x = position_update(x, v_next, dt);
            *v = *v_next;
        }
        Ok(())
    }
    // endregion: step

    fn dissipation(&self) -> Option<&Dissipation> {
        let d = self.dissipation.dissipation();
        (!d.is_none()).then_some(d)
    }
}

/// Settings of [`converged_step`](crate::solvers::converged_stage::converged_step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvergedStepOptions {
    /// Stop when the largest position update is below this, m.
    pub tolerance: f64,
    /// Give up after this many Newton iterations.
    pub max_iterations: usize,
}

impl Default for ConvergedStepOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-13,
            max_iterations: 200,
        }
    }
}

/// $`y = x_n + dt\,v_n`$, the inertial term's centre in Eq (20) (gravity is in the potential).
pub fn inertia(state: &State, dt: f64) -> Vec<Vec3> {
    state
        .x
        .iter()
        .zip(&state.v)
        .map(|(x, v)| x + dt * v)
        .collect()
}

/// The incremental potential of Eq (20): $`\frac{1}{2dt^2}(x - y)^\top M (x - y) + E(x)`$,
/// with $`E`$ the springs' energy plus gravity's potential and $`y = x_n + dt\,v_n`$.
pub fn incremental_potential(system: &MassSpringSystem, y: &[Vec3], x: &[Vec3], dt: f64) -> f64 {
    let inertia: f64 = system
        .nodes()
        .iter()
        .zip(x.iter().zip(y))
        .map(|(n, (x, y))| 0.5 * n.mass * (x - y).norm_squared())
        .sum();
    inertia / (dt * dt) + system.potential_energy(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::thesis_rope;

    /// Every bit of a state.
    fn bits(state: &State) -> Vec<u64> {
        let points = state.x.iter().chain(&state.v);
        points.flat_map(|p| p.iter().map(|c| c.to_bits())).collect()
    }

    /// A step that stops computing at a fixed point ([`same_bits`]) has the bits of the same
    /// step with all its Newton iterations computed: 2,000 reference steps of both ropes from
    /// rest, against Eq (12)'s iteration called five times a step. Fixed points are reached
    /// (counted, so that the shortcut is taken). Fails (checked) with the shortcut taken once
    /// an update moves no velocity by more than 1e-15 m/s instead of none.
    #[test]
    fn a_step_at_a_fixed_point_has_the_bits_of_all_its_iterations() {
        for k in [1e3, 1e6] {
            let system = thesis_rope(k).unwrap();
            let mut shortcut = BackwardEuler::reference(&system).unwrap();
            let mut full = shortcut.clone();
            let (mut a, mut b) = (system.initial_state(), system.initial_state());
            let mut fixed = 0;
            for _ in 0..2000 {
                shortcut.step(&mut a).unwrap();
                full.v_k.fill(Vec3::zeros());
                for _ in 0..REFERENCE_NEWTON_ITERATIONS {
                    fixed += usize::from(full.newton_iteration(&b, REFERENCE_DT).unwrap());
                }
                for ((x, v), v_next) in b.x.iter_mut().zip(b.v.iter_mut()).zip(&full.v_k) {
                    *x = position_update(x, v_next, REFERENCE_DT);
                    *v = *v_next;
                }
                assert_eq!(bits(&a), bits(&b), "k = {k}");
            }
            println!("k = {k}: {fixed} iterations at a fixed point");
            assert!(fixed > 500, "k = {k}: {fixed} iterations at a fixed point");
        }
    }
}

//! Labelled departures from Algorithm 4 (ADMM-PD), built from the building blocks of
//! [`crate::solvers::admm`], [`crate::solvers::projective`] and [`crate::model::boundary`]; never the default.
//!
//! They are the candidates for what the thesis's code did at dt = 0.1 and 0.01 s (forensic
//! finding 6 of `docs/thesis-scene.md`), each tried on the 18 published ADMM rows:
//! - [`StartPoint`]: the first iterate $`x^0`$ (line 2.1 prints $`\tilde x`$): $`x_n + dt\,v_n`$
//!   (gravity left out of the first iterate only; the right-hand side keeps $`M\tilde x`$), or
//!   $`x_n`$;
//! - `carry_dual`: $`\bar u`$ kept from the previous step instead of reset (line 2.2);
//! - [`Weights`]: $`\omega_i = k_i`$ or $`\omega_i^2 = \sqrt{k_i}`$ instead of $`\sqrt{k_i}`$;
//! - [`FixedNodes`]: the two other ways of fixing nodes that thesis §3.2 weighs: overwriting
//!   the fixed positions after each solve of the unconstrained system, or removing the fixed
//!   degrees of freedom ([`EliminatedSystem`]);
//! - `stale_rhs`: Eq (40)'s right-hand side, with the Eqs 45-47 correction $`b - A u`$, formed
//!   once per step (after the first local step) and left stale in later iterations.
//!
//! [`AdmmVariant::PRINTED`] is Algorithm 4 as printed, bit for bit [`AdmmPd`](crate::solvers::admm::AdmmPd)
//! (a test checks it).

use crate::error::{require_positive, Error, Result};
use crate::integrators::first_iterate::FirstIterate;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::boundary::EliminatedSystem;
use crate::model::linear::Factorization;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::admm::{default_omega, AdmmIterate};
use crate::solvers::batch::admm::{AdmmLaneData, AdmmRun};
use crate::solvers::projective::{finish_step, system_matrix, GlobalSolve};

/// The per-spring weights $`\omega_i`$ of a variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Weights {
    /// $`\omega_i = \sqrt{k_i}`$ (as printed, §2.3.2).
    SqrtStiffness,
    /// $`\omega_i = k_i`$.
    Stiffness,
    /// $`\omega_i^2 = \sqrt{k_i}`$.
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
    /// $`x^0 = \tilde x = x_n + dt\,v_n + dt^2 M^{-1} f_{ext}`$ (as printed, line 2.1).
    Prediction,
    /// $`x^0 = x_n + dt\,v_n`$, gravity left out of the first iterate only (the right-hand side
    /// of Eq 40 keeps $`M\tilde x`$).
    Inertial,
    /// $`x^0 = x_n`$.
    Previous,
}

impl StartPoint {
    /// The crate's [`FirstIterate`] that starts a step here.
    pub fn first_iterate(self) -> FirstIterate {
        match self {
            StartPoint::Prediction => FirstIterate::InertialPrediction,
            StartPoint::Inertial => FirstIterate::Inertial,
            StartPoint::Previous => FirstIterate::Previous,
        }
    }
}

/// How the fixed nodes enter the global step (the three ways of thesis §3.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FixedNodes {
    /// Eqs 43-47 on the prefactored matrix (as printed, the thesis's choice).
    Imposed,
    /// The unconstrained $`A`$ is solved with the fixed nodes free, and their positions are
    /// overwritten with $`x_n`$ after each solve.
    Overwritten,
    /// The fixed degrees of freedom are removed ([`EliminatedSystem`]).
    Eliminated,
}

/// A labelled departure from Algorithm 4 (see the module documentation).
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
    /// Algorithm 4 as printed.
    pub const PRINTED: AdmmVariant = AdmmVariant {
        start: StartPoint::Prediction,
        carry_dual: false,
        weights: Weights::SqrtStiffness,
        fixed_nodes: FixedNodes::Imposed,
        stale_rhs: false,
    };

    /// Whether the variant's runs can take a lane of a batch
    /// ([`crate::solvers::batch::admm`], whose step is Algorithm 4's with each lane's own
    /// weights and start): it departs from Algorithm 4 in its start and weights only.
    pub fn takes_a_lane(&self) -> bool {
        AdmmVariant {
            start: StartPoint::Prediction,
            weights: Weights::SqrtStiffness,
            ..*self
        } == AdmmVariant::PRINTED
    }

    /// The departures from Algorithm 4, comma-separated; empty for the printed method.
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

/// The prefactored global matrix with the fixed nodes handled as a [`FixedNodes`] says.
#[derive(Debug, Clone)]
enum GlobalMatrix {
    Imposed(GlobalSolve),
    Overwritten {
        factorization: Factorization,
        fixed: Vec<usize>,
    },
    Eliminated(EliminatedSystem),
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
                let edges: Vec<(usize, usize)> =
                    system.springs().iter().map(|s| (s.a, s.b)).collect();
                let a = system_matrix(system, dt, omega2)?;
                GlobalMatrix::Eliminated(EliminatedSystem::new(&a, &fixed, &edges)?)
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
            GlobalMatrix::Eliminated(a) => a.solve(b, x_n, 3),
        }
    }
}

/// ADMM-PD with the departures of an [`AdmmVariant`].
#[derive(Debug, Clone)]
pub struct VariantAdmm {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    variant: AdmmVariant,
    a: GlobalMatrix,
    iterate: AdmmIterate,
    /// Eq (40)'s right-hand side of the step's first iteration (`stale_rhs` only).
    first_rhs: Vec<f64>,
}

impl VariantAdmm {
    /// Algorithm 4, lines 1.1-1.5, with the weights and fixed-node handling of `variant`.
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        variant: AdmmVariant,
    ) -> Result<Self> {
        require_positive("dt", dt)?;
        system.require_positive_stiffness()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let omega = variant.weights.omega(system);
        let omega2: Vec<f64> = omega.iter().map(|w| w * w).collect();
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            variant,
            a: GlobalMatrix::new(system, dt, &omega2, variant.fixed_nodes)?,
            iterate: AdmmIterate::new(system, dt, omega),
            first_rhs: vec![
                0.0;
                if variant.stale_rhs {
                    3 * system.len()
                } else {
                    0
                }
            ],
        })
    }

    /// Line 2.1's first iterate under [`StartPoint`].
    fn start(&mut self, state: &State) {
        let it = &mut self.iterate;
        match self.variant.start {
            StartPoint::Prediction => it.x.copy_from_slice(&it.x_tilde),
            StartPoint::Previous => it.x.copy_from_slice(&it.x_n),
            StartPoint::Inertial => {
                let n = state.x.len();
                for (i, node) in self.system.nodes().iter().enumerate() {
                    let x0 = if node.fixed {
                        state.x[i]
                    } else {
                        state.x[i] + self.dt * state.v[i]
                    };
                    for c in 0..3 {
                        it.x[c * n + i] = x0[c];
                    }
                }
            }
        }
    }
}

/// A variant of start and weights in a lane ([`AdmmVariant::takes_a_lane`]): its data, which
/// the lanes' step (Algorithm 4's) runs as the variant's own step does (a test in
/// `solvers::batch`).
impl AdmmRun for VariantAdmm {
    /// # Panics
    /// For a variant that does not take a lane (its fixed nodes not imposed by Eqs 43-47).
    fn lane_data(&self) -> AdmmLaneData<'_> {
        assert!(
            self.variant.takes_a_lane(),
            "only a variant of start and weights takes a lane"
        );
        let GlobalMatrix::Imposed(a) = &self.a else {
            unreachable!("a variant that takes a lane imposes its fixed nodes")
        };
        AdmmLaneData {
            iterations: self.iterations,
            first_iterate: self.variant.start.first_iterate(),
            counts_iterations: true,
            iterate: &self.iterate,
            a,
        }
    }
}

impl TimeStepper for VariantAdmm {
    fn name(&self) -> String {
        format!(
            "ADMM-PD ({} iterations, variant: {})",
            self.iterations,
            self.variant.label()
        )
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.iterate.predict(&self.system, state, self.dt);
        self.start(state);
        let it = &mut self.iterate;
        if !self.variant.carry_dual {
            it.u_bar.fill(Vec3::zeros());
        }
        for iteration in 0..self.iterations {
            it.local_step();
            if self.variant.stale_rhs && iteration > 0 {
                it.x.copy_from_slice(&self.first_rhs);
            } else {
                it.global_rhs();
                if self.variant.stale_rhs {
                    self.first_rhs.copy_from_slice(&it.x);
                }
            }
            self.a.solve(&mut it.x, &it.x_n);
        }
        finish_step(state, &it.x, self.dt);
        Ok(())
    }
}

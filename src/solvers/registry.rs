//! The solver registry: one identifier per solver, with its parameters, used by the library's
//! experiments, `mss`, the report and the benches.
//!
//! [`SolverId`] names a solver; [`SolverId::info`] is the list of every solver, one entry each
//! (its names, its source, what its iterations mean, its options and how it is built), so
//! adding a solver is one variant and one entry there. [`SolverSpec`] is a solver with its
//! parameters: the iteration count and the options of [`SolverParams`].
//!
//! What the registry does not hold, on purpose: the forensic readings of the thesis's open
//! points ([`crate::studies::forensics::SolverChoice`], which builds departures from the printed
//! algorithms for the forensic chapter only) and the stopping rule and recording of a run
//! ([`crate::integrators::time_stepper::RunOptions`]), which belong to the run, not to the solver.

use crate::solvers::admm::AdmmPd;
use crate::solvers::anderson::{Anderson, AndersonParams};
use crate::solvers::backward_euler::{BackwardEuler, ConvergedStepOptions};
use crate::solvers::converged_stage::damped_converged_step;
use crate::solvers::chebyshev::{spectral_radius, Chebyshev, ChebyshevParams, RhoRule};
use crate::solvers::damped_admm::DampedAdmm;
use crate::integrators::damping::RayleighDamping;
use crate::integrators::dissipation::{Dissipation, PowerLawDrag, RayleighForm};
use crate::error::{require_within, shown, Error, Result};
use crate::solvers::fast_mass_spring::FastMassSpring;
use crate::integrators::first_iterate::FirstIterate;
use crate::solvers::local_global::{AdmmMerit, Base};
use crate::integrators::optimization_integrator::{Integrated, MinimizingSolver, OptimizationIntegrator};
use crate::particles::adaptive::AdaptiveStepper;
use crate::particles::integrators::{Integrator, ParticleStepper};
use crate::particles::ParticleSystem;
use crate::solvers::pbd::Pbd;
use crate::solvers::quasi_newton::{Lbfgs, LbfgsParams};
use crate::integrators::time_stepper::TimeStepper;
use crate::integrators::stopping::Stopping;
use crate::model::system::{MassSpringSystem, State};
use crate::solvers::vbd::{LocalHessian, Vbd, VbdParams};
use crate::solvers::xpbd::Xpbd;
use crate::solvers::xpbd_substeps::{Sweep, XpbdSubsteps, XpbdSubstepsParams};
use serde::{Deserialize, Serialize};

/// One identifier per solver: the thesis's (§2), the tutorial's integrators and the newer
/// solvers of the thesis's future work (§5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverId {
    BackwardEuler,
    Pbd,
    Xpbd,
    FastMassSpring,
    AdmmPd,
    ChebyshevLiu,
    ChebyshevAdmm,
    AndersonLiu,
    AndersonAdmm,
    DampedBackwardEuler,
    DampedAdmm,
    XpbdSubsteps,
    Lbfgs,
    Vbd,
    ExplicitEuler,
    SymplecticEuler,
    Rk4,
    Rk45,
}

/// Where a solver comes from, which decides where the report shows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// A solver of the thesis (§2).
    Thesis,
    /// One of the tutorial's integrators (or the adaptive pair beyond it).
    Tutorial,
    /// A solver after the thesis, from its future work (§5).
    Beyond,
}

/// What a solver is built from: a mass-spring system (springs and gravity only, the thesis's
/// model) or the tutorial's particle system (with drag, spring damping and a ground).
#[derive(Clone, Copy)]
pub enum Builder {
    Springs(fn(&MassSpringSystem, f64, &SolverSpec) -> Result<Box<dyn TimeStepper + Send>>),
    Particles(fn(ParticleSystem, f64, &SolverSpec) -> Result<Box<dyn TimeStepper>>),
}

/// A solver's option beyond the time step and the iteration count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OptionInfo {
    /// The name in [`SolverParams`] and, with dashes, on the command line.
    pub name: &'static str,
    /// What it is, its unit and its allowed range.
    pub help: &'static str,
}

/// A registry entry.
#[derive(Clone, Copy)]
pub struct SolverInfo {
    /// The identifier in CSV files and on the command line.
    pub id: &'static str,
    /// The one name the report gives the solver, in every table, legend and sentence: the
    /// abbreviation of thesis Table 8 for the thesis's solvers, a short readable name for the
    /// others (an accelerated solver names its base by that base's display name).
    pub display_name: &'static str,
    /// A one-line description.
    pub summary: &'static str,
    /// The section, algorithm or paper it implements.
    pub source: &'static str,
    /// The module that implements it.
    pub file: &'static str,
    pub family: Family,
    /// What one iteration is (Newton iteration, sweep, ...), or `None` for a solver without
    /// iterations.
    pub iteration: Option<&'static str>,
    pub options: &'static [OptionInfo],
    /// The time of one iteration (a step, for a solver without iterations) on the thesis rope
    /// relative to one of Liu 2013's, for scheduling only (`make bench`: Liu 117 ns, ADMM
    /// 142 ns, XPBD 162 ns per iteration, Backward Euler 5.29 µs per step of 5 Newton
    /// iterations; the newer solvers as their engineers measured them under load).
    pub relative_cost: f64,
    /// The solver whose iteration this one accelerates (same fixed point, same cost per
    /// iteration up to the acceleration's own work).
    pub accelerates: Option<SolverId>,
    pub builder: Builder,
}

impl std::fmt::Debug for SolverInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SolverInfo").field("id", &self.id).finish()
    }
}

impl SolverId {
    /// Every solver, in the order `mss --list-solvers` prints them.
    pub const ALL: [SolverId; 18] = [
        SolverId::BackwardEuler,
        SolverId::Pbd,
        SolverId::Xpbd,
        SolverId::FastMassSpring,
        SolverId::AdmmPd,
        SolverId::ChebyshevLiu,
        SolverId::ChebyshevAdmm,
        SolverId::AndersonLiu,
        SolverId::AndersonAdmm,
        SolverId::DampedBackwardEuler,
        SolverId::DampedAdmm,
        SolverId::XpbdSubsteps,
        SolverId::Lbfgs,
        SolverId::Vbd,
        SolverId::ExplicitEuler,
        SolverId::SymplecticEuler,
        SolverId::Rk4,
        SolverId::Rk45,
    ];

    /// The four solvers of the thesis's tables, in table order.
    pub const THESIS_TABLES: [SolverId; 4] = [
        SolverId::BackwardEuler,
        SolverId::Xpbd,
        SolverId::FastMassSpring,
        SolverId::AdmmPd,
    ];

    /// The registry: every solver's entry.
    pub fn info(self) -> SolverInfo {
        match self {
            SolverId::BackwardEuler => SolverInfo {
                id: "backward_euler",
                display_name: "Backward Euler",
                summary: "Backward Euler with Newton-Raphson, the thesis's reference",
                source: "thesis §2.1, Eqs 1-12",
                file: "src/solvers/backward_euler.rs",
                family: Family::Thesis,
                iteration: Some("Newton iteration"),
                options: &[FIRST_ITERATE_PREVIOUS, INTEGRATOR],
                relative_cost: 9.0,
                accelerates: None,
                builder: Builder::Springs(integrated),
            },
            SolverId::Pbd => SolverInfo {
                id: "pbd",
                display_name: "PBD",
                summary: "Position-Based Dynamics, Gauss-Seidel over the springs",
                source: "thesis §2.2, Algorithm 1, Eqs 13-14",
                file: "src/solvers/pbd.rs",
                family: Family::Thesis,
                iteration: Some("sweep over the springs"),
                options: &[OptionInfo {
                    name: "stiffness_factor",
                    help: "dimensionless factor in [0, 1] scaling each correction (not k)",
                }],
                relative_cost: 1.4,
                accelerates: None,
                builder: Builder::Springs(|system, dt, spec| {
                    Ok(Box::new(Pbd::new(
                        system,
                        dt,
                        spec.iterations,
                        spec.params.stiffness_factor,
                    )?))
                }),
            },
            SolverId::Xpbd => SolverInfo {
                id: "xpbd",
                display_name: "XPBD",
                summary: "Extended PBD, compliance 1/k",
                source: "thesis §2.2.1, Algorithm 2, Eqs 15-19, 48-51",
                file: "src/solvers/xpbd.rs",
                family: Family::Thesis,
                iteration: Some("sweep over the springs"),
                options: &[],
                relative_cost: 1.4,
                accelerates: None,
                builder: Builder::Springs(|system, dt, spec| {
                    Ok(Box::new(Xpbd::new(system, dt, spec.iterations)?))
                }),
            },
            SolverId::FastMassSpring => SolverInfo {
                id: "fast_mass_spring",
                display_name: "Fast m-s",
                summary: "Liu et al. 2013, fast simulation of mass-spring systems",
                source: "thesis §2.3.1, Algorithm 3, Eqs 20-29, 52-53",
                file: "src/solvers/fast_mass_spring.rs",
                family: Family::Thesis,
                iteration: Some("local/global iteration"),
                options: &[FIRST_ITERATE_PREVIOUS, INTEGRATOR],
                relative_cost: 1.0,
                accelerates: None,
                builder: Builder::Springs(integrated),
            },
            SolverId::AdmmPd => SolverInfo {
                id: "admm_pd",
                display_name: "ADMM",
                summary: "Overby et al. 2017, ADMM ⊇ Projective Dynamics, weights sqrt(k)",
                source: "thesis §2.3.2, Algorithm 4, Eqs 30-42, 54-56",
                file: "src/solvers/admm.rs",
                family: Family::Thesis,
                iteration: Some("ADMM iteration"),
                options: &[FIRST_ITERATE_PREDICTION, INTEGRATOR],
                relative_cost: 1.2,
                accelerates: None,
                builder: Builder::Springs(integrated),
            },
            SolverId::ChebyshevLiu => chebyshev(Base::Liu),
            SolverId::ChebyshevAdmm => chebyshev(Base::Admm),
            SolverId::AndersonLiu => anderson(Base::Liu),
            SolverId::AndersonAdmm => anderson(Base::Admm),
            SolverId::DampedBackwardEuler => SolverInfo {
                id: "damped_backward_euler",
                display_name: "Backward Euler damped",
                summary: "Backward Euler with Rayleigh damping, the damped ADMM's ground truth",
                source: "Brown, Overby, Forootaninia, Narain 2018, Accurate Dissipative Forces in Optimization Integrators",
                file: "src/solvers/backward_euler.rs",
                family: Family::Beyond,
                iteration: Some("Newton iteration"),
                options: &[
                    RAYLEIGH_ALPHA,
                    RAYLEIGH_BETA,
                    RAYLEIGH_FORM,
                    DRAG,
                    DRAG_EXPONENT,
                    FIRST_ITERATE_PREVIOUS,
                    INTEGRATOR,
                ],
                relative_cost: 9.0,
                accelerates: None,
                builder: Builder::Springs(integrated),
            },
            SolverId::DampedAdmm => SolverInfo {
                id: "damped_admm",
                display_name: "ADMM damped",
                summary: "ADMM-PD with Rayleigh damping in the optimisation (Brown et al. 2018)",
                source: "Brown, Overby, Forootaninia, Narain 2018, Accurate Dissipative Forces in Optimization Integrators",
                file: "src/solvers/damped_admm.rs",
                family: Family::Beyond,
                iteration: Some("ADMM iteration"),
                options: &[
                    RAYLEIGH_ALPHA,
                    RAYLEIGH_BETA,
                    RAYLEIGH_FORM,
                    DRAG,
                    DRAG_EXPONENT,
                    INTEGRATOR,
                    OptionInfo {
                        name: "first_iterate",
                        help: "first iterate of each step: previous-position, inertia, \
                               inertia-and-acceleration or adaptive (Chen 2024's (a)-(d)) \
                               [default: the damped prediction x̂, the inertial term's centre]",
                    },
                ],
                relative_cost: 1.5,
                accelerates: None,
                builder: Builder::Springs(integrated),
            },
            SolverId::XpbdSubsteps => SolverInfo {
                id: "xpbd_substeps",
                display_name: "XPBD substeps",
                summary: "XPBD with n substeps of one iteration per step (small steps)",
                source: "Macklin, Storey, Lu, Terdiman, Chentanez, Jeschke, Müller 2019, Small Steps in Physics Simulation",
                file: "src/solvers/xpbd_substeps.rs",
                family: Family::Beyond,
                iteration: Some("substep of one XPBD sweep (iterations = substeps)"),
                options: &[
                    OptionInfo {
                        name: "constraint_damping",
                        help: "Macklin 2019's constraint damping beta >= 0 (Eq. 8), in N·s/m \
                               [default: 0]",
                    },
                    OptionInfo {
                        name: "sweep",
                        help: "constraint pass: gauss-seidel or jacobi [default: gauss-seidel]",
                    },
                ],
                relative_cost: 2.0,
                accelerates: None,
                builder: Builder::Springs(|system, dt, spec| {
                    Ok(Box::new(XpbdSubsteps::new(
                        system,
                        dt,
                        spec.iterations,
                        spec.params.xpbd_substeps(),
                    )?))
                }),
            },
            SolverId::Lbfgs => SolverInfo {
                id: "lbfgs",
                display_name: "L-BFGS",
                summary: "quasi-Newton L-BFGS on the incremental potential, the Liu system matrix as initial Hessian",
                source: "Liu, Bouaziz, Kavan 2017, Quasi-Newton Methods for Real-Time Simulation of Hyperelastic Materials",
                file: "src/solvers/quasi_newton.rs",
                family: Family::Beyond,
                iteration: Some("L-BFGS iteration (one global solve and a line search)"),
                options: &[
                    OptionInfo {
                        name: "history",
                        help: "L-BFGS window m, past pairs kept, an integer from 1 to 100 [default: 5]",
                    },
                    FIRST_ITERATE_PREDICTION,
                    INTEGRATOR,
                ],
                relative_cost: 6.5,
                accelerates: Some(SolverId::FastMassSpring),
                builder: Builder::Springs(integrated),
            },
            SolverId::Vbd => SolverInfo {
                id: "vbd",
                display_name: "VBD",
                summary: "Vertex Block Descent: per-node Newton on the incremental potential, colour order",
                source: "Chen, Liu, Yang, Yuksel 2024, Vertex Block Descent",
                file: "src/solvers/vbd.rs",
                family: Family::Beyond,
                iteration: Some("sweep over the nodes"),
                options: &[
                    OptionInfo {
                        name: "first_iterate",
                        help: "initial guess of each step: previous-position, inertia, \
                               inertia-and-acceleration or adaptive (the paper's (a)-(d)) \
                               [default: adaptive]",
                    },
                    OptionInfo {
                        name: "hessian",
                        help: "local Hessian: exact (the paper's, a vertex skipped when \
                               |det H| <= 1e-10 (m/h²)³) or projected [default: exact]",
                    },
                    INTEGRATOR,
                ],
                relative_cost: 8.5,
                accelerates: None,
                builder: Builder::Springs(integrated),
            },
            SolverId::ExplicitEuler => tutorial_integrator(
                "explicit_euler",
                "Explicit Euler",
                "explicit Euler (order 1; grows without damping at every dt)",
            ),
            SolverId::SymplecticEuler => tutorial_integrator(
                "symplectic_euler",
                "Symplectic Euler",
                "symplectic Euler (order 1; stable for omega·dt < 2)",
            ),
            SolverId::Rk4 => tutorial_integrator(
                "rk4",
                "RK4",
                "classical Runge-Kutta (order 4; stable for omega·dt < 2·sqrt(2))",
            ),
            SolverId::Rk45 => SolverInfo {
                id: "rk45",
                display_name: "RK45",
                summary: "Dormand-Prince 5(4) with error control; dt is the sampling interval",
                source: "beyond the tutorial: Dormand & Prince 1980",
                file: "src/particles/adaptive.rs",
                family: Family::Tutorial,
                iteration: None,
                options: &[OptionInfo {
                    name: "tolerance",
                    help: "error tolerance of each adaptive step, from 1e-12 to 0.1, relative \
                           to 1 + |component|",
                }],
                relative_cost: 1.0,
                accelerates: None,
                builder: Builder::Particles(|particles, dt, spec| {
                    Ok(Box::new(
                        AdaptiveStepper::new(particles, dt, spec.params.tolerance)?
                            .with_attempt_limit(spec.params.adaptive_attempts),
                    ))
                }),
            },
        }
    }

    /// The identifier used in CSV files and on the command line.
    pub fn id(self) -> &'static str {
        self.info().id
    }

    /// The one name the report gives the solver ([`SolverInfo::display_name`]).
    pub fn display_name(self) -> &'static str {
        self.info().display_name
    }

    /// Parses an identifier of [`SolverId::id`] (dashes read as underscores).
    pub fn from_id(id: &str) -> Result<Self> {
        let normalised = id.replace('-', "_");
        Self::ALL
            .into_iter()
            .find(|s| s.id() == normalised)
            .ok_or_else(|| {
                let ids: Vec<&str> = Self::ALL.iter().map(|s| s.id()).collect();
                Error::invalid("solver", id, &format!("one of {}", ids.join(", ")))
            })
    }

    /// Whether its steps can stop at a tolerance ([`crate::integrators::stopping`]): every solver whose
    /// steps iterate toward the step's solution, so not the tutorial's integrators, nor XPBD's
    /// substeps, whose count is of substeps of the motion.
    pub fn stops_at_tolerance(self) -> bool {
        self.info().iteration.is_some() && self != SolverId::XpbdSubsteps
    }

    /// Whether it minimises thesis Eq 20's stage problems, and so runs under every
    /// optimization integrator (the option `integrator`).
    pub fn is_minimizing(self) -> bool {
        self.info().options.iter().any(|o| o.name == "integrator")
    }

    /// The tutorial's integrator this solver is, if it is one.
    pub fn integrator(self) -> Option<Integrator> {
        match self {
            SolverId::ExplicitEuler => Some(Integrator::ExplicitEuler),
            SolverId::SymplecticEuler => Some(Integrator::SymplecticEuler),
            SolverId::Rk4 => Some(Integrator::Rk4),
            _ => None,
        }
    }
}

impl std::fmt::Display for SolverId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id())
    }
}

impl std::str::FromStr for SolverId {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        Self::from_id(s)
    }
}

/// The options of the Rayleigh-damped solvers.
const RAYLEIGH_ALPHA: OptionInfo = OptionInfo {
    name: "alpha",
    help: "mass-proportional Rayleigh damping alpha from 0 to 1e6, in 1/s [default: 0]",
};
const RAYLEIGH_BETA: OptionInfo = OptionInfo {
    name: "beta",
    help: "stiffness-proportional Rayleigh damping beta from 0 to 1e3, in s [default: 0]",
};

/// The options of the dissipative solvers beyond Rayleigh's coefficients.
const RAYLEIGH_FORM: OptionInfo = OptionInfo {
    name: "rayleigh_form",
    help: "Rayleigh damping's form: classical (alpha M + beta K) or momentum-conserving \
           (this crate's: the springs' rates of stretching only) [default: classical]",
};
const DRAG: OptionInfo = OptionInfo {
    name: "drag",
    help: "power-law drag coefficient c >= 0 of D = c |v|^(p+1)/(p+1), in N·(s/m)^p \
           [default: 0]",
};
const DRAG_EXPONENT: OptionInfo = OptionInfo {
    name: "drag_exponent",
    help: "power-law drag exponent p, > 0 and < 1 [default: 0.5]",
};

/// The option of every minimizing solver: the optimization integrator.
const INTEGRATOR: OptionInfo = OptionInfo {
    name: "integrator",
    help: "optimization integrator: backward-euler, implicit-midpoint, bdf2 (started by one \
           TR-BDF2 step) or tr-bdf2 [default: backward-euler]",
};

/// A minimizing solver under the integrator of `spec` ([`Integrated`]): the builder of every
/// solver with the option `integrator`.
fn integrated(
    system: &MassSpringSystem,
    dt: f64,
    spec: &SolverSpec,
) -> Result<Box<dyn TimeStepper + Send>> {
    Ok(Box::new(Integrated::new(
        stage_solver(system, dt, spec)?,
        spec.params.integrator,
    )?))
}

/// The minimizing solver of `spec` alone, without an integrator: what solves each stage
/// problem ([`SolverSpec::build_stage_solver`]).
fn stage_solver(
    system: &MassSpringSystem,
    dt: f64,
    spec: &SolverSpec,
) -> Result<Box<dyn MinimizingSolver + Send>> {
    let params = &spec.params;
    let iterations = spec.iterations;
    let mut solver: Box<dyn MinimizingSolver + Send> = match spec.id {
        SolverId::BackwardEuler => Box::new(
            BackwardEuler::new(system, dt, iterations)?
                .with_first_iterate(params.first_iterate_or(FirstIterate::Previous)),
        ),
        SolverId::DampedBackwardEuler => Box::new(
            BackwardEuler::dissipative(system, dt, iterations, params.dissipation())?
                .with_first_iterate(params.first_iterate_or(FirstIterate::Previous)),
        ),
        SolverId::FastMassSpring => Box::new(
            FastMassSpring::new(system, dt, iterations)?
                .with_first_iterate(params.first_iterate_or(FirstIterate::Previous)),
        ),
        SolverId::AdmmPd => Box::new(
            AdmmPd::new(system, dt, iterations)?
                .with_first_iterate(params.first_iterate_or(FirstIterate::InertialPrediction)),
        ),
        SolverId::DampedAdmm => {
            let solver = DampedAdmm::dissipative(system, dt, iterations, params.dissipation())?;
            Box::new(match params.first_iterate {
                Some(first_iterate) => solver.with_first_iterate(first_iterate),
                None => solver,
            })
        }
        SolverId::ChebyshevLiu | SolverId::ChebyshevAdmm => Box::new(Chebyshev::new(
            system,
            dt,
            iterations,
            params.chebyshev(accelerated_base(spec.id)),
        )?),
        SolverId::AndersonLiu | SolverId::AndersonAdmm => Box::new(Anderson::new(
            system,
            dt,
            iterations,
            params.anderson(accelerated_base(spec.id)),
        )?),
        SolverId::Lbfgs => Box::new(
            Lbfgs::new(system, dt, iterations, params.lbfgs())?
                .with_first_iterate(params.first_iterate_or(FirstIterate::InertialPrediction)),
        ),
        SolverId::Vbd => Box::new(Vbd::new(system, dt, iterations, params.vbd())?),
        other => {
            return Err(Error::invalid(
                "solver",
                other,
                "a minimizing solver (one with the option integrator)",
            ))
        }
    };
    solver.set_stopping(spec.stopping)?;
    Ok(solver)
}

/// The first-iterate option of a solver that starts at $`x_n`$ by default.
const FIRST_ITERATE_PREVIOUS: OptionInfo = OptionInfo {
    name: "first_iterate",
    help: "first iterate of each step: previous-position, inertia, inertia-and-acceleration \
           or adaptive (Chen 2024's (a)-(d)) [default: previous-position]",
};

/// The first-iterate option of a solver that starts at the inertial prediction by default.
const FIRST_ITERATE_PREDICTION: OptionInfo = OptionInfo {
    name: "first_iterate",
    help: "first iterate of each step: previous-position, inertia, inertia-and-acceleration \
           or adaptive (Chen 2024's (a)-(d)) [default: inertia-and-acceleration]",
};

/// The solver of the thesis's tables that runs `base`'s iteration.
fn base_solver(base: Base) -> SolverId {
    match base {
        Base::Liu => SolverId::FastMassSpring,
        Base::Admm => SolverId::AdmmPd,
    }
}

/// The iteration an accelerated solver accelerates, as the accelerations name it.
fn accelerated_base(id: SolverId) -> Base {
    match id.info().accelerates {
        Some(SolverId::AdmmPd) => Base::Admm,
        _ => Base::Liu,
    }
}

/// The entry of Wang 2015's Chebyshev acceleration of `base`.
fn chebyshev(base: Base) -> SolverInfo {
    SolverInfo {
        id: match base {
            Base::Liu => "chebyshev_liu",
            Base::Admm => "chebyshev_admm",
        },
        display_name: match base {
            Base::Liu => "Chebyshev Fast m-s",
            Base::Admm => "Chebyshev ADMM",
        },
        summary: match base {
            Base::Liu => "Wang 2015's Chebyshev semi-iterative acceleration of Liu 2013",
            Base::Admm => "Wang 2015's Chebyshev semi-iterative acceleration of ADMM-PD",
        },
        source: "Wang 2015, A Chebyshev Semi-Iterative Approach for Accelerating Projective and Position-based Dynamics",
        file: "src/solvers/chebyshev.rs",
        family: Family::Beyond,
        iteration: Some("local/global iteration (one global solve)"),
        options: &[
            OptionInfo {
                name: "spectral_radius",
                help: "rho in (0, 1) of the base iteration [default: found by rho_rule on the scene's start]",
            },
            OptionInfo {
                name: "gamma",
                help: "under-relaxation in (0, 1] [default: 1]",
            },
            OptionInfo {
                name: "warmup",
                help: "iterations S with omega = 1, an integer >= 0 [default: 10]",
            },
            OptionInfo {
                name: "rho_rule",
                help: "how rho is found when not given: asymptotic-rate (of the plain \
                       iteration, ours) or gradient-ratio (Wang 2015 §5.1's start, at the \
                       iteration count used) [default: asymptotic-rate]",
            },
            FIRST_ITERATE_PREDICTION,
            INTEGRATOR,
        ],
        relative_cost: 2.0,
        accelerates: Some(base_solver(base)),
        builder: Builder::Springs(integrated),
    }
}

/// Anderson acceleration's window.
const ANDERSON_WINDOW: OptionInfo = OptionInfo {
    name: "window",
    help: "past iterates m in each extrapolation, an integer from 1 to 20 [default: 5]",
};

/// The entry of Anderson acceleration of `base` (Peng et al. 2018, Zhang et al. 2019).
fn anderson(base: Base) -> SolverInfo {
    SolverInfo {
        id: match base {
            Base::Liu => "anderson_liu",
            Base::Admm => "anderson_admm",
        },
        display_name: match base {
            Base::Liu => "Anderson Fast m-s",
            Base::Admm => "Anderson ADMM",
        },
        summary: match base {
            Base::Liu => "Peng et al. 2018's Anderson acceleration of Liu 2013, energy safeguard",
            Base::Admm => {
                "Zhang et al. 2019's Anderson acceleration of ADMM-PD, primal-residual safeguard"
            }
        },
        source: match base {
            Base::Liu => "Peng, Deng, Zhang, Geng, Qin, Liu 2018, Anderson Acceleration for Geometry Optimization and Physics Simulation",
            Base::Admm => "Zhang, Peng, Ouyang, Deng 2019, Accelerating ADMM for Efficient Simulation and Optimization",
        },
        file: "src/solvers/anderson.rs",
        family: Family::Beyond,
        iteration: Some("local/global iteration (one global solve)"),
        options: match base {
            Base::Liu => &[ANDERSON_WINDOW, FIRST_ITERATE_PREDICTION, INTEGRATOR],
            Base::Admm => &[
                ANDERSON_WINDOW,
                OptionInfo {
                    name: "safeguard",
                    help: "merit of the safeguard: primal-residual (Zhang 2019's, after the \
                           local step, a rejection costs no global solve) or combined-residual \
                           (after the global step) [default: primal-residual]",
                },
                FIRST_ITERATE_PREDICTION,
                INTEGRATOR,
            ],
        },
        relative_cost: 12.0,
        accelerates: Some(base_solver(base)),
        builder: Builder::Springs(integrated),
    }
}

/// The entry of a tutorial integrator with a fixed step.
fn tutorial_integrator(
    id: &'static str,
    display_name: &'static str,
    summary: &'static str,
) -> SolverInfo {
    SolverInfo {
        id,
        display_name,
        summary,
        source: "tutorial (seed 004): Baraff & Witkin's particle system",
        file: "src/particles/integrators.rs",
        family: Family::Tutorial,
        iteration: None,
        options: &[],
        relative_cost: 1.0,
        accelerates: None,
        builder: Builder::Particles(|particles, dt, spec| {
            let integrator = spec
                .id
                .integrator()
                .expect("the tutorial's entries are its integrators");
            Ok(Box::new(ParticleStepper::new(particles, integrator, dt)?))
        }),
    }
}

/// The options of the solvers that have any; each solver reads its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverParams {
    /// PBD: the dimensionless factor in [0, 1] scaling each constraint's correction.
    pub stiffness_factor: f64,
    /// rk45: the error tolerance of each adaptive step.
    pub tolerance: f64,
    /// Chebyshev: the base iteration's spectral radius; None: estimated on the scene.
    pub spectral_radius: Option<f64>,
    /// Chebyshev: the under-relaxation.
    pub gamma: f64,
    /// Chebyshev: the warm-up iterations.
    pub warmup: usize,
    /// Anderson: the window.
    pub window: usize,
    /// The damped solvers: Rayleigh damping.
    pub damping: RayleighDamping,
    /// L-BFGS: the window (pairs kept).
    pub history: usize,
    /// Every solver iterating on the incremental potential: where each step starts; None:
    /// the solver's own start (its paper's or the thesis's).
    pub first_iterate: Option<FirstIterate>,
    /// Chebyshev: how the spectral radius is found when not given.
    pub rho_rule: RhoRule,
    /// Anderson on ADMM: the safeguard's merit.
    pub safeguard: AdmmMerit,
    /// VBD: the local Hessian rule.
    pub hessian: LocalHessian,
    /// XPBD substeps: Macklin 2019's constraint damping, N·s/m.
    pub constraint_damping: f64,
    /// XPBD substeps: the constraint pass.
    pub sweep: Sweep,
    /// rk45: the most adaptive steps (accepted or rejected) a run may attempt, a work budget;
    /// None: no limit.
    pub adaptive_attempts: Option<u64>,
    /// Every minimizing solver: the optimization integrator.
    pub integrator: OptimizationIntegrator,
    /// The dissipative solvers: the form of their Rayleigh damping.
    pub rayleigh_form: RayleighForm,
    /// The dissipative solvers: power-law drag.
    pub drag: PowerLawDrag,
}

impl SolverParams {
    /// The option `name` (an [`OptionInfo::name`]) as text; None for an unset optional value
    /// or a name no solver has.
    pub fn get(&self, name: &str) -> Option<String> {
        Some(match name {
            "stiffness_factor" => self.stiffness_factor.to_string(),
            "tolerance" => self.tolerance.to_string(),
            "spectral_radius" => self.spectral_radius?.to_string(),
            "gamma" => self.gamma.to_string(),
            "warmup" => self.warmup.to_string(),
            "window" => self.window.to_string(),
            "alpha" => self.damping.alpha.to_string(),
            "beta" => self.damping.beta.to_string(),
            "history" => self.history.to_string(),
            "first_iterate" => self.first_iterate?.key().to_string(),
            "rho_rule" => self.rho_rule.key().to_string(),
            "safeguard" => self.safeguard.key().to_string(),
            "hessian" => self.hessian.key().to_string(),
            "constraint_damping" => self.constraint_damping.to_string(),
            "sweep" => self.sweep.key().to_string(),
            "integrator" => self.integrator.key().to_string(),
            "rayleigh_form" => self.rayleigh_form.key().to_string(),
            "drag" => self.drag.coefficient.to_string(),
            "drag_exponent" => self.drag.exponent.to_string(),
            _ => return None,
        })
    }

    /// Sets the option `name` (an [`OptionInfo::name`]) from its text, checked against its
    /// range by the solver that reads it.
    pub fn set(&mut self, name: &str, value: &str) -> Result<()> {
        let number = || -> Result<f64> {
            value
                .parse()
                .map_err(|_| Error::invalid(name, value, "a number"))
        };
        match name {
            "stiffness_factor" => {
                self.stiffness_factor = crate::solvers::pbd::require_factor(name, number()?)?;
            }
            "tolerance" => {
                self.tolerance = require_within(name, number()?, 1e-12, 0.1, TOLERANCE_UNIT)?
            }
            "spectral_radius" => self.spectral_radius = Some(number()?),
            "gamma" => self.gamma = number()?,
            "warmup" => self.warmup = require_integer(name, number()?, 0)?,
            "window" => self.window = require_integer(name, number()?, 1)?,
            "alpha" => self.damping.alpha = require_within(name, number()?, 0.0, 1e6, "1/s")?,
            "beta" => self.damping.beta = require_within(name, number()?, 0.0, 1e3, "s")?,
            "history" => self.history = require_count_within(name, number()?, 1, MAX_HISTORY)?,
            "first_iterate" => self.first_iterate = Some(value.parse()?),
            "rho_rule" => self.rho_rule = value.parse()?,
            "safeguard" => self.safeguard = value.parse()?,
            "hessian" => self.hessian = value.parse()?,
            "constraint_damping" => self.constraint_damping = number()?,
            "sweep" => self.sweep = value.parse()?,
            "integrator" => self.integrator = value.parse()?,
            "rayleigh_form" => self.rayleigh_form = value.parse()?,
            "drag" => self.drag.coefficient = number()?,
            "drag_exponent" => self.drag.exponent = number()?,
            _ => {
                let names: Vec<&str> = SolverId::ALL
                    .iter()
                    .flat_map(|s| s.info().options.iter().map(|o| o.name))
                    .collect();
                return Err(Error::invalid(
                    "option",
                    name,
                    &format!("one of {}", names.join(", ")),
                ));
            }
        }
        self.chebyshev(Base::Liu).validate()?;
        self.anderson(Base::Liu).validate()?;
        self.lbfgs().validate()?;
        self.xpbd_substeps().validate()?;
        self.dissipation().validate()
    }

    /// The dissipation of the dissipative solvers.
    pub fn dissipation(&self) -> Dissipation {
        Dissipation {
            rayleigh: self.damping,
            form: self.rayleigh_form,
            drag: self.drag,
        }
    }

    /// The first iterate set, or `own`.
    pub fn first_iterate_or(&self, own: FirstIterate) -> FirstIterate {
        self.first_iterate.unwrap_or(own)
    }

    /// The parameters of VBD.
    pub fn vbd(&self) -> VbdParams {
        let own = VbdParams::default();
        VbdParams {
            first_iterate: self.first_iterate_or(own.first_iterate),
            hessian: self.hessian,
        }
    }

    /// The parameters of XPBD with substeps (one iteration per substep).
    pub fn xpbd_substeps(&self) -> XpbdSubstepsParams {
        XpbdSubstepsParams {
            constraint_damping: self.constraint_damping,
            sweep: self.sweep,
            ..XpbdSubstepsParams::default()
        }
    }

    /// The parameters of L-BFGS (its line search at the defaults).
    pub fn lbfgs(&self) -> LbfgsParams {
        LbfgsParams {
            window: self.history,
            ..LbfgsParams::default()
        }
    }

    /// The parameters of Chebyshev acceleration of `base`.
    pub fn chebyshev(&self, base: Base) -> ChebyshevParams {
        let own = ChebyshevParams::default();
        ChebyshevParams {
            base,
            spectral_radius: self.spectral_radius,
            rho_rule: self.rho_rule,
            gamma: self.gamma,
            warmup: self.warmup,
            first_iterate: self.first_iterate_or(own.first_iterate),
        }
    }

    /// The parameters of Anderson acceleration of `base`.
    pub fn anderson(&self, base: Base) -> AndersonParams {
        let own = AndersonParams::default();
        AndersonParams {
            base,
            window: self.window,
            safeguard: self.safeguard,
            first_iterate: self.first_iterate_or(own.first_iterate),
        }
    }
}

/// The largest L-BFGS window the command line takes (Liu 2017 keeps 5 pairs).
pub const MAX_HISTORY: usize = 100;

/// What rk45's tolerance is relative to.
const TOLERANCE_UNIT: &str = "m and m/s, relative to 1 + |component|";

/// `value` as a count: a whole number at least `min`.
fn require_integer(field: &str, value: f64, min: usize) -> Result<usize> {
    if value.is_finite() && value.fract() == 0.0 && value >= min as f64 && value <= u32::MAX as f64
    {
        Ok(value as usize)
    } else {
        Err(Error::invalid(
            field,
            shown(value),
            &format!("an integer >= {min}"),
        ))
    }
}

/// `value` as a count from `min` to `max`.
fn require_count_within(field: &str, value: f64, min: usize, max: usize) -> Result<usize> {
    if value.is_finite() && value.fract() == 0.0 && (min as f64..=max as f64).contains(&value) {
        Ok(value as usize)
    } else {
        Err(Error::invalid(
            field,
            shown(value),
            &format!("an integer from {min} to {max}"),
        ))
    }
}

impl Default for SolverParams {
    fn default() -> Self {
        let chebyshev = ChebyshevParams::default();
        Self {
            stiffness_factor: 1.0,
            tolerance: 1e-6,
            spectral_radius: chebyshev.spectral_radius,
            gamma: chebyshev.gamma,
            warmup: chebyshev.warmup,
            window: AndersonParams::default().window,
            damping: RayleighDamping::NONE,
            history: LbfgsParams::default().window,
            first_iterate: None,
            rho_rule: chebyshev.rho_rule,
            safeguard: AndersonParams::default().safeguard,
            hessian: VbdParams::default().hessian,
            constraint_damping: XpbdSubstepsParams::default().constraint_damping,
            sweep: XpbdSubstepsParams::default().sweep,
            adaptive_attempts: None,
            integrator: OptimizationIntegrator::default(),
            rayleigh_form: RayleighForm::default(),
            drag: PowerLawDrag::NONE,
        }
    }
}

/// A solver with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSpec {
    pub id: SolverId,
    /// Iterations per step (see [`SolverInfo::iteration`]); 1 for a solver without iterations.
    /// The cap of a step in the tolerance mode.
    pub iterations: usize,
    /// When a step stops iterating: at `iterations` (the thesis's mode) or at a tolerance.
    pub stopping: Stopping,
    pub params: SolverParams,
}

impl SolverSpec {
    /// `id` with `iterations` per step and default options.
    pub fn new(id: SolverId, iterations: usize) -> Self {
        Self {
            id,
            iterations,
            stopping: Stopping::Count,
            params: SolverParams::default(),
        }
    }

    /// This solver stopping each step at `tolerance` m, `iterations` becoming the cap.
    pub fn to_tolerance(self, tolerance: f64) -> Result<Self> {
        Ok(Self {
            stopping: Stopping::tolerance(tolerance)?,
            ..self
        })
    }

    /// The step this solver's iteration converges to, solved to round-off: the Backward Euler
    /// step of the incremental potential (Eq. 20), with the solver's Rayleigh damping for the
    /// damped solvers; the oracle of the convergence curves. (The XPBD family and PBD converge
    /// elsewhere; their gap to it is what they miss it by.)
    pub fn converged_step(
        &self,
        system: &MassSpringSystem,
        state: &State,
        dt: f64,
    ) -> Result<State> {
        let damping = if matches!(
            self.id,
            SolverId::DampedBackwardEuler | SolverId::DampedAdmm
        ) {
            self.params.damping
        } else {
            RayleighDamping::NONE
        };
        damped_converged_step(system, state, dt, damping, ConvergedStepOptions::default())
    }

    /// This solver with every parameter it would estimate at build time on `system` and `dt`
    /// independently of its iteration count estimated once now (Chebyshev's spectral radius by
    /// the asymptotic rate), so that building it many times (one fresh solver per iteration
    /// count) does not repeat the estimate; the solver it builds is the same. Wang's
    /// gradient-ratio rule depends on the count and is left to each build.
    pub fn with_estimates(&self, system: &MassSpringSystem, dt: f64) -> Result<SolverSpec> {
        let mut spec = *self;
        // Under another integrator each stage step has its own rho, found by the solver.
        if matches!(self.id, SolverId::ChebyshevLiu | SolverId::ChebyshevAdmm)
            && self.params.integrator == OptimizationIntegrator::BackwardEuler
            && self.params.spectral_radius.is_none()
            && self.params.rho_rule == RhoRule::AsymptoticRate
        {
            let params = self.params.chebyshev(accelerated_base(self.id));
            spec.params.spectral_radius =
                Some(spectral_radius(system, dt, self.iterations, &params)?);
        }
        Ok(spec)
    }

    /// An integrator other than Backward Euler needs a minimizing solver (one with the option).
    fn check_integrator(&self) -> Result<()> {
        let takes = self
            .id
            .info()
            .options
            .iter()
            .any(|o| o.name == "integrator");
        if takes || self.params.integrator == OptimizationIntegrator::BackwardEuler {
            return Ok(());
        }
        Err(Error::invalid(
            "integrator",
            self.params.integrator,
            &format!(
                "not given: {} is not a minimizing solver (it integrates by its own scheme)",
                self.id
            ),
        ))
    }

    /// The minimizing solver alone, without its integrator, stopping as `stopping` says: the
    /// solver of stage problems ([`MinimizingSolver::solve`]); an error for a solver that is
    /// not one ([`SolverId::is_minimizing`]).
    pub fn build_stage_solver(
        &self,
        system: &MassSpringSystem,
        dt: f64,
    ) -> Result<Box<dyn MinimizingSolver + Send>> {
        stage_solver(system, dt, self)
    }

    /// The solver on a mass-spring system with time step `dt`. The tutorial's integrators run
    /// it as a particle system with no other force.
    pub fn build(&self, system: &MassSpringSystem, dt: f64) -> Result<Box<dyn TimeStepper>> {
        self.check_integrator()?;
        let mut solver: Box<dyn TimeStepper> = match self.id.info().builder {
            Builder::Springs(build) => build(system, dt, self)?,
            Builder::Particles(build) => {
                build(ParticleSystem::from_system(system.clone()), dt, self)?
            }
        };
        solver.set_stopping(self.stopping)?;
        Ok(solver)
    }

    /// The solver on a mass-spring system, for a worker thread: the solvers of springs and
    /// gravity only (not the tutorial's integrators, whose forces are not `Send`).
    pub fn build_send(
        &self,
        system: &MassSpringSystem,
        dt: f64,
    ) -> Result<Box<dyn TimeStepper + Send>> {
        self.check_integrator()?;
        match self.id.info().builder {
            Builder::Springs(build) => {
                let mut solver = build(system, dt, self)?;
                solver.set_stopping(self.stopping)?;
                Ok(solver)
            }
            Builder::Particles(_) => Err(Error::invalid(
                "solver",
                self.id,
                "a solver of springs and gravity (not a tutorial integrator) on a worker thread",
            )),
        }
    }

    /// The solver on the tutorial's particle system (drag, spring damping, ground): the
    /// tutorial's integrators only.
    pub fn build_particles(
        &self,
        particles: ParticleSystem,
        dt: f64,
    ) -> Result<Box<dyn TimeStepper>> {
        match self.id.info().builder {
            Builder::Particles(build) => {
                let mut solver = build(particles, dt, self)?;
                solver.set_stopping(self.stopping)?;
                Ok(solver)
            }
            Builder::Springs(_) => Err(Error::invalid(
                "solver",
                self.id,
                "explicit_euler, symplectic_euler, rk4 or rk45 on a particle system",
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_identifier_reads_back_and_is_unique() {
        for id in SolverId::ALL {
            assert_eq!(SolverId::from_id(id.id()).unwrap(), id);
            assert_eq!(
                SolverId::ALL.iter().filter(|s| s.id() == id.id()).count(),
                1
            );
        }
        assert_eq!(
            SolverId::from_id("explicit-euler").unwrap(),
            SolverId::ExplicitEuler
        );
        let err = SolverId::from_id("newton").unwrap_err().to_string();
        assert!(err.contains("solver") && err.contains("admm_pd"), "{err}");
    }

    #[test]
    fn every_display_name_is_unique_and_not_a_code_id() {
        for id in SolverId::ALL {
            let name = id.display_name();
            let same = SolverId::ALL.iter().filter(|s| s.display_name() == name);
            assert_eq!(same.count(), 1, "{name}");
            assert!(!name.contains('_'), "{name} reads as a code id");
        }
    }

    #[test]
    fn the_serde_name_is_the_identifier() {
        for id in SolverId::ALL {
            let json = serde_json::to_string(&id).unwrap();
            assert_eq!(json, format!("\"{}\"", id.id()));
        }
    }

    #[test]
    fn every_solver_builds_on_the_thesis_rope() {
        let system = crate::model::scene::thesis_rope(1e3).unwrap();
        for id in SolverId::ALL {
            let solver = SolverSpec::new(id, 2).build(&system, 1e-3).unwrap();
            assert!(!solver.name().is_empty(), "{id}");
        }
    }
}

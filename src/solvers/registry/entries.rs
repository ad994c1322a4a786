//! The registry's entries: what each solver is (names, source, what its iterations mean, its
//! options) and how it is built, one entry per [`SolverId`] (`SolverId::info`).

use super::{stage_solver, Builder, Family, OptionInfo, SolverId, SolverInfo, SolverSpec};
use crate::error::Result;
use crate::integrators::optimization_integrator::Integrated;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::MassSpringSystem;
use crate::particles::adaptive::AdaptiveStepper;
use crate::particles::integrators::ParticleStepper;
use crate::solvers::local_global::Base;
use crate::solvers::pbd::Pbd;
use crate::solvers::xpbd::Xpbd;
use crate::solvers::xpbd_substeps::XpbdSubsteps;

impl SolverId {
    /// The registry: every solver's entry.
    pub fn info(self) -> SolverInfo {
        match self {
            SolverId::BackwardEuler => SolverInfo {
                id: "backward_euler",
                display_name: "Newton",
                summary: "Backward Euler with Newton-Raphson, the thesis's reference",
                source: "thesis §2.1, Eqs 1-12",
                file: "src/solvers/backward_euler.rs",
                family: Family::Thesis,
                iteration: Some("Newton iteration"),
                options: &[
                    FIRST_ITERATE_PREVIOUS,
                    OptionInfo {
                        name: "hessian",
                        help: "Newton's Hessian: exact (Eq. (4) as printed; a step whose matrix \
                               is not positive definite fails) or projected (rebuilt there with \
                               each spring's transverse term clamped at 0) [default: exact]",
                    },
                    INTEGRATOR,
                ],
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
                display_name: "Newton damped",
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
                        help: "Macklin 2019's constraint damping beta (Eq. 8), from 0 to 1e9, in \
                               N·s/m [default: 0]",
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
    help: "power-law drag coefficient c of D = c |v|^(p+1)/(p+1), from 0 to 1e9, in \
           N·(s/m)^p [default: 0]",
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

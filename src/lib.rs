//! # mass-spring-solvers
//!
//! A re-implementation and verification of the master's thesis *Solvers de Elasticidad y
//! Restricciones en Simulación* (C. Peñalva Carbonell, URJC 2020): Backward Euler with
//! Newton-Raphson as ground truth (§2.1, Eqs 1-12), XPBD (§2.2.1, Algorithm 2), Liu 2013's
//! fast mass-spring solver (§2.3.1, Algorithm 3) and ADMM ⊇ Projective Dynamics (§2.3.2,
//! Algorithm 4) on a 10-node catenary rope, with fixed nodes imposed by Eqs 43-47; plus an
//! analytic catenary that checks the reference.
//!
//! Every function that implements a numbered equation of the thesis starts its documentation
//! with the tag `Eq. (N)`; the report's traceability table is built from these tags.

pub mod admm;
pub mod anderson;
pub mod backward_euler;
pub mod batch;
pub mod benchmark;
pub mod beyond;
pub mod boundary;
pub mod budget;
pub mod catenary;
pub mod chebyshev;
pub mod converged_stage;
pub mod damped_admm;
pub mod damping;
pub mod dissipation;
pub mod error;
pub mod experiments;
pub mod fast_mass_spring;
pub mod first_iterate;
pub mod forensics;
pub mod integrator_study;
pub mod lanes;
pub mod linear;
pub mod local_global;
pub mod metrics;
pub mod optimization_integrator;
pub mod output_file;
pub mod particles;
pub mod paths;
pub mod pbd;
pub mod projective;
pub mod quasi_newton;
pub mod registry;
pub mod report;
pub mod scene;
pub mod scene_file;
pub mod sheet_equilibrium;
pub mod solver;
pub mod spring;
pub mod stopping;
pub mod system;
pub mod vbd;
pub mod work_precision;
pub mod xpbd;
pub mod xpbd_substeps;

pub use error::{Error, Result};
pub use solver::{simulate, Run, RunOptions, TimeStepper};
pub use system::{MassSpringSystem, Node, Spring, State, Vec3};

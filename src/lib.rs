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
//!
//! ## Layers
//!
//! The folders are the architecture; each imports only from the layers above it in this list
//! (the test `tests/layers.rs` fails on an import that goes the other way or closes a circle):
//!
//! 1. [`platform`]: what the crate needs from the machine (paths, output files, memory);
//! 2. [`model`]: the mass-spring system, springs, scenes, fixed nodes, linear algebra, the exact
//!    references (catenary, the sheet's equilibrium) and the measurements of §4.2;
//! 3. [`integrators`]: the time stepper interface and its run loop, the stopping rule, the
//!    optimization integrators' stage problems, dissipation;
//! 4. [`particles`]: the tutorial's particle system (seed 004), its forces and explicit integrators;
//! 5. [`solvers`]: the thesis's solvers and the newer ones, the registry, the cost of a run;
//! 6. [`studies`]: the thesis's experiments and their forensics, the chapters beyond the thesis,
//!    the benchmark.
//!
//! [`error`] is shared by every layer. The report (Markdown, tables, figures, publishing) is the
//! workspace's other crate, `mass-spring-report` in `presentation/`, which depends on this one.

pub mod error;
pub mod integrators;
pub mod model;
pub mod particles;
pub mod platform;
pub mod solvers;
pub mod studies;

pub use error::{Error, Result};
pub use integrators::time_stepper::{simulate, Run, RunOptions, TimeStepper};
pub use model::system::{MassSpringSystem, Node, Spring, State, Vec3};

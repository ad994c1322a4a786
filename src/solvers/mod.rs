//! The solvers: the thesis's (Backward Euler with Newton, PBD, XPBD, Liu 2013, ADMM ⊇ PD) and the
//! newer ones beyond it, one module per method, with the registry that names them and the cost
//! estimate of a run.

pub mod admm;
pub mod anderson;
pub mod backward_euler;
pub mod batch;
pub mod budget;
pub mod chebyshev;
pub mod converged_stage;
pub mod damped_admm;
pub mod fast_mass_spring;
pub mod incidence;
pub mod local_global;
pub mod pbd;
pub mod projective;
pub mod quasi_newton;
pub mod registry;
pub mod vbd;
pub mod xpbd;
pub mod xpbd_substeps;

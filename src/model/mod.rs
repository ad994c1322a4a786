//! The model (thesis §2.1, §3.1-3.2): the mass-spring system, its springs, the scenes, fixed nodes,
//! the linear algebra, and the exact references that check the solvers (the catenary, the sheet's
//! equilibrium), with the measurements of §4.2.

pub mod boundary;
pub mod catenary;
pub mod continuum;
pub mod lanes;
pub mod linear;
pub mod metrics;
pub mod projected_newton;
pub mod scene;
pub mod sheet_equilibrium;
pub mod spring;
pub mod system;

/// The crate's 3D vector: the thesis writes its equations in 3D, the rope stays in its plane.
pub type Vec3 = nalgebra::Vector3<f64>;

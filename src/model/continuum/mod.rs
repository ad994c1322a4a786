//! The continuum one dimension up (`docs/fem-scenes.md`, the specification; the papers and
//! reference code in `docs/papers.md`, last section): linear finite elements (tetrahedra,
//! triangles in the plane, membrane triangles in 3D), five hyperelastic energies, the scenes
//! "beam", "membrane", "cook" and "patch", and Newton's static equilibrium as their ground
//! truth.
//!
//! - [`lame`]: the one conversion from (E, ν) to the Lamé parameters;
//! - [`svd`]: the rotation-variant SVD and polar decomposition, and the rotation's derivative;
//! - [`hyperelastic`]: what an energy provides (Ψ, P, ∂P/∂F, its clamped form) and the
//!   deformation gradient it is evaluated at;
//! - [`energy`]: the five energies (Sifakis and Barbič 2012; Bouaziz et al. 2014; Liu et al.
//!   2017; Smith, de Goes and Kim 2018);
//! - [`element`]: the element kernels (D_m, F, nodal forces, element Hessian);
//! - [`system`]: a continuum system (nodes, elements with their materials, loads), its energy,
//!   forces and sparse Hessian;
//! - [`statics`]: the projected Newton solver of static equilibrium;
//! - [`scenes`]: the meshes of fem-scenes.md;
//! - [`scene_file`]: a continuum scene as a TOML file, every field checked.

pub mod element;
pub mod energy;
pub mod hyperelastic;
pub mod lame;
pub mod scene_file;
pub mod scenes;
pub mod statics;
pub mod svd;
pub mod system;

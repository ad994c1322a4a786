//! The continuum chapter's science (`docs/fem-scenes.md`; the thesis's §5 future work, "FEM,
//! por ejemplo"): numbers computed from the model layer's scenes and Newton's statics, for the
//! report to present and the tests to recompute.
//!
//! - [`statics`]: the energies side by side on the soft beam and the membrane, Cook's
//!   convergence, the stiff beam against beam theory and the verification checks, at the
//!   report's size or at the tests' smaller one ([`ChapterSize`]).
//!
//! The dynamics (the beam's lowest bending frequency, its kinetic-energy peaks under each
//! integrator, energy and angular momentum on the free spinning beam) belong beside
//! [`statics`], in a module of their own, once the continuum runs under the integrators.

pub mod statics;

pub use statics::{ChapterSize, ContinuumStatics};

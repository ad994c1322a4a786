//! The continuum chapter's science (`docs/fem-scenes.md`; the thesis's §5 future work, "FEM,
//! por ejemplo"): numbers computed from the model layer's scenes, Newton's statics and the
//! optimization integrators, for the report to present and the tests to recompute.
//!
//! - [`statics`]: the energies side by side on the soft beam and the membrane, Cook's
//!   convergence, the stiff beam against beam theory and the verification checks, at the
//!   report's size or at the tests' smaller one ([`ChapterSize`]).
//! - [`dynamics`]: the released beam under each optimization integrator, the energy and
//!   angular momentum of its runs, and its lowest bending frequency against beam theory.

pub mod dynamics;
pub mod statics;

pub use statics::{ChapterSize, ContinuumStatics};

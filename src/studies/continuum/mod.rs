//! The continuum's studies (issue 50, `docs/fem-scenes.md`): what the report's continuum
//! chapter and the tests compute, as functions returning numbers.
//!
//! - [`dynamics`]: the released beam under each optimization integrator, the energy and
//!   angular momentum of its runs, and its lowest bending frequency against beam theory.

pub mod dynamics;

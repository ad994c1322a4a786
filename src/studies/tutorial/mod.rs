//! The tutorial's numerical studies (the report's tutorial chapter), each against a closed form or a stated
//! bound: convergence orders, stability limits, forces, collisions and the adaptive integrator.
//! Every function runs the crate's own integrators; nothing here is a published number.
//!
//! [`accuracy`] (the test oscillator, convergence orders, stability, energy), [`forces`] and
//! [`contact`] (collisions, the pendulum, the cloth, the adaptive integrator): the report's
//! tutorial chapter shows them.

pub mod accuracy;
pub mod contact;
pub mod forces;

pub use accuracy::*;
pub use contact::*;
pub use forces::*;

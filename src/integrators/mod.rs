//! Time integration apart from the solver (thesis §2.1, §4.2; issue "Optimization integrators"):
//! the time stepper interface and the run loop that measures it, when an iterative step stops, the
//! optimization integrators' stage problems, dissipation and damping, and where a step's iteration
//! starts.

pub mod continuum;
pub mod damping;
pub mod dissipation;
pub mod first_iterate;
pub mod optimization_integrator;
pub mod prediction;
pub mod stopping;
pub mod time_stepper;

//! The studies built from the solvers: the thesis's 56 experiments and their forensic reproduction,
//! the chapters beyond the thesis, and the benchmark.

pub mod benchmark;
pub mod beyond;
pub mod continuum;
pub mod experiments;
pub mod forensics;
pub mod integrator_study;
pub mod round_off;
pub mod tutorial;
pub mod work_precision;

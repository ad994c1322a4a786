//! Every test that needs the full result set (the 56 faithful experiments of
//! [`experiments::faithful_results`], the forensic configurations of
//! [`forensics::forensic_results`] and the benchmark on the rope), in one test binary so that
//! the set is computed once per `make test` rather than once per binary.
//!
//! [`experiments::faithful_results`]: mass_spring_solvers::studies::experiments::faithful_results
//! [`forensics::forensic_results`]: mass_spring_solvers::studies::forensics::forensic_results

#[path = "../asserted/mod.rs"]
mod asserted;
mod benchmark;
mod continuum;
mod evidence;
mod forensics;
mod lock;
mod reference;
mod report;
mod round_off;
mod tables_liu_admm;
mod tables_xpbd;

//! The solver registry: one identifier per solver, with its parameters, used by the library's
//! experiments, `mss`, the report and the benches.
//!
//! [`SolverId`] names a solver; [`SolverId::info`] is the list of every solver, one entry each
//! (its names, its source, what its iterations mean, its options and how it is built), so
//! adding a solver is one variant and one entry there. [`SolverSpec`] is a solver with its
//! parameters: the iteration count and the options of [`SolverParams`].
//!
//! What the registry does not hold, on purpose: the forensic readings of the thesis's open
//! points ([`crate::studies::experiments::SolverChoice`], which builds departures from the printed
//! algorithms for the forensic chapter only) and the stopping rule and recording of a run
//! ([`crate::integrators::time_stepper::RunOptions`]), which belong to the run, not to the solver.

use crate::error::{Error, Result};
use crate::integrators::damping::RayleighDamping;
use crate::integrators::first_iterate::FirstIterate;
use crate::integrators::optimization_integrator::{MinimizingSolver, OptimizationIntegrator};
use crate::integrators::stopping::Stopping;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State};
use crate::particles::integrators::Integrator;
use crate::particles::ParticleSystem;
use crate::solvers::admm::AdmmPd;
use crate::solvers::anderson::Anderson;
use crate::solvers::backward_euler::{BackwardEuler, ConvergedStepOptions};
use crate::solvers::chebyshev::{spectral_radius, Chebyshev, RhoRule};
use crate::solvers::converged_stage::damped_converged_step;
use crate::solvers::damped_admm::DampedAdmm;
use crate::solvers::fast_mass_spring::FastMassSpring;
use crate::solvers::local_global::Base;
use crate::solvers::quasi_newton::Lbfgs;
use crate::solvers::vbd::Vbd;
use serde::{Deserialize, Serialize};

mod entries;
mod params;
pub use params::{SolverParams, MAX_HISTORY};

/// One identifier per solver: the thesis's (§2), the tutorial's integrators and the newer
/// solvers of the thesis's future work (§5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverId {
    BackwardEuler,
    Pbd,
    Xpbd,
    FastMassSpring,
    AdmmPd,
    ChebyshevLiu,
    ChebyshevAdmm,
    AndersonLiu,
    AndersonAdmm,
    DampedBackwardEuler,
    DampedAdmm,
    XpbdSubsteps,
    Lbfgs,
    Vbd,
    ExplicitEuler,
    SymplecticEuler,
    Rk4,
    Rk45,
}

/// Where a solver comes from, which decides where the report shows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// A solver of the thesis (§2).
    Thesis,
    /// One of the tutorial's integrators (or the adaptive pair beyond it).
    Tutorial,
    /// A solver after the thesis, from its future work (§5).
    Beyond,
}

/// What a solver is built from: a mass-spring system (springs and gravity only, the thesis's
/// model) or the tutorial's particle system (with drag, spring damping and a ground).
#[derive(Clone, Copy)]
pub enum Builder {
    Springs(fn(&MassSpringSystem, f64, &SolverSpec) -> Result<Box<dyn TimeStepper + Send>>),
    Particles(fn(ParticleSystem, f64, &SolverSpec) -> Result<Box<dyn TimeStepper>>),
}

/// A solver's option beyond the time step and the iteration count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OptionInfo {
    /// The name in [`SolverParams`] and, with dashes, on the command line.
    pub name: &'static str,
    /// What it is, its unit and its allowed range.
    pub help: &'static str,
}

/// A registry entry.
#[derive(Clone, Copy)]
pub struct SolverInfo {
    /// The identifier in CSV files and on the command line.
    pub id: &'static str,
    /// The one name the report gives the solver, in every table, legend and sentence: the
    /// abbreviation of thesis Table 8 for the thesis's solvers, a short readable name for the
    /// others (an accelerated solver names its base by that base's display name).
    pub display_name: &'static str,
    /// A one-line description.
    pub summary: &'static str,
    /// The section, algorithm or paper it implements.
    pub source: &'static str,
    /// The module that implements it.
    pub file: &'static str,
    pub family: Family,
    /// What one iteration is (Newton iteration, sweep, ...), or `None` for a solver without
    /// iterations.
    pub iteration: Option<&'static str>,
    pub options: &'static [OptionInfo],
    /// The time of one iteration (a step, for a solver without iterations) on the thesis rope
    /// relative to one of Liu 2013's, for scheduling only (`make bench`: Liu 117 ns, ADMM
    /// 142 ns, XPBD 162 ns per iteration, Backward Euler 5.29 µs per step of 5 Newton
    /// iterations; the newer solvers as their engineers measured them under load).
    pub relative_cost: f64,
    /// The solver whose iteration this one accelerates (same fixed point, same cost per
    /// iteration up to the acceleration's own work).
    pub accelerates: Option<SolverId>,
    pub builder: Builder,
}

impl std::fmt::Debug for SolverInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SolverInfo").field("id", &self.id).finish()
    }
}

impl SolverId {
    /// Every solver, in the order `mss --list-solvers` prints them.
    pub const ALL: [SolverId; 18] = [
        SolverId::BackwardEuler,
        SolverId::Pbd,
        SolverId::Xpbd,
        SolverId::FastMassSpring,
        SolverId::AdmmPd,
        SolverId::ChebyshevLiu,
        SolverId::ChebyshevAdmm,
        SolverId::AndersonLiu,
        SolverId::AndersonAdmm,
        SolverId::DampedBackwardEuler,
        SolverId::DampedAdmm,
        SolverId::XpbdSubsteps,
        SolverId::Lbfgs,
        SolverId::Vbd,
        SolverId::ExplicitEuler,
        SolverId::SymplecticEuler,
        SolverId::Rk4,
        SolverId::Rk45,
    ];

    /// The four solvers of the thesis's tables, in table order.
    pub const THESIS_TABLES: [SolverId; 4] = [
        SolverId::BackwardEuler,
        SolverId::Xpbd,
        SolverId::FastMassSpring,
        SolverId::AdmmPd,
    ];

    /// The identifier used in CSV files and on the command line.
    pub fn id(self) -> &'static str {
        self.info().id
    }

    /// The one name the report gives the solver ([`SolverInfo::display_name`]).
    pub fn display_name(self) -> &'static str {
        self.info().display_name
    }

    /// Parses an identifier of [`SolverId::id`] (dashes read as underscores).
    pub fn from_id(id: &str) -> Result<Self> {
        let normalised = id.replace('-', "_");
        Self::ALL
            .into_iter()
            .find(|s| s.id() == normalised)
            .ok_or_else(|| {
                let ids: Vec<&str> = Self::ALL.iter().map(|s| s.id()).collect();
                Error::invalid("solver", id, &format!("one of {}", ids.join(", ")))
            })
    }

    /// Whether its steps can stop at a tolerance ([`crate::integrators::stopping`]): every solver whose
    /// steps iterate toward the step's solution, so not the tutorial's integrators, nor XPBD's
    /// substeps, whose count is of substeps of the motion.
    pub fn stops_at_tolerance(self) -> bool {
        self.info().iteration.is_some() && self != SolverId::XpbdSubsteps
    }

    /// Whether it minimises thesis Eq 20's stage problems, and so runs under every
    /// optimization integrator (the option `integrator`).
    pub fn is_minimizing(self) -> bool {
        self.info().options.iter().any(|o| o.name == "integrator")
    }

    /// The tutorial's integrator this solver is, if it is one.
    pub fn integrator(self) -> Option<Integrator> {
        match self {
            SolverId::ExplicitEuler => Some(Integrator::ExplicitEuler),
            SolverId::SymplecticEuler => Some(Integrator::SymplecticEuler),
            SolverId::Rk4 => Some(Integrator::Rk4),
            _ => None,
        }
    }
}

impl std::fmt::Display for SolverId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id())
    }
}

impl std::str::FromStr for SolverId {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        Self::from_id(s)
    }
}

/// A solver with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSpec {
    pub id: SolverId,
    /// Iterations per step (see [`SolverInfo::iteration`]); 1 for a solver without iterations.
    /// The cap of a step in the tolerance mode.
    pub iterations: usize,
    /// When a step stops iterating: at `iterations` (the thesis's mode) or at a tolerance.
    pub stopping: Stopping,
    pub params: SolverParams,
}

impl SolverSpec {
    /// `id` with `iterations` per step and default options.
    pub fn new(id: SolverId, iterations: usize) -> Self {
        Self {
            id,
            iterations,
            stopping: Stopping::Count,
            params: SolverParams::default(),
        }
    }

    /// This solver stopping each step at `tolerance` m, `iterations` becoming the cap.
    pub fn to_tolerance(self, tolerance: f64) -> Result<Self> {
        Ok(Self {
            stopping: Stopping::tolerance(tolerance)?,
            ..self
        })
    }

    /// The step this solver's iteration converges to, solved to round-off: the Backward Euler
    /// step of the incremental potential (Eq. 20), with the solver's Rayleigh damping for the
    /// damped solvers; the oracle of the convergence curves. (The XPBD family and PBD converge
    /// elsewhere; their gap to it is what they miss it by.)
    pub fn converged_step(
        &self,
        system: &MassSpringSystem,
        state: &State,
        dt: f64,
    ) -> Result<State> {
        let damping = if matches!(
            self.id,
            SolverId::DampedBackwardEuler | SolverId::DampedAdmm
        ) {
            self.params.damping
        } else {
            RayleighDamping::NONE
        };
        damped_converged_step(system, state, dt, damping, ConvergedStepOptions::default())
    }

    /// This solver with every parameter it would estimate at build time on `system` and `dt`
    /// independently of its iteration count estimated once now (Chebyshev's spectral radius by
    /// the asymptotic rate), so that building it many times (one fresh solver per iteration
    /// count) does not repeat the estimate; the solver it builds is the same. Wang's
    /// gradient-ratio rule depends on the count and is left to each build.
    pub fn with_estimates(&self, system: &MassSpringSystem, dt: f64) -> Result<SolverSpec> {
        let mut spec = *self;
        // Under another integrator each stage step has its own rho, found by the solver.
        if matches!(self.id, SolverId::ChebyshevLiu | SolverId::ChebyshevAdmm)
            && self.params.integrator == OptimizationIntegrator::BackwardEuler
            && self.params.spectral_radius.is_none()
            && self.params.rho_rule == RhoRule::AsymptoticRate
        {
            let params = self.params.chebyshev(accelerated_base(self.id));
            spec.params.spectral_radius =
                Some(spectral_radius(system, dt, self.iterations, &params)?);
        }
        Ok(spec)
    }

    /// An integrator other than Backward Euler needs a minimizing solver (one with the option).
    fn check_integrator(&self) -> Result<()> {
        let takes = self
            .id
            .info()
            .options
            .iter()
            .any(|o| o.name == "integrator");
        if takes || self.params.integrator == OptimizationIntegrator::BackwardEuler {
            return Ok(());
        }
        Err(Error::invalid(
            "integrator",
            self.params.integrator,
            &format!(
                "not given: {} is not a minimizing solver (it integrates by its own scheme)",
                self.id
            ),
        ))
    }

    /// The minimizing solver alone, without its integrator, stopping as `stopping` says: the
    /// solver of stage problems ([`MinimizingSolver::solve`]); an error for a solver that is
    /// not one ([`SolverId::is_minimizing`]).
    pub fn build_stage_solver(
        &self,
        system: &MassSpringSystem,
        dt: f64,
    ) -> Result<Box<dyn MinimizingSolver + Send>> {
        stage_solver(system, dt, self)
    }

    /// The solver on a mass-spring system with time step `dt`. The tutorial's integrators run
    /// it as a particle system with no other force.
    pub fn build(&self, system: &MassSpringSystem, dt: f64) -> Result<Box<dyn TimeStepper>> {
        self.check_integrator()?;
        let mut solver: Box<dyn TimeStepper> = match self.id.info().builder {
            Builder::Springs(build) => build(system, dt, self)?,
            Builder::Particles(build) => {
                build(ParticleSystem::from_system(system.clone()), dt, self)?
            }
        };
        solver.set_stopping(self.stopping)?;
        Ok(solver)
    }

    /// The solver on a mass-spring system, for a worker thread: the solvers of springs and
    /// gravity only (not the tutorial's integrators, whose forces are not `Send`).
    pub fn build_send(
        &self,
        system: &MassSpringSystem,
        dt: f64,
    ) -> Result<Box<dyn TimeStepper + Send>> {
        self.check_integrator()?;
        match self.id.info().builder {
            Builder::Springs(build) => {
                let mut solver = build(system, dt, self)?;
                solver.set_stopping(self.stopping)?;
                Ok(solver)
            }
            Builder::Particles(_) => Err(Error::invalid(
                "solver",
                self.id,
                "a solver of springs and gravity (not a tutorial integrator) on a worker thread",
            )),
        }
    }

    /// The solver on the tutorial's particle system (drag, spring damping, ground): the
    /// tutorial's integrators only.
    pub fn build_particles(
        &self,
        particles: ParticleSystem,
        dt: f64,
    ) -> Result<Box<dyn TimeStepper>> {
        match self.id.info().builder {
            Builder::Particles(build) => {
                let mut solver = build(particles, dt, self)?;
                solver.set_stopping(self.stopping)?;
                Ok(solver)
            }
            Builder::Springs(_) => Err(Error::invalid(
                "solver",
                self.id,
                "explicit_euler, symplectic_euler, rk4 or rk45 on a particle system",
            )),
        }
    }
}

/// The minimizing solver of `spec` alone, without an integrator: what solves each stage
/// problem ([`SolverSpec::build_stage_solver`]).
fn stage_solver(
    system: &MassSpringSystem,
    dt: f64,
    spec: &SolverSpec,
) -> Result<Box<dyn MinimizingSolver + Send>> {
    let params = &spec.params;
    let iterations = spec.iterations;
    let mut solver: Box<dyn MinimizingSolver + Send> = match spec.id {
        SolverId::BackwardEuler => Box::new(
            BackwardEuler::new(system, dt, iterations)?
                .with_first_iterate(params.first_iterate_or(FirstIterate::Previous))
                .with_hessian(params.hessian),
        ),
        SolverId::DampedBackwardEuler => Box::new(
            BackwardEuler::dissipative(system, dt, iterations, params.dissipation())?
                .with_first_iterate(params.first_iterate_or(FirstIterate::Previous)),
        ),
        SolverId::FastMassSpring => Box::new(
            FastMassSpring::new(system, dt, iterations)?
                .with_first_iterate(params.first_iterate_or(FirstIterate::Previous)),
        ),
        SolverId::AdmmPd => Box::new(
            AdmmPd::new(system, dt, iterations)?
                .with_first_iterate(params.first_iterate_or(FirstIterate::InertialPrediction)),
        ),
        SolverId::DampedAdmm => {
            let solver = DampedAdmm::dissipative(system, dt, iterations, params.dissipation())?;
            Box::new(match params.first_iterate {
                Some(first_iterate) => solver.with_first_iterate(first_iterate),
                None => solver,
            })
        }
        SolverId::ChebyshevLiu | SolverId::ChebyshevAdmm => Box::new(Chebyshev::new(
            system,
            dt,
            iterations,
            params.chebyshev(accelerated_base(spec.id)),
        )?),
        SolverId::AndersonLiu | SolverId::AndersonAdmm => Box::new(Anderson::new(
            system,
            dt,
            iterations,
            params.anderson(accelerated_base(spec.id)),
        )?),
        SolverId::Lbfgs => Box::new(
            Lbfgs::new(system, dt, iterations, params.lbfgs())?
                .with_first_iterate(params.first_iterate_or(FirstIterate::InertialPrediction)),
        ),
        SolverId::Vbd => Box::new(Vbd::new(system, dt, iterations, params.vbd())?),
        other => {
            return Err(Error::invalid(
                "solver",
                other,
                "a minimizing solver (one with the option integrator)",
            ))
        }
    };
    solver.set_stopping(spec.stopping)?;
    Ok(solver)
}

/// The iteration an accelerated solver accelerates, as the accelerations name it.
fn accelerated_base(id: SolverId) -> Base {
    match id.info().accelerates {
        Some(SolverId::AdmmPd) => Base::Admm,
        _ => Base::Liu,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_identifier_reads_back_and_is_unique() {
        for id in SolverId::ALL {
            assert_eq!(SolverId::from_id(id.id()).unwrap(), id);
            assert_eq!(
                SolverId::ALL.iter().filter(|s| s.id() == id.id()).count(),
                1
            );
        }
        assert_eq!(
            SolverId::from_id("explicit-euler").unwrap(),
            SolverId::ExplicitEuler
        );
        let err = SolverId::from_id("newton").unwrap_err().to_string();
        assert!(err.contains("solver") && err.contains("admm_pd"), "{err}");
    }

    #[test]
    fn every_display_name_is_unique_and_not_a_code_id() {
        for id in SolverId::ALL {
            let name = id.display_name();
            let same = SolverId::ALL.iter().filter(|s| s.display_name() == name);
            assert_eq!(same.count(), 1, "{name}");
            assert!(!name.contains('_'), "{name} reads as a code id");
        }
    }

    #[test]
    fn the_serde_name_is_the_identifier() {
        for id in SolverId::ALL {
            let json = serde_json::to_string(&id).unwrap();
            assert_eq!(json, format!("\"{}\"", id.id()));
        }
    }

    #[test]
    fn every_solver_builds_on_the_thesis_rope() {
        let system = crate::model::scene::thesis_rope(1e3).unwrap();
        for id in SolverId::ALL {
            let solver = SolverSpec::new(id, 2).build(&system, 1e-3).unwrap();
            assert!(!solver.name().is_empty(), "{id}");
        }
    }
}

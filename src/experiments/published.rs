//! The published numbers: the 56 rows of thesis Tables 1-7, transcribed in
//! `data/thesis_results.csv` and embedded at build time, so a plain clone needs nothing else.

use crate::admm::AdmmPd;
use crate::backward_euler::BackwardEuler;
use crate::error::{Error, Result};
use crate::fast_mass_spring::FastMassSpring;
use crate::solver::TimeStepper;
use crate::system::MassSpringSystem;
use crate::xpbd::Xpbd;
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// The published table, as transcribed.
pub const PUBLISHED_CSV: &str = include_str!("../../data/thesis_results.csv");

/// The solvers of the thesis's tables, named as in `thesis_results.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    BackwardEuler,
    Xpbd,
    FastMassSpring,
    AdmmPd,
}

impl SolverKind {
    /// Every kind, in table order.
    pub const ALL: [SolverKind; 4] = [
        SolverKind::BackwardEuler,
        SolverKind::Xpbd,
        SolverKind::FastMassSpring,
        SolverKind::AdmmPd,
    ];

    /// The identifier used in CSV files and on the command line.
    pub fn id(self) -> &'static str {
        match self {
            SolverKind::BackwardEuler => "backward_euler",
            SolverKind::Xpbd => "xpbd",
            SolverKind::FastMassSpring => "fast_mass_spring",
            SolverKind::AdmmPd => "admm_pd",
        }
    }

    /// The abbreviation of thesis Table 8.
    pub fn abbreviation(self) -> &'static str {
        match self {
            SolverKind::BackwardEuler => "BE",
            SolverKind::Xpbd => "XPBD",
            SolverKind::FastMassSpring => "Fast m-s",
            SolverKind::AdmmPd => "ADMM",
        }
    }

    /// Parses an identifier of [`SolverKind::id`].
    pub fn from_id(id: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|k| k.id() == id).ok_or_else(|| {
            Error::invalid(
                "solver",
                id,
                "one of backward_euler, xpbd, fast_mass_spring, admm_pd",
            )
        })
    }

    /// The solver with its faithful parameters.
    pub fn build(
        self,
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
    ) -> Result<Box<dyn TimeStepper + Send>> {
        Ok(match self {
            SolverKind::BackwardEuler => Box::new(BackwardEuler::new(system, dt, iterations)?),
            SolverKind::Xpbd => Box::new(Xpbd::new(system, dt, iterations)?),
            SolverKind::FastMassSpring => Box::new(FastMassSpring::new(system, dt, iterations)?),
            SolverKind::AdmmPd => Box::new(AdmmPd::new(system, dt, iterations)?),
        })
    }
}

/// One row of `thesis_results.csv`: an experiment and its published outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PublishedRow {
    pub table: u8,
    pub solver: SolverKind,
    pub dt_s: f64,
    pub iterations: usize,
    pub stiffness: f64,
    /// Rest-state error against the reference; empty for the reference itself.
    pub error: Option<f64>,
    pub ke_peaks: usize,
    pub half_period_s: f64,
    pub period_rel_error: Option<f64>,
}

/// The 56 published rows, in the thesis's order.
pub fn published_rows() -> &'static [PublishedRow] {
    static ROWS: OnceLock<Vec<PublishedRow>> = OnceLock::new();
    ROWS.get_or_init(|| {
        csv::Reader::from_reader(PUBLISHED_CSV.as_bytes())
            .deserialize()
            .collect::<std::result::Result<_, _>>()
            .expect("data/thesis_results.csv is embedded at build time and parses")
    })
}

/// The published reference row (Table 1) of a stiffness.
pub fn published_reference(stiffness: f64) -> &'static PublishedRow {
    published_rows()
        .iter()
        .find(|r| r.solver == SolverKind::BackwardEuler && r.stiffness == stiffness)
        .expect("Table 1 has both stiffnesses")
}

/// Whether two rows name the same experiment (table, solver, dt, iterations, stiffness).
pub fn same_experiment(a: &PublishedRow, b: &PublishedRow) -> bool {
    a.table == b.table
        && a.solver == b.solver
        && a.dt_s == b.dt_s
        && a.iterations == b.iterations
        && a.stiffness == b.stiffness
}

/// Solver iterations of the published run: duration / dt × iterations per step.
pub fn published_cost(row: &PublishedRow) -> f64 {
    row.ke_peaks as f64 * row.half_period_s / row.dt_s * row.iterations as f64
}

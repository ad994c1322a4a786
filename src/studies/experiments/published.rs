//! The published numbers: the 56 rows of thesis Tables 1-7, transcribed in
//! `data/thesis_results.csv` and embedded at build time, so a plain clone needs nothing else.

use crate::solvers::registry::SolverId;
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// The published table, as transcribed.
pub const PUBLISHED_CSV: &str = include_str!("../../../data/thesis_results.csv");

/// One row of `thesis_results.csv`: an experiment and its published outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PublishedRow {
    pub table: u8,
    pub solver: SolverId,
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
        .find(|r| r.solver == SolverId::BackwardEuler && r.stiffness == stiffness)
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

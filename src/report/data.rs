//! The machine-readable files of `report/data/`: the 56 results in the columns of
//! `thesis_results.csv`, Table 1 alone, the exact catenary, and (written by the figures) one
//! CSV per figure. Numbers are written as the shortest decimal that round-trips the `f64`.

use crate::experiments::{Measured, ResultSet, SolverKind};
use crate::report::format::{full, full_opt};
use crate::report::rest_state::Catenary;

/// The header of `results.csv` and `table1.csv`: the columns of `thesis_results.csv` (thesis
/// convention for `half_period_s`) plus the exact-convention half-period.
pub const RESULTS_HEADER: &str =
    "table,solver,dt_s,iterations,stiffness,error,ke_peaks,half_period_s,period_rel_error,half_period_exact_s";

fn row(m: &Measured) -> String {
    let p = &m.published;
    format!(
        "{},{},{},{},{},{},{},{},{},{}\n",
        p.table,
        p.solver.id(),
        full(p.dt_s),
        p.iterations,
        full(p.stiffness),
        full_opt(m.error_sum),
        m.peaks,
        full_opt(m.half_period_thesis),
        full_opt(m.period_rel_error),
        full_opt(m.half_period_exact)
    )
}

/// `results.csv`: every measured row, in the thesis's order.
pub fn results_csv(results: &ResultSet) -> String {
    let mut out = format!("{RESULTS_HEADER}\n");
    for m in &results.rows {
        out += &row(m);
    }
    out
}

/// `table1.csv`: the Backward Euler reference rows (Table 1).
pub fn table1_csv(results: &ResultSet) -> String {
    let mut out = format!("{RESULTS_HEADER}\n");
    for m in results
        .rows
        .iter()
        .filter(|m| m.published.table == 1 && m.published.solver == SolverKind::BackwardEuler)
    {
        out += &row(m);
    }
    out
}

/// `catenary.csv`: the exact static equilibrium of the discrete elastic chain of the thesis
/// rope, `stiffness,node,x,y`, for every stiffness available.
pub fn catenary_csv(catenary: &Catenary) -> Option<String> {
    let mut out = String::from("stiffness,node,x,y\n");
    let mut any = false;
    for (k, nodes) in catenary.all() {
        any = true;
        for (i, p) in nodes.iter().enumerate() {
            out += &format!("{},{i},{},{}\n", full(k), full(p.x), full(p.y));
        }
    }
    any.then_some(out)
}

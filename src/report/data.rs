//! The machine-readable files of `report/data/`: the 56 results in the columns of
//! `thesis_results.csv`, Table 1 alone, the exact catenary, the forensic reproduction (evidence
//! class per row, every named configuration's runs, the gravity-mismatch errors) and (written by
//! the figures) one CSV per figure. Numbers are written as the shortest decimal that
//! round-trips the `f64`.

use crate::experiments::{better_time_convention, Measured, PublishedRow, ResultSet};
use crate::forensics::Forensics;
use crate::registry::SolverId;
use crate::report::format::{full, full_opt};
use crate::report::rest_state::Catenary;
use crate::report::tables::half_period_deviation;

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
        .filter(|m| m.published.table == 1 && m.published.solver == SolverId::BackwardEuler)
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

/// The header of `reproduction.csv`: one row per published row with its evidence class, the
/// configuration that produced our numbers and the free choices it spent.
pub const REPRODUCTION_HEADER: &str = "table,solver,dt_s,iterations,stiffness,evidence,configuration,free_choices,published_peaks,our_peaks,published_half_period_s,our_half_period_s,half_period_rel_dev,marginal,better_time_convention,published_error,our_error";

fn experiment(p: &PublishedRow) -> String {
    format!(
        "{},{},{},{},{}",
        p.table,
        p.solver.id(),
        full(p.dt_s),
        p.iterations,
        full(p.stiffness)
    )
}

/// `reproduction.csv`: the evidence class of every row run, in the thesis's order. `our_error`
/// is the sum of per-node distances (convention 7); `better_time_convention` is the T/2
/// convention of ours closer to the published value.
pub fn reproduction_csv(forensics: &Forensics) -> String {
    let mut out = format!("{REPRODUCTION_HEADER}\n");
    for e in &forensics.evidence {
        let m = &e.measured;
        let p = &m.published;
        out += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            experiment(p),
            e.evidence.id(),
            e.configuration.id(),
            csv_text(&e.free_choices),
            p.ke_peaks,
            m.peaks,
            full(p.half_period_s),
            full_opt(m.half_period_thesis),
            full_opt(half_period_deviation(m)),
            m.marginal(),
            better_time_convention(p, m.half_period_thesis, m.half_period_exact)
                .map_or("", |c| c.id()),
            full_opt(p.error),
            full_opt(m.error_sum)
        );
    }
    out
}

/// A CSV field, quoted when it holds a comma or a quote.
fn csv_text(s: &str) -> String {
    if s.contains([',', '"']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The header of `configurations.csv`: every run of a named configuration other than the
/// faithful one (`outcome` is `ran` or the error of a failed run).
pub const CONFIGURATIONS_HEADER: &str = "configuration,table,solver,dt_s,iterations,stiffness,outcome,peaks,half_period_s,half_period_rel_dev,error_l1,error_sum,last_peak_energy_j,hit_time_limit,reproduces";

/// `configurations.csv`: the runs of every named configuration, configuration by
/// configuration, rows in the thesis's order.
pub fn configurations_csv(forensics: &Forensics) -> String {
    let mut out = format!("{CONFIGURATIONS_HEADER}\n");
    for run in &forensics.runs {
        for m in &run.rows {
            out += &format!(
                "{},{},ran,{},{},{},{},{},{},{},{}\n",
                run.id.id(),
                experiment(&m.published),
                m.peaks,
                full_opt(m.half_period_thesis),
                full_opt(half_period_deviation(m)),
                full_opt(m.error_l1),
                full_opt(m.error_sum),
                full_opt(m.last_peak_energy),
                m.hit_time_limit,
                m.reproduces()
            );
        }
        for (row, error) in &run.failed {
            out += &format!(
                "{},{},{},,,,,,,,false\n",
                run.id.id(),
                experiment(row),
                csv_text(error)
            );
        }
    }
    out
}

/// The header of `gravity-mismatch.csv`: per solver row, the published error and ours in both
/// norms with the reference and solver gravities of each hypothesis.
pub const GRAVITY_HEADER: &str = "table,solver,dt_s,iterations,stiffness,configuration,published_error,l1_same_gravity,sum_same_gravity,l1_reference_9_8,sum_reference_9_8,l1_solver_9_8,sum_solver_9_8,solver_9_8_peaks,solver_9_8_half_period_s";

/// `gravity-mismatch.csv`: the gravity-mismatch hypothesis for every solver row.
pub fn gravity_csv(forensics: &Forensics) -> String {
    let mut out = format!("{GRAVITY_HEADER}\n");
    for g in &forensics.gravity.rows {
        out += &format!(
            "{},{},{},{},{},{},{},{},{},{},{}\n",
            experiment(&g.published),
            g.configuration.id(),
            full_opt(g.published.error),
            full(g.same_gravity.l1),
            full(g.same_gravity.sum),
            full(g.reference_mismatched.l1),
            full(g.reference_mismatched.sum),
            full(g.solver_mismatched.l1),
            full(g.solver_mismatched.sum),
            g.solver_mismatched_run.peaks,
            full_opt(g.solver_mismatched_run.half_period_thesis)
        );
    }
    out
}

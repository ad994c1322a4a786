//! The gravity mismatch: the rows the thesis's numbers fit better at 9.8 m/s² than at 9.81, and
//! the verdict.

use super::evidence::*;

use crate::format::{opt4, sci3, short, sig, MarkdownTable};
use crate::tables::{stiffness_label, ERROR_RATIO_RANGE};
use mass_spring_solvers::model::scene::THESIS_GRAVITY;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{Measured, ResultSet};
use mass_spring_solvers::studies::forensics::gravity::{Hypothesis, DISTINCT_ERROR_M};
use mass_spring_solvers::studies::forensics::{Forensics, MISMATCHED_GRAVITY};

/// The gravity hypotheses counted: per stiffness, the floor observations within the band
/// against our reference runs (with their distinct values) and against the exact equilibria.
pub fn gravity_counts_table(f: &Forensics) -> MarkdownTable {
    let g = &f.gravity;
    let band = format!(
        "{}-{}",
        short(ERROR_RATIO_RANGE.0),
        short(ERROR_RATIO_RANGE.1)
    );
    let ours = format!(">within {band} of the published floor, against our reference");
    let distinct = format!(">distinct values among them (to {DISTINCT_ERROR_M:e} m)");
    let exact = format!(">within {band}, against the exact equilibrium");
    let mut t = MarkdownTable::new(&[
        "hypothesis",
        ">k (N/m)",
        ">floor observations",
        ours.as_str(),
        distinct.as_str(),
        exact.as_str(),
    ]);
    for c in &g.counts {
        t.row(vec![
            c.hypothesis.label().into(),
            stiffness_label(c.stiffness),
            c.rows.to_string(),
            c.within.to_string(),
            c.distinct.to_string(),
            c.within_exact.to_string(),
        ]);
    }
    t
}

/// The hypothesis with the most floor observations within the band at stiffness `k`, against
/// our reference (`exact` false) or the exact equilibria; ties give None.
pub fn gravity_leader(f: &Forensics, k: f64, exact: bool) -> Option<Hypothesis> {
    let within = |h: Hypothesis| {
        let c = f.gravity.count(h, k);
        if exact {
            c.within_exact
        } else {
            c.within
        }
    };
    let best = Hypothesis::ALL.into_iter().map(within).max()?;
    let mut leaders = Hypothesis::ALL.into_iter().filter(|h| within(*h) == best);
    let first = leaders.next()?;
    leaders.next().is_none().then_some(first)
}

/// The conclusion of the gravity study, from the numbers.
pub fn gravity_verdict(f: &Forensics) -> String {
    let g = &f.gravity;
    let mut s = String::new();
    let mut leaders = Vec::new();
    let mut margins_shrink = false;
    for r in &g.residuals {
        let k = r.stiffness;
        let (solver, reference) = (
            g.count(Hypothesis::SolverMismatched, k),
            g.count(Hypothesis::ReferenceMismatched, k),
        );
        s += &format!(
            "At k = {}, our reference stopped {} m (sum of distances) from the exact 9.81 m/s² equilibrium, {} % \
             of the {} m shift between the 9.81 and 9.8 equilibria. Of the {} floor observations, the solvers \
             at 9.8 m/s² put {} within the band and the reference at 9.8 m/s² puts {}; against the exact \
             equilibria, {} and {}. ",
            stiffness_label(k),
            sig(r.residual, 3),
            sig(100.0 * r.residual / r.shift, 2),
            sig(r.shift, 3),
            solver.rows,
            solver.within,
            reference.within,
            solver.within_exact,
            reference.within_exact,
        );
        leaders.push((gravity_leader(f, k, false), gravity_leader(f, k, true)));
        let margin = |a: usize, b: usize| a as i64 - b as i64;
        margins_shrink |= margin(solver.within_exact, reference.within_exact)
            < margin(solver.within, reference.within);
    }
    let first = leaders.first().and_then(|(ours, _)| *ours);
    let one_leader = first.is_some()
        && leaders
            .iter()
            .all(|(ours, exact)| *ours == first && *exact == first);
    s += &match (one_leader, first) {
        (true, Some(h)) => format!(
            "The same hypothesis leads at both stiffnesses and against both references: {}{}. ",
            h.label(),
            if margins_shrink {
                ", though by less against the exact equilibria: part of its lead comes from where our \
                 reference stopped"
            } else {
                ""
            }
        ),
        _ => "No one hypothesis leads at both stiffnesses against both references. ".to_string(),
    };
    s += "The floors are therefore at most **consistent with** a gravity mismatch: the study was not designed \
          before its run, and a floor depends on where each reference run stopped in its residual oscillation, \
          which for the thesis's reference no published number fixes. ";
    let broken = g.broken_by_mismatch();
    s += &format!(
        "The mismatch and the reproduced rows conflict at the 0.5 % edge: with the solvers at {} m/s², {} of the {} \
         rows reproduced at {} m/s² no longer meet the rule (peaks and T/2){}; under the rule of evidence \
         (section 6.1) those rows are interpretation.",
        short(MISMATCHED_GRAVITY),
        broken.len(),
        g.rows.iter().filter(|r| r.reproduced_at_981).count(),
        short(THESIS_GRAVITY),
        if broken.is_empty() {
            String::new()
        } else {
            format!(
                ": {}",
                label_list(&broken.iter().map(|r| &r.published).collect::<Vec<_>>())
            )
        }
    );
    s
}

/// The gravity study, every solver row: the published error beside ours with both runs at
/// 9.81 m/s², with the reference at 9.8, and with the solver at 9.8 (sum of distances;
/// ours/published in brackets, ✓ within the band).
pub fn gravity_table(f: &Forensics) -> MarkdownTable {
    let g = short(MISMATCHED_GRAVITY);
    let g0 = short(THESIS_GRAVITY);
    let same = format!(">both at {g0}");
    let reference = format!(">reference at {g}");
    let solver = format!(">solver at {g}");
    let peaks = format!("solver at {g}: peaks, T/2");
    let mut t = MarkdownTable::new(&[
        "row",
        "configuration",
        &crate::tables::summed_error_header("pub."),
        same.as_str(),
        reference.as_str(),
        solver.as_str(),
        peaks.as_str(),
    ]);
    for r in &f.gravity.rows {
        let row = &r.published;
        let m = &r.solver_mismatched_run;
        let floor = if r.is_floor() { " (floor)" } else { "" };
        t.row(vec![
            row_label(row),
            r.configuration.short_label(),
            format!("{}{floor}", row.error.map_or("–".into(), sci3)),
            ratio_cell(r.same_gravity.sum, row.error),
            ratio_cell(r.reference_mismatched.sum, row.error),
            ratio_cell(r.solver_mismatched.sum, row.error),
            format!(
                "{}, {}{}",
                m.peaks,
                opt4(m.half_period_thesis),
                if m.reproduces() { " ✓" } else { " ✗" }
            ),
        ]);
    }
    t
}

/// The faithful ADMM misses by the rule of evidence ([`Forensics::reproduces`]): how many
/// published runs oscillate longer than ours (more peaks), how many stop earlier, and how many
/// meet the reproduction rule but their rest error contradicts the published one.
pub fn admm_misses_by_direction(f: &Forensics, faithful: &ResultSet) -> (usize, usize, usize) {
    let misses: Vec<&Measured> = faithful
        .rows
        .iter()
        .filter(|m| m.published.solver == SolverId::AdmmPd && !f.reproduces(m))
        .collect();
    let rest_error = misses.iter().filter(|m| m.reproduces()).count();
    let longer = misses
        .iter()
        .filter(|m| !m.reproduces() && m.published.ke_peaks > m.peaks)
        .count();
    (longer, misses.len() - longer - rest_error, rest_error)
}

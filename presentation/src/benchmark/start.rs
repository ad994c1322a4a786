//! The one start of the benchmark (issue 47, item 1), read from what ran: the measured column
//! `start_distance_m`, and the own-start variant beside it.

use super::*;
use crate::format::{sig, MarkdownTable};
use mass_spring_solvers::studies::benchmark::verdicts::{
    cheapest, Regime, Schemes, DYNAMICS_LEVELS,
};

impl BenchmarkChapter {
    /// The start every run used, from the measured column `start_distance_m`: how many of the
    /// runs that iterate started each step at the inertial prediction to the bit, and how far
    /// from it the others started.
    pub fn start_summary(&self) -> String {
        let measured: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| r.start_distance_m.is_some())
            .collect();
        let exact = measured
            .iter()
            .filter(|r| r.start_distance_m == Some(0.0))
            .count();
        let off: Vec<&Row> = measured
            .iter()
            .copied()
            .filter(|r| r.start_distance_m != Some(0.0))
            .collect();
        let names = distinct(off.iter().map(|r| display_name(&r.solver)));
        let largest = off
            .iter()
            .filter_map(|r| r.start_distance_m)
            .fold(0.0, f64::max);
        let mut out = format!(
            "each step starting from the inertial prediction y = x_n + h v_n + h² M⁻¹ f_ext \
             (measured as each run went, in the column `start_distance_m`: the first iterate of \
             {exact} of the {} runs that iterate is y to the bit",
            measured.len()
        );
        if !off.is_empty() {
            out += &format!(
                ", of the other {} ({}, whose prediction rounds as x + h(v + h g)) within {} m of it",
                off.len(),
                names.join(", "),
                sig(largest, 2)
            );
        }
        let unmeasured = self
            .rows
            .iter()
            .filter(|r| {
                r.start_distance_m.is_none() && !r.finished() && !r.first_iterate.is_empty()
            })
            .count();
        if unmeasured > 0 {
            out += &format!("; {unmeasured} runs that failed record none");
        }
        out + ")"
    }

    /// The own-start variant against the one start: per rope case, solver and level, the
    /// cheapest cost from each start under Backward Euler, and the own start's measured
    /// distance from the inertial prediction.
    pub fn own_start_table(&self) -> String {
        let mut t = MarkdownTable::new(&[
            "case",
            "solver (own start)",
            ">own start's largest distance from y (m)",
            ">10 %: from y / own",
            ">1 %: from y / own",
            ">0.1 %: from y / own",
        ]);
        for case in self.cases() {
            let own: Vec<&Row> = self
                .own_start
                .iter()
                .filter(|r| r.finished() && of_case(&r.scene, r.stiffness_n_per_m, case))
                .collect();
            if own.is_empty() {
                continue;
            }
            let one = self.dynamics(case);
            let ids = distinct(own.iter().map(|r| r.solver.as_str()));
            for id in ids {
                let mine: Vec<&Row> = own.iter().copied().filter(|r| r.solver == id).collect();
                let distance = mine
                    .iter()
                    .filter_map(|r| r.start_distance_m)
                    .fold(0.0, f64::max);
                let mut cells = vec![
                    case.label(),
                    format!("{} ({})", display_name(id), mine[0].first_iterate),
                    sig(distance, 2),
                ];
                let Ok(solver) = SolverId::from_id(id) else {
                    continue;
                };
                for &level in &DYNAMICS_LEVELS {
                    let cost = |rows: &[&Row]| {
                        cheapest(
                            rows,
                            Regime::Dynamics,
                            solver,
                            level,
                            Schemes::BackwardEuler,
                        )
                        .and_then(|r| r.flops)
                    };
                    cells.push(format!(
                        "{} / {}",
                        cost(&one).map_or("–".into(), |c| sig(c, 2)),
                        cost(&mine).map_or("–".into(), |c| sig(c, 2))
                    ));
                }
                t.row(cells);
            }
        }
        t.render()
    }
}

/// The items of `items` in the order they first come, each once.
pub(super) fn distinct<T: PartialEq>(items: impl Iterator<Item = T>) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for item in items {
        if !out.contains(&item) {
            out.push(item);
        }
    }
    out
}

/// A registry id's display name.
pub(super) fn display_name(id: &str) -> &'static str {
    SolverId::from_id(id).map_or("?", |s| s.info().display_name)
}

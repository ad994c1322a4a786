//! The benchmark's chapter (work and precision, the thesis's first line of future work, §5), in
//! this one folder: every view of [`mass_spring_solvers::studies::benchmark`]'s one result set,
//! read from its rows (the content of `data/benchmark*.csv`) and from nothing else: the
//! thesis's question (`question.rs`), the start (`start.rs`), the figures, the views of
//! sections 10-11 (`views.rs`, [`families`]), wall time ([`wall`]) and the tolerance points
//! ([`tolerance`]).

use crate::benchmark::families::of_case;
use crate::benchmark::wall::WallTiming;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::optimization_integrator::OptimizationIntegrator;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::rows::{ReferenceRow, Row, TruthRow};
use mass_spring_solvers::studies::benchmark::sweep::STABILITY_MARGIN;
use mass_spring_solvers::studies::benchmark::thesis_protocol::{self, ProtocolRow};
use mass_spring_solvers::studies::benchmark::{Benchmark, Case};

pub mod families;
mod figures;
pub mod fronts;
pub mod long;
mod question;
mod start;
pub mod tolerance;
mod views;
pub mod wall;

pub use figures::stem;
pub use fronts::{epsilon_front, work_figure, work_figure_caption, FrontRow, FRONT_EPSILON};
pub use question::{ThesisCell, ASYMPTOTIC_ERROR, ASYMPTOTIC_SLOPE, THESIS_QUOTES};
pub use views::{
    errors_below_one, jackknife, mean_with_interval, RankingCell, BOOTSTRAP_RESAMPLES,
    ROUND_OFF_SPREAD, TAU_TIE, TAU_TIE_BESIDE, VIEW_DETAIL_DT, VIEW_DTS,
};

/// The chapter's data: the benchmark's rows.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchmarkChapter {
    pub rows: Vec<Row>,
    /// The own-start variant's rows (`data/benchmark_own_start.csv`).
    pub own_start: Vec<Row>,
    pub truths: Vec<TruthRow>,
    /// The solver-error references (`data/benchmark_references.csv`).
    pub references: Vec<ReferenceRow>,
    /// Reading (a) of the thesis's question: the runs by its protocol
    /// (`data/benchmark_thesis_protocol.csv`), set from the thesis part's results
    /// ([`thesis_protocol::protocol_rows`]); empty when the chapter is computed alone.
    pub protocol: Vec<ProtocolRow>,
    /// The Table 1 reference's peak count per stiffness, for reading (a).
    pub protocol_references: Vec<(f64, usize)>,
    /// The committed long runs of `make report-long` (`report/long/`), if any.
    pub long: Vec<Row>,
    /// The committed wall-time measurement of `make timing`, if the repository has one.
    pub wall: Option<WallTiming>,
}

/// A CSV of serialisable rows, written with `csv::Writer` (its header from the fields' names).
pub fn rows_csv<T: serde::Serialize>(rows: &[T]) -> String {
    let mut writer = csv::Writer::from_writer(Vec::new());
    for row in rows {
        writer
            .serialize(row)
            .expect("a row of numbers and words serialises");
    }
    String::from_utf8(writer.into_inner().expect("writing to memory cannot fail"))
        .expect("every field is UTF-8")
}

/// The least-squares slope of $`\log_{10} e`$ against $`\log_{10}\Delta t`$ over `points`
/// (dt, error).
pub fn log_slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for &(x, y) in points {
        let (x, y) = (x.log10(), y.log10());
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    Some((n * sxy - sx * sy) / (n * sxx - sx * sx))
}

impl BenchmarkChapter {
    /// The benchmark of every case.
    pub fn compute(progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        Self::compute_cases(&Case::ALL, progress)
    }

    /// The benchmark of `cases` only (the tests run a part).
    pub fn compute_cases(cases: &[Case], progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        let benchmark = Benchmark::compute(cases, progress)?;
        Ok(Self {
            rows: benchmark.rows(),
            own_start: benchmark.own_start_rows(),
            truths: benchmark.truth_rows(),
            references: benchmark.reference_rows(),
            protocol: Vec::new(),
            protocol_references: Vec::new(),
            long: Vec::new(),
            wall: None,
        })
    }

    /// Reading (a)'s runs, from the thesis part's `results` and its `real_time` runs.
    pub fn set_protocol(
        &mut self,
        results: &mass_spring_solvers::studies::experiments::ResultSet,
        real_time: Vec<ProtocolRow>,
    ) {
        self.protocol = thesis_protocol::protocol_rows(results, real_time);
        self.protocol_references = mass_spring_solvers::model::scene::THESIS_STIFFNESSES
            .into_iter()
            .filter(|&k| {
                results
                    .rows
                    .iter()
                    .any(|m| m.published.table == 1 && m.published.stiffness == k)
            })
            .map(|k| (k, results.reference(k).peaks))
            .collect();
    }

    /// The cases the chapter holds, in [`Case::ALL`]'s order.
    pub fn cases(&self) -> Vec<Case> {
        Case::ALL
            .into_iter()
            .filter(|c| {
                self.truths
                    .iter()
                    .any(|t| of_case(&t.scene, t.stiffness_n_per_m, *c))
            })
            .collect()
    }

    /// The truth of a case.
    pub fn truth(&self, case: Case) -> Option<&TruthRow> {
        self.truths
            .iter()
            .find(|t| of_case(&t.scene, t.stiffness_n_per_m, case))
    }

    /// The finished dynamics rows of a case at fixed iteration counts (the tolerance points
    /// have their own view, [`crate::benchmark::tolerance`]).
    pub fn dynamics(&self, case: Case) -> Vec<&Row> {
        self.rows
            .iter()
            .filter(|r| r.kind == "dynamics" && r.finished() && r.count_mode())
            .filter(|r| of_case(&r.scene, r.stiffness_n_per_m, case))
            .collect()
    }

    /// The statics rows of a case: this report's and the committed long ones of `make
    /// report-long` ([`mass_spring_solvers::studies::benchmark::statics::long_statics_configurations`]).
    pub fn statics(&self, case: Case) -> Vec<&Row> {
        self.rows
            .iter()
            .chain(&self.long)
            .filter(|r| r.kind == "statics")
            .filter(|r| of_case(&r.scene, r.stiffness_n_per_m, case))
            .collect()
    }

    /// A solver's work-precision front on a case under the thesis's scheme: the
    /// [`epsilon_front`] of its configurations (every setting and time step) in flops and
    /// relative physical error, cheapest first.
    pub fn front(&self, case: Case, solver: SolverId) -> Vec<&Row> {
        let integrator = if solver.is_minimizing() {
            OptimizationIntegrator::BackwardEuler.key()
        } else {
            ""
        };
        self.front_under(case, solver, integrator)
    }

    /// [`BenchmarkChapter::front`] under an integrator (its key; empty for a solver's own
    /// scheme).
    pub fn front_under(&self, case: Case, solver: SolverId, integrator: &str) -> Vec<&Row> {
        let rows: Vec<&Row> = self
            .dynamics(case)
            .into_iter()
            .filter(|r| r.solver == solver.id() && r.integrator == integrator)
            .filter(|r| r.flops.is_some() && r.physical_rel.is_some())
            .collect();
        let points: Vec<(f64, f64)> = rows
            .iter()
            .map(|r| (r.flops.unwrap(), r.physical_rel.unwrap()))
            .collect();
        epsilon_front(&points, FRONT_EPSILON)
            .into_iter()
            .map(|i| rows[i])
            .collect()
    }

    /// A solver's relative physical error against dt on a case at its first setting, under
    /// the thesis's scheme.
    pub fn convergence(&self, case: Case, solver: SolverId) -> Vec<(f64, f64)> {
        let integrator = if solver.is_minimizing() {
            OptimizationIntegrator::BackwardEuler.key()
        } else {
            ""
        };
        self.convergence_under(case, solver, integrator)
    }

    /// [`BenchmarkChapter::convergence`] under an integrator (its key).
    pub fn convergence_under(
        &self,
        case: Case,
        solver: SolverId,
        integrator: &str,
    ) -> Vec<(f64, f64)> {
        let mut points: Vec<(f64, f64)> = self
            .dynamics(case)
            .into_iter()
            .filter(|r| r.solver == solver.id() && r.iterations == first_setting(solver))
            .filter(|r| r.integrator == integrator)
            .filter_map(|r| Some((r.dt_s, r.physical_rel?)))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points
    }

    /// The fitted slope of a solver's relative physical error over the smallest decade of dt
    /// of a case, with the decade's ends.
    pub fn smallest_decade_slope(&self, case: Case, solver: SolverId) -> Option<(f64, f64, f64)> {
        decade_slope(&self.convergence(case, solver))
    }
}

/// The fitted slope over the smallest decade of dt of (dt, error) points sorted by dt, with
/// the decade's ends.
pub fn decade_slope(points: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let smallest = points.first()?.0;
    let decade: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(dt, _)| *dt <= 10.0 * smallest * (1.0 + 1e-9))
        .collect();
    Some((log_slope(&decade)?, smallest, decade.last()?.0))
}

impl BenchmarkChapter {
    /// The cheapest configuration of any solver that reaches a relative physical error of
    /// `level` on a case and may be recommended: an explicit baseline only within
    /// [`STABILITY_MARGIN`] of its stability limit.
    pub fn cheapest_overall(&self, case: Case, level: f64) -> Option<&Row> {
        self.recommendable(case, level)
            .min_by(|a, b| a.flops.unwrap().total_cmp(&b.flops.unwrap()))
    }

    /// The configurations of other solvers tied with [`Self::cheapest_overall`]: each other
    /// solver's cheapest that costs at most (1 + tie) times as much, cheapest first.
    pub fn tied_with_cheapest(&self, case: Case, level: f64) -> Vec<&Row> {
        let Some(best) = self.cheapest_overall(case, level) else {
            return Vec::new();
        };
        let bound =
            (1.0 + mass_spring_solvers::studies::benchmark::verdicts::TIE) * best.flops.unwrap();
        let mut tied: Vec<&Row> = Vec::new();
        let mut candidates: Vec<&Row> = self
            .recommendable(case, level)
            .filter(|r| r.solver != best.solver && r.flops.unwrap() <= bound)
            .collect();
        candidates.sort_by(|a, b| a.flops.unwrap().total_cmp(&b.flops.unwrap()));
        for r in candidates {
            if !tied.iter().any(|t| t.solver == r.solver) {
                tied.push(r);
            }
        }
        tied
    }

    /// The configurations of a case that reach `level` with a cost, an explicit baseline only
    /// within its stability margin.
    pub(crate) fn recommendable(&self, case: Case, level: f64) -> impl Iterator<Item = &Row> {
        self.dynamics(case)
            .into_iter()
            .filter(move |r| r.physical_rel.is_some_and(|e| e <= level) && r.flops.is_some())
            .filter(|r| {
                r.dt_over_stability_limit
                    .is_none_or(|f| f <= STABILITY_MARGIN)
            })
    }
}

fn first_setting(solver: SolverId) -> usize {
    mass_spring_solvers::studies::benchmark::sweep::settings(solver)[0].iterations
}

#[cfg(test)]
mod tests {
    use super::epsilon_front;

    /// Whether `a` ε-dominates `b`.
    fn dominates(a: (f64, f64), b: (f64, f64), epsilon: f64) -> bool {
        a.0 <= (1.0 + epsilon) * b.0 && a.1 <= (1.0 + epsilon) * b.1
    }

    #[test]
    fn the_epsilon_front_covers_every_point_and_no_point_of_it_dominates_another() {
        // Costs 1 to 12 with a plateau, near-duplicates and points off the front.
        let points = [
            (1.0, 1.0),
            (1.05, 0.5),  // 5 % dearer, twice as good: replaces (1, 1)
            (2.0, 0.49),  // 2 % better only: left out, covered by (1.05, 0.5)
            (3.0, 0.2),   // kept
            (3.2, 0.19),  // 5 % better: left out
            (6.0, 0.05),  // kept
            (5.0, 0.3),   // worse than a cheaper point
            (12.0, 0.01), // kept
        ];
        let front = epsilon_front(&points, 0.1);
        assert_eq!(front, vec![1, 3, 5, 7]);
        for (i, &p) in points.iter().enumerate() {
            if !front.contains(&i) {
                assert!(front.iter().any(|&f| dominates(points[f], p, 0.1)), "{i}");
            }
        }
        for &a in &front {
            for &b in front.iter().filter(|&&b| b != a) {
                assert!(!dominates(points[a], points[b], 0.1), "{a} over {b}");
            }
        }
        // The strict front keeps every improvement, however small (the failing case of the
        // ε-front's purpose: near-duplicates drawn as separate points).
        assert_eq!(epsilon_front(&points, 0.0), vec![0, 1, 2, 3, 4, 5, 7]);
    }
}

//! The work-precision chapter in wall-clock time (issue 14, step 3, written by `make timing`
//! into `report/timing/TIMING.md`): every configuration of [`crate::work_precision::sweep`]
//! that finished its window, with its physical error and its counted flops, timed on one core
//! in wall seconds per simulated second. The diagrams, the cheapest-configuration table and the
//! most accurate configuration within a budget, as the report's chapter
//! ([`crate::report::work_precision`]) gives them in flops, with the flops beside them and
//! where the two costs rank the solvers differently.
//!
//! The selections are generic over the cost and the error ([`cheapest_by`],
//! [`pareto_front_by`], [`most_accurate_within_by`]): one rule serves both costs.

use crate::beyond::kendall_tau;
use crate::error::Result;
use crate::registry::SolverId;
use crate::report::format::{full, sig4, MarkdownTable};
use crate::report::plot::{Axis, Chart, Panel, FULL_WIDTH_MM};
use crate::report::work_precision::{
    configuration_of, front_series, most_frequent, solver_list, stem, tolerance_cell,
};
use crate::report::ChapterFigure;
use crate::work_precision::{
    cheapest_by, most_accurate_within_by, pareto_front_by, sweep_solvers, Case, Point, WallTime,
    ERROR_LEVELS_M,
};

/// The wall-time budgets at which the solvers are compared for accuracy, s per simulated s
/// (1 is real time).
pub const WALL_BUDGETS: [f64; 5] = [1e-5, 1e-4, 1e-3, 1e-2, 1e-1];

/// The header of each figure's CSV: the points it draws.
pub const FIGURE_CSV_HEADER: &str =
    "solver,tolerance_m,iterations_mean,dt_s,wall_s_per_sim_s,wall_spread,cpu_s_per_sim_s,cpu_spread,flops,physical_error_m";

/// A configuration that finished its window, timed.
#[derive(Debug, Clone, PartialEq)]
pub struct Timed {
    pub point: Point,
    /// Floating-point operations of the window ([`crate::work_precision::run_flops`]).
    pub flops: f64,
    /// The physical error (summed node distance, worst sample), m.
    pub physical_error: f64,
    /// Wall seconds per simulated second: the least and the largest of the repeats' batch
    /// means.
    pub wall: WallTime,
    /// The thread's CPU seconds per simulated second, the same way.
    pub cpu: WallTime,
    /// Runs of the window per timed batch.
    pub batch: usize,
    /// Iterations per step, the mean its steps took.
    pub iterations_mean: f64,
}

impl Timed {
    /// Wall seconds per simulated second (the least batch mean).
    pub fn wall_s(&self) -> f64 {
        self.wall.min
    }

    /// Its physical error, as the selections take an error.
    pub fn error(&self) -> Option<f64> {
        Some(self.physical_error)
    }

    /// `dt = 0.01 s, 10 it.` or `dt = 0.01 s, to 1e-4 m (12.3 it.)`.
    fn configuration(&self) -> String {
        configuration_of(&self.point, self.iterations_mean)
    }
}

/// The two costs of a row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cost {
    Wall,
    Flops,
}

impl Cost {
    pub fn of(self, row: &Timed) -> f64 {
        match self {
            Cost::Wall => row.wall_s(),
            Cost::Flops => row.flops,
        }
    }

    fn show(self, value: f64) -> String {
        match self {
            Cost::Wall => format!("{} s/s", sig4(value)),
            Cost::Flops => format!("{} flops", sig4(value)),
        }
    }
}

/// The rows of `id` on `case`.
pub fn rows_of<'a>(
    rows: &'a [Timed],
    case: Case,
    id: SolverId,
) -> impl Iterator<Item = &'a Timed> + 'a {
    rows.iter()
        .filter(move |r| r.point.case == case && r.point.spec.id == id)
}

/// The cheapest configuration of `id` on `case` by `cost` that reaches a physical error of
/// `level`.
pub fn cheapest(
    rows: &[Timed],
    case: Case,
    id: SolverId,
    cost: Cost,
    level: f64,
) -> Option<&Timed> {
    cheapest_by(rows_of(rows, case, id), |r| cost.of(r), Timed::error, level)
}

/// The solvers that reach `level` on `case`, cheapest first by `cost` (each by its cheapest
/// configuration; ties in registry order).
pub fn ranking(rows: &[Timed], case: Case, cost: Cost, level: f64) -> Vec<(SolverId, f64)> {
    let mut ranked: Vec<(SolverId, f64)> = sweep_solvers()
        .into_iter()
        .filter_map(|id| cheapest(rows, case, id, cost, level).map(|r| (id, cost.of(r))))
        .collect();
    ranked.sort_by(|a, b| a.1.total_cmp(&b.1));
    ranked
}

/// The most accurate configuration on `case`, every solver competing, within `budget` of
/// `cost`.
pub fn most_accurate_within(rows: &[Timed], case: Case, cost: Cost, budget: f64) -> Option<&Timed> {
    most_accurate_within_by(
        rows.iter().filter(|r| r.point.case == case),
        |r| cost.of(r),
        Timed::error,
        budget,
    )
}

/// One case's figure: the physical error against the wall time per simulated second, log-log,
/// each solver's front in wall time, with the CSV of the points it draws.
pub fn figure(rows: &[Timed], case: Case) -> Result<ChapterFigure> {
    let mut panel = Panel::new(
        Axis::log("wall seconds per simulated second (one core)"),
        Axis::log("physical error (m)"),
    );
    let mut csv = format!("{FIGURE_CSV_HEADER}\n");
    for (i, id) in sweep_solvers().into_iter().enumerate() {
        let front = pareto_front_by(rows_of(rows, case, id), Timed::wall_s, Timed::error);
        for r in &front {
            csv += &format!(
                "{id},{},{},{},{},{:.4},{},{:.4},{},{}\n",
                tolerance_cell(&r.point),
                full(r.iterations_mean),
                full(r.point.dt_s),
                full(r.wall_s()),
                r.wall.spread(),
                full(r.cpu.min),
                r.cpu.spread(),
                full(r.flops),
                full(r.physical_error)
            );
        }
        if front.is_empty() {
            continue;
        }
        let points = front
            .iter()
            .map(|r| (r.wall_s(), r.physical_error))
            .collect();
        panel.series.push(front_series(i, id, points));
    }
    ChapterFigure::new(
        stem(case),
        &Chart::new(FULL_WIDTH_MM, 90.0, vec![panel]),
        csv,
    )
}

/// TIMING.md's section for one case: the figure, the cheapest-configuration table in wall
/// time beside the flops, where the two costs rank the solvers differently, and the most
/// accurate configuration within each of [`WALL_BUDGETS`].
pub fn case_section(rows: &[Timed], case: Case) -> String {
    let s = stem(case);
    let mut md = format!("### {}\n\n", case.label());
    md += &format!(
        "![{s}]({s}.svg)\n\n*Physical error against wall seconds per simulated second, {}: each \
         solver's configurations that none of its own beats in both.* Data: \
         [`{s}.csv`]({s}.csv).\n\n",
        case.label()
    );
    md += "The cheapest configuration of each solver that reaches a physical error, in wall \
           time (its flops in brackets), the cheapest in flops where it is another \
           configuration (its wall time in brackets), and the smallest error the solver reaches \
           in the sweep:\n\n";
    let mut header = vec!["solver".to_string()];
    for level in ERROR_LEVELS_M {
        header.push(format!("≤ {} m, wall", full(level)));
        header.push(format!("≤ {} m, flops", full(level)));
    }
    header.push("smallest reached".into());
    let mut t = MarkdownTable::new(&header);
    for id in sweep_solvers() {
        let mut row = vec![format!("`{id}`")];
        for level in ERROR_LEVELS_M {
            let by_wall = cheapest(rows, case, id, Cost::Wall, level);
            let by_flops = cheapest(rows, case, id, Cost::Flops, level);
            let cell = |r: &Timed, cost: Cost, other: Cost| {
                format!(
                    "{} ({}; {})",
                    cost.show(cost.of(r)),
                    r.configuration(),
                    other.show(other.of(r))
                )
            };
            row.push(by_wall.map_or("not reached".into(), |r| cell(r, Cost::Wall, Cost::Flops)));
            row.push(match (by_wall, by_flops) {
                (Some(w), Some(f)) if w.point == f.point => "the same".into(),
                (_, Some(f)) => cell(f, Cost::Flops, Cost::Wall),
                (_, None) => "not reached".into(),
            });
        }
        let front = pareto_front_by(rows_of(rows, case, id), Timed::wall_s, Timed::error);
        row.push(front.last().map_or("–".into(), |r| {
            format!(
                "{} m ({}; {})",
                sig4(r.physical_error),
                Cost::Wall.show(r.wall_s()),
                r.configuration()
            )
        }));
        t.row(row);
    }
    md += &t.render();
    md += "\n";
    for level in ERROR_LEVELS_M {
        let wall = ranking(rows, case, Cost::Wall, level);
        let flops = ranking(rows, case, Cost::Flops, level);
        let (Some(w), Some(f)) = (wall.first(), flops.first()) else {
            md += &format!("- ≤ {} m: no solver reaches it.\n", full(level));
            continue;
        };
        let ids = |r: &[(SolverId, f64)]| r.iter().map(|x| x.0).collect::<Vec<_>>();
        let tau =
            kendall_tau(&ids(&wall), &ids(&flops)).map_or("–".into(), |t| format!("{t:.2}"));
        md += &format!(
            "- ≤ {} m: {} of {} solvers reach it; the cheapest in wall time is `{}` ({}), in flops `{}` \
             ({}){}; Kendall τ between the two rankings {tau}.\n",
            full(level),
            wall.len(),
            sweep_solvers().len(),
            w.0,
            Cost::Wall.show(w.1),
            f.0,
            Cost::Flops.show(f.1),
            if w.0 == f.0 {
                ": they agree".to_string()
            } else {
                format!(
                    ": they differ (`{}` is {:.2} times slower than `{}` in wall time)",
                    f.0,
                    wall.iter().find(|x| x.0 == f.0).map_or(f64::NAN, |x| x.1) / w.1,
                    w.0
                )
            },
        );
    }
    md += "\n";
    if let Some(level) = common_level(rows, case) {
        md += &common_ranking(rows, case, level);
    }
    md += &format!("{}\n\n", answer(rows, case));
    md
}

/// The smallest physical error every solver with a row on `case` reaches: the largest of their
/// smallest, m.
pub fn common_level(rows: &[Timed], case: Case) -> Option<f64> {
    sweep_solvers()
        .into_iter()
        .filter_map(|id| {
            rows_of(rows, case, id)
                .map(|r| r.physical_error)
                .min_by(f64::total_cmp)
        })
        .max_by(f64::total_cmp)
}

/// Every solver ranked by the cost of its cheapest configuration that reaches `level`, in wall
/// time and in flops, with Kendall's τ between the two rankings.
fn common_ranking(rows: &[Timed], case: Case, level: f64) -> String {
    let wall = ranking(rows, case, Cost::Wall, level);
    let flops = ranking(rows, case, Cost::Flops, level);
    let ids = |r: &[(SolverId, f64)]| r.iter().map(|x| x.0).collect::<Vec<_>>();
    let tau = kendall_tau(&ids(&wall), &ids(&flops)).map_or("–".into(), |t| format!("{t:.2}"));
    let mut md = format!(
        "Every solver at the smallest physical error all of them reach, {} m (the largest of \
         their smallest), ranked by the cost of its cheapest configuration that reaches it \
         (Kendall τ between the two rankings: {tau}):\n\n",
        sig4(level)
    );
    let mut t = MarkdownTable::new(&[
        "solver",
        "wall (s/s)",
        "rank by wall",
        "flops",
        "rank by flops",
        "configuration (wall; flops where another)",
    ]);
    for (k, &(id, cost)) in wall.iter().enumerate() {
        let f = flops.iter().position(|x| x.0 == id);
        let by_wall = cheapest(rows, case, id, Cost::Wall, level);
        let by_flops = cheapest(rows, case, id, Cost::Flops, level);
        let configuration = match (by_wall, by_flops) {
            (Some(w), Some(f)) if w.point != f.point => {
                format!("{}; {}", w.configuration(), f.configuration())
            }
            (Some(w), _) => w.configuration(),
            (None, _) => "–".into(),
        };
        t.row(vec![
            format!("`{id}`"),
            sig4(cost),
            (k + 1).to_string(),
            f.map_or("–".into(), |i| sig4(flops[i].1)),
            f.map_or("–".into(), |i| (i + 1).to_string()),
            configuration,
        ]);
    }
    md += &t.render();
    md += "\n";
    md
}

/// The solver most often the most accurate within [`WALL_BUDGETS`] on `case`, with that count
/// and the number of budgets any configuration fits; ties go to the earlier in the registry.
pub fn most_frequent_wall_winner(
    rows: &[Timed],
    case: Case,
) -> Option<(Vec<SolverId>, usize, usize)> {
    let winners: Vec<SolverId> = WALL_BUDGETS
        .into_iter()
        .filter_map(|b| most_accurate_within(rows, case, Cost::Wall, b).map(|r| r.point.spec.id))
        .collect();
    most_frequent(&winners).map(|(ids, n)| (ids, n, winners.len()))
}

/// The paragraph that answers, on `case`, which solver gives the most accuracy per unit of
/// wall time: the most accurate configuration within each budget of [`WALL_BUDGETS`].
pub fn answer(rows: &[Timed], case: Case) -> String {
    let within: Vec<String> = WALL_BUDGETS
        .into_iter()
        .map(|b| {
            most_accurate_within(rows, case, Cost::Wall, b).map_or(
                format!("within {} s/s nothing", full(b)),
                |r| {
                    format!(
                        "within {} s/s `{}` reaches {} m ({}; {})",
                        full(b),
                        r.point.spec.id,
                        sig4(r.physical_error),
                        r.configuration(),
                        Cost::Wall.show(r.wall_s())
                    )
                },
            )
        })
        .collect();
    let winner = most_frequent_wall_winner(rows, case).map_or(
        "no configuration fits a budget".to_string(),
        |(ids, n, of)| {
            let each = if ids.len() == 1 { "" } else { "each " };
            format!(
                "{}, {each}the most accurate at {n} of the {of} budgets it has any \
                 configuration within",
                solver_list(&ids)
            )
        },
    );
    format!(
        "**The most accuracy per unit of wall time** on the {}: {}. Most often first: {winner}.",
        case.label(),
        within.join("; ")
    )
}

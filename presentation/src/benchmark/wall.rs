//! The benchmark's costs in wall time: every dynamics configuration of [`mass_spring_solvers::studies::benchmark`]
//! timed on one core by `make timing` (`presentation/src/bin/timing/`), written to
//! `report/timing/benchmark_wall.csv` with the machine that measured it in
//! `report/timing/machine.csv`, and read back by `make report` (which never writes
//! `report/timing/`): where the wall time and the counted flops rank the solvers differently,
//! and how far apart a flop of one solver and a flop of another are in wall time.
//!
//! The rankings are at matched accuracy, as the benchmark's verdicts are: at each relative
//! physical error of [`DYNAMICS_LEVELS`], each solver's cheapest configuration that reaches it
//! by each cost, the solvers ranked by both, Kendall's τ between the two rankings, and the
//! pairs the two costs order differently by more than a tie ([`TIE`]) in both.

use crate::benchmark::families::of_case;
use crate::benchmark::fronts::{epsilon_front, work_figure, FrontRow, FRONT_EPSILON};
use crate::chapter_figure::ChapterFigure;
use crate::format::{short, sig, MarkdownTable};
use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::integrators::optimization_integrator::OptimizationIntegrator;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::sweep::{
    solvers, stability_limit_from_rk4, Configuration, STABILITY_MARGIN,
};
use mass_spring_solvers::studies::benchmark::verdicts::{DYNAMICS_LEVELS, TIE};
use mass_spring_solvers::studies::benchmark::Case;
use mass_spring_solvers::studies::beyond::kendall_tau;
use mass_spring_solvers::studies::work_precision::rk4_stability_limit;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The timed configurations, in the output directory of `make timing`.
pub const WALL_CSV: &str = "benchmark_wall.csv";

/// The machine and commit of the measurement, beside it.
pub const MACHINE_CSV: &str = "machine.csv";

/// A configuration whose batch means spread by more than this (largest over least, less 1)
/// is flagged.
pub const WALL_SPREAD_FLAG: f64 = 0.2;

/// One timed configuration: its key columns as `benchmark.csv` names them, its times, and the
/// flops and relative physical error the benchmark counted and measured for it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WallRow {
    pub scene: String,
    pub stiffness_n_per_m: f64,
    pub solver: String,
    pub iterations: usize,
    /// A minimizing solver's optimization integrator, as in `benchmark.csv` (empty in files
    /// measured before the benchmark ran integrators: Backward Euler, the thesis's scheme).
    #[serde(default)]
    pub integrator: String,
    pub stopping: String,
    pub dt_s: f64,
    /// One run over the case's window (the solver built, then every step), the least of the
    /// batch means, s.
    pub wall_s: f64,
    /// The same in the thread's CPU time, s.
    pub cpu_s: f64,
    /// The largest batch mean over the least, less 1 (wall time).
    pub wall_spread: f64,
    /// Whether `wall_spread` exceeds [`WALL_SPREAD_FLAG`].
    pub flagged: bool,
    /// Floating-point operations of the run, as the benchmark counts them.
    pub flops: f64,
    /// Its RMS physical error over the exact motion's RMS amplitude.
    pub physical_rel: f64,
}

/// Wall and CPU time of one run: the least batch mean of each, and the wall time's spread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunTime {
    pub wall_s: f64,
    pub cpu_s: f64,
    pub wall_spread: f64,
}

impl WallRow {
    /// The row of a configuration.
    pub fn new(
        configuration: &Configuration,
        time: RunTime,
        flops: f64,
        physical_rel: f64,
    ) -> Self {
        // Every field of the configuration is a key column: a new dimension of the benchmark
        // does not compile here until it has one.
        let Configuration { case, spec, dt_s } = *configuration;
        Self {
            scene: case.scene.id().into(),
            stiffness_n_per_m: case.stiffness,
            solver: spec.id.id().into(),
            iterations: spec.iterations,
            integrator: if spec.id.is_minimizing() {
                spec.params.integrator.key().into()
            } else {
                String::new()
            },
            stopping: spec.stopping.id(),
            dt_s,
            wall_s: time.wall_s,
            cpu_s: time.cpu_s,
            wall_spread: time.wall_spread,
            flagged: time.wall_spread > WALL_SPREAD_FLAG,
            flops,
            physical_rel,
        }
    }

    /// Its case.
    pub fn case(&self) -> Option<Case> {
        Case::ALL.into_iter().find(|&c| of(self, c))
    }

    /// Whether it is `benchmark.csv`'s row `row`: the same key columns.
    pub fn is(&self, row: &mass_spring_solvers::studies::benchmark::rows::Row) -> bool {
        let integrator = self.integrator == row.integrator
            || (self.integrator.is_empty() && row.thesis_scheme());
        (&self.scene, self.stiffness_n_per_m, &self.solver)
            == (&row.scene, row.stiffness_n_per_m, &row.solver)
            && (self.iterations, &self.stopping, self.dt_s)
                == (row.iterations, &row.stopping, row.dt_s)
            && integrator
    }
}

/// The timed configurations by their key columns, for looking up `benchmark.csv`'s rows
/// ([`WallRow::is`]'s match, by hashing): each one's timed row.
#[derive(Debug, Default)]
pub struct WallIndex<'a>(std::collections::HashMap<String, &'a WallRow>);

impl<'a> WallIndex<'a> {
    /// The index of `rows`.
    pub fn new(rows: &'a [WallRow]) -> Self {
        Self(
            rows.iter()
                .map(|w| {
                    let key = Self::key(
                        (&w.scene, w.stiffness_n_per_m, &w.solver),
                        (w.iterations, &w.integrator, &w.stopping, w.dt_s),
                    );
                    (key, w)
                })
                .collect(),
        )
    }

    /// The timed row of `row`'s configuration (for a statics row, the dynamics run of the
    /// same configuration), if it was timed.
    pub fn timed(
        &self,
        row: &mass_spring_solvers::studies::benchmark::rows::Row,
    ) -> Option<&'a WallRow> {
        let key = Self::key(
            (&row.scene, row.stiffness_n_per_m, &row.solver),
            (row.iterations, &row.integrator, &row.stopping, row.dt_s),
        );
        self.0.get(&key).copied()
    }

    /// The key columns, the integrator's empty name (the thesis's scheme, or none) read as
    /// Backward Euler, as [`WallRow::is`] reads it.
    fn key(
        (scene, stiffness, solver): (&str, f64, &str),
        (iterations, integrator, stopping, dt): (usize, &str, &str, f64),
    ) -> String {
        let integrator = if integrator.is_empty() {
            "backward-euler"
        } else {
            integrator
        };
        format!("{scene}|{stiffness:?}|{solver}|{iterations}|{integrator}|{stopping}|{dt:?}")
    }
}

/// Who measured: the commit, the machine and when.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Machine {
    pub commit: String,
    /// Whether the working tree had changes outside `report/timing/`.
    pub uncommitted_changes: bool,
    pub cpu: String,
    pub cores: usize,
    pub toolchain: String,
    /// `2026-12-01 20:57:14 UTC`.
    pub measured_utc: String,
    /// The load averages over 1, 5 and 15 minutes before and after the run.
    pub load_before: String,
    pub load_after: String,
    pub run_time_s: f64,
}

/// A measurement: its rows and its machine.
#[derive(Debug, Clone, PartialEq)]
pub struct WallTiming {
    pub rows: Vec<WallRow>,
    pub machine: Machine,
    /// RK4's stability limit on each case the rows time, s ([`WallTiming::new`]).
    pub rk4_limits: Vec<(Case, f64)>,
}

/// Reads every record of a CSV strictly (a header, no ragged rows), naming the file on error.
pub(crate) fn read_csv<T: serde::de::DeserializeOwned>(path: &Path) -> Result<Vec<T>> {
    let bad = |e: &dyn std::fmt::Display| Error::Input(format!("{}: {e}", path.display()));
    let mut reader = csv::Reader::from_path(path).map_err(|e| bad(&e))?;
    reader
        .deserialize()
        .collect::<std::result::Result<Vec<T>, _>>()
        .map_err(|e| bad(&e))
}

impl WallTiming {
    /// The measurement in `dir` (`report/timing/`), None if it has no [`WALL_CSV`]; an error
    /// naming the file, the record and the field if it is malformed or its machine is missing.
    pub fn load(dir: &Path) -> Result<Option<Self>> {
        let path = dir.join(WALL_CSV);
        if !path.exists() {
            return Ok(None);
        }
        let rows: Vec<WallRow> = read_csv(&path)?;
        for (i, r) in rows.iter().enumerate() {
            let positive = [
                ("wall_s", r.wall_s),
                ("cpu_s", r.cpu_s),
                ("flops", r.flops),
                ("physical_rel", r.physical_rel),
            ];
            for (field, value) in positive {
                if !(value.is_finite() && value > 0.0) {
                    return Err(Error::invalid(
                        format!("{} record {} {field}", path.display(), i + 1),
                        value,
                        "a positive finite number",
                    ));
                }
            }
        }
        let machine_path = dir.join(MACHINE_CSV);
        let mut machines: Vec<Machine> = read_csv(&machine_path)?;
        if machines.len() != 1 {
            return Err(Error::Input(format!(
                "{}: {} records, expected one",
                machine_path.display(),
                machines.len()
            )));
        }
        Self::new(rows, machines.remove(0)).map(Some)
    }

    /// A measurement of `rows` on `machine`, with RK4's stability limit on each of its cases
    /// (the explicit baselines' margin, [`cheapest`]).
    pub fn new(rows: Vec<WallRow>, machine: Machine) -> Result<Self> {
        let mut timing = Self {
            rows,
            machine,
            rk4_limits: Vec::new(),
        };
        for case in timing.cases() {
            let limit = rk4_stability_limit(&case.scene.system(case.stiffness)?);
            timing.rk4_limits.push((case, limit));
        }
        Ok(timing)
    }

    /// The cases it holds, in [`Case::ALL`]'s order.
    pub fn cases(&self) -> Vec<Case> {
        Case::ALL
            .into_iter()
            .filter(|&c| self.rows.iter().any(|r| of(r, c)))
            .collect()
    }

    /// `commit 273194d (with uncommitted changes) on AMD EPYC, 2 cores, 2026-12-01 20:57:14 UTC`.
    pub fn provenance(&self) -> String {
        let m = &self.machine;
        format!(
            "commit `{}`{} on {}, {} cores, {}",
            m.commit.get(..12).unwrap_or(&m.commit),
            if m.uncommitted_changes {
                " (with uncommitted changes)"
            } else {
                ""
            },
            m.cpu,
            m.cores,
            m.measured_utc
        )
    }
}

fn of(row: &WallRow, case: Case) -> bool {
    of_case(&row.scene, row.stiffness_n_per_m, case)
}

fn rows_of<'a>(
    rows: &'a [WallRow],
    case: Case,
    id: SolverId,
) -> impl Iterator<Item = &'a WallRow> + 'a {
    rows.iter()
        .filter(move |r| of(r, case) && r.solver == id.id())
}

/// A solver's wall time per counted flop on a case: its wall time over its flops, each summed
/// over its configurations, ns.
pub fn ns_per_flop(rows: &[WallRow], case: Case, id: SolverId) -> Option<f64> {
    let (wall, flops) =
        rows_of(rows, case, id).fold((0.0, 0.0), |(w, f), r| (w + r.wall_s, f + r.flops));
    (flops > 0.0).then(|| wall / flops * 1e9)
}

/// The least and the largest of the solvers' [`ns_per_flop`] on a case.
pub fn ns_per_flop_range(
    rows: &[WallRow],
    case: Case,
) -> Option<((SolverId, f64), (SolverId, f64))> {
    let all: Vec<(SolverId, f64)> = solvers()
        .into_iter()
        .filter_map(|id| ns_per_flop(rows, case, id).map(|n| (id, n)))
        .collect();
    let least = all.iter().copied().min_by(|a, b| a.1.total_cmp(&b.1))?;
    let largest = all.iter().copied().max_by(|a, b| a.1.total_cmp(&b.1))?;
    Some((least, largest))
}

/// The two costs of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cost {
    Wall,
    Flops,
}

impl Cost {
    pub fn of(self, row: &WallRow) -> f64 {
        match self {
            Cost::Wall => row.wall_s,
            Cost::Flops => row.flops,
        }
    }
}

/// A solver's cheapest configuration by `cost` on `case` that reaches a relative physical
/// error of `level`, under any integrator; an explicit baseline's only within
/// [`STABILITY_MARGIN`] of its stability limit (from RK4's on the case, `rk4_limit_s`), as
/// the report's headline and section 12.4 recommend them.
pub fn cheapest(
    rows: &[WallRow],
    case: Case,
    id: SolverId,
    cost: Cost,
    level: f64,
    rk4_limit_s: f64,
) -> Option<&WallRow> {
    let limit = stability_limit_from_rk4(id, rk4_limit_s);
    rows_of(rows, case, id)
        .filter(|r| r.physical_rel <= level)
        .filter(|r| limit.is_none_or(|l| r.dt_s <= STABILITY_MARGIN * l))
        .min_by(|a, b| cost.of(a).total_cmp(&cost.of(b)))
}

/// The solvers that reach a relative physical error of `level` on `case`, each by its cheapest
/// configuration by `cost` that reaches it ([`cheapest`]), cheapest first (equal costs in the
/// benchmark's order of solvers).
pub fn ranking(
    rows: &[WallRow],
    case: Case,
    cost: Cost,
    level: f64,
    rk4_limit_s: f64,
) -> Vec<(SolverId, &WallRow)> {
    let mut ranked: Vec<(SolverId, &WallRow)> = solvers()
        .into_iter()
        .filter_map(|id| cheapest(rows, case, id, cost, level, rk4_limit_s).map(|r| (id, r)))
        .collect();
    ranked.sort_by(|a, b| cost.of(a.1).total_cmp(&cost.of(b.1)));
    ranked
}

/// The two rankings of a case at one level, and where they differ.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison<'a> {
    pub case: Case,
    pub level: f64,
    /// Each solver's cheapest configuration in flops, cheapest first.
    pub by_flops: Vec<(SolverId, &'a WallRow)>,
    /// The same in wall time (at the least batch mean).
    pub by_wall: Vec<(SolverId, &'a WallRow)>,
    /// Kendall's τ between the two rankings; None for fewer than two solvers.
    pub tau: Option<f64>,
    /// The pairs (a, b) that flops rank a before b and wall time b before a, each cost by
    /// more than a tie and the wall time beyond the timing's spread: a's flops under b's by
    /// more than [`TIE`], b's wall time at its largest batch mean under a's at its least by
    /// more than [`TIE`] (a machine's load moves a configuration within its spread).
    pub reversed: Vec<(SolverId, SolverId)>,
}

/// The comparison of the two costs on `case` at `level`, the explicit baselines within their
/// margin of RK4's stability limit `rk4_limit_s` ([`cheapest`]).
pub fn compare(rows: &[WallRow], case: Case, level: f64, rk4_limit_s: f64) -> Comparison<'_> {
    let by_flops = ranking(rows, case, Cost::Flops, level, rk4_limit_s);
    let by_wall = ranking(rows, case, Cost::Wall, level, rk4_limit_s);
    let ids = |r: &[(SolverId, &WallRow)]| r.iter().map(|x| x.0).collect::<Vec<_>>();
    fn of<'r>(r: &[(SolverId, &'r WallRow)], id: SolverId) -> Option<&'r WallRow> {
        r.iter().find(|x| x.0 == id).map(|x| x.1)
    }
    let mut reversed = Vec::new();
    for &(a, fa) in &by_flops {
        for &(b, fb) in &by_flops {
            let (Some(wa), Some(wb)) = (of(&by_wall, a), of(&by_wall, b)) else {
                continue;
            };
            let slowest_b = wb.wall_s * (1.0 + wb.wall_spread);
            if fa.flops * (1.0 + TIE) < fb.flops && slowest_b * (1.0 + TIE) < wa.wall_s {
                reversed.push((a, b));
            }
        }
    }
    Comparison {
        case,
        level,
        tau: kendall_tau(&ids(&by_flops), &ids(&by_wall)),
        by_flops,
        by_wall,
        reversed,
    }
}

/// Every comparison: the cases in order, each at every level of [`DYNAMICS_LEVELS`].
pub fn comparisons(timing: &WallTiming) -> Vec<Comparison<'_>> {
    timing
        .rk4_limits
        .iter()
        .flat_map(|&(case, limit)| {
            DYNAMICS_LEVELS.map(|level| compare(&timing.rows, case, level, limit))
        })
        .collect()
}

fn name(id: SolverId) -> &'static str {
    id.info().display_name
}

/// A timed configuration's solver, with its integrator where it has one ("ADMM under BDF2").
fn configured_name(row: &WallRow) -> String {
    let solver = match SolverId::from_id(&row.solver) {
        Ok(id) => name(id).to_string(),
        Err(_) => row.solver.clone(),
    };
    match row.integrator.parse::<OptimizationIntegrator>() {
        Ok(integrator) => format!("{solver} under {}", integrator.label()),
        Err(_) => solver,
    }
}

/// The wall time per flop of every solver on every case, with each case's largest over least.
pub fn ns_per_flop_table(timing: &WallTiming) -> MarkdownTable {
    let cases = timing.cases();
    let mut header = vec!["solver".to_string()];
    header.extend(
        cases
            .iter()
            .map(|c| format!(">{} (ns per flop)", c.label())),
    );
    let mut t = MarkdownTable::new(&header);
    for id in solvers() {
        let mut row = vec![name(id).to_string()];
        row.extend(
            cases
                .iter()
                .map(|&c| ns_per_flop(&timing.rows, c, id).map_or("–".into(), |n| sig(n, 2))),
        );
        t.row(row);
    }
    let mut row = vec!["largest / least".to_string()];
    row.extend(cases.iter().map(|&c| {
        ns_per_flop_range(&timing.rows, c).map_or("–".into(), |(lo, hi)| sig(hi.1 / lo.1, 2))
    }));
    t.row(row);
    t
}

/// One line per case and level: the solvers that reach it, τ between the two rankings and the
/// pairs they order differently.
pub fn rankings_table(timing: &WallTiming) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "case",
        ">relative physical error",
        ">solvers reaching it",
        ">Kendall τ (flops, wall)",
        "cheapest by flops",
        "cheapest by wall time",
        "ordered the other way by wall time, beyond ties",
    ]);
    for c in comparisons(timing) {
        // The cheapest configuration named with its integrator (the ranking takes the best of
        // the four) and its step.
        let first = |r: &[(SolverId, &WallRow)]| {
            r.first().map_or("–".to_string(), |x| {
                format!("{}, dt {} s", configured_name(x.1), short(x.1.dt_s))
            })
        };
        let reversed: Vec<String> = c
            .reversed
            .iter()
            .map(|(a, b)| format!("{} < {}", name(*a), name(*b)))
            .collect();
        t.row(vec![
            c.case.label(),
            format!("{} %", short(100.0 * c.level)),
            c.by_flops.len().to_string(),
            c.tau.map_or("–".into(), |t| format!("{t:.2}")),
            first(&c.by_flops),
            first(&c.by_wall),
            if reversed.is_empty() {
                "none".into()
            } else {
                format!("{}: {}", reversed.len(), reversed.join(", "))
            },
        ]);
    }
    t
}

/// What both files say of the two costs: the spread of the wall time per flop across solvers,
/// its table, and the rankings at matched accuracy.
pub fn costs_compared(timing: &WallTiming) -> String {
    let ranges: Vec<String> = timing
        .cases()
        .into_iter()
        .filter_map(|c| {
            let (lo, hi) = ns_per_flop_range(&timing.rows, c)?;
            Some(format!(
                "{}: {} ns ({}) to {} ns ({}), a factor {}",
                c.label(),
                sig(lo.1, 2),
                name(lo.0),
                sig(hi.1, 2),
                name(hi.0),
                sig(hi.1 / lo.1, 2)
            ))
        })
        .collect();
    let mut md = format!(
        "**A flop is not a flop.** Each solver's wall time per counted flop on a case (its wall \
         time over its flops, each summed over its configurations there, under every integrator) spreads across the \
         solvers: {}.\n\n",
        ranges.join("; ")
    );
    md += &ns_per_flop_table(timing).render();
    md += &format!(
        "\n**Where the two costs rank the solvers differently.** At each relative physical error, \
         each solver's cheapest configuration that reaches it by each cost, under any of the four \
         integrators (the two may be different configurations; the cheapest named with its \
         integrator and step), an explicit baseline only up to {} % of its stability limit, \
         the solvers ranked by both; a pair is ordered the other way when it is, in both costs, \
         by more than a tie ({} %), the wall time beyond the timing's spread (`a < b`: `a` is \
         cheaper in flops by more than the tie, `b`'s largest batch mean under `a`'s least by \
         more than the tie).\n\n",
        short(100.0 * STABILITY_MARGIN),
        short(100.0 * TIE)
    );
    md += &rankings_table(timing).render();
    md
}

/// Section 12's subsection `### {label} Costs in wall time`: who measured and where, then
/// [`costs_compared`]; or, without a measurement, that there is none.
pub fn section(
    label: &str,
    timing: Option<&WallTiming>,
    benchmark: &[mass_spring_solvers::studies::benchmark::rows::Row],
) -> String {
    let mut md = format!("### {label} Costs in wall time\n\n");
    let Some(timing) = timing else {
        md += &format!(
            "This clone has no `timing/{WALL_CSV}`: run `make timing` (under ten minutes) to time \
             every configuration of this benchmark; `make report` then reads it.\n\n"
        );
        return md;
    };
    let dynamics: Vec<&mass_spring_solvers::studies::benchmark::rows::Row> =
        benchmark.iter().filter(|r| r.kind == "dynamics").collect();
    let current = timing
        .rows
        .iter()
        .filter(|w| {
            dynamics
                .iter()
                .any(|r| w.is(r) && r.flops.is_some_and(|f| (f - w.flops).abs() <= 1e-9 * f))
        })
        .count();
    // Read from the CSV at report time: `make timing` re-measures it.
    let residual = timing.rows.iter().filter(|w| w.stopping != "count").count();
    md += &format!(
        "Measured by `make timing` at {} ([`timing/TIMING.md`](timing/TIMING.md), data \
         [`timing/{WALL_CSV}`](timing/{WALL_CSV}), the machine in \
         [`timing/{MACHINE_CSV}`](timing/{MACHINE_CSV})): each dynamics configuration of the \
         benchmark that finishes its window ({} at fixed iteration counts, {} stopped at a residual), built and \
         run over it on one core, its wall time the least of the means of repeated batches; {} of these times \
         spread by more than {} % between the batch means (largest over least, flagged in the CSV). Of its {} \
         timed configurations, {current} are configurations of this report's benchmark with the same counted \
         flops{}.\n\n",
        timing.provenance(),
        timing.rows.len() - residual,
        residual,
        timing
            .rows
            .iter()
            .filter(|w| w.wall_spread > WALL_SPREAD_FLAG)
            .count(),
        crate::format::short(100.0 * WALL_SPREAD_FLAG),
        timing.rows.len(),
        if current == timing.rows.len() {
            ""
        } else {
            " (the others were measured on a benchmark since changed: run `make timing` again)"
        }
    );
    md += &summary(timing);
    md += &costs_compared(timing);
    md += "\n";
    md
}

/// A τ from this up reads as two rankings that nearly agree.
pub const AGREEING_TAU: f64 = 0.8;

/// The comparisons in one sentence: the range of τ where at least three solvers reach a level,
/// and the pairs ordered the other way in all.
pub fn summary(timing: &WallTiming) -> String {
    let all = comparisons(timing);
    let taus: Vec<f64> = all
        .iter()
        .filter(|c| c.by_flops.len() >= 3)
        .filter_map(|c| c.tau)
        .collect();
    let reversed: usize = all.iter().map(|c| c.reversed.len()).sum();
    let (Some(lo), Some(hi)) = (
        taus.iter().copied().reduce(f64::min),
        taus.iter().copied().reduce(f64::max),
    ) else {
        return String::new();
    };
    let reading = if lo >= AGREEING_TAU {
        format!(
            "τ ≥ {AGREEING_TAU} everywhere: at matched accuracy the flops rank the solvers \
             nearly as the wall time does, their flops differing by more than their wall time \
             per flop"
        )
    } else {
        "the wall time reorders the solvers the flops rank".to_string()
    };
    let flagged = timing.rows.iter().filter(|r| r.flagged).count();
    format!(
        "The machine's load averages (1, 5 and 15 minutes) were {} before the run, and {flagged} \
         of the {} timed configurations' batch means spread by more than {} % (flagged): a \
         wall time here is one run's, within its spread, not a property of the solver. Where \
         at least three solvers reach a level ({} of the {} cells of case and level), Kendall's \
         τ between the flop ranking and the wall-time ranking is {lo:.2} to {hi:.2}, and \
         {reversed} {} of solvers in all {} ordered the other way beyond ties and the \
         spread; {reading}.\n\n",
        timing.machine.load_before,
        timing.rows.len(),
        short(WALL_SPREAD_FLAG * 100.0),
        taus.len(),
        all.len(),
        if reversed == 1 { "pair" } else { "pairs" },
        if reversed == 1 { "is" } else { "are" }
    )
}

/// The file stems of the wall-time figures, in [`Case::ALL`]'s order.
const STEMS: [&str; 4] = [
    "benchmark_wall_rope_k1e3",
    "benchmark_wall_rope_k1e6",
    "benchmark_wall_sheet_k1e3",
    "benchmark_wall_sheet_k1e6",
];

/// The wall-time figure's file stem of a case.
pub fn stem(case: Case) -> &'static str {
    STEMS[Case::ALL
        .iter()
        .position(|&c| c == case)
        .expect("a case of the benchmark")]
}

/// The work-precision figure of a case in wall time: the report's figure of section 12
/// ([`work_figure`]) with the wall time of a run for its flops, each front an ε-front in wall
/// time under its integrator, cut at the exact motion's `floor`.
pub fn figure(rows: &[WallRow], case: Case, floor: Option<f64>) -> Result<ChapterFigure> {
    work_figure(
        stem(case),
        ("wall time of a run (s)", "wall_s"),
        floor,
        |id, integrator| {
            let rows: Vec<&WallRow> = rows_of(rows, case, id)
                .filter(|r| r.integrator == integrator)
                .collect();
            let points: Vec<(f64, f64)> = rows.iter().map(|r| (r.wall_s, r.physical_rel)).collect();
            epsilon_front(&points, FRONT_EPSILON)
                .into_iter()
                .map(|i| rows[i])
                .collect()
        },
    )
}

/// The wall-time rows on a front: their cost is the wall time of a run.
impl FrontRow for WallRow {
    fn solver(&self) -> &str {
        &self.solver
    }
    fn integrator(&self) -> &str {
        &self.integrator
    }
    fn iterations(&self) -> usize {
        self.iterations
    }
    fn dt_s(&self) -> f64 {
        self.dt_s
    }
    fn cost(&self) -> f64 {
        self.wall_s
    }
    fn error(&self) -> f64 {
        self.physical_rel
    }
}

//! The benchmark in wall time: every dynamics configuration of
//! [`mass_spring_solvers::studies::benchmark`] (the report's section 12), its errors and flops from one
//! parallel run of [`Benchmark::compute`] (as `make report` computes them), then each that
//! finished its window timed on this thread, built and run over the window as the benchmark
//! runs it ([`build_solver`]): [`REPEATS`] batches of at least a batch's length, the least
//! batch mean in wall and thread CPU time. The rows, the costs compared
//! ([`mass_spring_report::benchmark::wall`]) and the work-precision figures in wall
//! time.

use crate::measure::{time_batches, REPEATS};
use mass_spring_report::benchmark::wall::{
    costs_compared, figure, stem, RunTime, WallRow, WallTiming, WALL_CSV, WALL_SPREAD_FLAG,
};
use mass_spring_report::benchmark::work_figure_caption;
use mass_spring_report::format::short;
use mass_spring_report::ChapterFigure;
use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::studies::benchmark::run::{build_solver, run, Outcome};
use mass_spring_solvers::studies::benchmark::sweep::{
    configurations, dts, Configuration, BASELINES,
};
use mass_spring_solvers::studies::benchmark::truth::CaseTruth;
use mass_spring_solvers::studies::benchmark::{Benchmark, Case};
use mass_spring_solvers::studies::experiments::run_parallel;
use std::fmt::Write as _;
use std::time::Instant;

/// A run longer than this, s, is timed in [`LONG_RUN_REPEATS`] batches (of one run each)
/// instead of [`REPEATS`]: the sheet's dearest runs would take most of the ten minutes.
const LONG_RUN_S: f64 = 0.1;
const LONG_RUN_REPEATS: usize = 3;

/// The configurations timed, with how they were timed.
pub struct Timed {
    pub rows: Vec<WallRow>,
    /// Configurations that did not finish their window (not timed).
    pub diverged: usize,
    /// Those whose thread CPU time spread by more than [`WALL_SPREAD_FLAG`].
    pub cpu_flagged: usize,
    /// Those that needed more than one run per batch.
    pub batched: usize,
    pub batch_seconds: f64,
    /// Each case's exact motion's floor: its halving gap over its amplitude (as the report's
    /// figures cut at it).
    pub floors: Vec<(Case, f64)>,
}

/// The cases of a run: every case, or with `quick` the soft rope.
pub fn cases(quick: bool) -> Vec<Case> {
    if quick {
        vec![Case::ALL[0]]
    } else {
        Case::ALL.to_vec()
    }
}

/// The outcomes to time and their cases' truths: the whole benchmark of `cases` computed in
/// parallel ([`Benchmark::compute`]); with `quick`, only the configurations of `cases` at
/// their two largest time steps, run in parallel against their case's exact motion alone (no
/// solver truths, no statics: the timing needs the flops and the physical error only).
fn compute_outcomes(cases: &[Case], quick: bool) -> Result<(Vec<CaseTruth>, Vec<Outcome>)> {
    let started = Instant::now();
    let progress = |done: usize, total: usize| {
        if done % 100 == 0 || done == total {
            eprintln!(
                "timing: benchmark errors {done}/{total}  [{:.0} s]",
                started.elapsed().as_secs_f64()
            );
        }
    };
    if !quick {
        let b = Benchmark::compute(cases, &progress)?;
        return Ok((b.truths, b.outcomes));
    }
    let truths = cases
        .iter()
        .map(|&c| CaseTruth::compute(c))
        .collect::<Result<Vec<_>>>()?;
    let jobs: Vec<(Configuration, &CaseTruth)> = truths
        .iter()
        .flat_map(|t| {
            configurations(t.case)
                .into_iter()
                .filter(|c| dts(c.case)[..2].contains(&c.dt_s))
                .map(move |c| (c, t))
        })
        .collect();
    let outcomes = run_parallel(&jobs, |_| 1.0, |(c, t)| run(c, t, None), &progress)
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
    Ok((truths, outcomes))
}

/// The benchmark's configurations of `cases` ([`compute_outcomes`]), every one that finished timed on
/// this thread in batches of at least `batch_seconds`, with progress on stderr.
pub fn time_benchmark(cases: &[Case], quick: bool, batch_seconds: f64) -> Result<Timed> {
    let (truths, outcomes) = compute_outcomes(cases, quick)?;
    let started = Instant::now();
    let mut timed = Timed {
        rows: Vec::new(),
        diverged: 0,
        cpu_flagged: 0,
        batched: 0,
        batch_seconds,
        floors: truths
            .iter()
            .map(|t| (t.case, t.halving_gap / t.amplitude))
            .collect(),
    };
    for (i, o) in outcomes.iter().enumerate() {
        let c = &o.configuration;
        let Ok(measured) = &o.measured else {
            timed.diverged += 1;
            continue;
        };
        let truth = truths
            .iter()
            .find(|t| t.case == c.case)
            .ok_or_else(|| Error::Input(format!("no truth for {}", c.case.label())))?;
        let steps = (truth.window / c.dt_s).round() as usize;
        let system = c.case.scene.system(c.case.stiffness)?;
        let initial = system.initial_state();
        let run = || -> Result<()> {
            let mut solver = build_solver(c, &system)?;
            let mut state = initial.clone();
            for _ in 0..steps {
                solver.step(&mut state)?;
            }
            std::hint::black_box(&state);
            Ok(())
        };
        let t = time_batches(run, batch_seconds, |once| {
            if once > LONG_RUN_S {
                LONG_RUN_REPEATS
            } else {
                REPEATS
            }
        })?;
        timed.cpu_flagged += usize::from(t.cpu_spread - 1.0 > WALL_SPREAD_FLAG);
        timed.batched += usize::from(t.batch > 1);
        let time = RunTime {
            wall_s: t.wall,
            cpu_s: t.cpu,
            wall_spread: t.spread - 1.0,
        };
        timed
            .rows
            .push(WallRow::new(c, time, o.flops, measured.physical.relative));
        if (i + 1) % 100 == 0 || i + 1 == outcomes.len() {
            eprintln!(
                "timing: benchmark timed {}/{}  [{:.0} s]",
                i + 1,
                outcomes.len(),
                started.elapsed().as_secs_f64()
            );
        }
    }
    Ok(timed)
}

impl Timed {
    /// The work-precision figures in wall time, one per case.
    pub fn figures(&self, cases: &[Case]) -> Result<Vec<ChapterFigure>> {
        cases
            .iter()
            .map(|&c| {
                let floor = self.floors.iter().find(|f| f.0 == c).map(|f| f.1);
                figure(&self.rows, c, floor)
            })
            .collect()
    }

    /// TIMING.md's section on the benchmark: how it was timed, the costs compared, the figures
    /// and the flagged configurations.
    pub fn md(&self, timing: &WallTiming, cases: &[Case]) -> String {
        let flagged = self.rows.iter().filter(|r| r.flagged).count();
        let mut md = format!(
            "## The benchmark in wall time\n\n\
             Every dynamics configuration of the benchmark of the report's section 12 \
             (`src/studies/benchmark/`: every solver, setting and time step on each case, over the \
             case's window), its errors and counted flops from one parallel run of the \
             benchmark, as `make report` computes them; {} did not finish the window and are not \
             timed. Each of the {} that did is timed on this thread: the solver built and run \
             over the window as the benchmark runs it (the errors not measured), one run, then \
             {REPEATS} batches of as many runs as last at least {} ms ({} configurations needed \
             more than one run per batch; a run longer than {} ms, {LONG_RUN_REPEATS} batches of \
             one); the least batch mean is its wall time \
             ([`{WALL_CSV}`]({WALL_CSV}), beside its flops and relative physical error), and \
             likewise its thread CPU time. {} configurations' batch means spread by more than \
             {} % in wall time (flagged, counted at the end), {} in the thread's CPU time (the \
             machine is shared: a batch that waited for the core spreads the wall time, not the \
             CPU time).\n\n",
            self.diverged,
            self.rows.len(),
            short(self.batch_seconds * 1e3),
            self.batched,
            short(LONG_RUN_S * 1e3),
            flagged,
            short(WALL_SPREAD_FLAG * 100.0),
            self.cpu_flagged
        );
        md += &costs_compared(timing);
        md += "\n### Work-precision diagrams in wall time\n\n";
        let cited: Vec<String> = cases
            .iter()
            .zip(1..)
            .map(|(case, n)| format!("Figure {n} the {}", case.label()))
            .collect();
        let _ = writeln!(
            md,
            "The report's work-precision diagrams with the wall time for the flops ({}).\n",
            cited.join("; ")
        );
        for (&case, n) in cases.iter().zip(1..) {
            let s = stem(case);
            let _ = writeln!(
                md,
                "![Figure {n}]({s}.svg)\n\n*Figure {n}. {}* Data: [`{WALL_CSV}`]({WALL_CSV}).\n",
                work_figure_caption(
                    &case.label(),
                    "the wall time of a run over the window on one core",
                    self.rows
                        .iter()
                        .any(|r| r.case() == Some(case)
                            && BASELINES.iter().any(|b| b.id() == r.solver))
                )
            );
        }
        let counts: Vec<String> = cases
            .iter()
            .map(|&case| {
                let of_case: Vec<&WallRow> = self
                    .rows
                    .iter()
                    .filter(|r| r.case() == Some(case))
                    .collect();
                format!(
                    "{}: {} of {}",
                    case.label(),
                    of_case.iter().filter(|r| r.flagged).count(),
                    of_case.len()
                )
            })
            .collect();
        let _ = writeln!(
            md,
            "Flagged (wall-time spread of the batch means above {} %; the `flagged` column of \
             [`{WALL_CSV}`]({WALL_CSV})): {}.\n",
            short(WALL_SPREAD_FLAG * 100.0),
            counts.join("; ")
        );
        md
    }
}

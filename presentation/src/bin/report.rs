//! `make report`: runs every experiment the thesis's tables and figures need (once, in
//! parallel), then the forensic configurations of the rows run, reads the committed wall-time
//! measurement of `make timing` (`report/timing/benchmark_wall.csv`, if any; never written
//! here), and replaces `report/`
//! atomically: `REPORT.md`, `figures/*.svg`, `data/*.csv`, `MANIFEST` and the git-ignored
//! `run-info.md`; what the previous report did not write is carried over (see
//! [`mass_spring_report::publish`]). The thesis's experiments, their forensics and
//! the figure runs run on one thread, the chapters beyond the thesis beside them on another
//! (each phase's pool uses every core). Each phase runs through
//! [`Phases::run`](mass_spring_report::output::Phases::run), which prints one line with
//! its wall and CPU time (and its budget, if it has one) to stderr and records them for
//! `run-info.md`; a live counter shows too when stderr is a terminal.

use clap::Parser;
use mass_spring_report::benchmark::wall::WallTiming;
use mass_spring_report::benchmark::BenchmarkChapter;
use mass_spring_report::beyond::BeyondChapter;
use mass_spring_report::continuum::ContinuumChapter;
use mass_spring_report::integrators::IntegratorsChapter;
use mass_spring_report::output::{process_cpu_time, OutputFile, Phases, RunInfo};
use mass_spring_report::publish::{fixture, ReportTarget};
use mass_spring_report::rest_state::Catenary;
use mass_spring_report::runs::FigureRuns;
use mass_spring_report::sheet::SheetChapter;
use mass_spring_report::tutorial::TutorialChapter;
use mass_spring_report::{crate_root, render, repository_containing, ReportData, Sources};
use mass_spring_solvers::error::Failure;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::thesis_protocol;
use mass_spring_solvers::studies::continuum::ChapterSize;
use mass_spring_solvers::studies::experiments::pool::yield_cores_to_other_threads;
use mass_spring_solvers::studies::experiments::{published_rows, PublishedRow};
use mass_spring_solvers::studies::forensics::{Evidence, Forensics};
use mass_spring_solvers::Error;
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// The budget of the chapter beyond the thesis: its convergence curves and acceleration
/// counts (the chapters beyond the thesis together: at most 45 s on 2 cores).
const BEYOND_BUDGET: Duration = Duration::from_secs(10);

/// The budget of the sheet chapter's exact equilibria.
const SHEET_BUDGET: Duration = Duration::from_secs(2);

/// The budget of the benchmark (the rest of the 45 s of the chapters beyond the thesis).
const BENCHMARK_BUDGET: Duration = Duration::from_secs(33);

/// The budget of the optimization-integrators chapter (issue 23: at most 10 s on 2 cores).
const INTEGRATORS_BUDGET: Duration = Duration::from_secs(10);

/// The budget of the continuum's statics (issue 50: the whole issue at most 8 s of CPU more;
/// measured 2.6 s on one core of the development machine).
const CONTINUUM_BUDGET: Duration = Duration::from_secs(5);

/// Files in the synthetic report of `--fixture`: enough that a kill lands inside the write.
const FIXTURE_FILES: usize = 400;

/// The environment variable naming the FIFO a `--fixture` run waits on before publishing.
const FIXTURE_PAUSE: &str = "REPORT_FIXTURE_PAUSE";

/// Regenerates the thesis's chapter 4 (Tables 1-12, Figures 1-15) and the tutorial's chapter
/// into `report/`.
///
/// The output directory is replaced as a whole and atomically; it must be new (in an existing
/// directory), empty, or a report this program wrote (its MANIFEST is the one report writes),
/// and neither a mount point nor holding one. Files in it that the report did not write are
/// kept. One run at a time per directory (a lock file beside it).
///
/// Exit status: 0 success; 1 the run failed; 2 bad input (an option, or an output directory
/// refused before anything runs, and then nothing was changed).
#[derive(Parser, Debug)]
#[command(version)]
struct Args {
    /// Output directory [default: report/ of the repository holding the current directory]
    #[arg(long)]
    out: Option<PathBuf>,
    /// Run only the rows of these tables (comma-separated, 1-7) for a quick partial report;
    /// the report then says which solvers were not run. Default: all 56 rows.
    #[arg(long, value_delimiter = ',', value_parser = clap::value_parser!(u8).range(1..=7))]
    tables: Vec<u8>,
    /// Tests only: write a synthetic report whose files name TAG instead of running anything.
    /// With the environment variable `REPORT_FIXTURE_PAUSE` naming a FIFO, the run waits
    /// between its checks and its publication until a writer opens that FIFO and closes it,
    /// which stands for the computation during which a test changes the target.
    #[arg(long, value_name = "TAG", hide = true)]
    fixture: Option<String>,
}

/// `label: done/total` on one stderr line, only when stderr is a terminal.
fn progress(label: &'static str) -> impl Fn(usize, usize) + Sync {
    let show = std::io::stderr().is_terminal();
    move |done, total| {
        if show {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r{label}: {done}/{total}");
            if done == total {
                let _ = writeln!(err);
            }
        }
    }
}

fn run(args: Args) -> Result<String, Failure> {
    let start = Instant::now();
    let root = crate_root();
    let out = match args.out {
        Some(out) => out,
        None => {
            let cwd = std::env::current_dir()
                .map_err(|e| Error::Input(format!("reading the current directory: {e}")))?;
            repository_containing(&cwd)
                .ok_or_else(|| {
                    Failure::Input(Error::Input(format!(
                        "{} is not inside the mass-spring-solvers repository: give --out DIR",
                        cwd.display()
                    )))
                })?
                .join("report")
        }
    };
    let target = ReportTarget::open(&out).map_err(Failure::Input)?;
    let out = target.dir().to_path_buf();
    for note in target.notes() {
        eprintln!("report: {note}");
    }
    if let Some(tag) = args.fixture {
        let files = fixture(&tag, FIXTURE_FILES);
        if let Some(pause) = std::env::var_os(FIXTURE_PAUSE) {
            // Blocks in the open until the test opens the FIFO for writing, then until it
            // closes it: the test decides when the "computation" ends.
            std::fs::read(&pause).map_err(|e| {
                Error::Input(format!(
                    "reading {FIXTURE_PAUSE} ({}): {e}",
                    PathBuf::from(&pause).display()
                ))
            })?;
        }
        target.publish(&files)?;
        return Ok(format!("wrote the {tag} fixture to {}", out.display()));
    }
    let rows: Vec<PublishedRow> = published_rows()
        .iter()
        .filter(|r| args.tables.is_empty() || args.tables.contains(&r.table) || r.table == 1)
        .cloned()
        .collect();
    // Read the sources first, so that a missing region marker fails before the long runs.
    let solvers: Vec<SolverId> = SolverId::THESIS_TABLES
        .into_iter()
        .filter(|s| rows.iter().any(|r| r.solver == *s))
        .collect();
    let sources = Sources::read(&root, &solvers)?;
    // The committed wall-time measurement of `make timing`, read (never written) before the
    // long runs, from the repository and not from the output directory: the report depends on
    // nothing of this machine's.
    let wall = WallTiming::load(&root.join("report/timing")).map_err(Failure::Input)?;
    // The committed long runs of `make report-long`, read the same way.
    let long = mass_spring_report::benchmark::long::load(&root.join("report/long"))
        .map_err(Failure::Input)?;
    // The chapters beyond the thesis need nothing of its runs: they run beside them, on a
    // thread of their own, so that while the thesis's pool waits for its longest job (the
    // forensic bisection's rounds) the other has the cores. They yield the cores to the
    // thesis's threads, which have them whenever they can use them.
    let (thesis, beyond_thesis) = std::thread::scope(|scope| {
        let beyond_thesis = scope.spawn(|| {
            yield_cores_to_other_threads();
            let mut phases = Phases::default();
            let tutorial = phases.run("the tutorial's chapter", None, TutorialChapter::compute)?;
            let beyond = phases.run(
                "beyond the thesis: newer solvers (parallel)",
                Some(BEYOND_BUDGET),
                || BeyondChapter::compute(&progress("beyond the thesis")),
            )?;
            let sheet = phases.run(
                "the sheet's exact equilibria",
                Some(SHEET_BUDGET),
                SheetChapter::compute,
            )?;
            let benchmark = phases.run(
                "the benchmark: work and precision (parallel)",
                Some(BENCHMARK_BUDGET),
                || BenchmarkChapter::compute(&progress("the benchmark")),
            )?;
            let integrators = phases.run(
                "optimization integrators (parallel)",
                Some(INTEGRATORS_BUDGET),
                || IntegratorsChapter::compute(&progress("optimization integrators")),
            )?;
            let continuum =
                phases.run("the continuum's statics", Some(CONTINUUM_BUDGET), || {
                    ContinuumChapter::compute(ChapterSize::Report)
                })?;
            Ok::<_, Error>((
                phases,
                tutorial,
                beyond,
                sheet,
                benchmark,
                integrators,
                continuum,
            ))
        });
        let thesis = (|| {
            let mut phases = Phases::default();
            // The faithful runs and the forensic ones in one phase: the first forensic batch
            // shares the faithful runs' pool (Forensics::compute_with_faithful).
            let (results, forensics) = phases.run(
                format!(
                    "{} thesis experiments, forensic configurations and gravity mismatch (parallel)",
                    rows.len()
                ),
                None,
                || Forensics::compute_with_faithful(&rows, &progress("experiments and forensics")),
            )?;
            let (runs, catenary) = phases.run("figure runs, sheet and catenary", None, || {
                Ok::<_, Error>((
                    FigureRuns::compute(&results, &progress("figure runs"))?,
                    Catenary::compute()?,
                ))
            })?;
            let real_time = phases.run(
                "the thesis's question at real-time steps (parallel)",
                None,
                || thesis_protocol::real_time_runs(&results),
            )?;
            Ok::<_, Error>((phases, results, forensics, runs, catenary, real_time))
        })();
        let beyond_thesis = beyond_thesis
            .join()
            .expect("the chapters beyond the thesis do not panic");
        (thesis, beyond_thesis)
    });
    let (mut phases, results, forensics, runs, catenary, real_time) = thesis?;
    let (beyond_phases, tutorial, beyond, sheet, mut benchmark, integrators, continuum) =
        beyond_thesis?;
    phases.extend(beyond_phases);
    benchmark.wall = wall;
    benchmark.long = long;
    benchmark.set_protocol(&results, real_time);
    let data = ReportData {
        results,
        forensics: Some(forensics),
        runs,
        catenary,
        tutorial,
        beyond,
        sheet,
        benchmark,
        integrators,
        continuum,
        sources,
    };
    let mut files = phases.run("rendering (Markdown, SVG, CSV)", None, || render(&data))?;
    let reproduced = data
        .results
        .rows
        .iter()
        .filter(|m| mass_spring_report::tables::reproduced(m, data.forensics.as_ref()))
        .count();
    let classes = data.forensics.as_ref().map_or(String::new(), |f| {
        let counts: Vec<String> = Evidence::ALL
            .iter()
            .zip(f.counts(None))
            .map(|(e, n)| format!("{n} {}", e.id()))
            .collect();
        format!("; evidence: {}", counts.join(", "))
    });
    let info = RunInfo {
        phases: phases.into_phases(),
        rows_run: data.results.rows.len(),
        wall: start.elapsed(),
        cpu: process_cpu_time(),
    };
    files.push(OutputFile::text("run-info.md", info.render(&root)));
    target.publish(&files)?;
    Ok(format!(
        "wrote {} files to {} in {:.1} s: {} of {} rows reproduced by the faithful configuration (the rule and the rest-error band){classes}",
        files.len(),
        out.display(),
        start.elapsed().as_secs_f64(),
        reproduced,
        data.results.rows.len()
    ))
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(summary) => {
            println!("{summary}");
            ExitCode::SUCCESS
        }
        Err(failure) => failure.exit("report"),
    }
}

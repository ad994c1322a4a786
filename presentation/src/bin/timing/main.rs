//! `make timing`: what the solvers cost in wall and CPU time on one core, outside the
//! byte-identical report (times differ from run to run).
//!
//! Two studies: the benchmark of the report's section 12 in wall time ([`benchmark`]: every
//! dynamics configuration, its wall time beside its counted flops, where the two costs rank
//! the solvers differently), and how each solver's cost grows with the sheet ([`scaling`]: n =
//! 10 to 320 nodes per side, each point in a child process). Every time is the least of
//! repeated batch means, with the spread beside it, in wall time and in the thread's CPU time
//! (`CLOCK_THREAD_CPUTIME_ID`): the machine is shared ([`measure`]).
//!
//! Writes `report/timing/` (or `--out DIR`): `TIMING.md`, `benchmark_wall.csv` (read by `make
//! report`, which quotes the commit and machine of `machine.csv`), the work-precision figures
//! in wall time `benchmark_wall_<case>.svg`, `scaling.csv`, `bandwidth.csv` and `scaling.svg`.
//! Every output file is checked and opened before the measurements ([`OutputFile`]: a symbolic
//! link among them is refused, a directory this user may not write too) and replaced
//! atomically after them, all or none: a full disk leaves the previous files whole. Exit
//! status 2 for bad input (found before anything is measured), 1 for a failure after.
//! The run holds, from before the files are opened to its end, the lock `report` takes for the
//! directory holding `DIR` when that is a report (`.report.lock` beside `report/` for
//! `report/timing`), else `DIR`'s own lock beside it ([`lock_for_output`]), so that a
//! report run never replaces that directory, and these files with it, while they are written.
//! `--quick` skips the scaling study and times the benchmark's configurations of the soft rope
//! at its two largest time steps only, in batches of 0.1 ms (about a second; for the tests).

mod benchmark;
mod measure;
mod scaling;
mod scaling_md;

use clap::Parser;
use mass_spring_report::benchmark::rows_csv;
use mass_spring_report::benchmark::wall::{WallTiming, MACHINE_CSV, WALL_CSV};
use mass_spring_report::navigation;
use mass_spring_report::publish::lock_for_output;
use mass_spring_solvers::error::{Error, Failure, Result};
use mass_spring_solvers::platform::output_file::{Links, OutputFile};
use measure::{checkout, load_average, machine, machine_md, BATCH_SECONDS};
use scaling::{measure as measure_point, point_line, scaling_study, solvers, SIDES};
use scaling_md::scaling_md;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser)]
#[command(
    about = "The solvers' costs in wall time: writes report/timing/ (TIMING.md, CSVs, figures)"
)]
struct Args {
    /// Output directory (default: report/timing of the crate).
    #[arg(long)]
    out: Option<PathBuf>,
    /// The scaling study's largest sheet, n nodes per side, an integer >= 10 (the study runs its
    /// sides up to it) [default: 320]; the benchmark runs whole whatever it is (--quick times a
    /// part of it and runs no study, so the two are refused together).
    #[arg(long)]
    max_side: Option<usize>,
    /// A quick look (and the tests): no scaling study, and the benchmark's configurations of
    /// the soft rope at its two largest time steps only, in batches of 0.1 ms.
    #[arg(long)]
    quick: bool,
    /// Internal: measure one point (solver id, n) and print it as one line on stdout (no file:
    /// --out is refused with it).
    #[arg(long, num_args = 2, value_names = ["SOLVER", "N"])]
    point: Option<Vec<String>>,
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(message) => {
            println!("{message}");
            ExitCode::SUCCESS
        }
        Err(failure) => failure.exit("timing"),
    }
}

/// The largest n of the study, and of `--point`'s N.
const MAX_SIDE: usize = SIDES[SIDES.len() - 1];

/// The least length of a timed batch of `--quick`, s.
const QUICK_BATCH_SECONDS: f64 = 1e-4;

/// Opens every file of the output directory before the measurements (see the module
/// documentation), creating the directory if it is missing.
fn open_outputs(out: &Path, names: &[String]) -> Result<Vec<(String, OutputFile)>> {
    std::fs::create_dir_all(out)
        .map_err(|e| Error::Input(format!("cannot create {}: {e}", out.display())))?;
    names
        .iter()
        .map(|name| {
            Ok((
                name.clone(),
                OutputFile::open("--out", &out.join(name), Links::Refuse)?,
            ))
        })
        .collect()
}

/// `--point SOLVER N`: one point of the scaling study, measured in this process.
fn point(args: &[String]) -> std::result::Result<String, Failure> {
    let all = solvers();
    let solver = all.iter().find(|s| s.id.id() == args[0]).ok_or_else(|| {
        let ids: Vec<&str> = all.iter().map(|s| s.id.id()).collect();
        Failure::Input(Error::invalid("--point SOLVER", &args[0], &ids.join(", ")))
    })?;
    let n: usize = args[1]
        .parse()
        .ok()
        .filter(|n| (3..=MAX_SIDE).contains(n))
        .ok_or_else(|| {
            Failure::Input(Error::invalid(
                "--point N",
                &args[1],
                &format!("an integer from 3 to {MAX_SIDE}, the study's sizes"),
            ))
        })?;
    Ok(point_line(&measure_point(solver, n)?))
}

fn run(args: Args) -> std::result::Result<String, Failure> {
    if let Some(p) = &args.point {
        if args.out.is_some() {
            return Err(Failure::Input(Error::Input(
                "--out does not apply to --point, which prints its row on stdout and writes no \
                 file"
                    .into(),
            )));
        }
        return point(p);
    }
    if args.quick && args.max_side.is_some() {
        return Err(Failure::Input(Error::Input(
            "--max-side sets the scaling study's largest sheet, and --quick runs no study: give \
             one of them"
                .into(),
        )));
    }
    let root = mass_spring_report::crate_root();
    let out = args.out.unwrap_or_else(|| root.join("report/timing"));
    let max_side = args.max_side.unwrap_or(MAX_SIDE);
    let sides: Vec<usize> = SIDES.into_iter().filter(|&n| n <= max_side).collect();
    if sides.is_empty() {
        return Err(Failure::Input(Error::invalid(
            "--max-side",
            max_side,
            "an integer >= 10",
        )));
    }
    // The lock of the report directory holding the output (report/ for report/timing), held
    // to the end: a report run replacing that directory meanwhile would drop these files.
    let _lock = lock_for_output(&out).map_err(Failure::Input)?;
    let cases = benchmark::cases(args.quick);
    let mut names: Vec<String> = ["TIMING.md", WALL_CSV, MACHINE_CSV]
        .map(String::from)
        .to_vec();
    names.extend(
        cases
            .iter()
            .map(|&c| format!("{}.svg", mass_spring_report::benchmark::wall::stem(c))),
    );
    if !args.quick {
        names.extend(["scaling.csv", "bandwidth.csv", "scaling.svg"].map(String::from));
    }
    let mut outputs = open_outputs(&out, &names).map_err(Failure::Input)?;
    let started = Instant::now();
    let checkout = checkout(&root);
    let load_before = load_average();
    let batch_seconds = if args.quick {
        QUICK_BATCH_SECONDS
    } else {
        // Most configurations run their window in under a millisecond to a few, where one
        // interruption by the scheduler would be the measurement: batches.
        BATCH_SECONDS
    };
    let timed = benchmark::time_benchmark(&cases, args.quick, batch_seconds)?;
    let scaling = if args.quick {
        None
    } else {
        Some(scaling_study(&sides)?)
    };
    let timing = WallTiming::new(
        timed.rows.clone(),
        machine(checkout, load_before, started.elapsed().as_secs_f64()),
    )?;

    let mut md = if args.quick {
        "# A quick look (`timing --quick`): the soft rope at its two largest time steps, no \
         scaling study\n\n"
            .to_string()
    } else {
        "# Timing (`make timing`)\n\nWhat the solvers cost in wall and CPU time on one core, \
         outside the byte-identical report (written by `presentation/src/bin/timing/`): the benchmark of the \
         report's section 12 in wall time, beside its counted flops \
         ([below](#the-benchmark-in-wall-time)), and how each solver's cost grows with the sheet \
         ([Scaling on the sheet](#scaling-on-the-sheet)).\n\n"
            .to_string()
    };
    md += &machine_md(&timing.machine);
    md += &timed.md(&timing, &cases);
    let mut files: Vec<(String, String)> = Vec::new();
    for f in timed.figures(&cases)? {
        files.push((format!("{}.svg", f.stem), f.svg));
    }
    if let Some(study) = &scaling {
        md += &scaling_md(study, cases.len() + 1);
        files.extend(scaling_md::files(study)?);
    }
    // The figures' anchors and every "Figure N" linked, as in REPORT.md.
    files.push(("TIMING.md".into(), navigation::linkify(&md)));
    files.push((WALL_CSV.into(), rows_csv(&timing.rows)));
    files.push((MACHINE_CSV.into(), rows_csv(&[timing.machine])));
    let mut written = Vec::new();
    for (name, text) in &files {
        let at = outputs.iter().position(|(n, _)| n == name).ok_or_else(|| {
            Error::Input(format!("{name} was not opened before the measurements"))
        })?;
        let (_, mut file) = outputs.swap_remove(at);
        file.writer()
            .write_all(text.as_bytes())
            .map_err(|e| Error::Input(format!("--out {}: {e}", out.join(name).display())))?;
        written.push(file);
    }
    OutputFile::finish_all(written)?;
    let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
    Ok(format!(
        "wrote {} to {} in {:.0} s",
        names.join(", "),
        out.display(),
        started.elapsed().as_secs_f64()
    ))
}

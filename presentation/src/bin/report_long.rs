//! `make report-long`: the benchmark's long runs ([`mass_spring_report::benchmark::long`]),
//! deterministic, into `report/long/` (or `--out DIR`): what does not fit `make report`'s
//! budget. The file is checked and opened before the runs and replaced atomically after them;
//! the run holds the lock `report` takes for the directory holding `DIR` when that is a report,
//! else `DIR`'s own ([`lock_for_output`]). Exit status 2 for
//! bad input, 1 for a failure after.

use clap::Parser;
use mass_spring_report::benchmark::long::LONG_CSV;
use mass_spring_report::benchmark::rows_csv;
use mass_spring_report::publish::lock_for_output;
use mass_spring_solvers::error::{Error, Failure};
use mass_spring_solvers::platform::output_file::{Links, OutputFile};
use mass_spring_solvers::studies::benchmark::{Benchmark, Case};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "The benchmark's long runs: writes report/long/ (deterministic CSV)")]
struct Args {
    /// Output directory (default: report/long of the crate).
    #[arg(long)]
    out: Option<PathBuf>,
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(message) => {
            println!("{message}");
            ExitCode::SUCCESS
        }
        Err(failure) => failure.exit("report_long"),
    }
}

fn run(args: Args) -> Result<String, Failure> {
    let started = Instant::now();
    let out = args
        .out
        .unwrap_or_else(|| mass_spring_report::crate_root().join("report/long"));
    let _lock = lock_for_output(&out).map_err(Failure::Input)?;
    std::fs::create_dir_all(&out).map_err(|e| {
        Failure::Input(Error::Input(format!(
            "cannot create {}: {e}",
            out.display()
        )))
    })?;
    let mut file =
        OutputFile::open("--out", &out.join(LONG_CSV), Links::Refuse).map_err(Failure::Input)?;
    let progress = |done: usize, total: usize| eprint!("\rreport_long: {done} of {total} runs");
    let benchmark = Benchmark::compute_long(&Case::ALL, &progress)?;
    eprintln!();
    file.writer()
        .write_all(rows_csv(&benchmark.rows()).as_bytes())
        .map_err(|e| Error::Input(format!("--out {}: {e}", out.join(LONG_CSV).display())))?;
    OutputFile::finish_all(vec![file])?;
    Ok(format!(
        "wrote {LONG_CSV} to {} in {:.0} s",
        out.display(),
        started.elapsed().as_secs_f64()
    ))
}

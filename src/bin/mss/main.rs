//! `mss`: one-off runs of the thesis's solvers (Backward Euler, XPBD, Liu 2013's fast
//! mass-spring, ADMM ⊇ PD) and the tutorial's integrators (explicit Euler, symplectic Euler,
//! RK4) on the thesis rope, an N-node rope, the cloths, the tutorial's pendulum or a TOML scene
//! file, measured as in thesis §4.2 (kinetic-energy peaks, the stopping rule, T/2 under the
//! thesis and the exact conventions, the rest-state error against the Backward Euler reference).
//!
//! Exit status: 0 on success, 2 for bad input (an option or a scene file out of range, a path
//! that cannot be written), 1 for a run that failed (diverged, or a step that failed).

mod cli;
mod continuum;
mod continuum_dynamics;
mod failure;
mod output;
mod scene;
mod settings;

use clap::Parser;
use cli::{scene_name, Cli};
use failure::Failure;
use mass_spring_solvers::error::{shown, Error};
use mass_spring_solvers::integrators::optimization_integrator::OptimizationIntegrator;
use mass_spring_solvers::integrators::time_stepper::{simulate, simulate_into, Run, RunOptions};
use mass_spring_solvers::platform::output_file::OutputFile;
use mass_spring_solvers::solvers::backward_euler::{
    BackwardEuler, REFERENCE_DT, REFERENCE_NEWTON_ITERATIONS,
};
use mass_spring_solvers::solvers::budget::DOPRI_EVALUATIONS;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::reproduces;
use output::{
    published_row, reference_summary, write_text, CsvRecorder, PublishedSummary, Report,
    RunSummary, SceneSummary, StopSummary,
};
use scene::{build_scene, build_stepper};
use settings::{check_work, list_solvers, settings};
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

fn run(cli: &Cli) -> Result<(), Failure> {
    if cli.scene.is_continuum() && cli.scene_file.is_none() {
        return continuum::run(cli);
    }
    if let Some(option) = [
        ("--energy", cli.energy.is_some()),
        ("--youngs", cli.youngs.is_some()),
        ("--duration", cli.duration.is_some()),
    ]
    .iter()
    .find_map(|(option, given)| given.then_some(option))
    {
        return Err(Failure::input(format!(
            "{option} applies to the continuum scenes only (beam, membrane, cook, patch; the scene is {})",
            scene_name(cli)
        )));
    }
    let mut settings = settings(cli)?;
    let scene = scene_name(cli);
    let model = build_scene(cli, &settings)?;
    settings.spec.params.adaptive_attempts =
        check_work(cli, &settings, model.system(), model.drag())?;
    let mut summary = SceneSummary::new(scene.clone(), model.system());
    let published = published_row(cli, &settings, model.system());
    let reference_system = if cli.compare_reference {
        Some(model.springs_only(&scene)?)
    } else {
        None
    };
    let (mut stepper, applied) = build_stepper(&settings.spec, model, &scene, cli.dt)?;
    summary.applied = applied;
    let mut outputs =
        OutputFile::open_all(&cli.requested_outputs(), cli.scene_file.as_deref())?.into_iter();
    let mut csv = CsvRecorder {
        dt: cli.dt,
        ke: cli.ke_csv.as_ref().and_then(|_| outputs.next()),
        positions: cli.positions_csv.as_ref().and_then(|_| outputs.next()),
        failed: false,
    };
    csv.headers()
        .map_err(|e| Failure::run(format!("writing the CSV headers: {e}")))?;

    let start = Instant::now();
    let initial = stepper.system().initial_state();
    let outcome = simulate_into(stepper.as_mut(), initial, &settings.options, &mut csv)
        .map_err(|e| match e {
            // The files' fault, not the input's.
            Error::Input(message) if csv.failed => Failure::run(message),
            // rk45 stopped by its cap: say which budget and what to change.
            e @ Error::StepFailed { .. } if settings.spec.params.adaptive_attempts.is_some() => {
                let mut failure = Failure::from(e);
                if failure.message.contains("work budget") {
                    failure.message += &format!(
                        "; --max-work {} allows that many steps of {DOPRI_EVALUATIONS} force \
                         evaluations over the springs: raise --max-work, loosen --tolerance or \
                         shorten --max-time",
                        shown(cli.max_work)
                    );
                }
                failure
            }
            e => Failure::from(e),
        })
        .and_then(|run| {
            // The report's reference: the thesis's stopping rule, no damping. A run with
            // exactly its parameters is its own reference.
            let reference_options = RunOptions::default();
            let is_reference = settings.spec.id == SolverId::BackwardEuler
                && settings.spec.params.integrator == OptimizationIntegrator::BackwardEuler
                && cli.dt == REFERENCE_DT
                && settings.spec.iterations == REFERENCE_NEWTON_ITERATIONS
                && settings.options.stop == reference_options.stop
                && settings.options.velocity_damping == reference_options.velocity_damping;
            let reference = reference_system
                .map(|system| {
                    if is_reference {
                        return Ok(Run {
                            kinetic_energy: Vec::new(),
                            positions: Vec::new(),
                            ..run.clone()
                        });
                    }
                    let mut reference = BackwardEuler::reference(&system)?;
                    simulate(&mut reference, system.initial_state(), &reference_options)
                })
                .transpose()
                .map_err(|e| Failure::from(e).with_context("reference run"))?;
            Ok((run, reference))
        });
    // A failed run drops its outputs, which leaves every destination as it was.
    let (run, reference) = outcome?;
    let wall_time_s = start.elapsed().as_secs_f64();
    // Per time step: a step of a two-stage integrator logs two stage solves.
    let iterations_mean = stepper
        .iteration_log()
        .filter(|_| run.steps > 0)
        .map(|log| log.iterations() as f64 / run.steps as f64);

    // Every series written to its end before any replaces its file.
    OutputFile::finish_all(csv.ke.into_iter().chain(csv.positions).collect())
        .map_err(|e| Failure::run(e.to_string()))?;
    let takes_integrator = settings
        .spec
        .id
        .info()
        .options
        .iter()
        .any(|o| o.name == "integrator");
    let report = Report {
        solver: cli.solver.id().to_string(),
        integrator: takes_integrator.then(|| settings.spec.params.integrator.key().to_string()),
        scene: summary,
        dt_s: cli.dt,
        iterations: (settings.spec.id.info().iteration.is_some())
            .then_some(settings.spec.iterations),
        stop_tolerance_m: settings.spec.stopping.tolerance_m(),
        iterations_mean,
        stop: StopSummary {
            threshold_j: settings.options.stop.threshold,
            max_time_s: settings.options.stop.max_time,
            exempt_first_peak: settings.options.stop.exempt_first_peak,
        },
        velocity_damping_per_s: settings.options.velocity_damping,
        published: published.map(|row| PublishedSummary {
            table: row.table,
            ke_peaks: row.ke_peaks,
            half_period_s: row.half_period_s,
            error: row.error,
            period_rel_error: row.period_rel_error,
            reproduced: reproduces(row, run.peak_count(), run.half_period_thesis()),
        }),
        reference: reference
            .as_ref()
            .map(|reference| reference_summary(&run, reference)),
        run: RunSummary::from(&run),
        wall_time_s,
    };
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let written = if cli.json {
        serde_json::to_writer_pretty(&mut out, &report)
            .map_err(std::io::Error::from)
            .and_then(|()| writeln!(out))
    } else {
        write_text(&mut out, &report)
    };
    match written.and_then(|()| out.flush()) {
        // A reader that stops early (`mss | head`) is not a failed run.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.map_err(|e| Failure::run(format!("writing the metrics: {e}"))),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if cli.list_solvers {
        print!("{}", list_solvers());
        return ExitCode::SUCCESS;
    }
    if cli.list_energies {
        print!("{}", continuum::list_energies());
        return ExitCode::SUCCESS;
    }
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            // Nothing more can be done if stderr is closed.
            let _ = writeln!(std::io::stderr(), "error: {}", failure.message);
            ExitCode::from(failure.status)
        }
    }
}

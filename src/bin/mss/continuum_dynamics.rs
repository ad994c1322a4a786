//! `mss --scene beam|membrane|cook|patch --duration S`: the continuum scene released from rest
//! and run for S seconds under `--integrator` with `--dt`, every stage solved by projected
//! Newton (`src/integrators/continuum.rs`); its kinetic energy and positions written like the
//! spring scenes' (`--ke-csv`, `--positions-csv`; a plane scene's z is 0).

use crate::cli::{Cli, SceneArg, DEFAULT_POSITIONS_EVERY};
use crate::failure::Failure;
use crate::output::CsvRecorder;
use mass_spring_solvers::error::{require_within, shown};
use mass_spring_solvers::integrators::continuum::{
    ContinuumIntegrator, ContinuumState, DEFAULT_TOLERANCE,
};
use mass_spring_solvers::integrators::optimization_integrator::OptimizationIntegrator;
use mass_spring_solvers::integrators::time_stepper::Recorder;
use mass_spring_solvers::model::continuum::scenes::beam_tip_deflection;
use mass_spring_solvers::model::continuum::system::ContinuumSystem;
use mass_spring_solvers::model::system::{State, Vec3};
use mass_spring_solvers::platform::output_file::OutputFile;

/// The longest `--duration`, s.
const MAX_DURATION: f64 = 1e4;
/// The most steps × elements a run may take (about an hour of Newton on this machine).
const MAX_ELEMENT_STEPS: f64 = 1e9;

/// The nodes' positions (rest plus displacement) as the spring scenes' state, z = 0 in the
/// plane.
fn positions(system: &ContinuumSystem, state: &ContinuumState) -> State {
    let d = system.dimension();
    let x = system.rest_positions();
    let point = |i: usize, data: &[f64], base: &[f64]| {
        Vec3::from_fn(|c, _| {
            if c < d {
                base[i * d + c] + data[i * d + c]
            } else {
                0.0
            }
        })
    };
    let zeros = vec![0.0; x.len()];
    State {
        x: (0..system.node_count())
            .map(|i| point(i, &state.u, x))
            .collect(),
        v: (0..system.node_count())
            .map(|i| point(i, &state.v, &zeros))
            .collect(),
    }
}

/// Runs the dynamics and prints what it reached.
pub(crate) fn run(
    cli: &Cli,
    system: &ContinuumSystem,
    duration: f64,
    n: usize,
) -> Result<(), Failure> {
    let duration = require_within("--duration", duration, 1e-9, MAX_DURATION, "s")?;
    let dt = require_within("--dt", cli.dt, 1e-9, duration, "s (at most --duration)")?;
    let integrator = match &cli.integrator {
        Some(name) => name.parse::<OptimizationIntegrator>().map_err(|_| {
            Failure::input(format!(
                "--integrator {name}: expected one of backward-euler, implicit-midpoint, \
                 bdf2, tr-bdf2"
            ))
        })?,
        None => OptimizationIntegrator::BackwardEuler,
    };
    let steps = (duration / dt).round().max(1.0);
    if steps * system.elements().len() as f64 > MAX_ELEMENT_STEPS {
        return Err(Failure::input(format!(
            "--duration / --dt: {} steps of {} elements is over {} element updates; shorten \
             --duration or lengthen --dt",
            shown(steps),
            system.elements().len(),
            shown(MAX_ELEMENT_STEPS)
        )));
    }
    let steps = steps as u64;
    let every = cli
        .positions_every
        .map_or(Ok(DEFAULT_POSITIONS_EVERY), |e| {
            require_within("--positions-every", e as f64, 1.0, 1e18, "steps").map(|e| e as u64)
        })?;
    let mut stepper = ContinuumIntegrator::new(system, integrator, dt, DEFAULT_TOLERANCE)?;
    let mut outputs = OutputFile::open_all(&cli.requested_outputs(), None)?.into_iter();
    let mut csv = CsvRecorder {
        dt,
        ke: cli.ke_csv.as_ref().and_then(|_| outputs.next()),
        positions: cli.positions_csv.as_ref().and_then(|_| outputs.next()),
        failed: false,
    };
    let io = |e: std::io::Error| Failure::run(format!("writing the CSV: {e}"));
    csv.headers().map_err(io)?;
    let mut state = ContinuumState::released(system);
    let mut largest_kinetic: f64 = 0.0;
    for step in 0..=steps {
        if step > 0 {
            stepper
                .step(&mut state)
                .map_err(|e| Failure::from(e).with_context(&format!("step {step} of {steps}")))?;
        }
        let kinetic = state.kinetic_energy(system);
        largest_kinetic = largest_kinetic.max(kinetic);
        csv.kinetic_energy(step, kinetic).map_err(io)?;
        if step % every == 0 || step == steps {
            csv.positions(step, &positions(system, &state))
                .map_err(io)?;
        }
    }
    OutputFile::finish_all(csv.ke.into_iter().chain(csv.positions).collect())
        .map_err(|e| Failure::run(e.to_string()))?;
    let log = stepper.log();
    println!(
        "scene: {}, energy: {}, nodes: {}, elements: {}",
        cli.scene.id(),
        system.material().energy.name(),
        system.node_count(),
        system.elements().len()
    );
    println!(
        "integrator: {}, dt {} s, {steps} steps to t = {} s",
        integrator.key(),
        shown(dt),
        shown(steps as f64 * dt)
    );
    println!(
        "Newton: {} iterations in {} stages, largest residual {:.2e} of the largest load \
         (tolerance {:.0e})",
        log.iterations, log.stages, log.largest_residual, DEFAULT_TOLERANCE
    );
    println!(
        "kinetic energy: largest {:.6e} J, final {:.6e} J",
        largest_kinetic,
        state.kinetic_energy(system)
    );
    if cli.scene == SceneArg::Beam {
        println!(
            "tip deflection at the end: {:.6e} m",
            beam_tip_deflection(n, &state.u)
        );
    }
    Ok(())
}

//! The options checked before a run: every value in range, every option used by the chosen
//! scene and method, and the run's memory and work within their budgets.

use crate::cli::{
    scene_name, Cli, SceneArg, ASSUMED_MEMORY, DEFAULT_ITERATIONS, DEFAULT_POSITIONS_EVERY,
};
use crate::failure::Failure;
use mass_spring_solvers::error::{require_within, shown, Error};
use mass_spring_solvers::integrators::time_stepper::{Recording, RunOptions};
use mass_spring_solvers::model::metrics::{Peak, StoppingRule};
use mass_spring_solvers::model::system::MassSpringSystem;
use mass_spring_solvers::particles::scene_file::LIMITS;
use mass_spring_solvers::platform::memory::available_memory;
use mass_spring_solvers::solvers::backward_euler::{REFERENCE_DT, REFERENCE_NEWTON_ITERATIONS};
use mass_spring_solvers::solvers::budget::{
    adaptive_steps, fastest_rate, memory_bytes, Shape, BASE_BYTES, DOPRI_EVALUATIONS,
    DOPRI_STABILITY,
};
use mass_spring_solvers::solvers::registry::{SolverId, SolverParams, SolverSpec};

/// The solver options given on the command line, by their registry name.
fn solver_options(cli: &Cli) -> [(&'static str, Option<String>); 19] {
    let text = |x: Option<f64>| x.map(|x| x.to_string());
    // As `--solver` reads `-` as `_`, `--first-iterate` reads `_` as `-`.
    let first_iterate = cli.first_iterate.as_ref().map(|i| i.replace('_', "-"));
    [
        ("tolerance", text(cli.tolerance)),
        ("stiffness_factor", text(cli.stiffness_factor)),
        ("spectral_radius", text(cli.spectral_radius)),
        ("gamma", text(cli.gamma)),
        ("warmup", text(cli.warmup)),
        ("window", text(cli.window)),
        ("alpha", text(cli.alpha)),
        ("beta", text(cli.beta)),
        ("history", text(cli.history)),
        ("first_iterate", first_iterate),
        ("rho_rule", cli.rho_rule.clone()),
        ("safeguard", cli.safeguard.clone()),
        ("hessian", cli.hessian.clone()),
        ("constraint_damping", text(cli.constraint_damping)),
        ("sweep", cli.sweep.clone()),
        ("integrator", cli.integrator.clone()),
        ("rayleigh_form", cli.rayleigh_form.clone()),
        ("drag", text(cli.drag)),
        ("drag_exponent", text(cli.drag_exponent)),
    ]
}

/// The solver with its iterations and options, each checked against the registry's entry.
fn solver_spec(cli: &Cli) -> Result<SolverSpec, Failure> {
    let info = cli.solver.info();
    let iterations = match (info.iteration, cli.iterations) {
        (Some(_), None) => DEFAULT_ITERATIONS,
        (Some(_), Some(n)) => check_count("--iterations", n, 1)?,
        (None, None) => 1,
        (None, Some(n)) => {
            return Err(Error::invalid(
                "--iterations",
                n,
                &format!("not given: {} takes no iterations", info.id),
            )
            .into())
        }
    };
    let mut spec = SolverSpec::new(cli.solver, iterations);
    if let Some(tolerance) = cli.stop_tolerance {
        if !cli.solver.stops_at_tolerance() {
            return Err(Error::invalid(
                "--stop-tolerance",
                tolerance,
                &format!("not given: {} has no iterations to stop", info.id),
            )
            .into());
        }
        spec = spec.to_tolerance(tolerance).map_err(|e| match e {
            Error::InvalidParameter { value, allowed, .. } => Error::InvalidParameter {
                field: "--stop-tolerance".into(),
                value,
                allowed,
            },
            other => other,
        })?;
    }
    for (name, value) in solver_options(cli) {
        let Some(value) = value else { continue };
        let option = format!("--{}", name.replace('_', "-"));
        if !info.options.iter().any(|o| o.name == name) {
            let takers: Vec<&str> = SolverId::ALL
                .iter()
                .filter(|s| s.info().options.iter().any(|o| o.name == name))
                .map(|s| s.id())
                .collect();
            return Err(Error::invalid(
                option,
                value,
                &format!(
                    "not given: {} has no such option ({} has)",
                    info.id,
                    takers.join(", ")
                ),
            )
            .into());
        }
        spec.params.set(name, &value).map_err(|e| match e {
            Error::InvalidParameter { value, allowed, .. } => Error::InvalidParameter {
                field: option,
                value,
                allowed,
            },
            e => e,
        })?;
    }
    Ok(spec)
}

/// `--list-solvers`: one line a solver.
pub(crate) fn list_solvers() -> String {
    let mut out = String::new();
    for id in SolverId::ALL {
        let info = id.info();
        let iterations = info.iteration.map_or_else(
            || "no iterations".to_string(),
            |i| format!("iteration: {i}"),
        );
        let options: Vec<String> = info
            .options
            .iter()
            .map(|o| format!("--{} ({})", o.name.replace('_', "-"), o.help))
            .collect();
        let options = if options.is_empty() {
            String::new()
        } else {
            format!("; options: {}", options.join(", "))
        };
        out += &format!(
            "{:<18} {} [{}; {iterations}{options}]\n",
            info.id, info.summary, info.source
        );
    }
    out
}

/// Rejects `value` unless it is finite and in range, naming the option and its unit.
pub(crate) fn check(option: &str, value: f64, ok: bool, allowed: &str) -> Result<f64, Failure> {
    if value.is_finite() && ok {
        Ok(value)
    } else {
        Err(Error::invalid(option, shown(value), allowed).into())
    }
}

/// Rejects an integer outside `min..=max`, naming the option (a size option: bounded before
/// anything is allocated).
pub(crate) fn check_range(option: &str, value: i64, min: i64, max: i64) -> Result<usize, Failure> {
    usize::try_from(value)
        .ok()
        .filter(|_| (min..=max).contains(&value))
        .ok_or_else(|| {
            Error::invalid(
                option,
                value,
                &format!(
                    "an integer from {min} to {max}; the memory estimate of the solver may allow \
                     fewer"
                ),
            )
            .into()
        })
}

/// Rejects an integer below `min`, naming the option.
pub(crate) fn check_count(option: &str, value: i64, min: i64) -> Result<usize, Failure> {
    usize::try_from(value)
        .ok()
        .filter(|_| value >= min)
        .ok_or_else(|| Error::invalid(option, value, &format!("an integer >= {min}")).into())
}

/// Bytes of one entry of the per-step histogram of iterations (`IterationLog`, a B-tree of
/// (count, steps) pairs): a node of at most 11 pairs of 16 bytes and its links, some 200
/// bytes, is at least 5 pairs full, plus the inner nodes' share.
const HISTOGRAM_ENTRY_BYTES: f64 = 48.0;

/// What a run of `steps` steps of at most `iterations` iterations keeps as it goes, besides its
/// state, in bytes, at most: its histogram of iterations (one entry a count some step took, so
/// no more than the steps nor the counts there are) and the kinetic-energy peaks of its stopping
/// rule (at most one every other step). The series of `--ke-csv` and `--positions-csv` go to
/// their files as the run goes and take no memory that grows with it.
fn per_step_bytes(steps: f64, iterations: f64) -> f64 {
    let histogram = steps.min(iterations + 1.0) * HISTOGRAM_ENTRY_BYTES;
    let peaks = (steps / 2.0).ceil() * std::mem::size_of::<Peak>() as f64;
    histogram + peaks
}

/// Refuses, before it starts, a run whose memory estimate ([`memory_bytes`], the reference
/// run's added) is over `--max-memory`, or over the memory available when it is not given.
/// With `steps`, the run's steps once the work budget has allowed them ([`check_work`]), what
/// the run keeps per step ([`per_step_bytes`]) is counted too; before that (the scene's size
/// checked before it is built) it is not.
pub(crate) fn check_memory(
    cli: &Cli,
    settings: &Settings,
    shape: Shape,
    steps: Option<f64>,
) -> Result<(), Failure> {
    let id = settings.spec.id;
    let mut estimate = memory_bytes(id, &settings.spec.params, shape);
    if let Some(steps) = steps {
        estimate += per_step_bytes(steps, settings.spec.iterations as f64);
    }
    let mut reference = String::new();
    if cli.compare_reference {
        let params = SolverParams::default();
        estimate += memory_bytes(SolverId::BackwardEuler, &params, shape) - BASE_BYTES;
        if steps.is_some() {
            let reference_steps = (RunOptions::default().stop.max_time / REFERENCE_DT).ceil();
            estimate += per_step_bytes(reference_steps, REFERENCE_NEWTON_ITERATIONS as f64);
        }
        reference = ", with the Backward Euler reference beside it".into();
    }
    let (limit, whence) = match cli.max_memory {
        Some(limit) => (limit, String::new()),
        None => (
            available_memory().map_or(ASSUMED_MEMORY, |b| b as f64),
            " (the default: the memory available to this process)".into(),
        ),
    };
    if estimate <= limit {
        return Ok(());
    }
    Err(Failure::input(format!(
        "invalid --max-memory: {} bytes{whence} (allowed: at least this run's estimate of \
         {estimate:.3e} bytes, {:.1} GiB: {id} on {} nodes and {} springs{reference}, at the \
         peak memory a node measured for it, src/solvers/budget.rs, and its histogram of \
         iterations and energy peaks, at most one entry a step); take a smaller scene or a leaner \
         solver, or raise --max-memory",
        shown(limit),
        estimate / (1u64 << 30) as f64,
        shape.nodes,
        shape.springs
    )))
}

/// Refuses, before it starts, a run that needs more than `--max-work` spring updates, then one
/// whose memory with what it keeps per step is over the limit ([`check_memory`]): every
/// step of the run (rk45's adaptive steps estimated from the scene's fastest rate) and the
/// reference run of `--compare-reference` at its own stopping rule. Returns the cap on rk45's
/// attempted steps, the budget left for it, which stops it if the estimate was short. `drag`
/// is the scene's viscous drag, N·s/m (it speeds up the fastest rate).
pub(crate) fn check_work(
    cli: &Cli,
    settings: &Settings,
    system: &MassSpringSystem,
    drag: f64,
) -> Result<Option<u64>, Failure> {
    let max_time = settings.options.stop.max_time;
    let springs = system.springs().len().max(1) as f64;
    let rk45 = settings.spec.id == SolverId::Rk45;
    let (steps, per_step, mut parts) = if rk45 {
        let steps = adaptive_steps(system, drag, max_time, cli.dt);
        let parts = format!(
            "{steps:.3e} adaptive steps (estimated: the scene's fastest rate, {:.3e} 1/s, over \
             Dormand-Prince's stability bound {DOPRI_STABILITY}, at least one per --dt) × \
             {DOPRI_EVALUATIONS} force evaluations × {springs} springs",
            fastest_rate(system, drag)
        );
        (steps, DOPRI_EVALUATIONS, parts)
    } else {
        let steps = (max_time / cli.dt).ceil();
        let iterations = settings.spec.iterations as f64;
        let parts = format!(
            "{steps:.3e} steps (--max-time / --dt) × {iterations} iterations × {springs} springs"
        );
        (steps, iterations, parts)
    };
    let mut work = steps * per_step * springs;
    let mut reference_work = 0.0;
    if cli.compare_reference {
        // The reference stops by the thesis's rule: at 3000 s at the latest.
        let reference_time = RunOptions::default().stop.max_time;
        let reference_steps = (reference_time / REFERENCE_DT).ceil();
        reference_work = reference_steps * REFERENCE_NEWTON_ITERATIONS as f64 * springs;
        work += reference_work;
        parts += &format!(
            ", and the reference run's {reference_steps:.3e} steps (up to {} s at dt = {} s) × \
             {REFERENCE_NEWTON_ITERATIONS} iterations × {springs} springs",
            shown(reference_time),
            shown(REFERENCE_DT)
        );
    }
    if work <= cli.max_work {
        check_memory(cli, settings, Shape::of(system), Some(steps))?;
        let attempts = (cli.max_work - reference_work) / (DOPRI_EVALUATIONS * springs);
        return Ok(rk45.then_some(attempts.floor() as u64));
    }
    let advice = if rk45 {
        "rk45's steps are bound by the stiffest spring on the lightest node, whatever its \
         tolerance: take a softer or heavier scene or a shorter --max-time"
    } else {
        "take a larger --dt, a shorter --max-time or fewer --iterations"
    };
    Err(Failure::input(format!(
        "invalid --max-work: the run needs about {work:.3e} spring updates ({parts}), more than \
         the budget of {}; {advice}, or raise --max-work",
        shown(cli.max_work)
    )))
}

/// The shortest `--dt` and `--max-time`, s.
const MIN_TIME: f64 = 1e-9;

/// The longest `--dt` and `--max-time`, s: some 30 years.
const MAX_TIME: f64 = 1e9;

/// The largest `--threshold`, J: far above any scene's energy within the scene files' bounds.
const MAX_THRESHOLD: f64 = 1e12;

/// The largest `--velocity-damping`, 1/s: Rayleigh's `--alpha`'s bound.
const MAX_VELOCITY_DAMPING: f64 = 1e6;

/// The largest `--max-work` (spring updates) and `--max-memory` (bytes): past it a budget is
/// none.
const MAX_BUDGET: f64 = 1e18;

/// The options, checked: every value in range, every option used by the chosen scene and method.
#[derive(Debug)]
pub(crate) struct Settings {
    pub(crate) spec: SolverSpec,
    pub(crate) options: RunOptions,
}

pub(crate) fn settings(cli: &Cli) -> Result<Settings, Failure> {
    let spec = solver_spec(cli)?;
    // A step below 1e-9 s is no time step of these scenes (and prints as hundreds of digits).
    require_within("--dt", cli.dt, MIN_TIME, MAX_TIME, "s")?;
    if let Some(k) = cli.stiffness {
        check("--stiffness", k, k > 0.0, "a number > 0, in N/m")?;
        LIMITS.stiffness.check("--stiffness", k)?;
    }
    if let Some(g) = cli.gravity {
        LIMITS.gravity.check("--gravity", g)?;
    }
    check(
        "--max-work",
        cli.max_work,
        (1.0..=MAX_BUDGET).contains(&cli.max_work),
        &format!(
            "a number from 1 to {}, in spring updates",
            shown(MAX_BUDGET)
        ),
    )?;
    if let Some(m) = cli.max_memory {
        require_within("--max-memory", m, 1e6, MAX_BUDGET, "bytes")?;
    }
    let rope_only = [
        ("--nodes", cli.nodes.is_some()),
        ("--rest-length", cli.rest_length.is_some()),
        ("--node-mass", cli.node_mass.is_some()),
        ("--span", cli.span.is_some()),
    ];
    if cli.n.is_some() && (cli.scene != SceneArg::Sheet || cli.scene_file.is_some()) {
        return Err(Failure::input(format!(
            "--n applies to --scene sheet only (the scene is {})",
            scene_name(cli)
        )));
    }
    if cli.scene != SceneArg::Rope || cli.scene_file.is_some() {
        if let Some((option, _)) = rope_only.iter().find(|(_, given)| *given) {
            return Err(Failure::input(format!(
                "{option} applies to --scene rope only (the scene is {})",
                scene_name(cli)
            )));
        }
    }
    let threshold = check(
        "--threshold",
        cli.threshold,
        cli.threshold > 0.0 && cli.threshold <= MAX_THRESHOLD,
        &format!("a number > 0 and at most {}, in J", shown(MAX_THRESHOLD)),
    )?;
    let max_time = require_within("--max-time", cli.max_time, MIN_TIME, MAX_TIME, "s")?;
    if cli.dt > max_time {
        return Err(Error::invalid(
            "--dt",
            shown(cli.dt),
            &format!(
                "at most --max-time ({} s): a longer step is never taken",
                shown(max_time)
            ),
        )
        .into());
    }
    let velocity_damping = require_within(
        "--velocity-damping",
        cli.velocity_damping,
        0.0,
        MAX_VELOCITY_DAMPING,
        "1/s",
    )?;
    let positions_every = match (&cli.positions_csv, cli.positions_every) {
        (None, _) => None,
        (Some(_), None) => Some(DEFAULT_POSITIONS_EVERY),
        (Some(_), Some(n)) => Some(check_count("--positions-every", n, 1)? as u64),
    };
    Ok(Settings {
        spec,
        options: RunOptions {
            stop: StoppingRule {
                threshold,
                max_time,
                exempt_first_peak: cli.exempt_first_peak,
            },
            velocity_damping,
            recording: Recording {
                kinetic_energy: cli.ke_csv.is_some(),
                positions_every,
            },
        },
    })
}

//! `mss`: one-off runs of the thesis's solvers (Backward Euler, XPBD, Liu 2013's fast
//! mass-spring, ADMM ⊇ PD) and the tutorial's integrators (explicit Euler, symplectic Euler,
//! RK4) on the thesis rope, an N-node rope, the cloths, the tutorial's pendulum or a TOML scene
//! file, measured as in thesis §4.2 (kinetic-energy peaks, the stopping rule, T/2 under the
//! thesis and the exact conventions, the rest-state error against the Backward Euler reference).
//!
//! Exit status: 0 on success, 2 for bad input (an option or a scene file out of range, a path
//! that cannot be written), 1 for a run that failed (diverged, or a step that failed).

use clap::{Parser, ValueEnum};
use mass_spring_solvers::backward_euler::{
    BackwardEuler, REFERENCE_DT, REFERENCE_NEWTON_ITERATIONS,
};
use mass_spring_solvers::error::Error;
use mass_spring_solvers::experiments::{published_rows, reproduces, PublishedRow, SolverKind};
use mass_spring_solvers::metrics::{
    rest_error_l2, rest_error_max, rest_error_sum, Peak, StoppingRule, MAX_SIMULATED_TIME_S,
    STOP_THRESHOLD_J,
};
use mass_spring_solvers::output_file::OutputFile;
use mass_spring_solvers::particles::scenes::{ClothDropParams, ClothParams, PendulumParams};
use mass_spring_solvers::particles::{
    AdaptiveStepper, Integrator, ParticleStepper, ParticleSystem,
};
use mass_spring_solvers::scene::{RopeParams, THESIS_GRAVITY, THESIS_NODES, THESIS_STIFFNESSES};
use mass_spring_solvers::scene_file::{self, SceneFile, LIMITS};
use mass_spring_solvers::solver::{
    simulate, simulate_into, Recorder, Recording, Run, RunOptions, TimeStepper,
};
use mass_spring_solvers::system::{MassSpringSystem, State, Vec3};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Iterations per step when `--iterations` is not given (the reference's Newton iterations).
const DEFAULT_ITERATIONS: usize = REFERENCE_NEWTON_ITERATIONS;
/// Steps between recorded positions when `--positions-every` is not given: keeps the series of
/// a long run (hundreds of thousands of steps) small.
const DEFAULT_POSITIONS_EVERY: u64 = 10;
/// Error tolerance of rk45 when `--tolerance` is not given.
const DEFAULT_TOLERANCE: f64 = 1e-6;
/// Stiffness of the built-in ropes when `--stiffness` is not given, N/m (the thesis's stiffer).
const DEFAULT_ROPE_STIFFNESS: f64 = THESIS_STIFFNESSES[1];
/// Spring updates (steps × iterations × springs) a run may need unless `--max-work` says
/// more: about a quarter of an hour of the slowest solver on this machine's kind.
const DEFAULT_MAX_WORK: f64 = 1e11;
/// Memory a node may need at most, in bytes, in any scene and solver: the bound of `--nodes`
/// and of a scene file's node count against the memory available.
const BYTES_PER_NODE: u64 = 4096;
/// The memory assumed available where the system does not say (`/proc/meminfo`), in bytes.
const ASSUMED_MEMORY: u64 = 1 << 32;

const AFTER_HELP: &str = "\
Output: the number of kinetic-energy peaks (a peak is a step whose KE is above the previous
one's and at least the next one's), T/2 under the thesis convention (last peak's detection
time, accumulated in f32, divided by the number of peaks) and the exact one (mean interval
between peaks), the end time and whether the time limit was hit. On the thesis rope with the
thesis's parameters the published row (Tables 1-7) is shown beside ours.

Scene file (--scene-file, TOML, SI units; see scenes/*.toml):
  gravity = [0.0, -9.81, 0.0]
  [[nodes]]    mass = 1.0, position = [x, y, z], velocity = [..] (optional), fixed = true|false
  [[springs]]  a = 0, b = 1 (node indices), stiffness = 1e6, rest_length (optional, default:
               the initial distance), damping (optional, N·s/m, tutorial integrators only)
  [forces]     drag = k_f (N·s/m), ground = { height = 0.0, restitution = 0.5 }
               (tutorial integrators only)

Examples:
  mss --scene thesis --solver xpbd --stiffness 1e6 --dt 1e-3 --iterations 20
  mss --scene rope --nodes 30 --solver fast_mass_spring --iterations 30 --compare-reference --json
  mss --scene pendulum --solver rk4 --dt 1e-4 --max-time 10 --positions-csv pendulum.csv
  mss --scene-file scenes/hanging-cloth.toml --solver admm_pd --iterations 20 --ke-csv ke.csv

Output files (--ke-csv, --positions-csv) are checked before the run: a directory, a read-only
file, a path whose directory is missing or not writable, the scene file, or one file given to
both options is bad input (exit 2). A new or existing regular file (links followed) is replaced
only when the run succeeds, and an interrupted run leaves nothing beside it; a path under /dev
or any other file that is not a regular file (a device, a named pipe) is written in place.

Limits (bad input, exit 2, before the run): a run needing more than --max-work spring updates
(steps × iterations × springs, the reference run's included); more nodes than the available
memory holds at 4 KiB a node; --dt longer than --max-time; a scene file over 16 MiB; values
outside the plausible ranges: masses 1e-9 to 1e9 kg, coordinates and rest lengths within 1e6 m,
velocities within 1e6 m/s, gravity within 1e4 m/s², stiffness up to 1e12 N/m, damping and drag
up to 1e9 N·s/m.

Exit status: 0 success; 1 the run failed (diverged or a step failed); 2 bad input.";

/// One-off runs of the thesis's mass-spring solvers and the tutorial's integrators.
#[derive(Debug, Parser)]
#[command(name = "mss", version, after_help = AFTER_HELP)]
struct Cli {
    /// Time-stepping method
    #[arg(long, value_enum, default_value_t = SolverArg::BackwardEuler, help_heading = "Solver")]
    solver: SolverArg,

    /// Time step dt, in s (> 0)
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1e-3,
        allow_negative_numbers = true,
        help_heading = "Solver"
    )]
    dt: f64,

    /// Iterations per time step, an integer >= 1: Newton iterations (backward_euler), sweeps
    /// over the springs (xpbd), local/global iterations (fast_mass_spring, admm_pd). Not
    /// accepted by the tutorial's integrators. [default: 5]
    #[arg(
        long,
        value_name = "N",
        allow_negative_numbers = true,
        help_heading = "Solver"
    )]
    iterations: Option<i64>,

    /// rk45 only: error tolerance T (> 0) of each adaptive step, relative to 1 + |component| of
    /// every position (m) and velocity (m/s); a bounce is located to within T m [default: 1e-6]
    #[arg(
        long,
        value_name = "T",
        allow_negative_numbers = true,
        help_heading = "Solver"
    )]
    tolerance: Option<f64>,

    /// Built-in scene
    #[arg(long, value_enum, default_value_t = SceneArg::Thesis, help_heading = "Scene")]
    scene: SceneArg,

    /// Read the scene from this TOML file instead (format below); conflicts with --scene
    #[arg(
        long,
        value_name = "PATH",
        conflicts_with = "scene",
        help_heading = "Scene"
    )]
    scene_file: Option<PathBuf>,

    /// Stiffness k of every spring, in N/m (> 0) [default: the scene's: 1e6 for thesis and
    /// rope, the cloth's and the pendulum's own, a scene file's own values]
    #[arg(
        long,
        value_name = "N/M",
        allow_negative_numbers = true,
        help_heading = "Scene"
    )]
    stiffness: Option<f64>,

    /// Gravity along -y, in m/s² (finite; >= 0 for the cloths and the pendulum); replaces a
    /// scene file's gravity vector by (0, -G, 0) [default: the scene's, 9.81 for the built-in
    /// scenes]
    #[arg(
        long,
        value_name = "M/S2",
        allow_negative_numbers = true,
        help_heading = "Scene"
    )]
    gravity: Option<f64>,

    /// rope: number of nodes, an integer >= 3 (the first and last are fixed) [default: 10]
    #[arg(
        long,
        value_name = "N",
        allow_negative_numbers = true,
        help_heading = "Scene"
    )]
    nodes: Option<i64>,

    /// rope: rest length of every spring, in m (> 0) [default: 1]
    #[arg(
        long,
        value_name = "M",
        allow_negative_numbers = true,
        help_heading = "Scene"
    )]
    rest_length: Option<f64>,

    /// rope: mass of every node, in kg (> 0) [default: 1]
    #[arg(
        long,
        value_name = "KG",
        allow_negative_numbers = true,
        help_heading = "Scene"
    )]
    node_mass: Option<f64>,

    /// rope: distance between the two fixed ends along x, in m (> 0); the rope starts straight
    /// and at rest [default: (nodes - 1) x rest length, every spring at its rest length]
    #[arg(
        long,
        value_name = "M",
        allow_negative_numbers = true,
        help_heading = "Scene"
    )]
    span: Option<f64>,

    /// Stop at the first kinetic-energy peak below this, in J (> 0); that peak is counted
    #[arg(long, value_name = "J", default_value_t = STOP_THRESHOLD_J, allow_negative_numbers = true, help_heading = "Stopping rule")]
    threshold: f64,

    /// Stop when the simulated time reaches this, in s (> 0); reported as "hit time limit"
    #[arg(long, value_name = "S", default_value_t = MAX_SIMULATED_TIME_S, allow_negative_numbers = true, help_heading = "Stopping rule")]
    max_time: f64,

    /// Variant (not the thesis's rule): the first kinetic-energy peak never stops the run
    #[arg(long, help_heading = "Stopping rule")]
    exempt_first_peak: bool,

    /// Variant (not the thesis's method): velocity damping c, in 1/s (>= 0), applied after
    /// every step as v <- v·exp(-c·dt); 0 is the faithful method
    #[arg(
        long,
        value_name = "PER_S",
        default_value_t = 0.0,
        allow_negative_numbers = true,
        help_heading = "Variants"
    )]
    velocity_damping: f64,

    /// Also run the Backward Euler reference of the same scene as the report runs it (dt = 1e-3
    /// s, 5 Newton iterations, the thesis's stopping rule, no damping, whatever this run's
    /// stopping options) and report the rest-state error of the final
    /// positions against it (sum, L2 and max over nodes of |x_i - x_ref_i|, in m) and the
    /// relative T/2 error (thesis convention)
    #[arg(long, help_heading = "Output")]
    compare_reference: bool,

    /// Print the metrics as one JSON object instead of text
    #[arg(long, help_heading = "Output")]
    json: bool,

    /// Write the kinetic energy of every step to this CSV file (columns time_s,kinetic_energy_j;
    /// from t = 0)
    #[arg(long, value_name = "PATH", help_heading = "Output")]
    ke_csv: Option<PathBuf>,

    /// Write node positions to this CSV file (columns time_s,node,x_m,y_m,z_m; t = 0, every
    /// --positions-every steps, and the final state)
    #[arg(long, value_name = "PATH", help_heading = "Output")]
    positions_csv: Option<PathBuf>,

    /// Refuse, before it starts, a run needing more than this many spring updates (steps ×
    /// iterations × springs, the reference run's included); raise it for a long run on purpose
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_WORK, help_heading = "Limits")]
    max_work: f64,

    /// With --positions-csv: write the positions every N steps, an integer >= 1 [default: 10]
    #[arg(
        long,
        value_name = "N",
        requires = "positions_csv",
        allow_negative_numbers = true,
        help_heading = "Output"
    )]
    positions_every: Option<i64>,
}

/// The methods on the command line: the thesis's solvers ([`SolverKind`]) and the tutorial's
/// integrators ([`Integrator`]). A new method is a variant here and an arm in
/// [`SolverArg::method`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
#[value(rename_all = "snake_case")]
enum SolverArg {
    /// Backward Euler with Newton-Raphson, the thesis's reference (§2.1)
    BackwardEuler,
    /// XPBD, thesis Algorithm 2 (§2.2.1), compliance 1/k
    Xpbd,
    /// Liu et al. 2013's fast mass-spring solver, thesis Algorithm 3 (§2.3.1)
    FastMassSpring,
    /// ADMM ⊇ Projective Dynamics, thesis Algorithm 4 (§2.3.2), weights sqrt(k)
    AdmmPd,
    /// Tutorial: explicit Euler (order 1; grows without damping at every dt)
    #[value(alias = "explicit-euler")]
    ExplicitEuler,
    /// Tutorial: symplectic Euler (order 1; stable for omega·dt < 2)
    #[value(alias = "symplectic-euler")]
    SymplecticEuler,
    /// Tutorial: classical Runge-Kutta (order 4; stable for omega·dt < 2·sqrt(2))
    Rk4,
    /// Beyond the tutorial: Dormand-Prince 5(4) with error control (--tolerance); --dt is then
    /// the sampling interval, each covered by as many adaptive steps as the tolerance needs
    Rk45,
}

/// A method: one of the thesis's solvers or one of the tutorial's integrators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Method {
    Thesis(SolverKind),
    Tutorial(Integrator),
    /// The adaptive Dormand-Prince 5(4) on the tutorial's particle system.
    Adaptive,
}

impl SolverArg {
    fn method(self) -> Method {
        match self {
            SolverArg::BackwardEuler => Method::Thesis(SolverKind::BackwardEuler),
            SolverArg::Xpbd => Method::Thesis(SolverKind::Xpbd),
            SolverArg::FastMassSpring => Method::Thesis(SolverKind::FastMassSpring),
            SolverArg::AdmmPd => Method::Thesis(SolverKind::AdmmPd),
            SolverArg::ExplicitEuler => Method::Tutorial(Integrator::ExplicitEuler),
            SolverArg::SymplecticEuler => Method::Tutorial(Integrator::SymplecticEuler),
            SolverArg::Rk4 => Method::Tutorial(Integrator::Rk4),
            SolverArg::Rk45 => Method::Adaptive,
        }
    }

    /// The name given on the command line.
    fn id(self) -> String {
        self.to_possible_value()
            .map_or_else(String::new, |v| v.get_name().to_string())
    }
}

/// The built-in scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
#[value(rename_all = "snake_case")]
enum SceneArg {
    /// The thesis rope (§3.1): 10 nodes of 1 kg, ends fixed 9 m apart, 1 m springs,
    /// g = 9.81 m/s², straight and at rest
    Thesis,
    /// A straight rope of --nodes nodes between two fixed ends (--rest-length, --node-mass,
    /// --span), at rest
    Rope,
    /// A square cloth pinned at its two top corners, undamped springs on the triangle edges,
    /// released at rest
    HangingCloth,
    /// The tutorial's cloth dropped flat from 10 m onto the floor y = 0, with damped springs,
    /// drag and restitution (tutorial integrators only)
    ClothDrop,
    /// The tutorial's pendulum: a chain of damped springs released horizontal from a pivot,
    /// bouncing on the floor (tutorial integrators only)
    Pendulum,
}

impl SceneArg {
    fn id(self) -> String {
        self.to_possible_value()
            .map_or_else(String::new, |v| v.get_name().to_string())
    }
}

/// Why `mss` stops: the message and the exit status.
#[derive(Debug)]
struct Failure {
    status: u8,
    message: String,
}

impl Failure {
    /// Bad input: an option, a scene file or an output path.
    fn input(message: impl Into<String>) -> Self {
        Self {
            status: 2,
            message: message.into(),
        }
    }

    /// A run that failed, or output that could not be written.
    fn run(message: impl Into<String>) -> Self {
        Self {
            status: 1,
            message: message.into(),
        }
    }

    fn with_context(self, context: &str) -> Self {
        Self {
            message: format!("{context}: {}", self.message),
            ..self
        }
    }
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        match e {
            Error::InvalidParameter { .. } | Error::Input(_) => Failure::input(e.to_string()),
            Error::StepFailed { .. } | Error::Diverged { .. } | Error::NotConverged { .. } => {
                Failure::run(e.to_string())
            }
        }
    }
}

/// Rejects `value` unless it is finite and in range, naming the option and its unit.
fn check(option: &str, value: f64, ok: bool, allowed: &str) -> Result<f64, Failure> {
    if value.is_finite() && ok {
        Ok(value)
    } else {
        Err(Error::invalid(option, value, allowed).into())
    }
}

/// Rejects an integer below `min`, naming the option.
fn check_count(option: &str, value: i64, min: i64) -> Result<usize, Failure> {
    usize::try_from(value)
        .ok()
        .filter(|_| value >= min)
        .ok_or_else(|| Error::invalid(option, value, &format!("an integer >= {min}")).into())
}

/// The memory available to a new process, in bytes (`MemAvailable` on Linux).
fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Refuses more nodes than the available memory holds at [`BYTES_PER_NODE`], naming `option`.
fn check_memory(option: &str, nodes: usize) -> Result<(), Failure> {
    let memory = available_memory().unwrap_or(ASSUMED_MEMORY);
    let max_nodes = memory / BYTES_PER_NODE;
    if nodes as u64 <= max_nodes {
        return Ok(());
    }
    Err(Failure::input(format!(
        "invalid {option}: {nodes} nodes (allowed: at most {max_nodes}, what the {} MiB of \
         memory available hold at {BYTES_PER_NODE} bytes a node)",
        memory >> 20
    )))
}

/// Refuses, before it starts, a run that needs more than `--max-work` spring updates.
fn check_work(cli: &Cli, settings: &Settings, springs: usize) -> Result<(), Failure> {
    let max_time = settings.options.stop.max_time;
    let springs = springs.max(1) as f64;
    let steps = (max_time / cli.dt).ceil();
    let mut work = steps * settings.iterations as f64 * springs;
    let mut parts = format!(
        "{steps:.3e} steps (--max-time / --dt) × {} iterations × {springs} springs",
        settings.iterations
    );
    if cli.compare_reference {
        let reference_steps = (max_time / REFERENCE_DT).ceil();
        work += reference_steps * REFERENCE_NEWTON_ITERATIONS as f64 * springs;
        parts += ", and the reference run's";
    }
    if work <= cli.max_work {
        return Ok(());
    }
    Err(Failure::input(format!(
        "invalid --max-work: the run needs about {work:.3e} spring updates ({parts}), more than \
         the budget of {:e}; take a larger --dt, a shorter --max-time or fewer --iterations, or \
         raise --max-work",
        cli.max_work
    )))
}

/// The options, checked: every value in range, every option used by the chosen scene and method.
#[derive(Debug)]
struct Settings {
    method: Method,
    iterations: usize,
    /// The adaptive method's error tolerance (rk45 only).
    tolerance: f64,
    options: RunOptions,
}

fn settings(cli: &Cli) -> Result<Settings, Failure> {
    let method = cli.solver.method();
    check("--dt", cli.dt, cli.dt > 0.0, "a number > 0, in s")?;
    let iterations = match (method, cli.iterations) {
        (Method::Thesis(_), None) => DEFAULT_ITERATIONS,
        (Method::Thesis(_), Some(n)) => check_count("--iterations", n, 1)?,
        (Method::Tutorial(_) | Method::Adaptive, None) => 1,
        (Method::Tutorial(_) | Method::Adaptive, Some(n)) => {
            return Err(Error::invalid(
                "--iterations",
                n,
                &format!("not given: {} takes no iterations", cli.solver.id()),
            )
            .into())
        }
    };
    let tolerance = match (method, cli.tolerance) {
        (Method::Adaptive, None) => DEFAULT_TOLERANCE,
        (Method::Adaptive, Some(t)) => check("--tolerance", t, t > 0.0, "a number > 0")?,
        (_, None) => 0.0,
        (_, Some(t)) => {
            return Err(Error::invalid(
                "--tolerance",
                t,
                &format!(
                    "not given: {} has no error control (rk45 has)",
                    cli.solver.id()
                ),
            )
            .into())
        }
    };
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
        cli.max_work >= 1.0,
        "a number >= 1, in spring updates",
    )?;
    let rope_only = [
        ("--nodes", cli.nodes.is_some()),
        ("--rest-length", cli.rest_length.is_some()),
        ("--node-mass", cli.node_mass.is_some()),
        ("--span", cli.span.is_some()),
    ];
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
        cli.threshold > 0.0,
        "a number > 0, in J",
    )?;
    let max_time = check(
        "--max-time",
        cli.max_time,
        cli.max_time > 0.0,
        "a number > 0, in s",
    )?;
    if cli.dt > max_time {
        return Err(Error::invalid(
            "--dt",
            cli.dt,
            &format!("at most --max-time ({max_time} s): a longer step is never taken"),
        )
        .into());
    }
    let velocity_damping = check(
        "--velocity-damping",
        cli.velocity_damping,
        cli.velocity_damping >= 0.0,
        "a number >= 0, in 1/s",
    )?;
    let positions_every = match (&cli.positions_csv, cli.positions_every) {
        (None, _) => None,
        (Some(_), None) => Some(DEFAULT_POSITIONS_EVERY),
        (Some(_), Some(n)) => Some(check_count("--positions-every", n, 1)? as u64),
    };
    Ok(Settings {
        method,
        iterations,
        tolerance,
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

/// What a scene is made of: a plain mass-spring system (every method runs it), a scene file
/// (which may ask for the tutorial's forces) or a tutorial particle system (drag and ground:
/// the tutorial's integrators only).
enum Model {
    Springs(MassSpringSystem),
    File(SceneFile),
    Particles(ParticleSystem),
}

impl Model {
    fn system(&self) -> &MassSpringSystem {
        match self {
            Model::Springs(system) => system,
            Model::File(file) => &file.system,
            Model::Particles(particles) => particles.system(),
        }
    }

    /// The system for the thesis's solvers, which model undamped springs and gravity only.
    fn springs_only(&self, scene: &str) -> Result<MassSpringSystem, Failure> {
        match self {
            Model::Springs(system) => Ok(system.clone()),
            Model::File(file) => {
                file.require_springs_and_gravity_only().map_err(|e| {
                    Failure::input(format!(
                        "{scene}: {e}; explicit_euler, symplectic_euler, rk4 and rk45 model it"
                    ))
                })?;
                Ok(file.system.clone())
            }
            Model::Particles(_) => Err(Failure::input(format!(
                "invalid --scene: {scene} (allowed with the thesis's solvers and with \
                 --compare-reference: thesis, rope, hanging_cloth or a scene file without drag, \
                 ground or spring damping; {scene} needs explicit_euler, symplectic_euler, rk4 or rk45)"
            ))),
        }
    }

    /// The tutorial's particle system of the scene.
    fn into_particles(self) -> Result<ParticleSystem, Failure> {
        Ok(match self {
            Model::Springs(system) => ParticleSystem::from_system(system),
            Model::File(file) => file.particle_system()?,
            Model::Particles(particles) => particles,
        })
    }
}

fn scene_name(cli: &Cli) -> String {
    match &cli.scene_file {
        Some(path) => format!("scene file {}", path.display()),
        None => cli.scene.id(),
    }
}

/// Builds the scene with the stiffness and gravity overrides.
fn build_scene(cli: &Cli) -> Result<Model, Failure> {
    let g = cli.gravity;
    if let Some(path) = &cli.scene_file {
        let mut file = scene_file::load(path)?;
        check_memory("--scene-file", file.system.len())?;
        if let Some(k) = cli.stiffness {
            file.system = file.system.with_stiffness(k)?;
        }
        if let Some(g) = g {
            file.system = file.system.with_gravity(Vec3::new(0.0, -g, 0.0))?;
        }
        return Ok(Model::File(file));
    }
    let k = cli.stiffness;
    Ok(match cli.scene {
        SceneArg::Thesis => {
            let mut rope = RopeParams::thesis(k.unwrap_or(DEFAULT_ROPE_STIFFNESS));
            rope.gravity = g.unwrap_or(THESIS_GRAVITY);
            Model::Springs(rope.build()?)
        }
        SceneArg::Rope => {
            let mut rope = RopeParams::thesis(k.unwrap_or(DEFAULT_ROPE_STIFFNESS));
            rope.nodes = match cli.nodes {
                Some(n) => check_count("--nodes", n, 3)?,
                None => THESIS_NODES,
            };
            check_memory("--nodes", rope.nodes)?;
            if let Some(l) = cli.rest_length {
                rope.rest_length = LIMITS.rest_length.check("--rest-length", l)?;
            }
            if let Some(m) = cli.node_mass {
                rope.node_mass = LIMITS.mass.check("--node-mass", m)?;
            }
            let span = match cli.span {
                Some(s) => {
                    check("--span", s, s > 0.0, "a number > 0, in m")?;
                    LIMITS.coordinate.check("--span", s)?
                }
                None => (rope.nodes - 1) as f64 * rope.rest_length,
            };
            rope.anchor_right = rope.anchor_left + Vec3::new(span, 0.0, 0.0);
            rope.gravity = g.unwrap_or(THESIS_GRAVITY);
            Model::Springs(rope.build()?)
        }
        SceneArg::HangingCloth => {
            let defaults = ClothParams::default();
            let cloth = ClothParams {
                stiffness: k.unwrap_or(defaults.stiffness),
                // The thesis's solvers model undamped springs; every method runs the same scene.
                damping: 0.0,
                gravity: g.unwrap_or(defaults.gravity),
                ..defaults
            };
            Model::Springs(cloth.hanging()?)
        }
        SceneArg::ClothDrop => {
            let mut drop = ClothDropParams::tutorial();
            drop.cloth.stiffness = k.unwrap_or(drop.cloth.stiffness);
            drop.cloth.gravity = g.unwrap_or(drop.cloth.gravity);
            Model::Particles(drop.build()?)
        }
        SceneArg::Pendulum => {
            let mut pendulum = PendulumParams::tutorial();
            pendulum.stiffness = k.unwrap_or(pendulum.stiffness);
            pendulum.gravity = g.unwrap_or(pendulum.gravity);
            Model::Particles(pendulum.build()?)
        }
    })
}

/// The time stepper of `method` on the scene, and the tutorial's force objects and ground it
/// applies (none for the thesis's solvers, which apply springs and gravity).
fn build_stepper(
    method: Method,
    model: Model,
    scene: &str,
    dt: f64,
    iterations: usize,
    tolerance: f64,
) -> Result<(Box<dyn TimeStepper>, Option<AppliedForces>), Failure> {
    Ok(match method {
        Method::Thesis(kind) => (
            kind.build(&model.springs_only(scene)?, dt, iterations)?,
            None,
        ),
        Method::Tutorial(_) | Method::Adaptive => {
            let particles = model.into_particles()?;
            let applied = AppliedForces {
                forces: particles.forces().iter().map(|f| f.name()).collect(),
                ground: particles.ground().map(|g| GroundSummary {
                    height_m: g.height(),
                    restitution: g.restitution(),
                }),
            };
            let stepper: Box<dyn TimeStepper> = match method {
                Method::Tutorial(integrator) => {
                    Box::new(ParticleStepper::new(particles, integrator, dt)?)
                }
                _ => Box::new(AdaptiveStepper::new(particles, dt, tolerance)?),
            };
            (stepper, Some(applied))
        }
    })
}

/// A number in CSV and text: the shortest representation that reads back to the same f64,
/// in scientific notation when it is very small or very large.
fn num(x: f64) -> String {
    if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A number in text output: at most 6 significant digits.
fn short(x: f64) -> String {
    let trim = |s: String| match s.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => format!(
            "{}e{exponent}",
            mantissa.trim_end_matches('0').trim_end_matches('.')
        ),
        Some(_) => s,
        None if s.contains('.') => s.trim_end_matches('0').trim_end_matches('.').to_string(),
        None => s,
    };
    if x == 0.0 || !x.is_finite() {
        format!("{x}")
    } else if (1e-3..1e6).contains(&x.abs()) {
        let decimals = (5 - x.abs().log10().floor() as i32).max(0) as usize;
        trim(format!("{x:.decimals$}"))
    } else {
        trim(format!("{x:.5e}"))
    }
}

/// Step times n·dt, rounded to 12 significant digits so that 3·0.1 reads 0.3.
fn step_time(step: u64, dt: f64) -> f64 {
    let t = step as f64 * dt;
    format!("{t:.11e}").parse().unwrap_or(t)
}

#[derive(Debug, Serialize)]
struct SceneSummary {
    name: String,
    nodes: usize,
    fixed_nodes: usize,
    springs: usize,
    stiffness_min_n_per_m: Option<f64>,
    stiffness_max_n_per_m: Option<f64>,
    gravity_m_per_s2: [f64; 3],
    /// The tutorial's force objects and ground, when a tutorial integrator runs the scene.
    #[serde(flatten)]
    applied: Option<AppliedForces>,
}

#[derive(Debug, Serialize)]
struct AppliedForces {
    forces: Vec<String>,
    ground: Option<GroundSummary>,
}

#[derive(Debug, Serialize)]
struct GroundSummary {
    height_m: f64,
    restitution: f64,
}

impl SceneSummary {
    fn new(name: String, system: &MassSpringSystem) -> Self {
        let k = system.springs().iter().map(|s| s.stiffness);
        Self {
            name,
            nodes: system.len(),
            fixed_nodes: system.nodes().iter().filter(|n| n.fixed).count(),
            springs: system.springs().len(),
            stiffness_min_n_per_m: k.clone().reduce(f64::min),
            stiffness_max_n_per_m: k.reduce(f64::max),
            gravity_m_per_s2: system.gravity().into(),
            applied: None,
        }
    }

    fn describe(&self) -> String {
        let k = match (self.stiffness_min_n_per_m, self.stiffness_max_n_per_m) {
            (Some(lo), Some(hi)) if lo == hi => format!(", k = {} N/m", short(lo)),
            (Some(lo), Some(hi)) => format!(", k = {} to {} N/m", short(lo), short(hi)),
            _ => String::new(),
        };
        let [gx, gy, gz] = self.gravity_m_per_s2;
        let mut text = format!(
            "{}: {} nodes ({} fixed), {} springs{k}, g = ({}, {}, {}) m/s²",
            self.name,
            self.nodes,
            self.fixed_nodes,
            self.springs,
            short(gx),
            short(gy),
            short(gz)
        );
        if let Some(applied) = &self.applied {
            text += &format!("\n{:<18}{}", "forces", applied.forces.join(", "));
            if let Some(g) = &applied.ground {
                text += &format!(
                    "\n{:<18}y = {} m, restitution {}",
                    "ground",
                    short(g.height_m),
                    short(g.restitution)
                );
            }
        }
        text
    }
}

#[derive(Debug, Serialize)]
struct StopSummary {
    threshold_j: f64,
    max_time_s: f64,
    exempt_first_peak: bool,
}

#[derive(Debug, Serialize)]
struct PeakSummary {
    energy_j: f64,
    /// Detection time in the thesis convention (f32 accumulation), s.
    time_thesis_s: f64,
    /// The peak sample's own time, s.
    time_exact_s: f64,
}

impl From<&Peak> for PeakSummary {
    fn from(p: &Peak) -> Self {
        Self {
            energy_j: p.energy,
            time_thesis_s: p.time_thesis,
            time_exact_s: p.time_exact,
        }
    }
}

/// The metrics of one run.
#[derive(Debug, Serialize)]
struct RunSummary {
    solver_name: String,
    steps: u64,
    end_time_s: f64,
    hit_time_limit: bool,
    ke_peaks: usize,
    /// T/2, thesis convention, s.
    half_period_s: Option<f64>,
    half_period_exact_s: Option<f64>,
    first_peak: Option<PeakSummary>,
    last_peak: Option<PeakSummary>,
}

impl From<&Run> for RunSummary {
    fn from(run: &Run) -> Self {
        Self {
            solver_name: run.solver.clone(),
            steps: run.steps,
            end_time_s: step_time(run.steps, run.dt),
            hit_time_limit: run.hit_time_limit,
            ke_peaks: run.peak_count(),
            half_period_s: run.half_period_thesis(),
            half_period_exact_s: run.half_period_exact(),
            first_peak: run.peaks.first().map(PeakSummary::from),
            last_peak: run.peaks.last().map(PeakSummary::from),
        }
    }
}

/// The Backward Euler reference of the same scene and what the run misses it by.
#[derive(Debug, Serialize)]
struct ReferenceSummary {
    run: RunSummary,
    /// |T/2 - T/2_ref| / T/2_ref, thesis convention.
    period_rel_error: Option<f64>,
    /// Rest-state error: sum over nodes of |x_i - x_ref_i|, m (the thesis's "error").
    rest_error_sum_m: f64,
    rest_error_l2_m: f64,
    rest_error_max_m: f64,
}

/// The published row of the same experiment (thesis rope, faithful configuration).
#[derive(Debug, Serialize)]
struct PublishedSummary {
    table: u8,
    ke_peaks: usize,
    half_period_s: f64,
    error: Option<f64>,
    period_rel_error: Option<f64>,
    /// The reproduction rule of the scene specification, thesis convention.
    reproduced: bool,
}

#[derive(Debug, Serialize)]
struct Report {
    solver: String,
    scene: SceneSummary,
    dt_s: f64,
    /// None for the tutorial's integrators.
    iterations: Option<usize>,
    stop: StopSummary,
    velocity_damping_per_s: f64,
    #[serde(flatten)]
    run: RunSummary,
    published: Option<PublishedSummary>,
    reference: Option<ReferenceSummary>,
    wall_time_s: f64,
}

/// The published row of this run, if it is one of the thesis's experiments run faithfully.
fn published_row(
    cli: &Cli,
    settings: &Settings,
    system: &MassSpringSystem,
) -> Option<&'static PublishedRow> {
    let Method::Thesis(kind) = settings.method else {
        return None;
    };
    let faithful = settings.options.stop == StoppingRule::default()
        && settings.options.velocity_damping == 0.0
        && cli.gravity.is_none_or(|g| g == THESIS_GRAVITY);
    if cli.scene_file.is_some() || cli.scene != SceneArg::Thesis || !faithful {
        return None;
    }
    let k = system.springs().first()?.stiffness;
    published_rows().iter().find(|r| {
        r.solver == kind
            && r.iterations == settings.iterations
            && r.stiffness == k
            && (r.dt_s - cli.dt).abs() <= 1e-9 * r.dt_s
    })
}

fn reference_summary(run: &Run, reference: &Run) -> ReferenceSummary {
    let x = &run.final_state.x;
    let x_ref = &reference.final_state.x;
    ReferenceSummary {
        run: RunSummary::from(reference),
        period_rel_error: run
            .half_period_thesis()
            .zip(reference.half_period_thesis())
            .map(|(t, t_ref)| mass_spring_solvers::metrics::relative_period_error(t, t_ref)),
        rest_error_sum_m: rest_error_sum(x, x_ref),
        rest_error_l2_m: rest_error_l2(x, x_ref),
        rest_error_max_m: rest_error_max(x, x_ref),
    }
}

fn opt(x: Option<f64>, unit: &str) -> String {
    x.map_or_else(|| "-".to_string(), |x| format!("{} {unit}", short(x)))
}

fn peak(p: &Option<PeakSummary>) -> String {
    p.as_ref().map_or_else(
        || "-".to_string(),
        |p| {
            format!(
                "{} J at t = {} s (thesis stamp {} s)",
                short(p.energy_j),
                short(p.time_exact_s),
                short(p.time_thesis_s)
            )
        },
    )
}

/// The metrics of a run, one per line, labels indented by `indent` and padded to one column.
fn write_run(out: &mut dyn Write, run: &RunSummary, indent: &str) -> std::io::Result<()> {
    let ending = if run.hit_time_limit {
        "hit the time limit"
    } else {
        "stopped by the threshold"
    };
    let rows = [
        ("steps", run.steps.to_string()),
        (
            "end time",
            format!("{} s ({ending})", short(run.end_time_s)),
        ),
        ("KE peaks", run.ke_peaks.to_string()),
        ("T/2 thesis", opt(run.half_period_s, "s")),
        ("T/2 exact", opt(run.half_period_exact_s, "s")),
        ("first peak", peak(&run.first_peak)),
        ("last peak", peak(&run.last_peak)),
    ];
    for (label, value) in rows {
        writeln!(out, "{:<18}{value}", format!("{indent}{label}"))?;
    }
    Ok(())
}

fn write_text(out: &mut dyn Write, r: &Report) -> std::io::Result<()> {
    writeln!(out, "{:<18}{} ({})", "solver", r.solver, r.run.solver_name)?;
    writeln!(out, "{:<18}{}", "scene", r.scene.describe())?;
    writeln!(out, "{:<18}{} s", "dt", short(r.dt_s))?;
    if let Some(n) = r.iterations {
        writeln!(out, "{:<18}{n}", "iterations")?;
    }
    writeln!(
        out,
        "{:<18}first peak{} below {} J, or t = {} s",
        "stopping rule",
        if r.stop.exempt_first_peak {
            " (the first one exempt)"
        } else {
            ""
        },
        short(r.stop.threshold_j),
        short(r.stop.max_time_s)
    )?;
    if r.velocity_damping_per_s > 0.0 {
        writeln!(
            out,
            "{:<18}{} 1/s (variant)",
            "velocity damping",
            short(r.velocity_damping_per_s)
        )?;
    }
    write_run(out, &r.run, "")?;
    if let Some(p) = &r.published {
        writeln!(
            out,
            "{:<18}Table {}: {} peaks, T/2 {} s{}: {}",
            "published",
            p.table,
            p.ke_peaks,
            short(p.half_period_s),
            p.error
                .map_or_else(String::new, |e| format!(", error {}", short(e))),
            if p.reproduced {
                "reproduced"
            } else {
                "not reproduced"
            }
        )?;
    }
    if let Some(reference) = &r.reference {
        writeln!(out, "reference         {}", reference.run.solver_name)?;
        write_run(out, &reference.run, "  ")?;
        writeln!(
            out,
            "{:<18}{}",
            "T/2 rel. error",
            reference.period_rel_error.map_or_else(|| "-".into(), short)
        )?;
        writeln!(
            out,
            "{:<18}sum {} m, L2 {} m, max {} m",
            "rest-state error",
            short(reference.rest_error_sum_m),
            short(reference.rest_error_l2_m),
            short(reference.rest_error_max_m)
        )?;
    }
    writeln!(out, "{:<18}{:.3} s", "wall time", r.wall_time_s)
}

/// Writes the recorded series into the output files as the run goes: a long series never
/// waits in memory.
struct CsvRecorder {
    dt: f64,
    ke: Option<OutputFile>,
    positions: Option<OutputFile>,
    /// Whether writing a file failed (the run then stops with that error).
    failed: bool,
}

impl CsvRecorder {
    fn headers(&mut self) -> std::io::Result<()> {
        if let Some(out) = &mut self.ke {
            writeln!(out.writer(), "time_s,kinetic_energy_j")?;
        }
        if let Some(out) = &mut self.positions {
            writeln!(out.writer(), "time_s,node,x_m,y_m,z_m")?;
        }
        Ok(())
    }

    fn noting_failure(
        &mut self,
        written: std::io::Result<()>,
        option: &str,
    ) -> std::io::Result<()> {
        written.map_err(|e| {
            self.failed = true;
            std::io::Error::new(e.kind(), format!("{option}: {e}"))
        })
    }
}

impl Recorder for CsvRecorder {
    fn kinetic_energy(&mut self, step: u64, energy: f64) -> std::io::Result<()> {
        let Some(out) = &mut self.ke else {
            return Ok(());
        };
        let time = num(step_time(step, self.dt));
        let written = writeln!(out.writer(), "{time},{}", num(energy));
        self.noting_failure(written, "--ke-csv")
    }

    fn positions(&mut self, step: u64, state: &State) -> std::io::Result<()> {
        let Some(out) = &mut self.positions else {
            return Ok(());
        };
        let time = num(step_time(step, self.dt));
        let written = state.x.iter().enumerate().try_for_each(|(i, x)| {
            writeln!(
                out.writer(),
                "{time},{i},{},{},{}",
                num(x[0]),
                num(x[1]),
                num(x[2])
            )
        });
        self.noting_failure(written, "--positions-csv")
    }
}

fn run(cli: &Cli) -> Result<(), Failure> {
    let settings = settings(cli)?;
    let scene = scene_name(cli);
    let model = build_scene(cli)?;
    check_work(cli, &settings, model.system().springs().len())?;
    let mut summary = SceneSummary::new(scene.clone(), model.system());
    let published = published_row(cli, &settings, model.system());
    let reference_system = if cli.compare_reference {
        Some(model.springs_only(&scene)?)
    } else {
        None
    };
    let (mut stepper, applied) = build_stepper(
        settings.method,
        model,
        &scene,
        cli.dt,
        settings.iterations,
        settings.tolerance,
    )?;
    summary.applied = applied;
    let requested: Vec<(&'static str, &Path)> = [
        ("--ke-csv", cli.ke_csv.as_deref()),
        ("--positions-csv", cli.positions_csv.as_deref()),
    ]
    .into_iter()
    .filter_map(|(option, path)| path.map(|p| (option, p)))
    .collect();
    let mut outputs = OutputFile::open_all(&requested, cli.scene_file.as_deref())?.into_iter();
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
            e => Failure::from(e),
        })
        .and_then(|run| {
            // The report's reference: the thesis's stopping rule, no damping. A run with
            // exactly its parameters is its own reference.
            let reference_options = RunOptions::default();
            let is_reference = settings.method == Method::Thesis(SolverKind::BackwardEuler)
                && cli.dt == REFERENCE_DT
                && settings.iterations == REFERENCE_NEWTON_ITERATIONS
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

    for output in csv.ke.into_iter().chain(csv.positions) {
        output.finish().map_err(|e| Failure::run(e.to_string()))?;
    }
    let report = Report {
        solver: cli.solver.id(),
        scene: summary,
        dt_s: cli.dt,
        iterations: matches!(settings.method, Method::Thesis(_)).then_some(settings.iterations),
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
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            // Nothing more can be done if stderr is closed.
            let _ = writeln!(std::io::stderr(), "error: {}", failure.message);
            ExitCode::from(failure.status)
        }
    }
}

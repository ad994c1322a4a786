//! The command line: its options (clap), their defaults and the limits of their ranges.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Parser, ValueEnum};
use mass_spring_solvers::model::metrics::{MAX_SIMULATED_TIME_S, STOP_THRESHOLD_J};
use mass_spring_solvers::model::scene::THESIS_STIFFNESSES;
use mass_spring_solvers::solvers::backward_euler::REFERENCE_NEWTON_ITERATIONS;
use mass_spring_solvers::solvers::registry::SolverId;
use std::path::PathBuf;

/// Iterations per step when `--iterations` is not given (the reference's Newton iterations).
pub(crate) const DEFAULT_ITERATIONS: usize = REFERENCE_NEWTON_ITERATIONS;
/// Steps between recorded positions when `--positions-every` is not given: keeps the series of
/// a long run (hundreds of thousands of steps) small.
pub(crate) const DEFAULT_POSITIONS_EVERY: u64 = 10;
/// Stiffness of the built-in ropes when `--stiffness` is not given, N/m (the thesis's stiffer).
pub(crate) const DEFAULT_ROPE_STIFFNESS: f64 = THESIS_STIFFNESSES[1];
/// Spring updates (steps × iterations × springs) a run may need unless `--max-work` says
/// more: about a quarter of an hour of the slowest solver on this machine's kind.
pub(crate) const DEFAULT_MAX_WORK: f64 = 1e11;
/// The memory assumed available where the system does not say (`/proc/meminfo`), in bytes.
pub(crate) const ASSUMED_MEMORY: f64 = 4.0 * 1024.0 * 1024.0 * 1024.0;
/// The largest `--n`: a sheet of 4e6 nodes (the memory estimate may allow fewer).
pub(crate) const MAX_SHEET_SIDE: i64 = 2000;
/// The largest `--nodes` (the memory estimate may allow fewer).
pub(crate) const MAX_ROPE_NODES: i64 = 10_000_000;

pub(crate) const AFTER_HELP: &str = "\
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
  mss --solver vbd --integrator tr-bdf2 --dt 1e-2 --iterations 20
  mss --scene rope --nodes 30 --solver fast_mass_spring --iterations 30 --compare-reference --json
  mss --scene pendulum --solver rk4 --dt 1e-4 --max-time 10 --positions-csv pendulum.csv
  mss --scene-file scenes/hanging-cloth.toml --solver admm_pd --iterations 20 --ke-csv ke.csv

Output files (--ke-csv, --positions-csv) are checked before the run, by what the path is
after resolving it: a new path or an existing regular file (links followed), wherever it is,
is replaced only when the run succeeds, and an interrupted run leaves nothing beside it; a
descriptor (/dev/stdout, /dev/fd/N) is written through, so `>> log.csv` appends; a character
device (/dev/null) is written in place, and so is a named pipe once a reader opens it within
1 s. Bad input (exit 2): a directory or a path ending in /, a name over 255 bytes, a read-only
file, a path whose directory is missing or not writable, a dangling symbolic link, another
user's file in a sticky directory, a mounted-over file, a named pipe no reader opens within
1 s, the scene file, or one file given to both options (a device aside).

Limits (bad input, exit 2, before the run): a run needing more than --max-work spring updates
(steps × iterations × springs; rk45's adaptive steps estimated from the scene's fastest rate,
and capped by the same budget while it runs; the reference run's at its own length); a memory
estimate over --max-memory (the solver's, and what the run keeps per step: its histogram of
iterations and its energy peaks); --dt longer than --max-time; a scene file over 16 MiB, or a named
pipe no writer opens within 1 s; values outside the plausible ranges: masses 1e-9 to 1e9 kg,
coordinates and rest lengths within 1e6 m, velocities within 1e6 m/s, gravity within 1e4 m/s²,
stiffness 1e-9 to 1e12 N/m, damping and drag up to 1e9 N·s/m; a spring that starts shorter
than 1e-6 of its rest length.

Exit status: 0 success; 1 the run failed (diverged or a step failed); 2 bad input.";

/// One-off runs of the thesis's mass-spring solvers and the tutorial's integrators.
#[derive(Debug, Parser)]
#[command(name = "mss", version, after_help = AFTER_HELP)]
pub(crate) struct Cli {
    /// Time-stepping method (`--list-solvers` describes each)
    #[arg(
        long,
        default_value = "backward_euler",
        value_parser = SolverParser,
        help_heading = "Solver"
    )]
    pub(crate) solver: SolverId,

    /// Print every solver, one line each (identifier, source, iterations, options), and exit
    #[arg(long, help_heading = "Solver")]
    pub(crate) list_solvers: bool,

    /// Print every continuum energy (--energy), one line each, and exit
    #[arg(long, help_heading = "Continuum")]
    pub(crate) list_energies: bool,

    /// The continuum scenes' energy: linear, arap, corotated, stvk or stable-neo-hookean
    /// (--list-energies) [default: linear for cook, stable-neo-hookean for the others]
    #[arg(long, value_name = "NAME", help_heading = "Continuum")]
    pub(crate) energy: Option<String>,

    /// The continuum scenes' Young's modulus E, in Pa (the membrane's Y = E·t, in N/m), from
    /// 1e-6 to 1e15 [default: 1e9 for beam, 1 for cook and patch, 8e6/3 for membrane]
    #[arg(
        long,
        value_name = "PA",
        allow_hyphen_values = true,
        help_heading = "Continuum"
    )]
    pub(crate) youngs: Option<f64>,

    /// The continuum scenes' dynamics: simulate this long, in s (> 0, up to 1e4), released
    /// from rest, with --integrator (default backward-euler) and --dt, every stage solved by
    /// Newton to a residual of 1e-9 of the largest nodal load [default: statics only]
    #[arg(
        long,
        value_name = "S",
        allow_hyphen_values = true,
        help_heading = "Continuum"
    )]
    pub(crate) duration: Option<f64>,

    /// Time step dt, in s, from 1e-9 to 1e9 and at most --max-time
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1e-3,
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) dt: f64,

    /// Iterations per time step, an integer >= 1, at most what --max-work allows (steps ×
    /// iterations × springs): Newton iterations (backward_euler), sweeps over the springs (pbd,
    /// xpbd), local/global iterations (fast_mass_spring, admm_pd). Not accepted by the
    /// tutorial's integrators. [default: 5]
    #[arg(
        long,
        value_name = "N",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) iterations: Option<i64>,

    /// Stop each step's iterations at the first iterate that moves no node by more than E m
    /// (E > 0 and at most 1e6); --iterations becomes the cap. Every iterative solver but xpbd_substeps
    /// [default: off, a fixed count]
    #[arg(
        long,
        value_name = "E",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) stop_tolerance: Option<f64>,

    /// rk45 only: error tolerance T, from 1e-12 to 0.1, of each adaptive step, relative to 1 +
    /// |component| of every position (m) and velocity (m/s); a bounce is located to within T m
    /// [default: 1e-6]
    #[arg(
        long,
        value_name = "T",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) tolerance: Option<f64>,

    /// pbd only: dimensionless stiffness factor in [0, 1] scaling each constraint's correction
    /// (not the stiffness in N/m) [default: 1]
    #[arg(
        long,
        value_name = "F",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) stiffness_factor: Option<f64>,

    /// chebyshev_*: spectral radius rho in (0, 1) of the base iteration [default: estimated
    /// on the scene's start state]
    #[arg(
        long,
        value_name = "RHO",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) spectral_radius: Option<f64>,

    /// chebyshev_*: under-relaxation gamma in (0, 1] [default: 1]
    #[arg(
        long,
        value_name = "G",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) gamma: Option<f64>,

    /// chebyshev_*: warm-up iterations S with omega = 1, an integer from 0 to 4294967295
    /// [default: 10]
    #[arg(
        long,
        value_name = "S",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) warmup: Option<f64>,

    /// anderson_*: window m, past iterates in each extrapolation, an integer from 1 to 20
    /// [default: 5]
    #[arg(
        long,
        value_name = "M",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) window: Option<f64>,

    /// damped_*: mass-proportional Rayleigh damping alpha, from 0 to 1e6, in 1/s [default: 0]
    #[arg(
        long,
        value_name = "PER_S",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) alpha: Option<f64>,

    /// damped_*: stiffness-proportional Rayleigh damping beta, from 0 to 1e3, in s [default: 0]
    #[arg(
        long,
        value_name = "S",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) beta: Option<f64>,

    /// lbfgs: the window m, past (s, y) pairs kept, an integer from 1 to 100 [default: 5]
    #[arg(
        long,
        value_name = "M",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) history: Option<f64>,

    /// Every solver iterating on the incremental potential: the first iterate of each step,
    /// previous-position, inertia, inertia-and-acceleration (the inertial prediction) or
    /// adaptive, Chen 2024's (a)-(d) [default: the solver's own, `--list-solvers`]
    #[arg(long, value_name = "RULE", help_heading = "Solver")]
    pub(crate) first_iterate: Option<String>,

    /// chebyshev_*: how rho is found when --spectral-radius is not given: asymptotic-rate
    /// (of the plain iteration, ours) or gradient-ratio (Wang 2015's start) [default:
    /// asymptotic-rate]
    #[arg(long, value_name = "RULE", help_heading = "Solver")]
    pub(crate) rho_rule: Option<String>,

    /// anderson_admm: the safeguard's merit, primal-residual (Zhang 2019's) or
    /// combined-residual [default: primal-residual]
    #[arg(long, value_name = "MERIT", help_heading = "Solver")]
    pub(crate) safeguard: Option<String>,

    /// vbd: the local Hessian, exact (the paper's) or projected [default: exact]
    #[arg(long, value_name = "RULE", help_heading = "Solver")]
    pub(crate) hessian: Option<String>,

    /// xpbd_substeps: Macklin 2019's constraint damping beta, from 0 to 1e9, in N·s/m
    /// [default: 0]
    #[arg(
        long,
        value_name = "N_S_PER_M",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) constraint_damping: Option<f64>,

    /// xpbd_substeps: the constraint pass, gauss-seidel or jacobi [default: gauss-seidel]
    #[arg(long, value_name = "SWEEP", help_heading = "Solver")]
    pub(crate) sweep: Option<String>,

    /// Every minimizing solver (those iterating on the incremental potential, not pbd, the
    /// xpbd family or the tutorial's integrators): the optimization integrator,
    /// backward-euler, implicit-midpoint, bdf2 (started by one TR-BDF2 step) or tr-bdf2
    /// [default: backward-euler]
    #[arg(long, value_name = "SCHEME", help_heading = "Solver")]
    pub(crate) integrator: Option<String>,

    /// damped_*: Rayleigh damping's form, classical or momentum-conserving (this crate's:
    /// the springs' rates of stretching only) [default: classical]
    #[arg(long, value_name = "FORM", help_heading = "Solver")]
    pub(crate) rayleigh_form: Option<String>,

    /// damped_*: power-law drag coefficient c of D = c |v|^(p+1)/(p+1), from 0 to 1e9, in
    /// N·(s/m)^p [default: 0]
    #[arg(
        long,
        value_name = "C",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) drag: Option<f64>,

    /// damped_*: power-law drag exponent p, > 0 and < 1 [default: 0.5]
    #[arg(
        long,
        value_name = "P",
        allow_hyphen_values = true,
        help_heading = "Solver"
    )]
    pub(crate) drag_exponent: Option<f64>,

    /// Built-in scene
    #[arg(long, value_enum, default_value_t = SceneArg::Thesis, help_heading = "Scene")]
    pub(crate) scene: SceneArg,

    /// Read the scene from this TOML file instead (format below); conflicts with --scene
    #[arg(
        long,
        value_name = "PATH",
        conflicts_with = "scene",
        help_heading = "Scene"
    )]
    pub(crate) scene_file: Option<PathBuf>,

    /// Stiffness k of every spring, in N/m, from 1e-9 to 1e12 [default: the scene's: 1e6 for thesis and
    /// rope, the cloth's and the pendulum's own, a scene file's own values]
    #[arg(
        long,
        value_name = "N/M",
        allow_hyphen_values = true,
        help_heading = "Scene"
    )]
    pub(crate) stiffness: Option<f64>,

    /// Gravity along -y, in m/s², from -1e4 to 1e4 (>= 0 for the cloths and the pendulum); replaces a
    /// scene file's gravity vector by (0, -G, 0) [default: the scene's, 9.81 for the built-in
    /// scenes]
    #[arg(
        long,
        value_name = "M/S2",
        allow_hyphen_values = true,
        help_heading = "Scene"
    )]
    pub(crate) gravity: Option<f64>,

    /// rope: number of nodes, an integer from 3 to 10000000 (the first and last are fixed; the
    /// memory estimate may allow fewer) [default: 10]
    #[arg(
        long,
        value_name = "N",
        allow_hyphen_values = true,
        help_heading = "Scene"
    )]
    pub(crate) nodes: Option<i64>,

    /// sheet: nodes per side n, an integer from 3 to 2000 (n² nodes; the four corners are fixed;
    /// the memory estimate may allow fewer) [default: 10]; beam: r, 1 to 64 [default: 2];
    /// membrane: n, 3 to 200 [default: 10]; cook: N, even, 2 to 1024 [default: 16]
    #[arg(
        long,
        value_name = "N",
        allow_hyphen_values = true,
        help_heading = "Scene"
    )]
    pub(crate) n: Option<i64>,

    /// rope: rest length of every spring, in m, from 1e-9 to 1e6 [default: 1]
    #[arg(
        long,
        value_name = "M",
        allow_hyphen_values = true,
        help_heading = "Scene"
    )]
    pub(crate) rest_length: Option<f64>,

    /// rope: mass of every node, in kg, from 1e-9 to 1e9 [default: 1]
    #[arg(
        long,
        value_name = "KG",
        allow_hyphen_values = true,
        help_heading = "Scene"
    )]
    pub(crate) node_mass: Option<f64>,

    /// rope: distance between the two fixed ends along x, in m, > 0 and at most 1e6; the rope starts straight
    /// and at rest [default: (nodes - 1) x rest length, every spring at its rest length]
    #[arg(
        long,
        value_name = "M",
        allow_hyphen_values = true,
        help_heading = "Scene"
    )]
    pub(crate) span: Option<f64>,

    /// Stop at the first kinetic-energy peak below this, in J (> 0 and at most 1e12); that peak
    /// is counted
    #[arg(long, value_name = "J", default_value_t = STOP_THRESHOLD_J, allow_hyphen_values = true, help_heading = "Stopping rule")]
    pub(crate) threshold: f64,

    /// Stop when the simulated time reaches this, in s, from 1e-9 to 1e9; reported as "hit
    /// time limit"
    #[arg(long, value_name = "S", default_value_t = MAX_SIMULATED_TIME_S, allow_hyphen_values = true, help_heading = "Stopping rule")]
    pub(crate) max_time: f64,

    /// Variant (not the thesis's rule): the first kinetic-energy peak never stops the run
    #[arg(long, help_heading = "Stopping rule")]
    pub(crate) exempt_first_peak: bool,

    /// Variant (not the thesis's method): velocity damping c, in 1/s, from 0 to 1e6, applied after
    /// every step as v <- v·exp(-c·dt); 0 is the faithful method
    #[arg(
        long,
        value_name = "PER_S",
        default_value_t = 0.0,
        allow_hyphen_values = true,
        help_heading = "Variants"
    )]
    pub(crate) velocity_damping: f64,

    /// Also run the Backward Euler reference of the same scene as the report runs it (dt = 1e-3
    /// s, 5 Newton iterations, the thesis's stopping rule, no damping, whatever this run's
    /// stopping options) and report the rest-state error of the final
    /// positions against it (sum, L2 and max over nodes of |x_i - x_ref_i|, in m) and the
    /// relative T/2 error (thesis convention)
    #[arg(long, help_heading = "Output")]
    pub(crate) compare_reference: bool,

    /// Print the metrics as one JSON object instead of text
    #[arg(long, help_heading = "Output")]
    pub(crate) json: bool,

    /// Write the kinetic energy of every step to this CSV file (columns time_s,kinetic_energy_j;
    /// from t = 0)
    #[arg(long, value_name = "PATH", help_heading = "Output")]
    pub(crate) ke_csv: Option<PathBuf>,

    /// Write node positions to this CSV file (columns time_s,node,x_m,y_m,z_m; t = 0, every
    /// --positions-every steps, and the final state)
    #[arg(long, value_name = "PATH", help_heading = "Output")]
    pub(crate) positions_csv: Option<PathBuf>,

    /// Refuse, before it starts, a run needing more than this many spring updates (steps ×
    /// iterations × springs, the reference run's included), a number from 1 to 1e18; raise it
    /// for a long run on purpose
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_WORK, help_heading = "Limits")]
    pub(crate) max_work: f64,

    /// Refuse, before it starts, a run whose memory estimate is over this many bytes (from 1e6
    /// to 1e18):
    /// the solver's peak memory per node, measured on the rope and the sheet (src/solvers/budget.rs),
    /// with a margin [default: the memory available: the least of MemAvailable, the
    /// address-space limit and the control group's limit]
    #[arg(
        long,
        value_name = "BYTES",
        allow_hyphen_values = true,
        help_heading = "Limits"
    )]
    pub(crate) max_memory: Option<f64>,

    /// With --positions-csv: write the positions every N steps, an integer >= 1 (one past the
    /// run's steps writes its first and last states only) [default: 10]
    #[arg(
        long,
        value_name = "N",
        requires = "positions_csv",
        allow_hyphen_values = true,
        help_heading = "Output"
    )]
    pub(crate) positions_every: Option<i64>,
}

impl Cli {
    /// The CSV files asked for on the command line, each with the option that names it.
    pub(crate) fn requested_outputs(&self) -> Vec<(&'static str, &std::path::Path)> {
        [
            ("--ke-csv", self.ke_csv.as_deref()),
            ("--positions-csv", self.positions_csv.as_deref()),
        ]
        .into_iter()
        .filter_map(|(option, path)| path.map(|p| (option, p)))
        .collect()
    }
}

/// The built-in scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
#[value(rename_all = "snake_case")]
pub(crate) enum SceneArg {
    /// The thesis rope (§3.1): 10 nodes of 1 kg, ends fixed 9 m apart, 1 m springs,
    /// g = 9.81 m/s², straight and at rest
    Thesis,
    /// A straight rope of --nodes nodes between two fixed ends (--rest-length, --node-mass,
    /// --span), at rest
    Rope,
    /// The sheet of docs/sheet-scene.md: an n × n net (--n), 9 m × 9 m, 100 kg in all,
    /// structural and shear springs at rest length, four corners fixed, flat and taut at rest
    Sheet,
    /// A square cloth pinned at its two top corners, undamped springs on the triangle edges,
    /// released at rest
    HangingCloth,
    /// The tutorial's cloth dropped flat from 10 m onto the floor y = 0, with damped springs,
    /// drag and restitution (tutorial integrators only)
    ClothDrop,
    /// The tutorial's pendulum: a chain of damped springs released horizontal from a pivot,
    /// bouncing on the floor (tutorial integrators only)
    Pendulum,
    /// docs/fem-scenes.md's tet cantilever 1 m × 0.1 m × 0.1 m (--n: r, default 2), clamped at
    /// x = 0, under its weight: its static equilibrium by Newton (statics only)
    Beam,
    /// docs/fem-scenes.md's sheet as membrane triangles (--n: n, default 10), four corners
    /// held, under its weight: its static equilibrium by Newton (statics only)
    Membrane,
    /// Cook's membrane in plane stress (--n: N, even, default 16), a unit vertical force on its
    /// right edge: its static equilibrium by Newton (statics only)
    Cook,
    /// The affine patch test on the unit cube (3 × 3 × 3 cubes of 6 tets): its static
    /// equilibrium by Newton (statics only)
    Patch,
}

impl SceneArg {
    /// True for the continuum scenes of docs/fem-scenes.md (statics only).
    pub(crate) fn is_continuum(self) -> bool {
        matches!(self, Self::Beam | Self::Membrane | Self::Cook | Self::Patch)
    }
}

impl SceneArg {
    pub(crate) fn id(self) -> String {
        self.to_possible_value()
            .map_or_else(String::new, |v| v.get_name().to_string())
    }
}

/// The `--solver` values: every registered solver, with its summary as help; dashes read as
/// underscores (`explicit-euler`).
#[derive(Clone)]
pub(crate) struct SolverParser;

impl SolverParser {
    fn values() -> impl Iterator<Item = PossibleValue> {
        SolverId::ALL
            .into_iter()
            .map(|s| PossibleValue::new(s.id()).help(s.info().summary))
    }
}

impl TypedValueParser for SolverParser {
    type Value = SolverId;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<SolverId, clap::Error> {
        let normalised = std::ffi::OsString::from(value.to_string_lossy().replace('-', "_"));
        let id = PossibleValuesParser::new(Self::values()).parse_ref(cmd, arg, &normalised)?;
        Ok(SolverId::from_id(&id).expect("the possible values are the registry's"))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(Self::values()))
    }
}

pub(crate) fn scene_name(cli: &Cli) -> String {
    match &cli.scene_file {
        Some(path) => format!("scene file {}", path.display()),
        None => cli.scene.id(),
    }
}

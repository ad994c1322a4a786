//! The `mss` command line, run as a user runs it: metrics, exit statuses, error messages,
//! CSV output and the help text.

use mass_spring_solvers::solvers::registry::{Builder, SolverId};
use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Output};

fn mss(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mss"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the mss binary starts")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Runs `mss --json` and returns the parsed object, asserting success.
fn json(args: &[&str]) -> Value {
    let output = mss(&[args, &["--json"]].concat());
    assert!(
        output.status.success(),
        "mss {args:?} failed: {}",
        stderr(&output)
    );
    serde_json::from_slice(&output.stdout).expect("--json prints one JSON object")
}

/// A file in the test's scratch directory.
fn scratch(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}"))
}

fn write_scratch(name: &str, contents: &str) -> String {
    let path = scratch(name);
    std::fs::write(&path, contents).expect("the scratch directory is writable");
    path.to_string_lossy().into_owned()
}

/// Asserts exit status 2 and an error message containing every `needle`.
fn assert_bad_input(args: &[&str], needles: &[&str]) {
    let output = mss(args);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "mss {args:?}: {err}");
    for needle in needles {
        assert!(
            err.contains(needle),
            "mss {args:?}: {needle:?} not in {err}"
        );
    }
    assert!(!err.contains("panicked"), "{err}");
}

/// Table 1: the thesis rope with the reference at k = 1e6 gives 175 peaks and T/2 = 0.2060 s.
#[test]
fn thesis_rope_backward_euler_reproduces_table_1() {
    let m = json(&[
        "--scene",
        "thesis",
        "--solver",
        "backward_euler",
        "--stiffness",
        "1e6",
        "--dt",
        "1e-3",
        "--iterations",
        "5",
    ]);
    assert_eq!(m["ke_peaks"], 175, "{m:#}");
    assert_eq!(m["hit_time_limit"], false);
    let half_period = m["half_period_s"].as_f64().unwrap();
    assert!(
        (half_period - 0.2060).abs() < 0.005 * 0.2060,
        "{half_period}"
    );
    assert!(m["half_period_exact_s"].as_f64().unwrap() > 0.2);
    assert_eq!(m["published"]["table"], 1);
    assert_eq!(m["published"]["ke_peaks"], 175);
    assert_eq!(m["published"]["reproduced"], true);
    assert_eq!(m["scene"]["nodes"], 10);
    assert_eq!(m["scene"]["fixed_nodes"], 2);
    // The stopping peak is the first one below 1e-3 J.
    assert!(m["last_peak"]["energy_j"].as_f64().unwrap() < 1e-3);
    assert!(m["reference"].is_null());
}

/// The scene file of the thesis rope is the same experiment as `--scene thesis`, bit for bit.
#[test]
fn thesis_rope_scene_file_matches_the_built_in_scene() {
    let built_in = json(&["--scene", "thesis", "--max-time", "5"]);
    let file = json(&["--scene-file", "scenes/thesis-rope.toml", "--max-time", "5"]);
    for key in [
        "steps",
        "ke_peaks",
        "half_period_s",
        "half_period_exact_s",
        "last_peak",
    ] {
        assert_eq!(built_in[key], file[key], "{key}");
    }
    // The published comparison is only made for the thesis's own runs (here the time limit
    // differs from the thesis's rule).
    assert!(file["published"].is_null() && built_in["published"].is_null());
}

/// The reference compared with itself has no error; a coarser run has a small one. The
/// reference is the report's, whatever the run's own stopping options: the thesis's rule, no
/// damping.
#[test]
fn compare_reference_reports_rest_state_errors() {
    let same = json(&["--stiffness", "1e6", "--compare-reference"]);
    assert_eq!(same["reference"]["rest_error_sum_m"], 0.0);
    let reference_steps = &same["steps"];
    let coarse = json(&[
        "--stiffness",
        "1e6",
        "--max-time",
        "3",
        "--dt",
        "2e-3",
        "--compare-reference",
    ]);
    let reference = &coarse["reference"];
    assert_eq!(&reference["run"]["steps"], reference_steps, "{reference:#}");
    let damped = json(&[
        "--stiffness",
        "1e6",
        "--velocity-damping",
        "0.05",
        "--compare-reference",
    ]);
    assert_eq!(&damped["reference"]["run"]["steps"], reference_steps);
    assert!(damped["reference"]["rest_error_sum_m"].as_f64().unwrap() > 0.0);
    let sum = reference["rest_error_sum_m"].as_f64().unwrap();
    let max = reference["rest_error_max_m"].as_f64().unwrap();
    let l2 = reference["rest_error_l2_m"].as_f64().unwrap();
    assert!(sum > 0.0 && max <= l2 && l2 <= sum, "{reference:#}");
}

#[test]
fn bad_stiffness_exits_2_naming_the_option() {
    assert_bad_input(&["--stiffness", "-5"], &["--stiffness", "-5", "> 0"]);
    assert_bad_input(&["--stiffness", "0"], &["--stiffness"]);
    assert_bad_input(&["--stiffness", "inf"], &["--stiffness"]);
    assert_bad_input(&["--stiffness", "stiff"], &["--stiffness"]);
}

#[test]
fn other_bad_options_exit_2_naming_the_option() {
    assert_bad_input(&["--dt", "0"], &["--dt"]);
    assert_bad_input(&["--iterations", "0"], &["--iterations", ">= 1"]);
    assert_bad_input(
        &["--solver", "rk4", "--iterations", "3"],
        &["--iterations", "rk4"],
    );
    assert_bad_input(&["--solver", "verlet"], &["verlet", "backward_euler"]);
    assert_bad_input(&["--threshold", "-1"], &["--threshold"]);
    assert_bad_input(&["--max-time", "0"], &["--max-time"]);
    assert_bad_input(&["--velocity-damping", "-0.1"], &["--velocity-damping"]);
    assert_bad_input(
        &["--scene", "rope", "--nodes", "2"],
        &["--nodes", "from 3 to"],
    );
    assert_bad_input(&["--scene", "thesis", "--nodes", "5"], &["--nodes", "rope"]);
    assert_bad_input(&["--positions-every", "5"], &["--positions-csv"]);
    assert_bad_input(
        &["--scene", "thesis", "--scene-file", "scenes/pendulum.toml"],
        &["--scene-file"],
    );
    assert_bad_input(
        &["--ke-csv", "no/such/directory/ke.csv", "--max-time", "1"],
        &["--ke-csv", "no/such/directory/ke.csv"],
    );
}

#[test]
fn bad_scene_files_exit_2_naming_line_and_field() {
    let syntax = write_scratch(
        "syntax.toml",
        "gravity = [0.0, -9.81, 0.0]\n\n[[nodes]]\nmass = = 1.0\n",
    );
    assert_bad_input(&["--scene-file", &syntax], &[&syntax, "line 4"]);

    let rope = std::fs::read_to_string("scenes/thesis-rope.toml").unwrap();
    let negative = rope.replacen("stiffness = 1e6", "stiffness = -1e6", 2);
    let line = 1 + negative
        .lines()
        .position(|l| l == "stiffness = -1e6")
        .unwrap();
    let negative = write_scratch("negative.toml", &negative);
    assert_bad_input(
        &["--scene-file", &negative],
        &["springs[0].stiffness", &format!("line {line}")],
    );

    let unknown = write_scratch(
        "unknown.toml",
        &rope.replacen("mass = 1.0", "weight = 1.0", 1),
    );
    assert_bad_input(&["--scene-file", &unknown], &["weight", "line"]);

    let missing = scratch("missing.toml").to_string_lossy().into_owned();
    assert_bad_input(&["--scene-file", &missing], &[&missing]);
}

#[test]
fn thesis_solvers_refuse_the_tutorial_forces() {
    assert_bad_input(&["--scene-file", "scenes/pendulum.toml"], &["forces.drag"]);
    assert_bad_input(&["--scene", "pendulum"], &["--scene", "pendulum", "rk4"]);
    assert_bad_input(
        &[
            "--scene",
            "cloth_drop",
            "--solver",
            "rk4",
            "--compare-reference",
        ],
        &["--scene"],
    );
}

/// The pendulum file is the tutorial's pendulum, bit for bit.
#[test]
fn pendulum_scene_file_matches_the_built_in_scene() {
    let args = ["--solver", "rk4", "--max-time", "2"];
    let built_in = json(&[&args[..], &["--scene", "pendulum"]].concat());
    let file = json(&[&args[..], &["--scene-file", "scenes/pendulum.toml"]].concat());
    assert_eq!(built_in["steps"], 2000);
    assert!(built_in["ke_peaks"].as_u64().unwrap() > 0);
    for key in [
        "steps",
        "ke_peaks",
        "half_period_s",
        "first_peak",
        "last_peak",
    ] {
        assert_eq!(built_in[key], file[key], "{key}");
    }
    assert!(file["iterations"].is_null());
    assert_eq!(file["scene"]["ground"], built_in["scene"]["ground"]);
    assert_eq!(file["scene"]["ground"]["restitution"], 0.5);
    assert_eq!(file["scene"]["forces"], built_in["scene"]["forces"]);
    assert!(file["scene"]["forces"].to_string().contains("drag"));
}

/// Explicit Euler grows at every dt on an undamped rope: the run fails with status 1.
#[test]
fn a_diverging_run_exits_1() {
    let previous = write_scratch("previous-ke.csv", "an earlier run's series\n");
    let output = mss(&[
        "--solver",
        "explicit_euler",
        "--dt",
        "1e-3",
        "--ke-csv",
        &previous,
    ]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(err.contains("diverged at step"), "{err}");
    assert!(stdout(&output).is_empty());
    // The failed run leaves the earlier file as it was, and no partial file.
    assert_eq!(
        std::fs::read_to_string(&previous).unwrap(),
        "an earlier run's series\n"
    );
    assert!(!PathBuf::from(format!("{previous}.partial")).exists());
}

/// Every solver of springs and gravity in the registry runs the thesis rope from the command
/// line (PBD included, which the thesis describes but does not measure).
#[test]
fn every_registered_rope_solver_runs_the_thesis_rope() {
    for id in SolverId::ALL
        .into_iter()
        .filter(|id| matches!(id.info().builder, Builder::Springs(_)))
    {
        let solver = id.id();
        let m = json(&["--solver", solver, "--iterations", "20", "--max-time", "1"]);
        assert_eq!(m["solver"], solver);
        assert_eq!(m["iterations"], 20);
        assert!(m["ke_peaks"].as_u64().unwrap() >= 4, "{solver}: {m:#}");
    }
}

#[test]
fn tutorial_integrators_and_the_other_scenes_run() {
    for solver in ["symplectic_euler", "rk4"] {
        let m = json(&["--solver", solver, "--dt", "1e-4", "--max-time", "1"]);
        assert_eq!(m["solver"], solver);
        assert!(m["ke_peaks"].as_u64().unwrap() >= 4, "{solver}: {m:#}");
    }
    let cloth = json(&["--scene", "hanging_cloth", "--max-time", "1"]);
    assert_eq!(cloth["scene"]["fixed_nodes"], 2);
    let drop = json(&[
        "--scene",
        "cloth_drop",
        "--solver",
        "rk4",
        "--max-time",
        "0.1",
    ]);
    assert_eq!(drop["scene"]["fixed_nodes"], 0);
    let rope = json(&["--scene", "rope", "--nodes", "30", "--max-time", "1"]);
    assert_eq!(rope["scene"]["springs"], 29);
    let file = json(&[
        "--scene-file",
        "scenes/hanging-cloth.toml",
        "--max-time",
        "1",
    ]);
    assert_eq!(
        (
            file["scene"]["nodes"].as_u64(),
            file["scene"]["springs"].as_u64()
        ),
        (Some(25), Some(56))
    );
}

#[test]
fn csv_series_have_one_row_per_step_and_per_node() {
    let ke = scratch("ke.csv");
    let positions = scratch("positions.csv");
    let m = json(&[
        "--max-time",
        "0.05",
        "--ke-csv",
        ke.to_str().unwrap(),
        "--positions-csv",
        positions.to_str().unwrap(),
        "--positions-every",
        "20",
    ]);
    assert_eq!(m["steps"], 50);
    let ke = std::fs::read_to_string(ke).unwrap();
    let rows: Vec<&str> = ke.lines().collect();
    assert_eq!(rows[0], "time_s,kinetic_energy_j");
    assert_eq!(rows.len(), 1 + 51, "t = 0 and every step");
    assert_eq!(rows[1], "0,0");
    assert!(rows[51].starts_with("0.05,"), "{}", rows[51]);
    let positions = std::fs::read_to_string(positions).unwrap();
    let rows: Vec<&str> = positions.lines().collect();
    assert_eq!(rows[0], "time_s,node,x_m,y_m,z_m");
    // t = 0, 0.02, 0.04 and the final 0.05 s, 10 nodes each.
    assert_eq!(rows.len(), 1 + 4 * 10);
    assert_eq!(rows[1], "0,0,0,0,0");
    assert_eq!(rows[10], "0,9,9,0,0");
    assert!(rows[11].starts_with("0.02,0,"), "{}", rows[11]);
    assert!(rows[40].starts_with("0.05,9,9,0,0"), "{}", rows[40]);
}

#[test]
fn text_output_names_every_metric() {
    let output = mss(&["--max-time", "2", "--compare-reference", "--dt", "2e-3"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    for label in [
        "solver",
        "scene",
        "KE peaks",
        "T/2 thesis",
        "T/2 exact",
        "end time",
        "hit the time limit",
        "reference",
        "rest-state error",
    ] {
        assert!(text.contains(label), "{label:?} not in\n{text}");
    }
}

#[test]
fn help_documents_every_option() {
    let output = mss(&["--help"]);
    assert!(output.status.success());
    let help = stdout(&output);
    for option in [
        "--solver",
        "--dt",
        "--iterations",
        "--scene ",
        "--scene-file",
        "--stiffness",
        "--gravity",
        "--nodes",
        "--rest-length",
        "--node-mass",
        "--span",
        "--threshold",
        "--max-time",
        "--exempt-first-peak",
        "--velocity-damping",
        "--compare-reference",
        "--json",
        "--ke-csv",
        "--positions-csv",
        "--positions-every",
        "--max-work",
        "--max-memory",
        "--list-solvers",
        "--stiffness-factor",
        "--tolerance",
        "--spectral-radius",
        "--gamma",
        "--warmup",
        "--window",
        "--alpha",
        "--beta",
    ] {
        assert!(help.contains(option), "{option} not in --help");
    }
    for id in SolverId::ALL {
        assert!(help.contains(id.id()), "{id} not in --help");
    }
    for value in ["thesis", "rope", "hanging_cloth", "cloth_drop", "pendulum"] {
        assert!(help.contains(value), "{value} not in --help");
    }
    for unit in [
        "in s",
        "N/m",
        "in J",
        "m/s²",
        "in kg",
        "1/s",
        "Exit status",
        "written in place",
        "1e-9 to 1e9 kg",
    ] {
        assert!(help.contains(unit), "{unit} not in --help");
    }
}

/// `--list-solvers` prints the registry: one line a solver, its identifier first, with its
/// source and its options.
#[test]
fn list_solvers_prints_one_line_per_registered_solver() {
    let output = mss(&["--list-solvers"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), SolverId::ALL.len(), "{text}");
    for (line, id) in lines.iter().zip(SolverId::ALL) {
        let info = id.info();
        assert!(line.starts_with(&format!("{} ", info.id)), "{line}");
        assert!(line.contains(info.source), "{line}");
        for option in info.options {
            assert!(
                line.contains(&format!("--{}", option.name.replace('_', "-"))),
                "{line}"
            );
        }
    }
}

/// A solver option is checked against its range and refused, naming it, by a solver that does
/// not take it.
#[test]
fn solver_options_are_checked_and_refused_where_they_do_not_apply() {
    assert_bad_input(
        &["--solver", "pbd", "--stiffness-factor", "2"],
        &["--stiffness-factor", "[0, 1]"],
    );
    assert_bad_input(
        &["--solver", "xpbd", "--stiffness-factor", "0.5"],
        &["--stiffness-factor", "xpbd has no such option", "pbd"],
    );
    assert_bad_input(
        &["--solver", "rk4", "--tolerance", "1e-3"],
        &["--tolerance", "rk45"],
    );
    // The three: a window of 0, a negative damping, a spectral radius of 1 or more.
    assert_bad_input(
        &["--solver", "anderson_liu", "--window", "0"],
        &["--window", ">= 1"],
    );
    assert_bad_input(
        &["--solver", "anderson_admm", "--window", "21"],
        &["--window", "20"],
    );
    assert_bad_input(
        &["--solver", "damped_admm", "--alpha", "-1"],
        &["--alpha", "from 0 to"],
    );
    assert_bad_input(
        &["--solver", "damped_backward_euler", "--beta=-1e-3"],
        &["--beta", "from 0 to"],
    );
    // A separate negative value in scientific notation is the option's value, not flags.
    assert_bad_input(
        &["--solver", "damped_backward_euler", "--beta", "-1e-3"],
        &["--beta", "from 0 to"],
    );
    assert_bad_input(
        &["--solver", "chebyshev_liu", "--spectral-radius", "1"],
        &["--spectral-radius", "< 1"],
    );
    assert_bad_input(
        &["--solver", "chebyshev_admm", "--warmup", "2.5"],
        &["--warmup", "integer"],
    );
    assert_bad_input(
        &["--solver", "admm_pd", "--stop-tolerance", "0"],
        &["--stop-tolerance", "> 0"],
    );
    assert_bad_input(
        &["--solver", "xpbd_substeps", "--stop-tolerance", "1e-3"],
        &["--stop-tolerance", "no iterations"],
    );
    assert_bad_input(
        &["--solver", "rk4", "--stop-tolerance", "1e-3"],
        &["--stop-tolerance", "no iterations"],
    );
    let m = json(&[
        "--solver",
        "pbd",
        "--stiffness-factor",
        "0.5",
        "--max-time",
        "0.5",
    ]);
    assert!(m["solver_name"].as_str().unwrap().contains("0.5"), "{m:#}");
}

/// `--scene sheet --n N`: the sheet of docs/sheet-scene.md at any size from 3; `--n` is refused
/// elsewhere and below 3.
#[test]
fn sheet_scene_runs_at_any_size() {
    let m = json(&[
        "--scene",
        "sheet",
        "--n",
        "4",
        "--solver",
        "admm_pd",
        "--iterations",
        "5",
        "--dt",
        "0.01",
        "--max-time",
        "0.5",
    ]);
    assert_eq!(m["scene"]["nodes"], 16);
    assert_eq!(m["scene"]["fixed_nodes"], 4);
    // 2·4·3 structural and 2·3·3 shear springs.
    assert_eq!(m["scene"]["springs"], 42);
    assert_bad_input(&["--scene", "sheet", "--n", "2"], &["--n", "from 3 to"]);
    assert_bad_input(&["--scene", "rope", "--n", "5"], &["--n", "sheet"]);
}

/// `--stop-tolerance` runs a solver to a tolerance, `--iterations` its cap: the mean taken is
/// reported, below the cap where the iteration converges (Anderson on Liu at k = 1e6), at it
/// where it cannot within the cap (plain Liu 2013, which needs about 1600).
#[test]
fn a_run_to_a_tolerance_reports_the_iterations_taken() {
    let args = |solver| {
        json(&[
            "--solver",
            solver,
            "--stiffness",
            "1e6",
            "--dt",
            "0.01",
            "--iterations",
            "200",
            "--stop-tolerance",
            "1e-6",
            "--max-time",
            "1",
        ])
    };
    let accelerated = args("anderson_liu");
    assert_eq!(accelerated["stop_tolerance_m"], 1e-6);
    assert_eq!(accelerated["iterations"], 200);
    let mean = accelerated["iterations_mean"].as_f64().unwrap();
    assert!((1.0..50.0).contains(&mean), "{mean}");
    let plain = args("fast_mass_spring");
    assert!(plain["iterations_mean"].as_f64().unwrap() > 150.0);
    let fixed = json(&[
        "--solver",
        "admm_pd",
        "--iterations",
        "7",
        "--max-time",
        "0.1",
    ]);
    assert_eq!(fixed["stop_tolerance_m"], Value::Null);
    assert_eq!(fixed["iterations_mean"], 7.0);
}

/// The tutorial's adaptive integrator from the command line (chapter 9 of the report): a
/// tolerance runs Dormand-Prince 5(4); a tolerance out of range, or one given to a fixed-step
/// integrator, exits 2 naming `--tolerance`.
#[test]
fn mss_runs_rk45_and_rejects_a_bad_tolerance() {
    let output = mss(&[
        "--scene",
        "pendulum",
        "--solver",
        "rk45",
        "--tolerance",
        "1e-6",
        "--dt",
        "0.01",
        "--max-time",
        "1",
    ]);
    assert_eq!(output.status.code(), Some(0));
    assert!(
        stdout(&output).contains("Dormand-Prince 5(4)"),
        "{}",
        stdout(&output)
    );
    for bad in ["0", "-0.001", "nan", "inf"] {
        let tolerance = format!("--tolerance={bad}");
        let args = ["--scene", "pendulum", "--solver", "rk45", &tolerance];
        assert_bad_input(&args, &["--tolerance"]);
    }
    let fixed_step = [
        "--scene",
        "pendulum",
        "--solver",
        "rk4",
        "--tolerance",
        "1e-6",
    ];
    assert_bad_input(&fixed_step, &["--tolerance"]);
}

/// The continuum scenes from the command line: `--list-energies` names the five energies, and
/// Cook's membrane at N = 4 prints its Newton residual and u_y at (48, 52) (11.25199, as
/// tests/continuum measures); every bad field is refused (exit 2) with the option or field
/// named: an unknown energy, E ≤ 0, an `--n` out of range or given for the patch, a linear
/// membrane, `--energy` on a spring scene and a spring option on a continuum scene. Wrong
/// implementation it catches (tried): the continuum scenes not routed to their statics (every
/// run refused as a scene without time stepping).
#[test]
fn the_continuum_scenes_run_statics_and_refuse_bad_fields() {
    let listed = stdout(&mss(&["--list-energies"]));
    for name in ["linear", "arap", "corotated", "stvk", "stable-neo-hookean"] {
        assert!(listed.contains(name), "{name} not in {listed}");
    }
    let output = mss(&["--scene", "cook", "--n", "4"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("u_y at (48, 52): 11.25199"), "{text}");
    assert!(text.contains("residual"), "{text}");
    assert_bad_input(
        &["--scene", "beam", "--energy", "rubber"],
        &["--energy", "stable-neo-hookean"],
    );
    assert_bad_input(
        &["--scene", "beam", "--youngs", "-1"],
        &["--youngs", "from 1e-6 to"],
    );
    assert_bad_input(&["--scene", "beam", "--youngs", "1e-300"], &["--youngs"]);
    assert_bad_input(&["--scene", "beam", "--n", "0"], &["--n"]);
    assert_bad_input(
        &["--scene", "cook", "--n", "3"],
        &["cook.elements_per_side"],
    );
    assert_bad_input(&["--scene", "patch", "--n", "3"], &["--n", "patch"]);
    assert_bad_input(
        &["--scene", "membrane", "--energy", "linear"],
        &["energy", "membranes"],
    );
    assert_bad_input(
        &["--scene", "thesis", "--energy", "arap"],
        &["--energy", "continuum"],
    );
    assert_bad_input(
        &["--scene", "cook", "--stiffness", "1e3"],
        &["--stiffness", "continuum"],
    );
}

/// The continuum's dynamics from the command line (issue 50): `--duration` runs the soft
/// stable neo-Hookean beam under each optimization integrator, prints the Newton residual
/// reached (at most the stated 1e-9 of the largest load) and writes its kinetic energy as a
/// CSV read back strictly (one row a step from t = 0, the first at rest, the beam moving
/// after). Spring-only solvers are refused with why (Liu 2013 by its springs' Laplacian), and
/// the options that do not apply are named (`--integrator` without `--duration`, the spring
/// stopping rule's `--max-time`, `--duration` on a spring scene). Wrong implementations it
/// catches: the dynamics options ignored with a continuum scene (statics printed, no CSV); a
/// solver other than Newton silently run as Newton.
#[test]
fn the_continuum_scenes_run_every_integrator_and_refuse_spring_solvers() {
    for integrator in ["backward-euler", "implicit-midpoint", "bdf2", "tr-bdf2"] {
        let ke = scratch(&format!("continuum-ke-{integrator}.csv"));
        let output = mss(&[
            "--scene",
            "beam",
            "--energy",
            "stable-neo-hookean",
            "--youngs",
            "1e6",
            "--integrator",
            integrator,
            "--dt",
            "0.05",
            "--duration",
            "0.1",
            "--ke-csv",
            ke.to_str().unwrap(),
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        let text = stdout(&output);
        assert!(
            text.contains(&format!("integrator: {integrator}")),
            "{text}"
        );
        let residual: f64 = text
            .split("largest residual ")
            .nth(1)
            .and_then(|rest| rest.split_whitespace().next())
            .and_then(|r| r.parse().ok())
            .unwrap_or_else(|| panic!("no residual in {text}"));
        assert!(residual <= 1e-9, "{residual:e}");
        let mut reader = csv::ReaderBuilder::new().from_path(&ke).unwrap();
        assert_eq!(
            reader.headers().unwrap(),
            vec!["time_s", "kinetic_energy_j"]
        );
        let rows: Vec<(f64, f64)> = reader
            .records()
            .map(|r| {
                let r = r.unwrap();
                (r[0].parse().unwrap(), r[1].parse().unwrap())
            })
            .collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[0], (0.0, 0.0));
        assert!(rows[2].0 == 0.1 && rows[2].1 > 0.0);
    }
    assert_bad_input(
        &["--scene", "beam", "--solver", "fast_mass_spring"],
        &["fast_mass_spring", "springs only", "Laplacian"],
    );
    assert_bad_input(
        &["--scene", "cook", "--solver", "xpbd"],
        &["xpbd", "springs"],
    );
    assert_bad_input(
        &["--scene", "beam", "--integrator", "bdf2"],
        &["--integrator", "--duration"],
    );
    assert_bad_input(
        &["--scene", "beam", "--duration", "1", "--max-time", "3"],
        &["--max-time", "--duration"],
    );
    assert_bad_input(
        &["--scene", "beam", "--duration", "0.1", "--dt", "1"],
        &["--dt"],
    );
    assert_bad_input(
        &["--scene", "thesis", "--duration", "1"],
        &["--duration", "continuum"],
    );
}

//! `mss --scene beam|membrane|cook|patch`: a continuum scene of `docs/fem-scenes.md` solved
//! for its static equilibrium by projected Newton (`src/model/continuum/statics.rs`), with the
//! scene's measurement; with `--duration`, its motion released from rest under an optimization
//! integrator (`src/integrators/continuum.rs`), every stage solved by the same Newton; and
//! `--list-energies`. Newton is the only solver of elements: every other solver, and the
//! spring scenes' options that do not apply, are refused with a reason.

use crate::cli::{Cli, SceneArg};
use crate::failure::Failure;
use mass_spring_solvers::error::{require_within, shown};
use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::continuum::scenes::{
    beam, beam_tip_deflection, cook, cook_node, membrane, patch, BEAM_YOUNGS, COOK_YOUNGS,
    PATCH_MAP, PATCH_SHIFT, PATCH_YOUNGS,
};
use mass_spring_solvers::model::continuum::statics::{static_equilibrium, DEFAULT_TOLERANCE};
use mass_spring_solvers::model::continuum::system::ContinuumSystem;
use mass_spring_solvers::model::metrics::{MAX_SIMULATED_TIME_S, STOP_THRESHOLD_J};
use mass_spring_solvers::solvers::registry::{Builder, SolverId};

/// The range of `--youngs`, Pa (N/m for the membrane's Y).
const YOUNGS_RANGE: (f64, f64) = (1e-6, 1e15);

/// The membrane's Y = E·t when `--youngs` is not given, N/m: 8k/3 at the sheet's k = 1e6 N/m.
const DEFAULT_MEMBRANE_YOUNGS: f64 = 8e6 / 3.0;

/// Every energy, one line each: its name and what it is.
pub(crate) fn list_energies() -> String {
    let what = |kind: EnergyKind| {
        match kind {
        EnergyKind::Linear => "μ‖ε‖² + λ/2 (tr ε)², ε = sym(F) − I: small strain, not rotation invariant; no membranes",
        EnergyKind::Arap => "μ‖F − R‖²: Projective Dynamics' strain energy, no Poisson effect",
        EnergyKind::Corotated => "μ‖F − R‖² + λ/2 (tr(RᵀF) − d)²",
        EnergyKind::StVenantKirchhoff => "μ‖E‖² + λ/2 (tr E)², E = (FᵀF − I)/2: weak in compression",
        EnergyKind::StableNeoHookean => "μ/2 (tr(FᵀF) − d) + λ′/2 (J − α)², λ′ = λ + μ, α = 1 + μ/λ′",
    }
    };
    EnergyKind::ALL
        .iter()
        .map(|&kind| format!("{:<20}{}\n", kind.name(), what(kind)))
        .collect()
}

/// The continuum scene's system from the options, each checked: `--energy` (a name of
/// `--list-energies`), `--youngs` (E in Pa; the membrane's Y = E·t in N/m), `--n` (beam r,
/// membrane n, Cook's N); the options of the spring scenes' dynamics refused.
fn system(cli: &Cli) -> Result<(ContinuumSystem, EnergyKind, f64, usize), Failure> {
    let scene = cli.scene;
    if cli.solver != SolverId::BackwardEuler {
        return Err(Failure::input(format!(
            "--solver {} cannot take the continuum scene {}: {}; Newton (--solver \
             backward_euler, every stage solved to a residual) is the continuum's solver",
            cli.solver.id(),
            scene.id(),
            springs_only_reason(cli.solver)
        )));
    }
    let spring_options = [
        ("--stiffness", cli.stiffness.is_some()),
        ("--gravity", cli.gravity.is_some()),
        ("--nodes", cli.nodes.is_some()),
        ("--compare-reference", cli.compare_reference),
        ("--json", cli.json),
        ("--iterations", cli.iterations.is_some()),
        ("--stop-tolerance", cli.stop_tolerance.is_some()),
        ("--tolerance", cli.tolerance.is_some()),
        ("--first-iterate", cli.first_iterate.is_some()),
        ("--exempt-first-peak", cli.exempt_first_peak),
        ("--velocity-damping", cli.velocity_damping != 0.0),
        (
            "--max-time (the continuum's run lasts --duration)",
            cli.max_time != MAX_SIMULATED_TIME_S,
        ),
        (
            "--threshold (the continuum's run lasts --duration)",
            cli.threshold != STOP_THRESHOLD_J,
        ),
    ];
    if let Some((option, _)) = spring_options.iter().find(|(_, given)| *given) {
        return Err(Failure::input(format!(
            "{option} does not apply to the continuum scene {}",
            scene.id()
        )));
    }
    if cli.duration.is_none() {
        let dynamics = [
            ("--integrator", cli.integrator.is_some()),
            ("--ke-csv", cli.ke_csv.is_some()),
            ("--positions-csv", cli.positions_csv.is_some()),
        ];
        if let Some((option, _)) = dynamics.iter().find(|(_, given)| *given) {
            return Err(Failure::input(format!(
                "{option} needs --duration with the continuum scene {} (without it, statics \
                 only)",
                scene.id()
            )));
        }
    }
    let energy = match &cli.energy {
        Some(name) => EnergyKind::parse("--energy", name)?,
        None if scene == SceneArg::Cook => EnergyKind::Linear,
        None => EnergyKind::StableNeoHookean,
    };
    let youngs = cli.youngs.unwrap_or(match scene {
        SceneArg::Cook => COOK_YOUNGS,
        SceneArg::Patch => PATCH_YOUNGS,
        SceneArg::Membrane => DEFAULT_MEMBRANE_YOUNGS,
        _ => BEAM_YOUNGS[1],
    });
    // Bounded before any work, so that an energy's stresses and their Newton steps stay
    // finite: the scenes' moduli run from 1 (Cook) to 1e9 Pa.
    let youngs = require_within("--youngs", youngs, YOUNGS_RANGE.0, YOUNGS_RANGE.1, "Pa")?;
    let (default_n, min_n, max_n) = match scene {
        SceneArg::Beam => (2, 1, 64),
        SceneArg::Membrane => (10, 3, 200),
        _ => (16, 2, 1024),
    };
    if scene == SceneArg::Patch && cli.n.is_some() {
        return Err(Failure::input(
            "--n does not apply to --scene patch (a fixed 3 × 3 × 3 mesh)",
        ));
    }
    let n = cli.n.unwrap_or(default_n);
    let n = require_within(
        "--n",
        n as f64,
        min_n as f64,
        max_n as f64,
        "cells or nodes a side",
    )? as usize;
    let system = match scene {
        SceneArg::Beam => beam(n, energy, youngs),
        SceneArg::Membrane => membrane(n, energy, 3.0 * youngs / 8.0),
        SceneArg::Cook => cook(n, energy, youngs),
        _ => patch(energy),
    }?;
    Ok((system, energy, youngs, n))
}

/// Why `solver` cannot take a continuum scene's elements.
fn springs_only_reason(solver: SolverId) -> &'static str {
    match solver {
        SolverId::FastMassSpring => {
            "Liu 2013 solves springs only: its global matrix is the springs' Laplacian and its \
             local step projects each spring to its rest length, and a finite element has \
             neither (the thesis's §5: with FEM, Liu drops out)"
        }
        _ if matches!(solver.info().builder, Builder::Particles(_)) => {
            "the tutorial's integrators move particles and springs only"
        }
        _ => {
            "its iteration is written against springs (their constraints or local steps); \
             this crate gives it no finite elements yet"
        }
    }
}

/// Solves the scene's statics, or with `--duration` its dynamics, and prints what it reached
/// and the scene's measurement.
pub(crate) fn run(cli: &Cli) -> Result<(), Failure> {
    let (system, energy, youngs, n) = system(cli)?;
    if let Some(duration) = cli.duration {
        return crate::continuum_dynamics::run(cli, &system, duration, n);
    }
    let eq = static_equilibrium(&system, DEFAULT_TOLERANCE)?;
    let u = &eq.displacement;
    let fixed = (0..system.node_count())
        .filter(|&i| system.is_fixed(i))
        .count();
    let size = match cli.scene {
        SceneArg::Patch => String::new(),
        _ => format!(" (n = {n})"),
    };
    println!(
        "scene: {}{size}, energy: {}, Young's modulus {}",
        cli.scene.id(),
        energy.name(),
        shown(youngs)
    );
    println!(
        "nodes: {} ({fixed} fixed), elements: {}",
        system.node_count(),
        system.elements().len()
    );
    println!(
        "Newton: {} iterations ({} with the projected Hessian), residual {:.2e} of {} N",
        eq.iterations,
        eq.projected_iterations,
        eq.relative_residual,
        shown(eq.scale)
    );
    match cli.scene {
        SceneArg::Beam => println!("tip deflection: {:.6e} m", beam_tip_deflection(n, u)),
        SceneArg::Cook => println!(
            "u_y at (48, 52): {:.6}, at (48, 60): {:.6}",
            u[2 * cook_node(n, n, n / 2) + 1],
            u[2 * cook_node(n, n, n) + 1]
        ),
        SceneArg::Membrane => {
            let lowest = u.iter().skip(1).step_by(3).fold(0.0_f64, |a, &b| a.min(b));
            println!("lowest node: {lowest:.6e} m below its rest height");
        }
        _ => {
            let x = system.rest_positions();
            let off = (0..system.node_count())
                .flat_map(|i| (0..3).map(move |r| (i, r)))
                .map(|(i, r)| {
                    let mapped: f64 = (0..3).map(|c| PATCH_MAP[r][c] * x[3 * i + c]).sum::<f64>()
                        + PATCH_SHIFT[r];
                    (x[3 * i + r] + u[3 * i + r] - mapped).abs()
                })
                .fold(0.0, f64::max);
            println!("largest distance from the affine map: {off:.3e} m");
        }
    }
    Ok(())
}

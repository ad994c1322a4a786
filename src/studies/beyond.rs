//! Beyond the thesis (§5, future work): the solvers the thesis did not measure, their settings
//! (the benchmark of [`crate::studies::benchmark`] runs them), the scenes, and every solver's
//! convergence toward the converged Backward Euler step.
//!
//! **Convergence.** One step of dt from a start state, with $`m = 1 \dots 200`$ iterations
//! (a fresh solver for each $`m`$), against the step solved to round-off
//! ([`SolverSpec::converged_step`]): the gap $`\max_i |x_i - x_i^\ast|`$ after $`m`$
//! iterations. The start is the thesis rope at rest, or [`Start::Step10`], a moving state.
//! Every solver's step starts from the inertial prediction
//! $`y = x_n + h v_n + h^2 M^{-1} f_{ext}`$ ([`COMPARISON_START`]), so that the curves compare
//! solvers, not starts; [`own_start_effects`] measures what each solver's own start changes.

use crate::error::Result;
use crate::integrators::damping::RayleighDamping;
use crate::integrators::first_iterate::FirstIterate;
use crate::model::catenary::ElasticChain;
use crate::model::metrics::rest_error_max;
use crate::model::scene::{thesis_rope, SheetParams, SHEET_NODES_PER_SIDE, THESIS_STIFFNESSES};
use crate::model::sheet_equilibrium::sheet_equilibrium;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::backward_euler::ConvergedStepOptions;
use crate::solvers::converged_stage::converged_step;
use crate::solvers::registry::{Builder, SolverId, SolverSpec};
use crate::studies::experiments::run_parallel;

/// The time steps of Tables 2-7, s.
pub const GRID_DTS: [f64; 3] = [0.1, 0.01, 0.001];

/// The dampings of the damped solvers in the grid: none, mass-proportional, and
/// stiffness-proportional (the thesis rope's lowest mode, about 3 rad/s, gets
/// ζ = α/(2ω) ≈ 0.08 from the second and ζ = βω/2 ≈ 0.003 from the third; its stiff modes far
/// more).
pub const GRID_DAMPINGS: [RayleighDamping; 3] = [
    RayleighDamping::NONE,
    RayleighDamping {
        alpha: 0.5,
        beta: 0.0,
    },
    RayleighDamping {
        alpha: 0.0,
        beta: 2e-3,
    },
];

/// The damping of the damped solvers' convergence curves (both terms at once).
pub const CONVERGENCE_DAMPING: RayleighDamping = RayleighDamping {
    alpha: 0.5,
    beta: 2e-3,
};

/// Iterations of the convergence curves.
pub const CONVERGENCE_ITERATIONS: usize = 200;

/// The time step of [`Start::Step10`]'s ten Backward Euler steps, s.
pub const STEP10_DT: f64 = 1e-2;

/// The three settings of a solver in the grid (for the thesis's four, their tables'
/// iteration counts are the thesis's own and they are not rerun here).
pub fn grid_settings(id: SolverId) -> Option<Vec<SolverSpec>> {
    let counts = |counts: &[usize]| Some(counts.iter().map(|&m| SolverSpec::new(id, m)).collect());
    match id {
        // The thesis's own, at the counts of its Tables 1-7.
        SolverId::BackwardEuler => counts(&[5]),
        SolverId::Xpbd | SolverId::AdmmPd => counts(&[1, 20, 50]),
        SolverId::FastMassSpring => counts(&[1, 30, 70]),
        SolverId::Pbd => counts(&[1, 20, 50]),
        // The accelerated forms at their base's counts (Tables 4-7).
        SolverId::ChebyshevLiu | SolverId::AndersonLiu => counts(&[1, 30, 70]),
        SolverId::ChebyshevAdmm | SolverId::AndersonAdmm => counts(&[1, 20, 50]),
        // XPBD's counts as substeps: the same number of constraint sweeps as Tables 2-3.
        SolverId::XpbdSubsteps => counts(&[1, 20, 50]),
        SolverId::Lbfgs | SolverId::Vbd => counts(&[1, 5, 20]),
        // The damped pair at fixed iterations, three dampings: none, mass- and
        // stiffness-proportional.
        SolverId::DampedBackwardEuler | SolverId::DampedAdmm => {
            let iterations = if id == SolverId::DampedAdmm { 50 } else { 5 };
            Some(
                GRID_DAMPINGS
                    .iter()
                    .map(|&damping| {
                        let mut spec = SolverSpec::new(id, iterations);
                        spec.params.damping = damping;
                        spec
                    })
                    .collect(),
            )
        }
        _ => None,
    }
}

/// The scenes of the grid: the thesis rope and the sheet of `docs/sheet-scene.md`
/// ([`SHEET_NODES_PER_SIDE`] nodes a side), the thesis's experiment one dimension up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GridScene {
    Rope,
    Sheet,
}

impl GridScene {
    pub const ALL: [GridScene; 2] = [GridScene::Rope, GridScene::Sheet];

    /// The identifier in the CSV files.
    pub fn id(self) -> &'static str {
        match self {
            GridScene::Rope => "rope",
            GridScene::Sheet => "sheet",
        }
    }

    /// The scene at `stiffness`.
    pub fn system(self, stiffness: f64) -> Result<MassSpringSystem> {
        match self {
            GridScene::Rope => thesis_rope(stiffness),
            GridScene::Sheet => SheetParams::spec(SHEET_NODES_PER_SIDE, stiffness).build(),
        }
    }

    /// The exact static equilibrium at `stiffness`: the discrete elastic chain (rope), the
    /// Newton minimiser of [`crate::model::sheet_equilibrium`] (sheet).
    pub fn equilibrium(self, stiffness: f64) -> Result<Vec<Vec3>> {
        match self {
            GridScene::Rope => Ok(ElasticChain::thesis_rope(stiffness)
                .and_then(|chain| chain.solve_equilibrium())
                .map_err(|e| {
                    crate::Error::Input(format!("exact catenary at k = {stiffness} N/m: {e}"))
                })?
                .positions),
            GridScene::Sheet => {
                Ok(sheet_equilibrium(&SheetParams::spec(SHEET_NODES_PER_SIDE, stiffness))?.x)
            }
        }
    }
}

/// The solvers of the grid, in registry order.
pub fn grid_solvers() -> Vec<SolverId> {
    SolverId::ALL
        .into_iter()
        .filter(|&id| grid_settings(id).is_some())
        .collect()
}

/// A short label of a setting: its iterations and the options that differ from the defaults.
pub fn setting_label(spec: &SolverSpec) -> String {
    let info = spec.id.info();
    let mut label = match info.iteration {
        Some(_) => format!("{} it.", spec.iterations),
        None => String::new(),
    };
    let defaults = SolverSpec::new(spec.id, spec.iterations);
    for option in info.options {
        let value = spec.params.get(option.name);
        if value != defaults.params.get(option.name) {
            if let Some(value) = value {
                label += &format!(", {} = {value}", option.name);
            }
        }
    }
    label
}

/// The state a convergence curve starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// The thesis rope at rest, straight (the first step of every thesis run).
    Rest,
    /// After ten converged Backward Euler steps of [`STEP10_DT`] from rest: a moving state.
    Step10,
}

impl Start {
    pub const ALL: [Start; 2] = [Start::Rest, Start::Step10];

    /// The identifier in `convergence.csv`.
    pub fn id(self) -> &'static str {
        match self {
            Start::Rest => "rest",
            Start::Step10 => "step10",
        }
    }

    /// Its name in the report's text and figures.
    pub fn label(self) -> &'static str {
        match self {
            Start::Rest => "at rest",
            Start::Step10 => "moving",
        }
    }

    /// The start state on `system`.
    pub fn state(self, system: &MassSpringSystem) -> Result<State> {
        let mut state = system.initial_state();
        if self == Start::Step10 {
            for _ in 0..10 {
                state = converged_step(system, &state, STEP10_DT, ConvergedStepOptions::default())?;
            }
        }
        Ok(state)
    }
}

/// $`\max_i |x_i - y_i|`$, m.
pub fn gap(x: &State, y: &State) -> f64 {
    rest_error_max(&x.x, &y.x)
}

/// One convergence curve: the gap after each iteration count.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvergenceCurve {
    /// The solver (its iteration count is the curve's variable).
    pub spec: SolverSpec,
    pub scene: &'static str,
    pub start: Start,
    pub stiffness: f64,
    pub dt_s: f64,
    /// The gap after m = 1, 2, ... iterations, m; None where the step failed.
    pub gaps: Vec<Option<f64>>,
}

impl ConvergenceCurve {
    /// The fewest iterations whose gap is below `tolerance`, if any within the curve.
    pub fn iterations_to(&self, tolerance: f64) -> Option<usize> {
        self.gaps
            .iter()
            .position(|g| g.is_some_and(|g| g < tolerance))
            .map(|i| i + 1)
    }
}

/// The gap after $`m = 1 \dots`$ `iterations` iterations of one step of `spec` from `state`.
pub fn gap_curve(
    spec: &SolverSpec,
    system: &MassSpringSystem,
    state: &State,
    dt: f64,
    iterations: usize,
) -> Result<Vec<Option<f64>>> {
    let oracle = spec.converged_step(system, state, dt)?;
    let spec = &spec.with_estimates(system, dt)?;
    Ok((1..=iterations)
        .map(|m| {
            let mut next = state.clone();
            let spec = SolverSpec {
                iterations: m,
                ..*spec
            };
            spec.build_send(system, dt)
                .and_then(|mut solver| solver.step(&mut next))
                .ok()
                .map(|()| gap(&next, &oracle))
        })
        .collect())
}

/// The first iterate of every solver in the comparisons: the inertial prediction.
pub const COMPARISON_START: FirstIterate = FirstIterate::InertialPrediction;

/// `spec` starting each step at [`COMPARISON_START`], if it takes a first iterate (PBD, XPBD
/// and its substeps start at the prediction by construction).
pub fn from_comparison_start(mut spec: SolverSpec) -> SolverSpec {
    if takes_first_iterate(spec.id) {
        spec.params.first_iterate = Some(COMPARISON_START);
    }
    spec
}

/// Whether `id` has the `first_iterate` option.
pub fn takes_first_iterate(id: SolverId) -> bool {
    id.info().options.iter().any(|o| o.name == "first_iterate")
}

/// The solvers of the convergence curves: every solver of springs and gravity with
/// iterations, at its default options, from [`COMPARISON_START`].
pub fn convergence_solvers() -> Vec<SolverSpec> {
    SolverId::ALL
        .into_iter()
        .filter(|id| {
            let info = id.info();
            matches!(info.builder, Builder::Springs(_)) && info.iteration.is_some()
        })
        .map(|id| {
            let mut spec = SolverSpec::new(id, 1);
            if matches!(id, SolverId::DampedBackwardEuler | SolverId::DampedAdmm) {
                spec.params.damping = CONVERGENCE_DAMPING;
            }
            from_comparison_start(spec)
        })
        .collect()
}

/// What a solver's own start changes: iterations to a tolerance from its own first iterate
/// and from [`COMPARISON_START`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StartEffect {
    /// The solver at its own start (the registry's default).
    pub spec: SolverSpec,
    pub own: Option<usize>,
    pub shared: Option<usize>,
}

/// [`StartEffect`] of every solver of [`convergence_solvers`] whose own start is not the
/// comparison's, one step of `dt` from `state` at `tolerance`, searched up to `max`. A solver
/// with history (VBD's adaptive guess) first takes the step from `previous` (the state one
/// step of the same motion earlier), so that its own start is what a running solver uses.
pub fn own_start_effects(
    system: &MassSpringSystem,
    previous: &State,
    state: &State,
    dt: f64,
    tolerance: f64,
    max: usize,
) -> Result<Vec<StartEffect>> {
    convergence_solvers()
        .into_iter()
        .filter(|spec| takes_first_iterate(spec.id))
        .filter_map(|shared| {
            let own = SolverSpec {
                params: crate::solvers::registry::SolverParams {
                    first_iterate: None,
                    ..shared.params
                },
                ..shared
            };
            let own_rule = own_first_iterate(own.id);
            (own_rule != Some(COMPARISON_START)).then_some((own, shared))
        })
        .map(|(own, shared)| {
            let warm = own_first_iterate(own.id) == Some(FirstIterate::Adaptive);
            Ok(StartEffect {
                spec: own,
                own: iterations_to_warm(
                    &own,
                    system,
                    warm.then_some(previous),
                    state,
                    dt,
                    tolerance,
                    max,
                )?,
                shared: iterations_to(&shared, system, state, dt, tolerance, max)?,
            })
        })
        .collect()
}

/// The first iterate `id` starts from by default: `None` for damped ADMM's own $`\hat x`$.
pub fn own_first_iterate(id: SolverId) -> Option<FirstIterate> {
    match id {
        SolverId::BackwardEuler | SolverId::DampedBackwardEuler | SolverId::FastMassSpring => {
            Some(FirstIterate::Previous)
        }
        SolverId::Vbd => Some(FirstIterate::Adaptive),
        SolverId::DampedAdmm => None,
        _ => Some(FirstIterate::InertialPrediction),
    }
}

/// [`iterations_to`], each solver first stepping from `previous` when given (its history),
/// by a linear scan up to `max`.
fn iterations_to_warm(
    spec: &SolverSpec,
    system: &MassSpringSystem,
    previous: Option<&State>,
    state: &State,
    dt: f64,
    tolerance: f64,
    max: usize,
) -> Result<Option<usize>> {
    let Some(previous) = previous else {
        return iterations_to(spec, system, state, dt, tolerance, max);
    };
    let oracle = spec.converged_step(system, state, dt)?;
    for m in 1..=max {
        let mut solver = SolverSpec {
            iterations: m,
            ..*spec
        }
        .build_send(system, dt)?;
        solver.step(&mut previous.clone())?;
        let mut next = state.clone();
        solver.step(&mut next)?;
        if gap(&next, &oracle) < tolerance {
            return Ok(Some(m));
        }
    }
    Ok(None)
}

/// One point of the scan of Chebyshev-Liu's $`\rho`$: the iterations to a tolerance with
/// `rho` given, or found by Wang's gradient-ratio rule (`rho` `None`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RhoPoint {
    pub rho: Option<f64>,
    pub iterations: Option<usize>,
}

/// Iterations of Chebyshev-Liu from [`COMPARISON_START`] to `tolerance` for each $`\rho`$ of
/// `rhos`, and by the gradient-ratio rule (last), up to `max`.
pub fn rho_scan(
    system: &MassSpringSystem,
    state: &State,
    dt: f64,
    rhos: &[f64],
    tolerance: f64,
    max: usize,
) -> Result<Vec<RhoPoint>> {
    let base = from_comparison_start(SolverSpec::new(SolverId::ChebyshevLiu, 1));
    let given = rhos.iter().map(|&rho| {
        let mut spec = base;
        spec.params.spectral_radius = Some(rho);
        (Some(rho), spec)
    });
    let mut wang = base;
    wang.params.rho_rule = crate::solvers::chebyshev::RhoRule::GradientRatio;
    given
        .chain(std::iter::once((None, wang)))
        .map(|(rho, spec)| {
            Ok(RhoPoint {
                rho,
                iterations: iterations_to(&spec, system, state, dt, tolerance, max)?,
            })
        })
        .collect()
}

/// Every convergence curve of the report: every solver of [`convergence_solvers`], the thesis
/// rope, both starts, both stiffnesses, dt = 1e-2 and 1e-3 s.
pub fn convergence_curves(
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<ConvergenceCurve>> {
    let mut jobs = Vec::new();
    for spec in convergence_solvers() {
        for stiffness in THESIS_STIFFNESSES {
            for dt_s in [1e-2, 1e-3] {
                for start in Start::ALL {
                    jobs.push((spec, stiffness, dt_s, start));
                }
            }
        }
    }
    run_parallel(
        &jobs,
        |_| 1.0,
        |&(spec, stiffness, dt_s, start)| {
            let system = thesis_rope(stiffness)?;
            let state = start.state(&system)?;
            Ok(ConvergenceCurve {
                spec,
                scene: "rope",
                start,
                stiffness,
                dt_s,
                gaps: gap_curve(&spec, &system, &state, dt_s, CONVERGENCE_ITERATIONS)?,
            })
        },
        progress,
    )
    .into_iter()
    .collect()
}

/// The fewest iterations of one step of `spec` from `state` whose gap to the converged step is
/// below `tolerance`, searched up to `max`: one fresh solver per count tried. Up to
/// [`CONVERGENCE_ITERATIONS`] every count is tried in turn (the first crossing, as the curves
/// show it); past it by doubling and bisection, which assumes the gap, once past that many
/// iterations, stays below the tolerance after it first falls below it (a contraction's late
/// iterates: true of Liu 2013 and ADMM-PD here, whose curves fall steadily by then).
pub fn iterations_to(
    spec: &SolverSpec,
    system: &MassSpringSystem,
    state: &State,
    dt: f64,
    tolerance: f64,
    max: usize,
) -> Result<Option<usize>> {
    let oracle = spec.converged_step(system, state, dt)?;
    let spec = &spec.with_estimates(system, dt)?;
    let below = |m: usize| -> Result<bool> {
        let mut next = state.clone();
        SolverSpec {
            iterations: m,
            ..*spec
        }
        .build_send(system, dt)?
        .step(&mut next)?;
        Ok(gap(&next, &oracle) < tolerance)
    };
    let linear = CONVERGENCE_ITERATIONS.min(max);
    for m in 1..=linear {
        if below(m)? {
            return Ok(Some(m));
        }
    }
    // Doubling: the first power-of-two multiple of `linear` below the tolerance.
    let (mut lo, mut hi) = (linear, linear);
    loop {
        if hi >= max {
            if !below(max)? {
                return Ok(None);
            }
            hi = max;
            break;
        }
        hi = (2 * hi).min(max);
        if below(hi)? {
            break;
        }
        lo = hi;
    }
    // Bisection on (lo, hi]: lo is above the tolerance, hi below.
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if below(mid)? {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(Some(hi))
}

/// Kendall's τ-b between two sets of scores of the same items (the lower the better), the
/// items in common only: two scores within `tie` of each other, relative to the larger, are
/// a tie, which orders nothing, and τ-b scales by the pairs each side orders,
/// (C − D) / √((P − T_a)(P − T_b)) over P pairs, T_a and T_b tied on either side
/// [Kendall 1945, τ_b]. Items whose scores tie on both sides are one computation read twice
/// (solvers that compute the same iterate) and are merged into one before counting. None when
/// either side orders no pair.
pub fn kendall_tau_b(a: &[(SolverId, f64)], b: &[(SolverId, f64)], tie: f64) -> Option<f64> {
    let tied = |x: f64, y: f64| (x - y).abs() <= tie * x.abs().max(y.abs());
    let mut items: Vec<(f64, f64)> = Vec::new();
    for &(id, x) in a {
        let Some(&(_, y)) = b.iter().find(|(other, _)| *other == id) else {
            continue;
        };
        if !items.iter().any(|&(u, v)| tied(u, x) && tied(v, y)) {
            items.push((x, y));
        }
    }
    let (mut concordant, mut discordant, mut tied_a, mut tied_b, mut pairs) =
        (0i64, 0i64, 0i64, 0i64, 0i64);
    for i in 0..items.len() {
        for j in i + 1..items.len() {
            let ((xi, yi), (xj, yj)) = (items[i], items[j]);
            pairs += 1;
            let (ta, tb) = (tied(xi, xj), tied(yi, yj));
            tied_a += i64::from(ta);
            tied_b += i64::from(tb);
            if !ta && !tb {
                if (xi < xj) == (yi < yj) {
                    concordant += 1;
                } else {
                    discordant += 1;
                }
            }
        }
    }
    let scale = (((pairs - tied_a) * (pairs - tied_b)) as f64).sqrt();
    (scale > 0.0).then(|| (concordant - discordant) as f64 / scale)
}

/// Kendall's τ between two rankings of the same items (1: the same order, −1: reversed);
/// None for fewer than two items in common.
pub fn kendall_tau(a: &[SolverId], b: &[SolverId]) -> Option<f64> {
    let common: Vec<SolverId> = a.iter().copied().filter(|id| b.contains(id)).collect();
    let position = |list: &[SolverId], id: SolverId| list.iter().position(|&x| x == id);
    let mut concordant = 0i64;
    let mut discordant = 0i64;
    for i in 0..common.len() {
        for j in i + 1..common.len() {
            let in_a = position(a, common[i])?.cmp(&position(a, common[j])?);
            let in_b = position(b, common[i])?.cmp(&position(b, common[j])?);
            if in_a == in_b {
                concordant += 1;
            } else {
                discordant += 1;
            }
        }
    }
    let pairs = concordant + discordant;
    (pairs > 0).then(|| (concordant - discordant) as f64 / pairs as f64)
}

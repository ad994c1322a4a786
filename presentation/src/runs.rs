//! The runs the figures need beyond the 56 measured rows: the same experiments with their
//! kinetic energy and positions recorded (Figures 11-15), and the sheet of Figure 1.
//!
//! Each run is made once per process, for the solvers present in the result set, in
//! parallel over the available cores.

use crate::tables::iteration_count;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::time_stepper::{simulate, Recording, Run, RunOptions};
use mass_spring_solvers::model::metrics::StoppingRule;
use mass_spring_solvers::model::scene::{
    RopeParams, SheetParams, SheetSupport, SHEET_NODES_PER_SIDE,
};
use mass_spring_solvers::model::system::{MassSpringSystem, Vec3};
use mass_spring_solvers::solvers::backward_euler::BackwardEuler;
use mass_spring_solvers::solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::studies::experiments::pool::spawn_charged;
use mass_spring_solvers::studies::experiments::ResultSet;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// A recorded run of the thesis rope.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FigureRunSpec {
    /// Key the figures look the run up by.
    pub key: &'static str,
    pub solver: SolverId,
    pub stiffness: f64,
    pub dt: f64,
    pub iterations: usize,
    /// Stop here (s) instead of at the stopping rule's peak.
    pub max_time: Option<f64>,
    /// Record the positions at every step.
    pub positions: bool,
}

/// Simulated time of the recorded k = 1e3 reference start (Figures 12 and 13), s.
pub const SOFT_START_S: f64 = 60.0;

/// Key of the k = 1e3 reference, first [`SOFT_START_S`] seconds with positions.
pub const BE_SOFT: &str = "be-soft";
/// Key of the k = 1e6 reference, whole run.
pub const BE_STIFF: &str = "be-stiff";
/// Key of Fast m-s at k = 1e3, dt = 0.1 s, fewest iterations (Figure 13).
pub const FMS_SOFT_COARSE: &str = "fms-soft-coarse";
/// Keys of the k = 1e6, dt = 0.01 s runs with the middle iteration count (Figures 14-15).
pub const STIFF_MIDDLE: [(SolverId, &str); 3] = [
    (SolverId::Xpbd, "xpbd-stiff-middle"),
    (SolverId::FastMassSpring, "fms-stiff-middle"),
    (SolverId::AdmmPd, "admm-stiff-middle"),
];

/// Every recorded run the figures use.
pub fn figure_run_specs() -> Vec<FigureRunSpec> {
    let reference = |key, stiffness, max_time, positions| FigureRunSpec {
        key,
        solver: SolverId::BackwardEuler,
        stiffness,
        dt: mass_spring_solvers::solvers::backward_euler::REFERENCE_DT,
        iterations: mass_spring_solvers::solvers::backward_euler::REFERENCE_NEWTON_ITERATIONS,
        max_time,
        positions,
    };
    let mut specs = vec![
        reference(BE_SOFT, 1e3, Some(SOFT_START_S), true),
        reference(BE_STIFF, 1e6, None, false),
    ];
    if let Some(iterations) = iteration_count(SolverId::FastMassSpring, 0) {
        specs.push(FigureRunSpec {
            key: FMS_SOFT_COARSE,
            solver: SolverId::FastMassSpring,
            stiffness: 1e3,
            dt: 0.1,
            iterations,
            max_time: None,
            positions: true,
        });
    }
    for (solver, key) in STIFF_MIDDLE {
        if let Some(iterations) = iteration_count(solver, 1) {
            specs.push(FigureRunSpec {
                key,
                solver,
                stiffness: 1e6,
                dt: 0.01,
                iterations,
                max_time: None,
                positions: false,
            });
        }
    }
    specs
}

/// Runs one recorded experiment from the thesis rope at rest, faithful configuration.
pub fn run_spec(spec: &FigureRunSpec) -> Result<Run> {
    let system = RopeParams::thesis(spec.stiffness).build()?;
    let mut solver = SolverSpec::new(spec.solver, spec.iterations).build_send(&system, spec.dt)?;
    let mut stop = StoppingRule::default();
    if let Some(t) = spec.max_time {
        // Only the time limit ends the run: the figure shows a fixed window.
        stop.max_time = t;
        stop.threshold = f64::MIN_POSITIVE;
    }
    let options = RunOptions {
        stop,
        velocity_damping: 0.0,
        recording: Recording {
            kinetic_energy: true,
            positions_every: spec.positions.then_some(1),
        },
    };
    simulate(solver.as_mut(), system.initial_state(), &options)
}

/// The sheet of Figure 1: the scene, and its positions at a few instants.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetFrames {
    pub params: SheetParams,
    pub system: MassSpringSystem,
    pub dt: f64,
    /// (time, positions), the first at t = 0.
    pub frames: Vec<(f64, Vec<Vec3>)>,
}

/// Stiffness of the sheet of Figure 1, N/m: the thesis's softer value, whose stretch shows.
pub const SHEET_FIGURE_STIFFNESS: f64 = 1e3;
/// Instants of the sheet drawn in Figure 1, s.
pub const SHEET_TIMES_S: [f64; 4] = [0.0, 0.6, 1.2, 2.4];
/// Time step of the sheet's Backward Euler run, s.
pub const SHEET_DT_S: f64 = 2e-3;

/// Simulates the sheet of `docs/sheet-scene.md` hanging from two corners with Backward Euler
/// and keeps the frames at [`SHEET_TIMES_S`].
pub fn sheet() -> Result<SheetFrames> {
    let params = SheetParams::spec(SHEET_NODES_PER_SIDE, SHEET_FIGURE_STIFFNESS)
        .with_support(SheetSupport::TwoCorners);
    let system = params.build()?;
    let mut solver = BackwardEuler::new(
        &system,
        SHEET_DT_S,
        mass_spring_solvers::solvers::backward_euler::REFERENCE_NEWTON_ITERATIONS,
    )?;
    let last = SHEET_TIMES_S[SHEET_TIMES_S.len() - 1];
    let every = (SHEET_TIMES_S[1] / SHEET_DT_S).round() as u64;
    let options = RunOptions {
        stop: StoppingRule {
            threshold: f64::MIN_POSITIVE,
            max_time: last,
            exempt_first_peak: false,
        },
        velocity_damping: 0.0,
        recording: Recording {
            kinetic_energy: false,
            positions_every: Some(every),
        },
    };
    let run = simulate(&mut solver, system.initial_state(), &options)?;
    let frames = SHEET_TIMES_S
        .iter()
        .filter_map(|&t| {
            run.positions
                .iter()
                .find(|(time, _)| (time - t).abs() < 0.5 * SHEET_DT_S)
                .map(|(time, state)| (*time, state.x.clone()))
        })
        .collect();
    Ok(SheetFrames {
        params,
        system,
        dt: SHEET_DT_S,
        frames,
    })
}

/// The recorded runs and the sheet.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureRuns {
    pub runs: BTreeMap<&'static str, (FigureRunSpec, Run)>,
    pub sheet: SheetFrames,
}

impl FigureRuns {
    /// The recorded run of a key, if its solver is part of the report.
    pub fn get(&self, key: &str) -> Option<&(FigureRunSpec, Run)> {
        self.runs.get(key)
    }

    /// Makes every recorded run whose solver appears in `results`, and the sheet, in
    /// parallel; `progress(done, total)` after each.
    pub fn compute(results: &ResultSet, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        let specs: Vec<FigureRunSpec> = figure_run_specs()
            .into_iter()
            .filter(|s| results.rows.iter().any(|m| m.published.solver == s.solver))
            .collect();
        // Job 0 is the sheet; the longest rope runs (k = 1e6 reference) come first after it.
        let total = specs.len() + 1;
        let next = AtomicUsize::new(0);
        let done = AtomicUsize::new(0);
        let runs: Mutex<Vec<Option<Result<Run>>>> = Mutex::new(vec![None; specs.len()]);
        let sheet_result: Mutex<Option<Result<SheetFrames>>> = Mutex::new(None);
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .min(total);
        std::thread::scope(|scope| {
            for _ in 0..threads {
                spawn_charged(scope, || loop {
                    let job = next.fetch_add(1, Ordering::Relaxed);
                    if job == 0 {
                        *sheet_result.lock().expect("no panic holding the lock") = Some(sheet());
                    } else if let Some(spec) = specs.get(job - 1) {
                        let run = run_spec(spec);
                        runs.lock().expect("no panic holding the lock")[job - 1] = Some(run);
                    } else {
                        break;
                    }
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                });
            }
        });
        let sheet = sheet_result
            .into_inner()
            .expect("no panic holding the lock")
            .expect("the sheet job ran")?;
        let mut map = BTreeMap::new();
        let runs = runs.into_inner().expect("no panic holding the lock");
        for (spec, run) in specs.into_iter().zip(runs) {
            map.insert(spec.key, (spec, run.expect("every job ran")?));
        }
        Ok(Self { runs: map, sheet })
    }
}

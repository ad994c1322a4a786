//! What a run prints (text or JSON) and the CSV series it writes as it goes.

use crate::cli::{Cli, SceneArg};
use crate::settings::Settings;
use mass_spring_solvers::integrators::optimization_integrator::OptimizationIntegrator;
use mass_spring_solvers::integrators::time_stepper::{Recorder, Run};
use mass_spring_solvers::model::metrics::{
    rest_error_l2, rest_error_max, rest_error_sum, Peak, StoppingRule,
};
use mass_spring_solvers::model::scene::THESIS_GRAVITY;
use mass_spring_solvers::model::system::{MassSpringSystem, State};
use mass_spring_solvers::platform::output_file::OutputFile;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{published_rows, PublishedRow};
use serde::Serialize;
use std::io::Write;

/// A number in CSV and text: the shortest representation that reads back to the same f64,
/// in scientific notation when it is very small or very large.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A number in text output: at most 6 significant digits.
pub(crate) fn short(x: f64) -> String {
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
pub(crate) fn step_time(step: u64, dt: f64) -> f64 {
    let t = step as f64 * dt;
    format!("{t:.11e}").parse().unwrap_or(t)
}

#[derive(Debug, Serialize)]
pub(crate) struct SceneSummary {
    pub(crate) name: String,
    pub(crate) nodes: usize,
    pub(crate) fixed_nodes: usize,
    pub(crate) springs: usize,
    pub(crate) stiffness_min_n_per_m: Option<f64>,
    pub(crate) stiffness_max_n_per_m: Option<f64>,
    gravity_m_per_s2: [f64; 3],
    /// The tutorial's force objects and ground, when a tutorial integrator runs the scene.
    #[serde(flatten)]
    pub(crate) applied: Option<AppliedForces>,
}

#[derive(Debug, Serialize)]
pub(crate) struct AppliedForces {
    pub(crate) forces: Vec<String>,
    pub(crate) ground: Option<GroundSummary>,
}

#[derive(Debug, Serialize)]
pub(crate) struct GroundSummary {
    pub(crate) height_m: f64,
    pub(crate) restitution: f64,
}

impl SceneSummary {
    pub(crate) fn new(name: String, system: &MassSpringSystem) -> Self {
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
pub(crate) struct StopSummary {
    pub(crate) threshold_j: f64,
    pub(crate) max_time_s: f64,
    pub(crate) exempt_first_peak: bool,
}

#[derive(Debug, Serialize)]
pub(crate) struct PeakSummary {
    pub(crate) energy_j: f64,
    /// Detection time in the thesis convention (f32 accumulation), s.
    pub(crate) time_thesis_s: f64,
    /// The peak sample's own time, s.
    pub(crate) time_exact_s: f64,
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
pub(crate) struct RunSummary {
    pub(crate) solver_name: String,
    pub(crate) steps: u64,
    pub(crate) end_time_s: f64,
    pub(crate) hit_time_limit: bool,
    pub(crate) ke_peaks: usize,
    /// T/2, thesis convention, s.
    pub(crate) half_period_s: Option<f64>,
    pub(crate) half_period_exact_s: Option<f64>,
    pub(crate) first_peak: Option<PeakSummary>,
    pub(crate) last_peak: Option<PeakSummary>,
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
pub(crate) struct ReferenceSummary {
    pub(crate) run: RunSummary,
    /// |T/2 - T/2_ref| / T/2_ref, thesis convention.
    pub(crate) period_rel_error: Option<f64>,
    /// Rest-state error: sum over nodes of |x_i - x_ref_i|, m (the thesis's "error").
    pub(crate) rest_error_sum_m: f64,
    rest_error_l2_m: f64,
    pub(crate) rest_error_max_m: f64,
}

/// The published row of the same experiment (thesis rope, faithful configuration).
#[derive(Debug, Serialize)]
pub(crate) struct PublishedSummary {
    pub(crate) table: u8,
    pub(crate) ke_peaks: usize,
    pub(crate) half_period_s: f64,
    pub(crate) error: Option<f64>,
    pub(crate) period_rel_error: Option<f64>,
    /// The reproduction rule of the scene specification, thesis convention.
    pub(crate) reproduced: bool,
}

#[derive(Debug, Serialize)]
pub(crate) struct Report {
    pub(crate) solver: String,
    /// The optimization integrator of a minimizing solver (`--integrator`); None for the
    /// others, which integrate by their own scheme.
    pub(crate) integrator: Option<String>,
    pub(crate) scene: SceneSummary,
    pub(crate) dt_s: f64,
    /// None for the tutorial's integrators.
    pub(crate) iterations: Option<usize>,
    /// The tolerance each step stopped at (`--stop-tolerance`), m; `iterations` is then a cap.
    pub(crate) stop_tolerance_m: Option<f64>,
    /// The iterations per step the run took, on average; None for a solver without them.
    pub(crate) iterations_mean: Option<f64>,
    pub(crate) stop: StopSummary,
    pub(crate) velocity_damping_per_s: f64,
    #[serde(flatten)]
    pub(crate) run: RunSummary,
    pub(crate) published: Option<PublishedSummary>,
    pub(crate) reference: Option<ReferenceSummary>,
    pub(crate) wall_time_s: f64,
}

/// The published row of this run, if it is one of the thesis's experiments run faithfully.
pub(crate) fn published_row(
    cli: &Cli,
    settings: &Settings,
    system: &MassSpringSystem,
) -> Option<&'static PublishedRow> {
    let kind = settings.spec.id;
    if !SolverId::THESIS_TABLES.contains(&kind) {
        return None;
    }
    let faithful = settings.options.stop == StoppingRule::default()
        && settings.options.velocity_damping == 0.0
        && settings.spec.params.integrator == OptimizationIntegrator::BackwardEuler
        && cli.gravity.is_none_or(|g| g == THESIS_GRAVITY);
    if cli.scene_file.is_some() || cli.scene != SceneArg::Thesis || !faithful {
        return None;
    }
    let k = system.springs().first()?.stiffness;
    published_rows().iter().find(|r| {
        r.solver == kind
            && r.iterations == settings.spec.iterations
            && r.stiffness == k
            && (r.dt_s - cli.dt).abs() <= 1e-9 * r.dt_s
    })
}

pub(crate) fn reference_summary(run: &Run, reference: &Run) -> ReferenceSummary {
    let x = &run.final_state.x;
    let x_ref = &reference.final_state.x;
    ReferenceSummary {
        run: RunSummary::from(reference),
        period_rel_error: run
            .half_period_thesis()
            .zip(reference.half_period_thesis())
            .map(|(t, t_ref)| mass_spring_solvers::model::metrics::relative_period_error(t, t_ref)),
        rest_error_sum_m: rest_error_sum(x, x_ref),
        rest_error_l2_m: rest_error_l2(x, x_ref),
        rest_error_max_m: rest_error_max(x, x_ref),
    }
}

pub(crate) fn opt(x: Option<f64>, unit: &str) -> String {
    x.map_or_else(|| "-".to_string(), |x| format!("{} {unit}", short(x)))
}

pub(crate) fn peak(p: &Option<PeakSummary>) -> String {
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
pub(crate) fn write_run(
    out: &mut dyn Write,
    run: &RunSummary,
    indent: &str,
) -> std::io::Result<()> {
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

pub(crate) fn write_text(out: &mut dyn Write, r: &Report) -> std::io::Result<()> {
    writeln!(out, "{:<18}{} ({})", "solver", r.solver, r.run.solver_name)?;
    if let Some(integrator) = &r.integrator {
        writeln!(out, "{:<18}{integrator}", "integrator")?;
    }
    writeln!(out, "{:<18}{}", "scene", r.scene.describe())?;
    writeln!(out, "{:<18}{} s", "dt", short(r.dt_s))?;
    match (r.iterations, r.stop_tolerance_m) {
        (Some(n), None) => writeln!(out, "{:<18}{n}", "iterations")?,
        (Some(n), Some(t)) => writeln!(out, "{:<18}to {t:e} m, at most {n}", "iterations")?,
        (None, _) => {}
    }
    if let (Some(mean), Some(_)) = (r.iterations_mean, r.stop_tolerance_m) {
        writeln!(out, "{:<18}{mean:.2} per step", "  taken")?;
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
pub(crate) struct CsvRecorder {
    pub(crate) dt: f64,
    pub(crate) ke: Option<OutputFile>,
    pub(crate) positions: Option<OutputFile>,
    /// Whether writing a file failed (the run then stops with that error).
    pub(crate) failed: bool,
}

impl CsvRecorder {
    pub(crate) fn headers(&mut self) -> std::io::Result<()> {
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

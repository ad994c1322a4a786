//! The chapter after the thesis's: the solvers its future work (§5) points to, on the thesis
//! rope ([`mass_spring_solvers::studies::beyond`]): the benchmark's view of the rope (section 12's protocol), and
//! every solver's convergence toward the converged Backward Euler step.

use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::{full, full_opt, short, sig, sig4, MarkdownTable};
use crate::output::OutputFile;
use crate::tables::stiffness_label;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::model::scene::{thesis_rope, THESIS_STIFFNESSES};
use mass_spring_solvers::model::system::State;
use mass_spring_solvers::solvers::backward_euler::ConvergedStepOptions;
use mass_spring_solvers::solvers::chebyshev::{spectral_radius, ChebyshevParams};
use mass_spring_solvers::solvers::converged_stage::converged_step;
use mass_spring_solvers::solvers::local_global::Base;
use mass_spring_solvers::solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::studies::beyond::{
    convergence_curves, from_comparison_start, grid_settings, grid_solvers, iterations_to,
    own_first_iterate, own_start_effects, rho_scan, setting_label, ConvergenceCurve, GridScene,
    RhoPoint, Start, StartEffect, COMPARISON_START, CONVERGENCE_ITERATIONS, GRID_DTS, STEP10_DT,
};
use mass_spring_solvers::studies::round_off::{nudged_starts, NUDGES_ULP};

mod figure;

/// The solvers the chapter's tables show: the grid's, less the thesis's four (whose tables
/// are Tables 1-7; they run in the grid for the sheet chapter's rankings).
pub fn chapter_solvers() -> Vec<SolverId> {
    grid_solvers()
        .into_iter()
        .filter(|id| !SolverId::THESIS_TABLES.contains(id))
        .collect()
}

/// The gap the chapter counts iterations to, m.
pub const GAP_TOLERANCE: f64 = 1e-6;

/// The time step and stiffness of the convergence figure and table (the setting).
pub const CONVERGENCE_DT: f64 = 1e-2;
pub const CONVERGENCE_STIFFNESS: f64 = 1e6;

/// A gap below this is drawn at it (log axis), m.
const GAP_FLOOR: f64 = 1e-16;

/// The header of `beyond_results.csv`: the columns of `results.csv`, then the configuration
/// (the setting's label) and the scene.
pub const BEYOND_HEADER: &str = "table,solver,dt_s,iterations,stiffness,error,ke_peaks,half_period_s,period_rel_error,half_period_exact_s,configuration,scene,end_time_s,hit_time_limit,equilibrium_error";

/// An accelerated solver against the iteration it accelerates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Acceleration {
    pub solver: SolverId,
    pub base: SolverId,
    /// Iterations to a gap below [`GAP_TOLERANCE`] at the figure's setting from step10.
    pub iterations: Option<usize>,
    pub base_iterations: Option<usize>,
    /// The same two counts from each of the start's nudges by ±1 to ±4 units in the last
    /// place ([`nudged_starts`]), one pair per nudge.
    pub nudged: [(Option<usize>, Option<usize>); NUDGES_ULP.len()],
}

impl Acceleration {
    /// How many times fewer iterations the accelerated solver needs.
    pub fn ratio(&self) -> Option<f64> {
        Some(self.base_iterations? as f64 / self.iterations? as f64)
    }

    /// The least and largest [`Acceleration::ratio`] over the start and its nudges: how much
    /// of the ratio is round-off (an iteration that stalls near the tolerance crosses it a few
    /// iterations earlier or later from starts a few units in the last place apart).
    pub fn ratio_range(&self) -> Option<(f64, f64)> {
        let mut ratios = vec![self.ratio()?];
        for &(n, b) in &self.nudged {
            ratios.push(b? as f64 / n? as f64);
        }
        let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Some((lo, hi))
    }

    /// `31`, with the range over the nudged starts where it moves: `31 (29-322)`; the
    /// accelerated solver's count (`base` false) or its base's.
    pub fn count_label(&self, base: bool) -> String {
        let pick = |pair: (Option<usize>, Option<usize>)| if base { pair.1 } else { pair.0 };
        let label = |n: Option<usize>| {
            n.map_or(format!("> {ACCELERATION_MAX_ITERATIONS}"), |n| {
                n.to_string()
            })
        };
        let start = pick((self.iterations, self.base_iterations));
        let all: Vec<Option<usize>> = std::iter::once(start)
            .chain(self.nudged.iter().map(|&p| pick(p)))
            .collect();
        if all.iter().all(|n| *n == start) {
            label(start)
        } else {
            // A start that does not converge within the search ends the range open.
            let lo = all.iter().flatten().min().copied();
            let hi = if all.contains(&None) {
                None
            } else {
                all.iter().flatten().max().copied()
            };
            format!("{} ({}-{})", label(start), label(lo), label(hi))
        }
    }

    /// `59.0×`, with the range over the nudged starts where it differs: `59.0× (55.4-63.1×)`.
    pub fn ratio_label(&self) -> Option<String> {
        let r = self.ratio()?;
        Some(match self.ratio_range() {
            Some((lo, hi)) if lo < hi => format!("{}× ({}-{}×)", sig(r, 3), sig(lo, 3), sig(hi, 3)),
            _ => format!("{}×", sig(r, 3)),
        })
    }
}

/// The most iterations [`Acceleration`] searches, per solver.
pub const ACCELERATION_MAX_ITERATIONS: usize = 5000;

/// Every result of the chapter.
#[derive(Debug, Clone, PartialEq)]
pub struct BeyondChapter {
    pub curves: Vec<ConvergenceCurve>,
    pub acceleration: Vec<Acceleration>,
    /// What each solver's own start changes (from step10).
    pub starts: Vec<StartEffect>,
    /// Chebyshev-Liu's iterations against rho, and the asymptotic-rate rho the tables use.
    pub rho_scan: Vec<RhoPoint>,
    pub rho_default: f64,
}

/// The ratios of the acceleration table before issue 22, when Liu 2013 and its accelerations
/// started each step at x_n and the others at the inertial prediction (report of commit
/// 818181e): solver, base, ratio.
pub const RATIOS_BEFORE_ONE_START: [(SolverId, SolverId, f64); 5] = [
    (SolverId::ChebyshevLiu, SolverId::FastMassSpring, 13.41),
    (SolverId::ChebyshevAdmm, SolverId::AdmmPd, 17.92),
    (SolverId::AndersonLiu, SolverId::FastMassSpring, 93.06),
    (SolverId::AndersonAdmm, SolverId::AdmmPd, 63.03),
    (SolverId::Lbfgs, SolverId::FastMassSpring, 17.20),
];

/// The values of rho scanned, besides the asymptotic rate and Wang's gradient ratio.
pub const RHO_SCAN: [f64; 6] = [0.99, 0.993, 0.996, 0.997, 0.998, 0.999];

/// The most iterations the rho scan searches.
pub const RHO_SCAN_MAX: usize = 2000;

/// The state one converged step of [`STEP10_DT`] before step10 (step9), for the solvers whose
/// start uses the previous step.
fn step9(
    system: &mass_spring_solvers::model::system::MassSpringSystem,
) -> Result<mass_spring_solvers::model::system::State> {
    let mut state = system.initial_state();
    for _ in 0..9 {
        state = converged_step(system, &state, STEP10_DT, ConvergedStepOptions::default())?;
    }
    Ok(state)
}

/// What each solver's own start changes, the rho scan and the default rho, at the figure's
/// setting from step10.
pub fn starts_and_rho() -> Result<(Vec<StartEffect>, Vec<RhoPoint>, f64)> {
    let system = thesis_rope(CONVERGENCE_STIFFNESS)?;
    let state = Start::Step10.state(&system)?;
    let starts = own_start_effects(
        &system,
        &step9(&system)?,
        &state,
        CONVERGENCE_DT,
        GAP_TOLERANCE,
        ACCELERATION_MAX_ITERATIONS,
    )?;
    let params = ChebyshevParams {
        first_iterate: COMPARISON_START,
        ..ChebyshevParams::default()
    };
    let rho_default = spectral_radius(&system, CONVERGENCE_DT, 1, &params)?;
    let mut rhos = RHO_SCAN.to_vec();
    rhos.push(rho_default);
    rhos.sort_by(f64::total_cmp);
    let scan = rho_scan(
        &system,
        &state,
        CONVERGENCE_DT,
        &rhos,
        GAP_TOLERANCE,
        RHO_SCAN_MAX,
    )?;
    debug_assert_eq!(params.base, Base::Liu);
    Ok((starts, scan, rho_default))
}

/// Iterations to [`GAP_TOLERANCE`] for every accelerated solver and its base, from step10 at
/// the figure's dt and stiffness.
pub fn accelerations() -> Result<Vec<Acceleration>> {
    let system = thesis_rope(CONVERGENCE_STIFFNESS)?;
    let state = Start::Step10.state(&system)?;
    let nudged = nudged_starts(&state);
    let count = |id: SolverId, state: &State| {
        iterations_to(
            &from_comparison_start(SolverSpec::new(id, 1)),
            &system,
            state,
            CONVERGENCE_DT,
            GAP_TOLERANCE,
            ACCELERATION_MAX_ITERATIONS,
        )
    };
    SolverId::ALL
        .into_iter()
        .filter_map(|id| id.info().accelerates.map(|base| (id, base)))
        .map(|(solver, base)| {
            let mut pairs = [(None, None); NUDGES_ULP.len()];
            for (pair, s) in pairs.iter_mut().zip(&nudged) {
                *pair = (count(solver, s)?, count(base, s)?);
            }
            Ok(Acceleration {
                solver,
                base,
                iterations: count(solver, &state)?,
                base_iterations: count(base, &state)?,
                nudged: pairs,
            })
        })
        .collect()
}

impl BeyondChapter {
    /// The convergence curves, the accelerations, the starts and the ρ scan.
    pub fn compute(progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        let (starts, rho_scan, rho_default) = starts_and_rho()?;
        Ok(Self {
            curves: convergence_curves(progress)?,
            acceleration: accelerations()?,
            starts,
            rho_scan,
            rho_default,
        })
    }

    /// The chapter's files: the figure and `data/convergence.csv`.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files = crate::chapter_figure::chapter_figure_files(figures);
        files.push(OutputFile::text(
            "data/convergence.csv",
            self.convergence_csv(),
        ));
        files
    }

    /// `convergence.csv`: one row per curve and iteration; a failed step has no gap.
    pub fn convergence_csv(&self) -> String {
        let mut out = CsvFile::new(&[
            "solver",
            "configuration",
            "scene",
            "start",
            "stiffness_n_per_m",
            "dt_s",
            "iteration",
            "gap_m",
        ]);
        for c in &self.curves {
            let configuration = setting_label(&SolverSpec {
                iterations: 1,
                ..c.spec
            })
            .replace("1 it.", "default");
            for (i, g) in c.gaps.iter().enumerate() {
                out.record(vec![
                    c.spec.id.to_string(),
                    configuration.to_string(),
                    c.scene.to_string(),
                    c.start.id().to_string(),
                    full(c.stiffness),
                    full(c.dt_s),
                    (i + 1).to_string(),
                    full_opt(*g),
                ]);
            }
        }
        out.text()
    }

    /// The iterations each solver needs for a gap below [`GAP_TOLERANCE`] at the figure's
    /// setting, from `start`, with the gap after [`CONVERGENCE_ITERATIONS`].
    pub fn iterations_to_tolerance(
        &self,
        start: Start,
    ) -> Vec<(SolverId, Option<usize>, Option<f64>)> {
        self.figure_curves(start)
            .map(|c| {
                (
                    c.spec.id,
                    c.iterations_to(GAP_TOLERANCE),
                    c.gaps.last().copied().flatten(),
                )
            })
            .collect()
    }

    /// The chapter's section of `REPORT.md`, headed `## {number}.`.
    pub fn section(
        &self,
        number: u32,
        figures: &[ChapterFigure],
        benchmark: &crate::benchmark::BenchmarkChapter,
    ) -> String {
        let solvers = chapter_solvers();
        let mut md =
            format!("## {number}. Beyond the thesis: newer solvers on the thesis rope (§5)\n\n");
        md += &format!(
            "The thesis ends (§5) by asking for more Projective-Dynamics solvers and for a timing \
             study. This chapter runs {} solvers the thesis did not measure on its rope, with its \
             settings: the benchmark of section 12 on the rope (dt = {} s × three settings × \
             k = {} N/m, errors against the exact motion), and the convergence of every iterative \
             solver toward the converged Backward Euler step. Every solver comes from the registry \
             (`src/solvers/registry/`), which `mss --list-solvers` prints.\n\n",
            solvers.len(),
            GRID_DTS.map(full).join(", "),
            THESIS_STIFFNESSES.map(stiffness_label).join(" and "),
        );
        md += crate::integrators::UNDER_BACKWARD_EULER;
        md += "\n\n";

        md += &format!("### {number}.1 The solvers and their settings\n\n");
        let mut t = MarkdownTable::new(&[
            "solver",
            "source",
            "module",
            "one iteration",
            "settings in the grid",
        ]);
        for &id in &solvers {
            let info = id.info();
            let settings = grid_settings(id).expect("a grid solver has settings");
            t.row(vec![
                info.display_name.to_string(),
                info.source.to_string(),
                format!("[`{}`]({})", info.file, format_args!("../{}", info.file)),
                info.iteration.unwrap_or("-").to_string(),
                settings
                    .iter()
                    .map(setting_label)
                    .collect::<Vec<_>>()
                    .join("; "),
            ]);
        }
        md += &t.render();
        md += "\n";

        md += &format!("### {number}.2 The rope in the benchmark\n\n");
        md += &benchmark.scene_view_intro(GridScene::Rope, 12);
        for case in benchmark
            .cases()
            .into_iter()
            .filter(|c| c.scene == GridScene::Rope)
        {
            md += &format!("**{}**\n\n", case.label());
            md += &benchmark.scene_view(case).render();
            md += "\n";
        }

        md += &format!("### {number}.3 Convergence toward the converged Backward Euler step\n\n");
        md += &format!(
            "One step of dt = {} s at k = {} N/m, from the rope at rest and from a moving state \
             (after ten converged Backward Euler steps of {} s from rest; `step10` in the data), with m = 1 to \
             {CONVERGENCE_ITERATIONS} iterations, each m a fresh solver; the gap is the largest \
             node distance to the step solved by Newton to round-off. **One start for every \
             solver:** each step starts from the inertial prediction y = x_n + h v_n + h² M⁻¹ \
             f_ext (the option `first_iterate = {}`; PBD, XPBD and XPBD's substeps start there by \
             construction), so that the curves and the tables below compare solvers, not starts; \
             what each solver's own start changes is measured after them. Chebyshev's ρ is the \
             plain iteration's asymptotic rate (this crate's rule, `rho_rule = asymptotic-rate`), \
             and Anderson ADMM uses Zhang et al. 2019's primal-residual safeguard. The XPBD family and PBD \
             converge to their own constraint solution, not to this step: their curves level off \
             at what they miss it by (Figure B1). All curves (both stiffnesses, dt = 1e-2 and 1e-3 s) are in \
             `data/convergence.csv`.\n\n",
            full(CONVERGENCE_DT),
            stiffness_label(CONVERGENCE_STIFFNESS),
            full(STEP10_DT),
            COMPARISON_START.key(),
        );
        if let Some(f) = figures.iter().find(|f| f.stem == "beyond_convergence") {
            md += &format!(
                "![beyond_convergence](figures/{s}.svg)\n\n*Figure B1. Gap (the largest node \
                 distance) to the converged step against the iterations of one step (dt = {} s, k = {} N/m), every solver \
                 starting from the inertial prediction: a row per family (the thesis's solvers; \
                 the accelerated Projective-Dynamics solvers; {}, {} and the damped pair), from \
                 rest (left) and from the moving state after ten steps (right); the dotted grey line is the \
                 tolerance the tables count iterations to, {} m; gaps below {} m are drawn at it. \
                 Curves within {} decade of each other at every iteration are drawn once and named \
                 together (≈). The curves that rise or level off high do not converge to this \
                 step by design: {} and {} solve their own constraint problem ({}: rigid springs), \
                 and {}'s iterations are substeps, so more of them approach the motion of smaller \
                 steps, not this Backward Euler step; their gap tends to the distance between the \
                 two.* Data: [`data/{s}.csv`](data/{s}.csv).\n\n",
                full(CONVERGENCE_DT),
                stiffness_label(CONVERGENCE_STIFFNESS),
                SolverId::XpbdSubsteps.display_name(),
                SolverId::Vbd.display_name(),
                short(GAP_TOLERANCE),
                full(GAP_FLOOR),
                short(crate::style::COINCIDE_DECADES),
                SolverId::Pbd.display_name(),
                SolverId::Xpbd.display_name(),
                SolverId::Pbd.display_name(),
                SolverId::XpbdSubsteps.display_name(),
                s = f.stem
            );
        }
        // From rest the step barely moves the rope from the inertial prediction the solvers
        // start at, so a count from rest is one iteration and measures nothing; the solvers for
        // which it is not are named.
        let tolerance = format!("{GAP_TOLERANCE:e}");
        let shown =
            |n: Option<usize>| n.map_or(format!("> {CONVERGENCE_ITERATIONS}"), |n| n.to_string());
        let exceptions: Vec<String> = self
            .iterations_to_tolerance(Start::Rest)
            .iter()
            .filter(|(_, n, _)| *n != Some(1))
            .map(|(id, n, _)| format!("{} ({})", id.display_name(), shown(*n)))
            .collect();
        md += &format!(
            "From rest every solver{} is within {tolerance} m of the step after its first iteration \
             (the step barely moves the rope from the inertial prediction they start at), so the table \
             counts from the moving state only.\n\n",
            if exceptions.is_empty() {
                String::new()
            } else {
                format!(" but {}", exceptions.join(", "))
            }
        );
        let mut t = MarkdownTable::new(&[
            "solver",
            &format!(
                "iterations to {tolerance} m, from the moving state (an accelerated solver's range over starts ±1 to ±4 ulp apart, where it moves)"
            ),
            &format!("gap after {CONVERGENCE_ITERATIONS}, from the moving state (m)"),
        ]);
        for (id, from_step10, last) in self.iterations_to_tolerance(Start::Step10) {
            // An accelerated solver's count with its range over the nudged starts, where it
            // moves (measured below).
            let count = self
                .acceleration
                .iter()
                .find(|a| a.solver == id && a.iterations == from_step10)
                .map_or_else(|| shown(from_step10), |a| a.count_label(false));
            t.row(vec![
                id.display_name().to_string(),
                count,
                last.map_or("step failed".into(), sig4),
            ]);
        }
        md += &t.render();
        md += "\n";

        md += &format!(
            "**Acceleration.** The same step (dt = {} s, k = {} N/m, from the moving state): the iterations \
             to a gap below {} m of each accelerated solver and of the iteration it accelerates, \
             searched up to {ACCELERATION_MAX_ITERATIONS} (one by one to {CONVERGENCE_ITERATIONS}, \
             then by doubling and bisection). An iteration of each costs one global solve; the \
             accelerations add their own work (Anderson's small least-squares problem, L-BFGS's \
             line search), measured by `make bench`.\n\n",
            full(CONVERGENCE_DT),
            stiffness_label(CONVERGENCE_STIFFNESS),
            full(GAP_TOLERANCE),
        );
        let mut t = MarkdownTable::new(&[
            "solver",
            "iterations (range over starts ±1 to ±4 ulp apart)",
            "base",
            "base iterations (range)",
            "fewer (range)",
        ]);
        for a in &self.acceleration {
            t.row(vec![
                a.solver.display_name().to_string(),
                a.count_label(false),
                a.base.display_name().to_string(),
                a.count_label(true),
                a.ratio_label().unwrap_or_else(|| "-".into()),
            ]);
        }
        md += &t.render();
        md += "\n";
        let chebyshev: Vec<String> = self
            .acceleration
            .iter()
            .filter(|a| matches!(a.solver, SolverId::ChebyshevLiu | SolverId::ChebyshevAdmm))
            .map(|a| {
                let ratio = a.ratio();
                format!(
                    "on {} {} ({})",
                    a.base.display_name(),
                    ratio.map_or("not measured".into(), |r| format!("{}× fewer", sig4(r))),
                    if ratio.is_some_and(|r| r >= 10.0) {
                        "holds"
                    } else {
                        "does not hold"
                    }
                )
            })
            .collect();
        if !chebyshev.is_empty() {
            md += &format!(
                "Wang 2015 claims Chebyshev acceleration cuts the iterations of Projective Dynamics \
                 by about an order of magnitude: here {}.\n\n",
                chebyshev.join("; ")
            );
        }
        // How near the tolerance each count falls: the gap at the counted iteration and at the
        // one before, over the tolerance (a count whose gap sits just under the tolerance is
        // one that round-off can move).
        let margins: Vec<String> = self
            .acceleration
            .iter()
            .filter_map(|a| {
                let n = a.iterations?;
                let curve = self
                    .figure_curves(Start::Step10)
                    .find(|c| c.spec.id == a.solver)?;
                let at = |m: usize| curve.gaps.get(m.checked_sub(1)?).copied().flatten();
                let (here, before) = (at(n)? / GAP_TOLERANCE, at(n - 1)? / GAP_TOLERANCE);
                Some(format!(
                    "{} {} below it at {n} iterations ({} above at {})",
                    a.solver.display_name(),
                    sig(1.0 - here, 2),
                    sig(before - 1.0, 2),
                    n - 1
                ))
            })
            .collect();
        if !margins.is_empty() {
            md += &format!(
                "How near the tolerance each count within the curves falls, as the relative margin of \
                 the gap to {} m: {}.\n\n",
                full(GAP_TOLERANCE),
                margins.join("; ")
            );
        }
        let moved: Vec<String> = RATIOS_BEFORE_ONE_START
            .iter()
            .filter_map(|&(solver, base, before)| {
                let now = self
                    .acceleration
                    .iter()
                    .find(|a| a.solver == solver && a.base == base)?
                    .ratio()?;
                Some(format!(
                    "{} on {} {before}× → {}×",
                    solver.display_name(),
                    base.display_name(),
                    sig4(now)
                ))
            })
            .collect();
        md += &format!(
            "**What the one start moved.** Before every solver started from the inertial \
             prediction, Fast m-s and its two accelerations started each step at x_n and the others at the inertial prediction, so the ratios \
             compared starts as well as solvers; from one start they are {}. ADMM's \
             accelerations now extrapolate (x, ū), Zhang et al. 2019's variable, instead of \
             (z, ū).\n\n",
            moved.join("; ")
        );
        md += &self.starts_section(number);
        md
    }

    /// What each solver's own start changes, and the scan of Chebyshev's rho.
    fn starts_section(&self, number: u32) -> String {
        let mut md = format!("### {number}.4 Each solver's own start, and Chebyshev's ρ\n\n");
        md += &format!(
            "The same step (dt = {} s, k = {} N/m, from the moving state, a gap below {} m): the iterations \
             from each solver's own first iterate, where it is not the inertial prediction, and \
             from the inertial prediction. VBD's adaptive guess (d) uses the previous step's \
             acceleration: its solvers first take the step that ends at the moving state, so that its own start is a running solver's; a fresh solver's (d) is (c).\n\n",
            full(CONVERGENCE_DT),
            stiffness_label(CONVERGENCE_STIFFNESS),
            full(GAP_TOLERANCE),
        );
        let mut t = MarkdownTable::new(&[
            "solver",
            "own start",
            "iterations from it",
            "from the inertial prediction",
        ]);
        let count = |n: Option<usize>| {
            n.map_or(format!("> {ACCELERATION_MAX_ITERATIONS}"), |n| {
                n.to_string()
            })
        };
        for e in &self.starts {
            t.row(vec![
                e.spec.id.display_name().to_string(),
                own_first_iterate(e.spec.id).map_or(
                    "x̂ = (x̃ + αh x_n)/(1 + αh), its damped prediction".into(),
                    |f| f.formula().to_string(),
                ),
                count(e.own),
                count(e.shared),
            ]);
        }
        md += &t.render();
        md += "\n";
        md += &format!(
            "**ρ.** The tables above use ρ = {} for {cheb}, the plain iteration's \
             asymptotic rate on the rope's start (`rho_rule = asymptotic-rate`, this crate's \
             rule, one ρ for every iteration count). Wang 2015 (§5.1) starts instead from the \
             ratio of the objective's gradient norms at the last two of the K iterations used \
             (`rho_rule = gradient-ratio`, ρ depending on K) and then tunes by hand. The scan: \
             iterations of {cheb} to {} m at the same step against ρ, searched up to \
             {RHO_SCAN_MAX}.\n\n",
            sig4(self.rho_default),
            full(GAP_TOLERANCE),
            cheb = SolverId::ChebyshevLiu.display_name(),
        );
        let mut t = MarkdownTable::new(&["ρ", "iterations to 1e-6 m"]);
        for p in &self.rho_scan {
            let rho = match p.rho {
                Some(rho) if rho == self.rho_default => {
                    format!("{} (asymptotic rate, the default)", sig4(rho))
                }
                Some(rho) => full(rho),
                None => "Wang's gradient ratio at each K".to_string(),
            };
            t.row(vec![
                rho,
                p.iterations
                    .map_or(format!("> {RHO_SCAN_MAX}"), |n| n.to_string()),
            ]);
        }
        md += &t.render();
        md += "\n";
        let best = self
            .rho_scan
            .iter()
            .filter_map(|p| Some((p.rho?, p.iterations?)))
            .min_by_key(|&(_, n)| n);
        let wang = self.rho_scan.iter().find(|p| p.rho.is_none());
        if let (Some((rho, n)), Some(wang)) = (best, wang) {
            md +=
                &format!(
                "The fewest iterations of the scan, {n}, are at ρ = {}, {} the asymptotic rate; \
                 the rate itself needs {}, Wang's gradient ratio {}. Iterations to 1e-6 m depend \
                 on ρ by a factor of {} over the scan, so the tables' counts for Chebyshev are \
                 those of this crate's rule, not of a hand-tuned ρ.\n\n",
                sig4(rho),
                if rho > self.rho_default { "above" } else { "at or below" },
                self.rho_scan
                    .iter()
                    .find(|p| p.rho == Some(self.rho_default))
                    .and_then(|p| p.iterations)
                    .map_or("-".into(), |n| n.to_string()),
                wang.iterations.map_or(format!("> {RHO_SCAN_MAX}"), |n| n.to_string()),
                self.rho_scan
                    .iter()
                    .filter_map(|p| p.iterations)
                    .max()
                    .map_or("-".into(), |worst| sig4(worst as f64 / n as f64)),
            );
        }
        md += &format!(
            "{} runs here, in the grid and in the curves with Gauss-Seidel sweeps and without \
             constraint damping, its defaults; Macklin 2019's constraint damping (§4.1, Eq. 8) \
             and its Jacobi sweep are options (`constraint_damping`, `sweep`), tested in \
             `tests/newer_solvers.rs`. {} runs with the exact local Hessian, the paper's; the \
             projection is the option `hessian = projected`.\n\n",
            SolverId::XpbdSubsteps.display_name(),
            SolverId::Vbd.display_name(),
        );
        md
    }
}

//! The views of sections 10 and 11 on the benchmark's rows: one scene's solvers at the thesis's
//! settings, and the rankings of the solvers across the cases with their bootstrap intervals.

use super::*;
use crate::benchmark::families::of_case;
use crate::format::{full, sig, MarkdownTable};
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::rows::Row;
use mass_spring_solvers::studies::benchmark::sweep::solvers;
use mass_spring_solvers::studies::benchmark::Case;
use mass_spring_solvers::studies::beyond::{kendall_tau_b, GridScene};

/// The time steps of the per-solver views of sections 10 and 11: the thesis's.
pub const VIEW_DTS: [f64; 3] = [0.1, 0.01, 0.001];

/// The time step of the views' phase, amplitude and solver-error columns, s.
pub const VIEW_DETAIL_DT: f64 = 0.01;

impl BenchmarkChapter {
    /// The dynamics row of a solver at a setting and time step on a case.
    pub fn row(&self, case: Case, solver: SolverId, iterations: usize, dt_s: f64) -> Option<&Row> {
        self.rows.iter().find(|r| {
            r.kind == "dynamics"
                && r.thesis_scheme()
                && r.count_mode()
                && of_case(&r.scene, r.stiffness_n_per_m, case)
                && r.solver == solver.id()
                && r.iterations == iterations
                && r.dt_s == dt_s
        })
    }

    /// The benchmark on one scene at the thesis's time steps, every solver and setting: the
    /// relative physical error at each of [`VIEW_DTS`], and at [`VIEW_DETAIL_DT`] the phase,
    /// amplitude and solver errors (the views of sections 10.2 and 11.2).
    pub fn scene_view(&self, case: Case) -> MarkdownTable {
        let detail = full(VIEW_DETAIL_DT);
        let headers = [
            "solver".to_string(),
            ">setting".to_string(),
            format!(">error, dt {}", full(VIEW_DTS[0])),
            format!(">error, dt {}", full(VIEW_DTS[1])),
            format!(">error, dt {}", full(VIEW_DTS[2])),
            format!(">phase, dt {detail}"),
            format!(">energy lost per period, dt {detail}"),
            format!(">solver error, dt {detail}"),
        ];
        let header: Vec<&str> = headers.iter().map(String::as_str).collect();
        let mut t = MarkdownTable::new(&header);
        let percent =
            |x: Option<f64>| x.map_or("–".to_string(), |x| format!("{} %", sig(100.0 * x, 2)));
        for id in solvers() {
            for spec in mass_spring_solvers::studies::benchmark::sweep::settings(id) {
                let at = |dt: f64| self.row(case, id, spec.iterations, dt);
                let error = |dt: f64| match at(dt) {
                    None => "–".to_string(),
                    Some(r) if !r.finished() => "diverged".to_string(),
                    Some(r) => percent(r.physical_rel),
                };
                let d = at(VIEW_DETAIL_DT).filter(|r| r.finished());
                t.row(vec![
                    id.info().display_name.into(),
                    mass_spring_solvers::studies::beyond::setting_label(&spec),
                    error(VIEW_DTS[0]),
                    error(VIEW_DTS[1]),
                    error(VIEW_DTS[2]),
                    percent(d.and_then(|r| r.phase_error)),
                    percent(d.and_then(|r| r.energy_decay_per_period)),
                    percent(d.and_then(|r| r.solver_rel)),
                ]);
            }
        }
        t
    }

    /// The view's opening sentence: the window, the truths, the metrics.
    pub fn scene_view_intro(&self, scene: GridScene, number: u32) -> String {
        let windows: Vec<String> = self
            .cases()
            .into_iter()
            .filter(|c| c.scene == scene)
            .filter_map(|c| {
                self.truth(c)
                    .map(|t| format!("{} s at k = {:e} N/m", full(t.window_s), c.stiffness))
            })
            .collect();
        format!(
            "The benchmark of section {number}, this scene's part: every solver, setting and time step of \
             the thesis's grid runs from the thesis's start over the case's window ({}), three periods of \
             the lowest mode. Errors are relative, the RMS per free node of the distance to the exact motion \
             over the exact motion's RMS amplitude (1 is doing nothing); phase error: the lowest mode's \
             period against the exact motion's; energy lost per period: the lowest mode's (the exact \
             motion's own loss is in section {number}.1); solver error: against the same method with every \
             step solved to round-off. Peaks and T/2 are not shown: over a window they count the window, \
             not the solver.\n\n",
            windows.join(", ")
        )
    }
}

/// Resamples of the ranking cells for τ's interval.
pub const BOOTSTRAP_RESAMPLES: usize = 2000;

/// One cell of the rankings' comparison: the solvers ordered by their relative physical error
/// at one stiffness, time step and setting index, on the rope and on the sheet.
#[derive(Debug, Clone, PartialEq)]
pub struct RankingCell {
    pub stiffness: f64,
    pub dt_s: f64,
    pub setting: usize,
    pub rope: Vec<SolverId>,
    pub sheet: Vec<SolverId>,
    /// Each ranked solver's relative physical error on the rope and on the sheet, best first.
    pub rope_errors: Vec<(SolverId, f64)>,
    pub sheet_errors: Vec<(SolverId, f64)>,
    /// Kendall's τ-b between the two, ties at [`TAU_TIE`] ([`RankingCell::tau_at`]).
    pub tau: Option<f64>,
    /// How many of the ranked solvers' rows on the rope and on the sheet are before the
    /// asymptotic regime ([`BenchmarkChapter::before_asymptotic`]).
    pub before_asymptotic: (usize, usize),
}

/// Two errors within this relative difference are tied in τ-b: the round-off level of
/// [`ROUND_OFF_SPREAD`] (six solvers compute the same first iteration in a 1-iteration cell,
/// several equal the Backward Euler step to 1e-10 in a converged one).
pub const TAU_TIE: f64 = ROUND_OFF_SPREAD;

/// The tie tolerance whose mean τ-b the report shows beside [`TAU_TIE`]'s.
pub const TAU_TIE_BESIDE: f64 = 1e-3;

impl RankingCell {
    /// Kendall's τ-b between the rope's and the sheet's errors, errors within a relative `tie`
    /// tied, solvers tied on both scenes merged as one computation.
    pub fn tau_at(&self, tie: f64) -> Option<f64> {
        kendall_tau_b(&self.rope_errors, &self.sheet_errors, tie)
    }

    /// [`RankingCell::tau`] with `left_out` dropped from both scenes (the jackknife).
    pub fn tau_without(&self, left_out: SolverId) -> Option<f64> {
        let keep = |e: &[(SolverId, f64)]| -> Vec<(SolverId, f64)> {
            e.iter()
                .copied()
                .filter(|(id, _)| *id != left_out)
                .collect()
        };
        kendall_tau_b(&keep(&self.rope_errors), &keep(&self.sheet_errors), TAU_TIE)
    }

    /// Whether more than half of its ranked solvers, on either scene, are before the
    /// asymptotic regime: τ there compares errors that do not yet fall with the step.
    pub fn pre_asymptotic(&self) -> bool {
        2 * self.before_asymptotic.0 > self.rope.len()
            || 2 * self.before_asymptotic.1 > self.sheet.len()
    }
}

/// Errors within this relative spread are the same to round-off: a cell where every solver's
/// error agrees so closely ranks nothing.
pub const ROUND_OFF_SPREAD: f64 = 1e-9;

impl BenchmarkChapter {
    /// The solvers ranked on a case at one time step and setting index, best first; None when
    /// every error agrees to round-off (or fewer than two solvers finished).
    fn ranking(
        &self,
        case: Case,
        dt_s: f64,
        setting: usize,
        ranked: &[SolverId],
    ) -> Option<Vec<(SolverId, f64)>> {
        let mut errors: Vec<(SolverId, f64)> = ranked
            .iter()
            .filter_map(|&id| {
                let spec = mass_spring_solvers::studies::benchmark::sweep::settings(id)
                    .get(setting)
                    .copied()?;
                let e = self.row(case, id, spec.iterations, dt_s)?.physical_rel?;
                Some((id, e))
            })
            .collect();
        errors.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (lo, hi) = (errors.first()?.1, errors.last()?.1);
        (errors.len() >= 2 && hi - lo > ROUND_OFF_SPREAD * hi).then_some(errors)
    }

    /// The rope's and the sheet's rankings, cell by cell (stiffness × the thesis's time steps
    /// × the three settings), the solvers with three settings only.
    pub fn rankings(&self) -> Vec<RankingCell> {
        let ranked: Vec<SolverId> = solvers()
            .into_iter()
            .filter(|id| mass_spring_solvers::studies::benchmark::sweep::settings(*id).len() == 3)
            .collect();
        let mut cells = Vec::new();
        for stiffness in mass_spring_solvers::model::scene::THESIS_STIFFNESSES {
            let rope = Case {
                scene: GridScene::Rope,
                stiffness,
            };
            let sheet = Case {
                scene: GridScene::Sheet,
                stiffness,
            };
            for dt_s in VIEW_DTS {
                for setting in 0..3 {
                    if let (Some(rope_errors), Some(sheet_errors)) = (
                        self.ranking(rope, dt_s, setting, &ranked),
                        self.ranking(sheet, dt_s, setting, &ranked),
                    ) {
                        let ids = |e: &[(SolverId, f64)]| -> Vec<SolverId> {
                            e.iter().map(|(id, _)| *id).collect()
                        };
                        let (r, s) = (ids(&rope_errors), ids(&sheet_errors));
                        let tau = kendall_tau_b(&rope_errors, &sheet_errors, TAU_TIE);
                        let before = |case: Case, ids: &[SolverId]| {
                            ids.iter()
                                .filter(|&&id| {
                                    let iterations =
                                        mass_spring_solvers::studies::benchmark::sweep::settings(
                                            id,
                                        )[setting]
                                            .iterations;
                                    self.row(case, id, iterations, dt_s)
                                        .is_none_or(|row| self.before_asymptotic(case, row))
                                })
                                .count()
                        };
                        let before_asymptotic = (before(rope, &r), before(sheet, &s));
                        cells.push(RankingCell {
                            stiffness,
                            dt_s,
                            setting,
                            rope: r,
                            sheet: s,
                            rope_errors,
                            sheet_errors,
                            tau,
                            before_asymptotic,
                        });
                    }
                }
            }
        }
        cells
    }
}

/// The leave-one-solver-out jackknife of the mean τ-b: for each solver ranked in any cell, the
/// mean over the cells of τ-b without it (cells left with no ordered pair drop out), sorted by
/// solver order. Resampling solvers with replacement would duplicate a solver, a tie made by
/// construction; leaving one out does not.
pub fn jackknife(cells: &[RankingCell]) -> Vec<(SolverId, f64)> {
    let mut solvers: Vec<SolverId> = cells.iter().flat_map(|c| c.rope.iter().copied()).collect();
    solvers.sort();
    solvers.dedup();
    solvers
        .into_iter()
        .filter_map(|id| {
            let taus: Vec<f64> = cells.iter().filter_map(|c| c.tau_without(id)).collect();
            (!taus.is_empty()).then(|| (id, taus.iter().sum::<f64>() / taus.len() as f64))
        })
        .collect()
}

/// How many of the cells' ranked errors (rope and sheet) are below 1, a relative physical
/// error under 100 %, and how many there are.
pub fn errors_below_one(cells: &[RankingCell]) -> (usize, usize) {
    let errors = || {
        cells
            .iter()
            .flat_map(|c| c.rope_errors.iter().chain(&c.sheet_errors))
    };
    (errors().filter(|(_, e)| *e < 1.0).count(), errors().count())
}

/// The mean of `taus` and its bootstrap interval (the 2.5 and 97.5 percentiles of the mean
/// over [`BOOTSTRAP_RESAMPLES`] resamples of the cells with replacement, drawn by a fixed
/// xorshift generator so the report is byte-identical).
pub fn mean_with_interval(taus: &[f64]) -> Option<(f64, f64, f64)> {
    if taus.is_empty() {
        return None;
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut means: Vec<f64> = (0..BOOTSTRAP_RESAMPLES)
        .map(|_| {
            let sample: Vec<f64> = (0..taus.len())
                .map(|_| taus[(next() % taus.len() as u64) as usize])
                .collect();
            mean(&sample)
        })
        .collect();
    means.sort_by(f64::total_cmp);
    let at = |q: f64| means[((q * (means.len() - 1) as f64).round() as usize).min(means.len() - 1)];
    Some((mean(taus), at(0.025), at(0.975)))
}

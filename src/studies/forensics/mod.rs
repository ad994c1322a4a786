//! Forensic reproduction: how each published number of Tables 1-7 arose, with the evidence
//! behind every claim (the forensic findings of `docs/thesis-scene.md`).
//!
//! The faithful solvers know nothing of this module. Here:
//! - [`configurations`]: the named configurations (Liu's other reading of its open point, the
//!   grid of the Liu hypothesis, the ADMM candidates), each a labelled departure;
//! - [`admm_variants`]: the ADMM candidates, built from the building blocks of
//!   [`crate::solvers::admm`], [`crate::solvers::projective`] and [`crate::model::boundary`];
//! - [`liu_fit`]: the Liu hypothesis's fit and its parameters' admissible intervals;
//! - [`twins`]: rows that are one observation, not two;
//! - [`evidence`]: the rule of evidence and the class of each row;
//! - [`gravity`]: the gravity-mismatch hypothesis of the error floors.
//!
//! [`Forensics::compute_with_faithful`] runs the faithful experiments and everything else on the
//! rows it concerns; [`faithful_results`] and [`forensic_results`] cache it once per process
//! for the tests.

pub mod admm_variants;
pub mod configurations;
pub mod evidence;
pub mod gravity;
pub mod liu_fit;
pub mod twins;

pub use admm_variants::{AdmmVariant, FixedNodes, StartPoint, VariantAdmm, Weights};
pub use configurations::{AdmmCandidate, ConfigurationId, ConfigurationRun, LiuHypothesis};
pub use evidence::{Evidence, RowEvidence, NOISE_PEAK_J};
pub use gravity::{GravityRow, GravityStudy, MISMATCHED_GRAVITY};
pub use liu_fit::LiuFit;
pub use twins::Twins;

use crate::error::Result;
use crate::integrators::time_stepper::Run;
use crate::model::metrics::rest_error_sum;
use crate::model::system::Vec3;
use crate::solvers::registry::SolverId;
use crate::studies::experiments::batched::run_experiments;
use crate::studies::experiments::pool::spawn_charged;
use crate::studies::experiments::{
    measure, published_rows, same_experiment, Configuration, Measured, PublishedRow, Reference,
    ResultSet,
};
use evidence::{classify, run_of, select, Candidates, SceneReadings, Selection};
use gravity::ErrorPair;
use liu_fit::{best_fit, GridPoint};
use std::sync::OnceLock;

/// Everything the forensic sections of the report show.
#[derive(Debug, Clone, PartialEq)]
pub struct Forensics {
    /// Liu's other reading and every ADMM candidate, on the rows each concerns.
    pub runs: Vec<ConfigurationRun>,
    /// The Liu hypothesis's grid and fits.
    pub liu: LiuFit,
    /// Liu started at y with one iteration, run on the ADMM one-iteration rows (measured
    /// against the ADMM published rows).
    pub liu_as_admm: Vec<Measured>,
    /// The twin pairs of the faithful result set (each counts as one observation).
    pub twins: Twins,
    /// One class per row of the faithful result set, in its order.
    pub evidence: Vec<RowEvidence>,
    pub gravity: GravityStudy,
    /// The printed method's rest errors of every row that publishes one, against the reference
    /// at 9.81 and at 9.8 m/s², m: what [`evidence::REST_ERROR_BAND`] reads.
    pub rest_errors: Vec<(Measured, [f64; 2])>,
    /// The references the rest errors are read against: per stiffness, the final positions
    /// at 9.81 and at 9.8 m/s².
    pub rest_references: Vec<(f64, [Vec<Vec3>; 2])>,
}

/// The outcomes of (row, configuration) jobs, each job run once however often it is asked for:
/// the faithful runs, the forensic batches and the gravity study share one, so that a job run in
/// an earlier pool is not run again.
#[derive(Default)]
pub struct RunMemo {
    jobs: Vec<(PublishedRow, Configuration)>,
    outcomes: Vec<Result<Run>>,
}

impl RunMemo {
    /// The outcome of every job of `jobs`, in order: those not run before are run first
    /// (in parallel, the batchable ones in batches: [`run_experiments`]), identical jobs once.
    pub fn run(
        &mut self,
        jobs: &[(PublishedRow, Configuration)],
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Vec<Result<Run>> {
        let known = self.jobs.len();
        let index: Vec<usize> = jobs
            .iter()
            .map(|job| {
                self.jobs
                    .iter()
                    .position(|u| same_experiment(&u.0, &job.0) && u.1 == job.1)
                    .unwrap_or_else(|| {
                        self.jobs.push(job.clone());
                        self.jobs.len() - 1
                    })
            })
            .collect();
        let new: Vec<(&PublishedRow, &Configuration)> =
            self.jobs[known..].iter().map(|(r, c)| (r, c)).collect();
        let outcomes = run_experiments(&new, progress);
        self.outcomes.extend(outcomes);
        index
            .into_iter()
            .map(|i| self.outcomes[i].clone())
            .collect()
    }
}

/// The jobs of the first forensic batch, in the order [`Forensics::compute_with`] reads their
/// outcomes: the named configurations on the rows each concerns, the grid's points without the
/// exemption on the Liu rows, and Liu started at y on the ADMM one-iteration rows. They need
/// nothing of the faithful runs but their rows.
struct FirstBatch {
    named: Vec<ConfigurationId>,
    unexempt: Vec<LiuHypothesis>,
    liu_rows: Vec<PublishedRow>,
    admm_one_iteration: Vec<PublishedRow>,
    jobs: Vec<(PublishedRow, Configuration)>,
}

impl FirstBatch {
    fn of(rows: &[&PublishedRow]) -> Self {
        let liu_rows: Vec<PublishedRow> = rows
            .iter()
            .filter(|r| r.solver == SolverId::FastMassSpring)
            .map(|r| (*r).clone())
            .collect();
        let named: Vec<ConfigurationId> = std::iter::once(ConfigurationId::LiuStartInertial)
            .chain(AdmmCandidate::ALL.into_iter().map(ConfigurationId::Admm))
            .collect();
        let mut jobs: Vec<(PublishedRow, Configuration)> = Vec::new();
        for id in &named {
            for row in rows.iter().filter(|r| id.concerns(r)) {
                jobs.push(((*row).clone(), id.configuration(row)));
            }
        }
        let unexempt: Vec<LiuHypothesis> = LiuHypothesis::grid()
            .into_iter()
            .filter(|h| !h.exempt_first_peak && *h != LiuHypothesis::PRINTED)
            .collect();
        for h in &unexempt {
            for row in &liu_rows {
                jobs.push((row.clone(), ConfigurationId::Liu(*h).configuration(row)));
            }
        }
        let admm_one_iteration: Vec<PublishedRow> = rows
            .iter()
            .filter(|r| r.solver == SolverId::AdmmPd && r.iterations == 1)
            .map(|r| PublishedRow {
                solver: SolverId::FastMassSpring,
                ..(*r).clone()
            })
            .collect();
        for row in &admm_one_iteration {
            jobs.push((
                row.clone(),
                ConfigurationId::LiuStartInertial.configuration(row),
            ));
        }
        Self {
            named,
            unexempt,
            liu_rows,
            admm_one_iteration,
            jobs,
        }
    }
}

/// The gravity study's run of `row` under `configuration`: at [`MISMATCHED_GRAVITY`], the
/// reference rows' reference gravity and the other rows' solver gravity.
fn at_mismatched_gravity(row: &PublishedRow, mut configuration: Configuration) -> Configuration {
    if row.solver == SolverId::BackwardEuler {
        configuration.reference_gravity = MISMATCHED_GRAVITY;
    } else {
        configuration.gravity = MISMATCHED_GRAVITY;
    }
    configuration
}

/// The gravity study's runs started with the faithful runs, before the selection they depend
/// on: the faithful configuration at 9.8 m/s² of the Backward Euler, XPBD and ADMM rows. The
/// first two have no other candidate, so their selection is the faithful configuration; an
/// ADMM row whose selection is another candidate runs that one in the third batch, and its
/// early run goes unused. A scheduling choice: every outcome is the one the third batch would
/// compute, and the runs share the first pool's lanes and cores with the faithful runs of the
/// same solvers (the k = 1e3 N/m, dt = 1e-3 s runs at both gravities, the longest of all, side
/// by side).
fn early_gravity_jobs(rows: &[&PublishedRow]) -> Vec<(PublishedRow, Configuration)> {
    rows.iter()
        .filter(|r| {
            matches!(
                r.solver,
                SolverId::BackwardEuler | SolverId::Xpbd | SolverId::AdmmPd
            )
        })
        .map(|r| {
            let faithful = ConfigurationId::Faithful.configuration(r);
            ((*r).clone(), at_mismatched_gravity(r, faithful))
        })
        .collect()
}

fn reference_of(faithful: &ResultSet, k: f64) -> Reference<'_> {
    let m = faithful.reference(k);
    Reference {
        final_positions: &m.final_positions,
        half_period_thesis: m.half_period_thesis,
    }
}

impl Forensics {
    /// The faithful result set of `rows` and the forensics on it ([`Self::compute_with`]). The
    /// faithful runs go into one pool with every forensic run that needs nothing of their
    /// outcomes (the first forensic batch and the early gravity runs of
    /// `early_gravity_jobs`), so that runs of one solver share the lanes of its batches and
    /// the cores do not wait at a barrier between the faithful runs and the forensic ones.
    pub fn compute_with_faithful(
        rows: &[PublishedRow],
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<(ResultSet, Self)> {
        let faithful = Configuration::faithful();
        let refs: Vec<&PublishedRow> = rows.iter().collect();
        let mut jobs: Vec<(PublishedRow, Configuration)> =
            rows.iter().map(|row| (row.clone(), faithful)).collect();
        jobs.extend(FirstBatch::of(&refs).jobs);
        jobs.extend(early_gravity_jobs(&refs));
        let mut memo = RunMemo::default();
        let runs = memo
            .run(&jobs, progress)
            .into_iter()
            .take(rows.len())
            .collect::<Result<Vec<Run>>>()?;
        let results = ResultSet::measured(rows, &faithful, &runs);
        let forensics = Self::compute_with(&results, &mut memo, progress)?;
        Ok((results, forensics))
    }

    /// Runs every named configuration on the rows of `faithful` it concerns, fits the Liu
    /// hypothesis and locates its intervals, selects each row's configuration, runs it at
    /// 9.8 m/s² (the gravity study and the other reading of the gravity), then classifies
    /// every row; a job `memo` holds is not run again.
    pub fn compute_with(
        faithful: &ResultSet,
        memo: &mut RunMemo,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Self> {
        let rows: Vec<&PublishedRow> = faithful.rows.iter().map(|m| &m.published).collect();
        let measure_against = |row: &PublishedRow, run: &Run| {
            measure(row, run, Some(reference_of(faithful, row.stiffness)))
        };
        let faithful_row = |row: &PublishedRow| -> &Measured {
            faithful
                .rows
                .iter()
                .find(|m| same_experiment(&m.published, row))
                .expect("the faithful set holds the row")
        };

        // Batch 1: the named configurations, the grid without the exemption, Liu as ADMM.
        let FirstBatch {
            named,
            unexempt,
            liu_rows,
            admm_one_iteration,
            jobs,
        } = FirstBatch::of(&rows);
        let grid = LiuHypothesis::grid();
        let mut outcomes = memo.run(&jobs, progress).into_iter();

        let mut runs: Vec<ConfigurationRun> = Vec::new();
        for id in &named {
            let mut set = ConfigurationRun {
                id: *id,
                rows: Vec::new(),
                failed: Vec::new(),
            };
            for row in rows.iter().filter(|r| id.concerns(r)) {
                match outcomes.next().expect("one outcome per job") {
                    Ok(run) => set.rows.push(measure_against(row, &run)),
                    // Liu's other reading must run: the classes stand on it.
                    Err(e) if *id == ConfigurationId::LiuStartInertial => return Err(e),
                    Err(e) => set.failed.push(((*row).clone(), e.to_string())),
                }
            }
            runs.push(set);
        }
        let mut points: Vec<GridPoint> = vec![GridPoint {
            hypothesis: LiuHypothesis::PRINTED,
            rows: liu_rows.iter().map(|r| faithful_row(r).clone()).collect(),
        }];
        for h in &unexempt {
            let mut point = GridPoint {
                hypothesis: *h,
                rows: Vec::new(),
            };
            for row in &liu_rows {
                let run = outcomes.next().expect("one outcome per job")?;
                point.rows.push(measure_against(row, &run));
            }
            points.push(point);
        }
        let mut liu_as_admm = Vec::new();
        for row in &admm_one_iteration {
            let run = outcomes.next().expect("one outcome per job")?;
            let admm_row = rows
                .iter()
                .find(|r| {
                    r.solver == SolverId::AdmmPd
                        && r.table == row.table
                        && r.dt_s == row.dt_s
                        && r.iterations == 1
                })
                .expect("the ADMM row it was made from");
            liu_as_admm.push(measure(
                admm_row,
                &run,
                Some(reference_of(faithful, row.stiffness)),
            ));
        }

        // Batch 2: the exempt grid points. The exemption changes a run only if its first peak
        // stopped it; elsewhere the exempt run is the unexempt one.
        let mut jobs = Vec::new();
        let mut exempt_points = Vec::new();
        for h in grid.iter().filter(|h| h.exempt_first_peak) {
            let base = LiuHypothesis {
                exempt_first_peak: false,
                ..*h
            };
            let base_rows = points
                .iter()
                .find(|p| p.hypothesis == base)
                .expect("every unexempt point ran")
                .rows
                .clone();
            for m in &base_rows {
                if m.peaks == 1 && !m.hit_time_limit {
                    jobs.push((
                        m.published.clone(),
                        ConfigurationId::Liu(*h).configuration(&m.published),
                    ));
                }
            }
            exempt_points.push((*h, base_rows));
        }
        let mut outcomes = memo.run(&jobs, progress).into_iter();
        for (h, base_rows) in exempt_points {
            let mut point = GridPoint {
                hypothesis: h,
                rows: Vec::new(),
            };
            for m in base_rows {
                if m.peaks == 1 && !m.hit_time_limit {
                    let run = outcomes.next().expect("one outcome per job")?;
                    point.rows.push(measure_against(&m.published, &run));
                } else {
                    point.rows.push(m);
                }
            }
            points.push(point);
        }
        // Grid order (the fit's tie-break).
        points.sort_by_key(|p| grid.iter().position(|h| *h == p.hypothesis));
        let twins = Twins::of(&faithful.rows);
        let in_sample = best_fit(&points, &twins);
        let fitted_point = points
            .iter()
            .find(|p| p.hypothesis == in_sample)
            .expect("the fit picks a point of the grid");
        // The references at 9.8 m/s² (run beside the faithful runs, `early_gravity_jobs`): the
        // rest errors' other gravity reading, so that a floor the mismatch explains never
        // contradicts a row.
        let reference_jobs: Vec<(PublishedRow, Configuration)> = rows
            .iter()
            .filter(|r| r.solver == SolverId::BackwardEuler)
            .map(|r| {
                let c = at_mismatched_gravity(r, ConfigurationId::Faithful.configuration(r));
                ((*r).clone(), c)
            })
            .collect();
        let references_9_8: Vec<(f64, Vec<Vec3>)> = reference_jobs
            .iter()
            .zip(memo.run(&reference_jobs, progress))
            .map(|((r, _), run)| Ok((r.stiffness, run?.final_state.x)))
            .collect::<Result<_>>()?;
        let rest_errors = |m: &Measured| -> [f64; 2] {
            let k = m.published.stiffness;
            let at_9_8 = &references_9_8
                .iter()
                .find(|(s, _)| *s == k)
                .expect("a reference at 9.8 per stiffness")
                .1;
            [
                rest_error_sum(&m.final_positions, &faithful.reference(k).final_positions),
                rest_error_sum(&m.final_positions, at_9_8),
            ]
        };
        let selections: Vec<Selection> = faithful
            .rows
            .iter()
            .map(|m| {
                let row = &m.published;
                let is_liu = row.solver == SolverId::FastMassSpring;
                select(&Candidates {
                    faithful: m,
                    liu_start_inertial: run_of(&runs, ConfigurationId::LiuStartInertial, row),
                    liu_fitted: is_liu
                        .then(|| fitted_point.row(row).map(|f| (in_sample, f)))
                        .flatten(),
                    admm: AdmmCandidate::ALL
                        .into_iter()
                        .filter_map(|c| Some((c, run_of(&runs, ConfigurationId::Admm(c), row)?)))
                        .collect(),
                    others: if is_liu {
                        points.iter().filter_map(|p| p.row(row)).collect()
                    } else {
                        Vec::new()
                    },
                    rest_errors: &rest_errors,
                })
            })
            .collect();

        // Batch 3: the gravity study, each row under its selected configuration at 9.8 m/s²
        // (the reference rows: the reference at 9.8).
        let jobs: Vec<(PublishedRow, Configuration)> = selections
            .iter()
            .map(|s| {
                let row = &s.measured.published;
                let c = at_mismatched_gravity(row, s.configuration.configuration(row));
                (row.clone(), c)
            })
            .collect();
        // The Liu intervals' sequential bisection runs beside the gravity batch (it needs only
        // the fitted point): the two share the cores instead of waiting for each other.
        let (liu, outcomes) = std::thread::scope(|scope| {
            let intervals = spawn_charged(scope, || {
                fit_intervals(points, in_sample, &twins, &measure_against, &|_, _| {})
            });
            let outcomes = memo.run(&jobs, progress);
            (
                intervals.join().expect("the interval runs do not panic"),
                outcomes,
            )
        });
        let liu = liu?;
        let mut mismatched_references = Vec::new();
        let mut at_9_8 = Vec::new();
        let mut solver_runs = Vec::new();
        for (s, run) in selections.iter().zip(outcomes) {
            let run = run?;
            let row = &s.measured.published;
            if row.solver == SolverId::BackwardEuler {
                let m = measure(row, &run, None);
                at_9_8.push(m.clone());
                mismatched_references.push(m);
            } else {
                at_9_8.push(measure_against(row, &run));
                solver_runs.push((s, run));
            }
        }
        let evidence: Vec<RowEvidence> = selections
            .iter()
            .zip(&at_9_8)
            .map(|(s, g)| {
                classify(
                    s.clone(),
                    &SceneReadings {
                        gravity_9_8: Some(g),
                    },
                )
            })
            .collect();
        let equilibria = gravity::Equilibria::solve(&[1e3, 1e6])?;
        let gravity_rows = solver_runs
            .into_iter()
            .map(|(s, run)| {
                let row = &s.measured.published;
                let ours = &s.measured.final_positions;
                let reference_981 = &faithful.reference(row.stiffness).final_positions;
                let reference_98 = &mismatched_references
                    .iter()
                    .find(|m| m.published.stiffness == row.stiffness)
                    .expect("a mismatched reference per stiffness")
                    .final_positions;
                GravityRow {
                    published: row.clone(),
                    configuration: s.configuration,
                    same_gravity: ErrorPair::between(ours, reference_981),
                    reference_mismatched: ErrorPair::between(ours, reference_98),
                    solver_mismatched: ErrorPair::between(&run.final_state.x, reference_981),
                    solver_mismatched_run: measure_against(row, &run),
                    to_exact: gravity::ErrorsToExact::new(
                        ours,
                        &run.final_state.x,
                        row.stiffness,
                        &equilibria,
                    ),
                    reproduced_at_981: s.evidence.reproduced(),
                }
            })
            .collect();
        let faithful_rest_errors = faithful
            .rows
            .iter()
            .filter(|m| m.published.error.is_some())
            .map(|m| (m.clone(), rest_errors(m)))
            .collect();
        let references: Vec<(f64, &[Vec3])> = [1e3, 1e6]
            .into_iter()
            .map(|k| (k, faithful.reference(k).final_positions.as_slice()))
            .collect();
        let gravity = GravityStudy::new(
            gravity_rows,
            mismatched_references,
            &references,
            &equilibria,
            &twins,
        );
        Ok(Self {
            runs,
            liu,
            liu_as_admm,
            twins,
            evidence,
            gravity,
            rest_errors: faithful_rest_errors,
            rest_references: references_9_8
                .into_iter()
                .map(|(k, at_9_8)| (k, [faithful.reference(k).final_positions.clone(), at_9_8]))
                .collect(),
        })
    }

    /// The run of a named configuration.
    pub fn run(&self, id: ConfigurationId) -> Option<&ConfigurationRun> {
        self.runs.iter().find(|r| r.id == id)
    }

    /// The class of a published row.
    pub fn evidence_of(&self, row: &PublishedRow) -> Option<&RowEvidence> {
        self.evidence
            .iter()
            .find(|e| same_experiment(&e.measured.published, row))
    }

    /// How many observations (twins once) have each class, in [`Evidence::ALL`] order.
    pub fn observation_counts(&self) -> [usize; 7] {
        evidence::counts(
            self.twins
                .observations(&self.evidence, |e| &e.measured.published),
        )
    }

    /// The rows not used to fit the scene (outside [`evidence::SCENE_FIT_TABLE`]), and how many
    /// of them the printed equations reproduce (faithful or interpretation): the headline's
    /// count, since the rows the scene was fitted on cannot test it.
    pub fn rows_not_used_to_fit_the_scene(&self) -> (usize, usize) {
        let tested = self
            .evidence
            .iter()
            .filter(|e| e.measured.published.table != evidence::SCENE_FIT_TABLE);
        let reproduced = tested
            .clone()
            .filter(|e| matches!(e.evidence, Evidence::Faithful | Evidence::Interpretation))
            .count();
        (tested.count(), reproduced)
    }

    /// The rows the printed method reproduces by the rule whose rest error contradicts the
    /// published one at `band` ([`evidence::rest_error_contradicts`]), with ours/published
    /// against the reference at 9.81 m/s².
    pub fn contradicted_by_rest_error(&self, band: [f64; 2]) -> Vec<(&Measured, f64)> {
        self.rest_errors
            .iter()
            .filter(|(m, errors)| {
                m.reproduces() && evidence::rest_error_contradicts(m.published.error, errors, band)
            })
            .map(|(m, errors)| (m, errors[0] / m.published.error.expect("filtered")))
            .collect()
    }

    /// A run's rest errors against the reference of its stiffness at 9.81 and at 9.8 m/s², m.
    pub fn rest_errors_of(&self, m: &Measured) -> [f64; 2] {
        let [at_981, at_98] = &self
            .rest_references
            .iter()
            .find(|(k, _)| *k == m.published.stiffness)
            .expect("a reference per stiffness")
            .1;
        [
            rest_error_sum(&m.final_positions, at_981),
            rest_error_sum(&m.final_positions, at_98),
        ]
    }

    /// Whether `m` reproduces its row as the rule of evidence decides it: the reproduction
    /// rule, and a rest error [`evidence::REST_ERROR_BAND`] does not contradict at either
    /// gravity. Every ✓ of the report reads this.
    pub fn reproduces(&self, m: &Measured) -> bool {
        self.reproduces_under(
            m,
            evidence::REST_ERROR_BAND,
            evidence::GravityReading::Either,
        )
    }

    /// [`Forensics::reproduces`] at another band or gravity reading (the report's sensitivity
    /// counts).
    pub fn reproduces_under(
        &self,
        m: &Measured,
        band: [f64; 2],
        reading: evidence::GravityReading,
    ) -> bool {
        evidence::reproduces_under(m, &self.rest_errors_of(m), band, reading)
    }

    /// How many rows of `table` (all tables for None) have each class, in [`Evidence::ALL`]
    /// order.
    pub fn counts(&self, table: Option<u8>) -> [usize; 7] {
        evidence::counts(
            self.evidence
                .iter()
                .filter(|e| table.is_none_or(|t| e.measured.published.table == t)),
        )
    }
}

/// Locates the fitted point's damping interval by bisection and its threshold interval from
/// runs that go on to [`liu_fit::THRESHOLD_FLOOR_J`] (the design of [`liu_fit`]).
fn fit_intervals(
    grid: Vec<GridPoint>,
    in_sample: LiuHypothesis,
    twins: &Twins,
    measure_against: &(dyn Fn(&PublishedRow, &Run) -> Measured + Sync),
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<LiuFit> {
    let point = |h: LiuHypothesis| -> &GridPoint {
        grid.iter()
            .find(|p| p.hypothesis == h)
            .expect("a point of the grid")
    };
    let reproduced: Vec<&Measured> = twins
        .observations(&point(in_sample).rows, |m| &m.published)
        .filter(|m| m.reproduces())
        .collect();
    let threshold = in_sample.threshold(configurations::LIU_THRESHOLD_STIFFNESS);
    let fitted = in_sample.velocity_damping();
    // Each end starts from the fitted value and its grid neighbour; the rows to run at a
    // probe are those that fail at the neighbour (the others pass over the whole bracket).
    let side = |neighbour: Option<usize>| {
        neighbour.map(|damping| {
            let at = point(LiuHypothesis {
                damping,
                ..in_sample
            });
            let failing: Vec<PublishedRow> = reproduced
                .iter()
                .filter(|m| !at.row(&m.published).is_some_and(Measured::reproduces))
                .map(|m| m.published.clone())
                .collect();
            (
                liu_fit::Bracket {
                    inside: fitted,
                    outside: configurations::LIU_DAMPING_GRID[damping],
                },
                failing,
            )
        })
    };
    let mut sides = [
        side(in_sample.damping.checked_sub(1)),
        side(Some(in_sample.damping + 1).filter(|&d| d < configurations::LIU_DAMPING_GRID.len())),
    ];
    let threshold_rows: Vec<&PublishedRow> = reproduced
        .iter()
        .map(|m| &m.published)
        .filter(|r| r.stiffness >= configurations::LIU_THRESHOLD_STIFFNESS)
        .collect();
    let mut probes = Vec::new();
    let mut threshold_runs: Vec<(PublishedRow, Vec<crate::model::metrics::Peak>)> = Vec::new();
    let mut memo = RunMemo::default();
    for round in 0..liu_fit::DAMPING_BISECTIONS {
        let mut jobs: Vec<(PublishedRow, Configuration)> = Vec::new();
        for (bracket, rows) in sides.iter().flatten() {
            for row in rows {
                jobs.push((
                    row.clone(),
                    in_sample.probe(row, bracket.midpoint(), threshold),
                ));
            }
        }
        if round == 0 {
            for row in &threshold_rows {
                jobs.push((
                    (*row).clone(),
                    in_sample.probe(row, fitted, liu_fit::THRESHOLD_FLOOR_J),
                ));
            }
        }
        let mut outcomes = memo.run(&jobs, progress).into_iter();
        for (bracket, rows) in sides.iter_mut().flatten() {
            let mut probe = liu_fit::DampingProbe {
                damping: bracket.midpoint(),
                rows: Vec::new(),
            };
            for row in rows.iter() {
                let run = outcomes.next().expect("one outcome per job")?;
                probe.rows.push(measure_against(row, &run));
            }
            *bracket = bracket.halved(probe.rows.iter().all(Measured::reproduces));
            probes.push(probe);
        }
        if round == 0 {
            for row in &threshold_rows {
                let run = outcomes.next().expect("one outcome per job")?;
                threshold_runs.push(((*row).clone(), run.peaks));
            }
        }
    }
    let bracket_of = |s: &Option<(liu_fit::Bracket, Vec<PublishedRow>)>| {
        s.as_ref().map_or(
            liu_fit::Bracket {
                inside: fitted,
                outside: fitted,
            },
            |(b, _)| *b,
        )
    };
    let threshold_interval = liu_fit::threshold_interval(
        &threshold_runs
            .iter()
            .map(|(r, p)| (r, p.as_slice()))
            .collect::<Vec<_>>(),
        threshold,
        in_sample.exempt_first_peak,
    );
    Ok(LiuFit {
        damping: liu_fit::Interval {
            low: bracket_of(&sides[0]),
            high: bracket_of(&sides[1]),
        },
        damping_probes: probes,
        threshold: threshold_interval,
        threshold_runs,
        grid,
        in_sample,
    })
}

/// The faithful result set and the forensics of all 56 rows, computed once per process
/// ([`Forensics::compute_with_faithful`]) and shared by the tests of a test binary (the report
/// binary computes them itself, to show progress and return errors).
///
/// # Panics
/// If a faithful or forensic run fails: the tests treat that as a failure.
fn thesis_results() -> &'static (ResultSet, Forensics) {
    static THESIS: OnceLock<(ResultSet, Forensics)> = OnceLock::new();
    THESIS.get_or_init(|| {
        Forensics::compute_with_faithful(published_rows(), &|_, _| {})
            .expect("the faithful experiments and the forensic configurations run without error")
    })
}

/// The faithful result set of all 56 rows (`thesis_results`).
///
/// # Panics
/// As `thesis_results`.
pub fn faithful_results() -> &'static ResultSet {
    &thesis_results().0
}

/// The forensic results of all 56 rows (`thesis_results`).
///
/// # Panics
/// As `thesis_results`.
pub fn forensic_results() -> &'static Forensics {
    &thesis_results().1
}

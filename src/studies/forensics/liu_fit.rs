//! The Liu hypothesis (forensic findings 2-4 of `docs/thesis-scene.md`): its grid, the point
//! that fits the published Liu rows best, and the interval of each continuous parameter over
//! which the rows it reproduces stay reproduced.
//!
//! Its values were chosen with these rows in view: the damping c = 0.05 s⁻¹ and the 1e-4 J
//! threshold are findings 3 and 4 of `docs/thesis-scene.md`, fitted on the Liu rows' peak
//! counts and present since the repository's first commit; the grid of
//! [`LiuHypothesis::grid`] was laid around them later. So every row the hypothesis reproduces
//! is *fitted* (the rule of [`super::evidence`]), and a split of the same rows cannot make it
//! predicted. What this module measures instead is how tightly the rows pin the parameters:
//!
//! - the **fit**: a grid point's score is the number of exact peak counts (the printed counts
//!   are integers: the fit uses all they say), then the number within the rule's tolerance,
//!   then the number of rows fully reproduced, over the Liu rows with twins taken once; ties go
//!   to the least departure from the printed method (the grid's order);
//! - the **damping interval**: with the fit's exemption and threshold, the interval of c around
//!   the fitted value over which every row the fit reproduces still meets the rule, found by
//!   bisection between the fitted value and its grid neighbours (each row's peak count falls
//!   with c, so a row that passes at both ends of an interval passes inside it);
//! - the **threshold interval**: with the fitted damping, the interval of stopping thresholds at
//!   k = 1e6 over which those rows stay reproduced, read off runs that go on to
//!   [`THRESHOLD_FLOOR_J`] (the threshold only decides at which peak a run stops).

use super::configurations::LiuHypothesis;
use super::twins::Twins;
use crate::model::metrics::{half_period_thesis, Peak};
use crate::studies::experiments::{
    peak_tolerance, reproduces, same_experiment, Measured, PublishedRow,
};

/// The Liu rows measured at one grid point, in published order.
#[derive(Debug, Clone, PartialEq)]
pub struct GridPoint {
    pub hypothesis: LiuHypothesis,
    pub rows: Vec<Measured>,
}

impl GridPoint {
    /// The measurement of `row`.
    pub fn row(&self, row: &PublishedRow) -> Option<&Measured> {
        self.rows
            .iter()
            .find(|m| same_experiment(&m.published, row))
    }

    /// (exact peak counts, peak counts within tolerance, rows reproduced) over the rows that
    /// are observations (twins once).
    fn score(&self, twins: &Twins) -> (usize, usize, usize) {
        twins.observations(&self.rows, |m| &m.published).fold(
            (0, 0, 0),
            |(exact, within, rule), m| {
                (
                    exact + usize::from(!m.hit_time_limit && m.peaks == m.published.ke_peaks),
                    within + usize::from(peaks_within_tolerance(m)),
                    rule + usize::from(m.reproduces()),
                )
            },
        )
    }
}

/// Whether a run's peak count is within the rule's tolerance (and the run was not cut).
pub fn peaks_within_tolerance(m: &Measured) -> bool {
    !m.hit_time_limit
        && m.peaks.abs_diff(m.published.ke_peaks) <= peak_tolerance(m.published.ke_peaks)
}

/// The grid point that fits best, among `grid` (every point holding the same Liu rows), with
/// twins taken once.
pub fn best_fit(grid: &[GridPoint], twins: &Twins) -> LiuHypothesis {
    // The first maximum in grid order: the least departure among equals.
    let mut best = 0;
    for (i, point) in grid.iter().enumerate() {
        if point.score(twins) > grid[best].score(twins) {
            best = i;
        }
    }
    grid[best].hypothesis
}

/// One end of an admissible interval, bracketed by runs: the parameter value where every row
/// still passes and the nearest value tried where one does not.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bracket {
    pub inside: f64,
    pub outside: f64,
}

impl Bracket {
    /// The bracket halved at its midpoint, by whether the rows pass there.
    pub fn halved(self, passes_at_midpoint: bool) -> Self {
        let mid = 0.5 * (self.inside + self.outside);
        if passes_at_midpoint {
            Self {
                inside: mid,
                ..self
            }
        } else {
            Self {
                outside: mid,
                ..self
            }
        }
    }

    /// The midpoint at which the next run is made.
    pub fn midpoint(self) -> f64 {
        0.5 * (self.inside + self.outside)
    }
}

/// An admissible interval: its two ends, each bracketed by runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    pub low: Bracket,
    pub high: Bracket,
}

impl Interval {
    /// The values known to be admissible, [low.inside, high.inside].
    pub fn inside(&self) -> (f64, f64) {
        (self.low.inside, self.high.inside)
    }
}

/// One run made while bisecting the damping interval: the value of c and the rows run.
#[derive(Debug, Clone, PartialEq)]
pub struct DampingProbe {
    pub damping: f64,
    pub rows: Vec<Measured>,
}

/// Halvings of each grid bracket of the damping: 0.01 s⁻¹ / 2⁷ ≈ 8e-5 s⁻¹.
pub const DAMPING_BISECTIONS: usize = 7;

/// The threshold the runs of the threshold interval go on to, J: a tenth of the fitted one.
pub const THRESHOLD_FLOOR_J: f64 = 1e-5;

/// The fit, the grid it was chosen from and the parameters' intervals.
#[derive(Debug, Clone, PartialEq)]
pub struct LiuFit {
    pub grid: Vec<GridPoint>,
    /// The grid point that fits best.
    pub in_sample: LiuHypothesis,
    /// The damping interval and the runs that located it.
    pub damping: Interval,
    pub damping_probes: Vec<DampingProbe>,
    /// The threshold interval at k = 1e6 (None when no k = 1e6 row is reproduced), J.
    pub threshold: Option<(f64, f64)>,
    /// The peaks of the runs it was read off: the fitted point's reproduced k = 1e6 rows, run
    /// on to [`THRESHOLD_FLOOR_J`].
    pub threshold_runs: Vec<(PublishedRow, Vec<Peak>)>,
}

impl LiuFit {
    /// The rows measured at a grid point.
    pub fn point(&self, hypothesis: LiuHypothesis) -> &GridPoint {
        self.grid
            .iter()
            .find(|p| p.hypothesis == hypothesis)
            .expect("a point of the grid")
    }

    /// The rows the fitted point reproduces (twins once).
    pub fn reproduced<'a>(&'a self, twins: &'a Twins) -> Vec<&'a Measured> {
        twins
            .observations(&self.point(self.in_sample).rows, |m| &m.published)
            .filter(|m| m.reproduces())
            .collect()
    }
}

/// Where a run with these peaks stops under `threshold` (the first peak below it, the first
/// peak exempt if `exempt_first_peak`), and the thesis T/2 it then reports.
pub fn stop_under(peaks: &[Peak], threshold: f64, exempt_first_peak: bool) -> (usize, Option<f64>) {
    let stop = peaks
        .iter()
        .enumerate()
        .position(|(i, p)| p.energy < threshold && !(exempt_first_peak && i == 0))
        .map_or(peaks.len(), |i| i + 1);
    (stop, half_period_thesis(&peaks[..stop]))
}

/// The interval of thresholds, around `fitted`, under which every row of `runs` (row, the
/// peaks of a run that went on to [`THRESHOLD_FLOOR_J`]) meets the rule, J. The threshold is
/// scanned at every peak energy of the runs (the only values where a stop can move); the
/// interval's ends are peak energies, the lower one open.
pub fn threshold_interval(
    runs: &[(&PublishedRow, &[Peak])],
    fitted: f64,
    exempt_first_peak: bool,
) -> Option<(f64, f64)> {
    let passes = |threshold: f64| {
        runs.iter().all(|(row, peaks)| {
            let (stop, half_period) = stop_under(peaks, threshold, exempt_first_peak);
            reproduces(row, stop, half_period)
        })
    };
    if !passes(fitted) {
        return None;
    }
    // Candidate ends: every peak energy; between two consecutive ones the outcome is constant.
    let mut energies: Vec<f64> = runs
        .iter()
        .flat_map(|(_, peaks)| peaks.iter().map(|p| p.energy))
        .filter(|e| *e >= THRESHOLD_FLOOR_J)
        .collect();
    energies.push(THRESHOLD_FLOOR_J);
    energies.sort_by(f64::total_cmp);
    energies.dedup();
    // A threshold just above energy e stops at the peak of energy e; at e itself it does not.
    let above = |e: f64| e * (1.0 + 1e-12);
    let mut low = fitted;
    for &e in energies.iter().rev().filter(|&&e| e < fitted) {
        if passes(above(e)) {
            low = e;
        } else {
            break;
        }
    }
    let mut high = fitted;
    for &e in energies.iter().filter(|&&e| e > fitted) {
        if passes(e) {
            high = e;
        } else {
            break;
        }
    }
    Some((low, high))
}

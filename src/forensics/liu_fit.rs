//! The Liu hypothesis (forensic findings 2-4) fitted on the published peak counts, in sample
//! and leaving one row out.
//!
//! Design, fixed before any run: the hypothesis has three free parameters (the first-peak
//! exemption, the velocity damping c, the threshold at k = 1e6), searched on the grid of
//! [`LiuHypothesis::grid`]. A grid point's score on a set of rows is the number of exact peak
//! counts (the printed counts are integers: the fit uses all they say), then the number
//! within the rule's tolerance, then the number of rows fully reproduced; ties go to the least
//! departure from the printed method (the grid's order). The in-sample fit uses all 18
//! Liu rows; for each row, the leave-one-out fit uses the other 17 and predicts the left-out
//! row, which counts as predicted only if it meets the full rule (peaks and T/2).

use super::configurations::LiuHypothesis;
use crate::experiments::{peak_tolerance, same_experiment, Measured, PublishedRow};

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

    /// (exact peak counts, peak counts within tolerance, rows reproduced) over the rows not
    /// equal to `left_out`.
    fn score(&self, left_out: Option<&PublishedRow>) -> (usize, usize, usize) {
        let kept = self
            .rows
            .iter()
            .filter(|m| left_out.is_none_or(|r| !same_experiment(&m.published, r)));
        kept.fold((0, 0, 0), |(exact, within, rule), m| {
            (
                exact + usize::from(!m.hit_time_limit && m.peaks == m.published.ke_peaks),
                within + usize::from(peaks_within_tolerance(m)),
                rule + usize::from(m.reproduces()),
            )
        })
    }
}

/// Whether a run's peak count is within the rule's tolerance (and the run was not cut).
pub fn peaks_within_tolerance(m: &Measured) -> bool {
    !m.hit_time_limit
        && m.peaks.abs_diff(m.published.ke_peaks) <= peak_tolerance(m.published.ke_peaks)
}

/// One left-out row: the hypothesis fitted without it and what that gives on it.
#[derive(Debug, Clone, PartialEq)]
pub struct LeftOut {
    pub hypothesis: LiuHypothesis,
    pub measured: Measured,
}

/// The grid, the in-sample fit and the leave-one-out predictions.
#[derive(Debug, Clone, PartialEq)]
pub struct LiuFit {
    pub grid: Vec<GridPoint>,
    pub in_sample: LiuHypothesis,
    /// One per Liu row, in published order.
    pub left_out: Vec<LeftOut>,
}

impl LiuFit {
    /// Fits the hypothesis on the measured `grid` (every point holding the same Liu rows).
    pub fn new(grid: Vec<GridPoint>) -> Self {
        let best = |left_out: Option<&PublishedRow>| -> usize {
            // The first maximum in grid order: the least departure among equals.
            let mut best = 0;
            for (i, point) in grid.iter().enumerate() {
                if point.score(left_out) > grid[best].score(left_out) {
                    best = i;
                }
            }
            best
        };
        let in_sample = grid[best(None)].hypothesis;
        let left_out = grid[0]
            .rows
            .iter()
            .map(|m| {
                let point = &grid[best(Some(&m.published))];
                LeftOut {
                    hypothesis: point.hypothesis,
                    measured: point
                        .row(&m.published)
                        .expect("every grid point holds every Liu row")
                        .clone(),
                }
            })
            .collect();
        Self {
            grid,
            in_sample,
            left_out,
        }
    }

    /// The rows measured at a grid point.
    pub fn point(&self, hypothesis: LiuHypothesis) -> &GridPoint {
        self.grid
            .iter()
            .find(|p| p.hypothesis == hypothesis)
            .expect("a point of the grid")
    }

    /// The leave-one-out prediction of `row`.
    pub fn left_out(&self, row: &PublishedRow) -> Option<&LeftOut> {
        self.left_out
            .iter()
            .find(|l| same_experiment(&l.measured.published, row))
    }

    /// How many rows the leave-one-out fits predict (full rule).
    pub fn predicted(&self) -> usize {
        self.left_out
            .iter()
            .filter(|l| l.measured.reproduces())
            .count()
    }
}

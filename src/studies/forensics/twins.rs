//! Twins: published rows that are one observation, not two.
//!
//! Two rows of one table and time step are twins when every published number they print is
//! the same (error, peaks, T/2, relative T error) and our faithful runs of them coincide to
//! round-off: the same peak count, the same thesis T/2 to [`TWIN_HALF_PERIOD_REL`], final
//! positions within [`TWIN_POSITION_M`] (sum of per-node distances). Their iteration counts
//! differ, but both runs have converged each step, so the second row adds no information: every
//! fit, split and headline count takes a pair once (the rule of [`super::evidence`]).

use crate::model::metrics::rest_error_sum;
use crate::studies::experiments::{same_experiment, Measured, PublishedRow};

/// Largest relative difference of our two T/2 that still counts as the same value.
pub const TWIN_HALF_PERIOD_REL: f64 = 1e-9;
/// Largest sum of per-node distances between our two final states that still counts as the
/// same state, m.
pub const TWIN_POSITION_M: f64 = 1e-6;

/// Whether every number the thesis prints for the two rows is the same.
pub fn published_alike(a: &PublishedRow, b: &PublishedRow) -> bool {
    a.table == b.table
        && a.solver == b.solver
        && a.dt_s == b.dt_s
        && a.stiffness == b.stiffness
        && a.error == b.error
        && a.ke_peaks == b.ke_peaks
        && a.half_period_s == b.half_period_s
        && a.period_rel_error == b.period_rel_error
}

/// Whether our two runs coincide to round-off.
pub fn outputs_alike(a: &Measured, b: &Measured) -> bool {
    let same_period = match (a.half_period_thesis, b.half_period_thesis) {
        (Some(x), Some(y)) => (x - y).abs() <= TWIN_HALF_PERIOD_REL * x.abs().max(y.abs()),
        (None, None) => true,
        _ => false,
    };
    a.peaks == b.peaks
        && a.hit_time_limit == b.hit_time_limit
        && same_period
        && rest_error_sum(&a.final_positions, &b.final_positions) <= TWIN_POSITION_M
}

/// The twin pairs among `rows` (our faithful measurements), each as (first, second) in the
/// order of `rows`: the second of a pair is the one merged into the first.
pub fn twin_pairs(rows: &[Measured]) -> Vec<(PublishedRow, PublishedRow)> {
    let mut pairs = Vec::new();
    for (i, a) in rows.iter().enumerate() {
        for b in &rows[i + 1..] {
            if a.published.iterations != b.published.iterations
                && published_alike(&a.published, &b.published)
                && outputs_alike(a, b)
            {
                pairs.push((a.published.clone(), b.published.clone()));
            }
        }
    }
    pairs
}

/// The twins of a result set, and the rows that count as observations.
#[derive(Debug, Clone, PartialEq)]
pub struct Twins {
    pub pairs: Vec<(PublishedRow, PublishedRow)>,
}

impl Twins {
    /// The twin pairs of our faithful measurements.
    pub fn of(rows: &[Measured]) -> Self {
        Self {
            pairs: twin_pairs(rows),
        }
    }

    /// Whether `row` is the second of a twin pair (merged into the first).
    pub fn is_merged(&self, row: &PublishedRow) -> bool {
        self.pairs.iter().any(|(_, b)| same_experiment(b, row))
    }

    /// The twin of `row`, if it has one.
    pub fn twin_of(&self, row: &PublishedRow) -> Option<&PublishedRow> {
        self.pairs.iter().find_map(|(a, b)| {
            if same_experiment(a, row) {
                Some(b)
            } else if same_experiment(b, row) {
                Some(a)
            } else {
                None
            }
        })
    }

    /// The observations among `rows`: each row but the second of a twin pair.
    pub fn observations<'a, T: 'a>(
        &'a self,
        rows: impl IntoIterator<Item = &'a T>,
        published: impl Fn(&T) -> &PublishedRow + 'a,
    ) -> impl Iterator<Item = &'a T> {
        rows.into_iter()
            .filter(move |r| !self.is_merged(published(r)))
    }
}

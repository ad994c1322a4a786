//! The reproduction rule of `docs/thesis-scene.md`, used everywhere (tests, report,
//! summaries).

use super::published::PublishedRow;

/// Allowed peak-count deviation: max(1, round(0.005 × published)).
pub fn peak_tolerance(published_peaks: usize) -> usize {
    ((0.005 * published_peaks as f64).round() as usize).max(1)
}

/// Allowed relative T/2 deviation (0.5 %).
pub const HALF_PERIOD_TOLERANCE: f64 = 0.005;

/// The reproduction rule of the scene specification, used everywhere: under the thesis
/// convention, |peaks − published| ≤ max(1, round(0.005·published)) and
/// |T/2 − published| ≤ 0.5 % of published.
pub fn reproduces(published: &PublishedRow, peaks: usize, half_period: Option<f64>) -> bool {
    reproduces_within(published, peaks, half_period, HALF_PERIOD_TOLERANCE)
}

/// [`reproduces`] with the relative T/2 tolerance `tolerance` in place of 0.5 %: the report's
/// sweep of it, since 0.5 % was set in the first commit with the prototype's counts in view.
pub fn reproduces_within(
    published: &PublishedRow,
    peaks: usize,
    half_period: Option<f64>,
    tolerance: f64,
) -> bool {
    let peaks_ok = peaks.abs_diff(published.ke_peaks) <= peak_tolerance(published.ke_peaks);
    let period_ok = half_period.is_some_and(|t| {
        (t - published.half_period_s).abs() <= tolerance * published.half_period_s
    });
    peaks_ok && period_ok
}
/// A passing row whose T/2 deviation exceeds this fraction is flagged "marginal": it passes
/// the 0.5 % test with little room, so a small change of convention could flip it.
pub const MARGINAL_HALF_PERIOD: f64 = 0.004;

/// Whether `half_period` (thesis convention) deviates from the published T/2 by more than
/// [`MARGINAL_HALF_PERIOD`].
pub fn is_marginal(published: &PublishedRow, half_period: Option<f64>) -> bool {
    half_period.is_some_and(|t| {
        (t - published.half_period_s).abs() > MARGINAL_HALF_PERIOD * published.half_period_s
    })
}

/// The two ways of measuring T/2 (`docs/thesis-scene.md`, conventions 4-5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TimeConvention {
    /// Peaks stamped at their detection step, time accumulated in f32, last stamp / peaks.
    Thesis,
    /// Peaks at their own sample, time in f64, mean interval between peaks.
    Exact,
}

impl TimeConvention {
    /// The identifier of the report and `reproduction.csv`.
    pub fn id(self) -> &'static str {
        match self {
            TimeConvention::Thesis => "f32-detection-step",
            TimeConvention::Exact => "exact",
        }
    }
}

/// The convention whose T/2 is closer to the published one (None when either is missing or
/// both are equally close).
pub fn better_time_convention(
    published: &PublishedRow,
    thesis: Option<f64>,
    exact: Option<f64>,
) -> Option<TimeConvention> {
    let (t, e) = (thesis?, exact?);
    let (dt, de) = (
        (t - published.half_period_s).abs(),
        (e - published.half_period_s).abs(),
    );
    match dt.total_cmp(&de) {
        std::cmp::Ordering::Less => Some(TimeConvention::Thesis),
        std::cmp::Ordering::Greater => Some(TimeConvention::Exact),
        std::cmp::Ordering::Equal => None,
    }
}

/// Rows whose published rest-state error exceeds this are expected within
/// [`ERROR_RATIO_RANGE`] of it; smaller errors are floors, compared but not asserted.
pub const ERROR_CHECK_ABOVE: f64 = 0.1;
/// The band of ours/published for the rest-state error (scene specification).
pub const ERROR_RATIO_RANGE: (f64, f64) = (0.8, 1.25);

/// Whether `ours / published` lies in [`ERROR_RATIO_RANGE`].
pub fn within_band(ours: f64, published: f64) -> bool {
    (ERROR_RATIO_RANGE.0..=ERROR_RATIO_RANGE.1).contains(&(ours / published))
}

#[cfg(test)]
mod sweep_tests {
    use super::*;
    use crate::studies::experiments::published_rows;

    /// A constructed run at +0.48 % (the T6 dt = 0.001 s rows' deviation) passes at 0.5 and
    /// 0.6 % and fails at 0.4 %; the rule's own tolerance gives the rule's verdict. Negative
    /// case: a sweep that ignored its tolerance (always 0.5 %) would pass it at 0.4 %.
    #[test]
    fn the_tolerance_decides_a_row_near_its_edge() {
        let row = &published_rows()[0];
        let t = Some(row.half_period_s * 1.0048);
        assert!(!reproduces_within(row, row.ke_peaks, t, 0.004));
        assert!(reproduces_within(row, row.ke_peaks, t, 0.005));
        assert!(reproduces_within(row, row.ke_peaks, t, 0.006));
        assert_eq!(
            reproduces(row, row.ke_peaks, t),
            reproduces_within(row, row.ke_peaks, t, HALF_PERIOD_TOLERANCE)
        );
    }
}

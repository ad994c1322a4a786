//! What the thesis's figures share: a figure and its files, the look of an error series, the
//! reduction of long series, the CSV of what a figure draws.

use crate::data::CsvFile;
use crate::format::{full, sig4};
use crate::inputs::ReportData;
use crate::plot::{layout, power_of_ten, Chart, Layout, Line, Panel, Rgb, Series};
use crate::style::iteration_marker;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::time_stepper::Run;
use mass_spring_solvers::model::system::Vec3;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{Measured, PublishedRow};

/// One figure: file stem (`fig05-error-dt-k1e3`), caption, layout, SVG and CSV text.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// The caption's key: the thesis's number, or one of ours (`P1`) that
    /// [`crate::navigation::number_figures`] numbers.
    pub key: String,
    pub stem: String,
    pub caption: String,
    /// Every text box, data mark and axes rectangle, for the figure test.
    pub layout: Layout,
    pub svg: String,
    pub csv: String,
}

impl Figure {
    pub(super) fn new(
        key: impl ToString,
        stem: impl Into<String>,
        caption: String,
        chart: &Chart,
        csv: String,
    ) -> Result<Self> {
        let layout = layout(chart)?;
        Ok(Self {
            key: key.to_string(),
            stem: stem.into(),
            caption,
            svg: layout.svg(),
            layout,
            csv,
        })
    }
}

/// Long series are reduced to this many buckets (min and max of each) before drawing.
pub(super) const MAX_BUCKETS: usize = 1500;

/// The class of a published row in the parity figure: its evidence class (issue 8) when the
/// forensic reproduction ran, else "unclassified".
pub fn row_class(data: &ReportData, row: &PublishedRow) -> String {
    data.forensics
        .as_ref()
        .and_then(|f| f.evidence_of(row))
        .map_or_else(
            || "unclassified".to_string(),
            |e| e.evidence.id().to_string(),
        )
}

/// `10³`: a stiffness as a typeset power of ten.
pub(super) fn stiffness_text(k: f64) -> String {
    let e = k.log10().round();
    if (10f64.powf(e) - k).abs() <= 1e-9 * k {
        power_of_ten(e as i32)
    } else {
        sig4(k)
    }
}

/// Long-format CSV of named (x, y) series.
pub(super) fn series_csv(
    x: &'static str,
    y: &'static str,
    series: &[(String, Vec<(f64, f64)>)],
) -> String {
    let mut out = CsvFile::new(&["series", x, y]);
    for (name, points) in series {
        for &(a, b) in points {
            out.record(vec![name.to_string(), full(a), full(b)]);
        }
    }
    out.text()
}

/// Node positions (x, y) of named shapes as CSV.
pub(super) fn shapes_csv(shapes: &[(String, Vec<Vec3>)]) -> String {
    let mut out = CsvFile::new(&["series", "node", "x_m", "y_m"]);
    for (name, nodes) in shapes {
        for (i, p) in nodes.iter().enumerate() {
            out.record(vec![name.to_string(), i.to_string(), full(p.x), full(p.y)]);
        }
    }
    out.text()
}

/// A series reduced to the minimum and maximum of each of at most `buckets` consecutive
/// runs of samples, in time order, so that peaks survive the reduction.
pub fn decimate(points: &[(f64, f64)], buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= 2 * buckets {
        return points.to_vec();
    }
    let size = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets + 1);
    for chunk in points.chunks(size) {
        let lo = chunk
            .iter()
            .enumerate()
            .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
            .map(|(i, _)| i);
        let hi = chunk
            .iter()
            .enumerate()
            .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
            .map(|(i, _)| i);
        let (Some(lo), Some(hi)) = (lo, hi) else {
            continue;
        };
        let (first, second) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        out.push(chunk[first]);
        if second != first {
            out.push(chunk[second]);
        }
    }
    if let (Some(last), Some(end)) = (out.last(), points.last()) {
        if last != end {
            out.push(*end);
        }
    }
    out
}

/// The kinetic energy of a run against time, up to `until` seconds.
pub(super) fn energy_series(run: &Run, until: f64) -> Vec<(f64, f64)> {
    run.kinetic_energy
        .iter()
        .enumerate()
        .map(|(i, &e)| (i as f64 * run.dt, e))
        .take_while(|&(t, _)| t <= until + 0.5 * run.dt)
        .collect()
}

/// "20 ≈ 50 it." for a group of iteration counts.
pub(super) fn group_label(iterations: &[usize], group: &[usize]) -> String {
    let counts: Vec<String> = group.iter().map(|&i| iterations[i].to_string()).collect();
    format!("{} it.", counts.join(" ≈ "))
}

/// The look of one error series: published hollow and dashed, ours filled and solid.
pub(super) fn error_style(index: usize, color: Rgb, published: bool) -> Series {
    let s = Series::line("", Vec::new(), color).with_marker(iteration_marker(index), !published);
    if published {
        s.with_line(Line::Dashed)
    } else {
        s
    }
}

pub(super) fn xy(nodes: &[Vec3]) -> Vec<(f64, f64)> {
    nodes.iter().map(|p| (p.x, p.y)).collect()
}

pub(super) fn opt_sig(x: Option<f64>) -> String {
    x.map_or_else(|| "–".into(), sig4)
}

/// The data extent of a panel's series on one axis (finite values only).
pub(super) fn series_extent(panel: &Panel, pick: fn(&(f64, f64)) -> f64) -> (f64, f64) {
    panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(pick))
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

pub(super) fn reference(data: &ReportData, stiffness: f64) -> Option<&Measured> {
    data.results.rows.iter().find(|m| {
        m.published.solver == SolverId::BackwardEuler && m.published.stiffness == stiffness
    })
}

/// A short decimal (`0.25`, `1`, `0.001`) for captions.
pub(super) fn sig_short(x: f64) -> String {
    let s = sig4(x);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Sets a linear y range with `fraction` of the data's span free above the curves, for
/// direct labels.
pub(super) fn headroom(panel: &mut Panel, fraction: f64) {
    let (lo, hi) = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|y| y.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
            (lo.min(y), hi.max(y))
        });
    if lo < hi {
        let span = hi - lo;
        panel.y = panel
            .y
            .clone()
            .range(lo - 0.05 * span, hi + fraction * span);
    }
}

/// The last x of a panel's series.
pub(super) fn panel_end(series: &[Series]) -> f64 {
    series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0))
        .fold(1.0, f64::max)
}

/// The marks of one class and solver in a parity panel: (class, solver, (published, ours)).
pub(super) type ParityGroup = (String, SolverId, Vec<(f64, f64)>);

/// `₁₂`: an index as subscript digits.
pub(super) fn subscript(i: usize) -> String {
    i.to_string()
        .bytes()
        .map(|d| char::from_u32(0x2080 + (d - b'0') as u32).unwrap_or('?'))
        .collect()
}

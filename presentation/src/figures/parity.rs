//! The parity figure: every published number of Tables 1-7 against ours, by evidence class.

use super::common::*;

use crate::data::CsvFile;
use crate::format::{full, full_opt};
use crate::inputs::ReportData;
use crate::plot::{
    Axis, Band, Chart, Entry, Line, Marker, Panel, Rgb, Series, Style, FULL_WIDTH_MM,
};
use crate::style::{class_colour, GREY};
use crate::tables::measured;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::studies::experiments::{
    peak_tolerance, published_rows, Measured, PublishedRow, HALF_PERIOD_TOLERANCE,
};
use mass_spring_solvers::studies::forensics::Evidence;

/// One row of the parity figure: the published numbers, ours (faithful configuration) and
/// the row's class.
pub(super) struct ParityRow<'a> {
    published: &'a PublishedRow,
    ours: &'a Measured,
    class: String,
}

/// Points (published, ours) of one quantity, grouped by class and solver in order of first
/// appearance; rows where either side is missing or not positive are left out.
pub(super) fn parity_points(
    rows: &[ParityRow],
    pick: impl Fn(&ParityRow) -> Option<(f64, f64)>,
) -> (Vec<ParityGroup>, usize) {
    let mut groups: Vec<ParityGroup> = Vec::new();
    let mut count = 0;
    for r in rows {
        let Some(p) = pick(r).filter(|p| p.0 > 0.0 && p.1 > 0.0) else {
            continue;
        };
        count += 1;
        let solver = r.published.solver;
        match groups.iter_mut().find(|g| g.0 == r.class && g.1 == solver) {
            Some(g) => g.2.push(p),
            None => groups.push((r.class.clone(), solver, vec![p])),
        }
    }
    (groups, count)
}

/// Log-spaced samples over a panel's extent, for the diagonal and the bands.
pub(super) fn log_samples(lo: f64, hi: f64) -> Vec<f64> {
    let (a, b) = (lo.log10(), hi.log10());
    (0..=120)
        .map(|i| 10f64.powf(a + (b - a) * i as f64 / 120.0))
        .collect()
}

/// A parity panel: ours against published, y = x, an optional reproduction band
/// `band(x) -> (lower, upper)`.
pub(super) fn parity_panel(
    quantity: &str,
    unit: &str,
    groups: &[ParityGroup],
    band: Option<&dyn Fn(f64) -> (f64, f64)>,
) -> Panel {
    let (lo, hi) = groups
        .iter()
        .flat_map(|g| g.2.iter().flat_map(|p| [p.0, p.1]))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    // Room for the markers at both ends: 6 % of the span and 0.1 decade.
    let (lo, hi) = if lo.is_finite() {
        let pad = 10f64.powf(0.06 * (hi / lo).log10() + 0.1);
        (lo / pad, hi * pad)
    } else {
        (0.1, 10.0)
    };
    let mut panel = Panel::new(
        Axis::log(format!("published {quantity}{unit}")).range(lo, hi),
        Axis::log(format!("ours{unit}")).range(lo, hi),
    );
    let xs = log_samples(lo, hi);
    if let Some(band) = band {
        let (lower, upper): (Vec<_>, Vec<_>) = xs
            .iter()
            .map(|&x| {
                let (l, u) = band(x);
                ((x, l.max(lo)), (x, u.min(hi)))
            })
            .unzip();
        panel.bands.push(Band {
            lower,
            upper,
            color: Rgb(215, 215, 215),
        });
    }
    panel.series.push(
        Series::line("", vec![(lo, lo), (hi, hi)], GREY)
            .with_weight(0.6)
            .with_line(Line::Dashed),
    );
    for (class, _, points) in groups {
        let (marker, filled) = class_marker(class);
        panel.series.push(
            Series::points("", points.clone(), class_colour(class)).with_marker(marker, filled),
        );
    }
    panel
}

/// The marker of an evidence class (with [`class_colour`], so that the classes read apart in
/// grey print too): a shape and a fill of its own for each of the seven.
pub(super) fn class_marker(class: &str) -> (Marker, bool) {
    match class {
        "faithful" => (Marker::Circle, true),
        "interpretation" => (Marker::Circle, false),
        "predicted" => (Marker::Triangle, true),
        "selected" => (Marker::Square, true),
        "fitted" => (Marker::Triangle, false),
        "noise-limited" => (Marker::Cross, true),
        _ => (Marker::Square, false),
    }
}

/// The parity figure: ours against published for all 56 rows, one panel each for the peak
/// count, T/2 and the rest-state error, marks coloured by the row's class.
pub(super) fn parity(data: &ReportData) -> Result<Figure> {
    let rows: Vec<ParityRow> = published_rows()
        .iter()
        .filter_map(|p| {
            measured(&data.results, p).map(|ours| ParityRow {
                published: p,
                ours,
                class: row_class(data, p),
            })
        })
        .collect();
    let mut csv = CsvFile::new(&[
        "table",
        "solver",
        "dt_s",
        "iterations",
        "stiffness_n_per_m",
        "class",
        "peaks_published",
        "peaks_ours",
        "half_period_published_s",
        "half_period_ours_s",
        "error_published_m",
        "error_ours_m",
    ]);
    for r in &rows {
        let p = r.published;
        csv.record(vec![
            p.table.to_string(),
            p.solver.id().to_string(),
            full(p.dt_s),
            p.iterations.to_string(),
            full(p.stiffness),
            r.class.to_string(),
            p.ke_peaks.to_string(),
            r.ours.peaks.to_string(),
            full(p.half_period_s),
            full_opt(r.ours.half_period_thesis),
            full_opt(p.error),
            full_opt(r.ours.error_sum),
        ]);
    }
    let (peaks, n_peaks) = parity_points(&rows, |r| {
        Some((r.published.ke_peaks as f64, r.ours.peaks as f64))
    });
    let (half, n_half) = parity_points(&rows, |r| {
        r.ours
            .half_period_thesis
            .map(|t| (r.published.half_period_s, t))
    });
    let (error, n_error) = parity_points(&rows, |r| r.published.error.zip(r.ours.error_sum));
    let peak_band = |x: f64| {
        let tol = peak_tolerance(x.round() as usize) as f64;
        (x - tol, x + tol)
    };
    let period_band = |x: f64| {
        (
            x * (1.0 - HALF_PERIOD_TOLERANCE),
            x * (1.0 + HALF_PERIOD_TOLERANCE),
        )
    };
    let panels = vec![
        parity_panel("peak count", "", &peaks, Some(&peak_band)),
        parity_panel("T/2", " (s)", &half, Some(&period_band)),
        parity_panel("rest-state error", " (m)", &error, None),
    ];
    let mut chart = Chart::new(FULL_WIDTH_MM, 80.0, panels);
    let mut classes: Vec<String> = rows.iter().map(|r| r.class.clone()).collect();
    // Strongest class first, as in the forensic chapter.
    classes.sort_by_key(|c| Evidence::ALL.iter().position(|e| e.id() == c));
    classes.dedup();
    for class in &classes {
        let (marker, filled) = class_marker(class);
        chart.legend.push(Entry {
            label: class.clone(),
            style: Series::points("", Vec::new(), class_colour(class))
                .with_marker(marker, filled)
                .style,
        });
    }
    chart.legend.push(Entry {
        label: "ours = published".into(),
        style: Series::line("", Vec::new(), GREY)
            .with_weight(0.6)
            .with_line(Line::Dashed)
            .style,
    });
    chart.legend.push(Entry {
        label: "reproduction band".into(),
        style: Style {
            color: Rgb(215, 215, 215),
            line: Line::Solid,
            marker: Marker::None,
            filled: true,
            width: 6.0,
            radius: 0.0,
        },
    });
    Figure::new(
        PARITY_FIGURE,
        "parity",
        format!(
            "Figure {PARITY_FIGURE}. Ours against published for every row, log-log: (a) the kinetic-energy peak count \
             ({n_peaks} rows), (b) T/2 under the thesis convention ({n_half} rows) and (c) the rest-state error \
             ({n_error} solver rows; Table 1 has none). Ours are the faithful configuration's numbers; the dashed \
             line is ours = published and the grey band the reproduction rule (peaks within max(1, round(0.005 × \
             published)), T/2 within {} %); the rest-state error has no rule. Marker and colour, each alone \
             enough: the row's evidence class of section 6 ({}), which names the configuration that reproduces it \
             while the mark stays at the faithful numbers (the solver of each point is in the data file). Rows \
             where a side is missing or zero are left out.",
            sig_short(100.0 * HALF_PERIOD_TOLERANCE),
            classes.join(", ")
        ),
        &chart,
        csv.text(),
    )
}

/// The parity figure's key (it is not the thesis's).
pub const PARITY_FIGURE: &str = "P1";

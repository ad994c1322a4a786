//! Figures 11-15: the kinetic energy and the motion of the rope, the five instants, the
//! Backward-Euler and Fast m-s motions beside each other.

use super::common::*;

use crate::data::CsvFile;
use crate::format::{full, sig4};
use crate::plot::{
    Align, Axis, Chart, Line, Marker, Panel, Rgb, Series, COLUMN_WIDTH_MM, FULL_WIDTH_MM,
};
use crate::runs::{FigureRuns, BE_SOFT, BE_STIFF, FMS_SOFT_COARSE, STIFF_MIDDLE};
use crate::style::{colour, solver_line, BLACK, GREY, RED, TIME_ORDER};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::time_stepper::Run;
use mass_spring_solvers::solvers::registry::SolverId;

/// The peaks of a run inside a window, for markers.
pub(super) fn peaks_until(run: &Run, until: f64) -> Vec<(f64, f64)> {
    run.peaks
        .iter()
        .filter(|p| p.time_exact <= until)
        .map(|p| (p.time_exact, p.energy))
        .collect()
}

/// The five instants of Figure 12: release, first peak, first minimum after it, second
/// peak, second minimum (sample indices).
pub fn five_instants(kinetic_energy: &[f64]) -> Vec<usize> {
    let mut instants = vec![0];
    let mut want_peak = true;
    for i in 1..kinetic_energy.len().saturating_sub(1) {
        let (a, b, c) = (
            kinetic_energy[i - 1],
            kinetic_energy[i],
            kinetic_energy[i + 1],
        );
        let hit = if want_peak {
            a < b && b >= c
        } else {
            a > b && b <= c
        };
        if hit {
            instants.push(i);
            want_peak = !want_peak;
            if instants.len() == 5 {
                break;
            }
        }
    }
    instants
}

/// Figure 11: two periods of the reference's kinetic energy, k = 10⁶.
pub(super) fn figure11(runs: &FigureRuns) -> Result<Figure> {
    let mut panel = Panel::new(Axis::linear("time (s)"), Axis::linear("kinetic energy (J)"));
    let mut csv_series = Vec::new();
    let mut caption_extra = String::new();
    if let Some((_, run)) = runs.get(BE_STIFF) {
        // Two periods T = 4 half-periods: up to the fifth kinetic-energy peak.
        let until = run.peaks.get(4).map_or(1.0, |p| p.time_exact) + 0.02;
        let ke = energy_series(run, until);
        let peaks = peaks_until(run, until);
        if peaks.len() > 1 {
            let intervals: Vec<String> = peaks.windows(2).map(|w| sig4(w[1].0 - w[0].0)).collect();
            caption_extra = format!(
                " Intervals between peaks 1 to 5: {} s (the thesis's T/2 is their mean over the whole run).",
                intervals.join(", ")
            );
        }
        for (i, &p) in peaks.iter().enumerate() {
            panel.label(p, (0.0, 6.0), Align::Middle, format!("{}", i + 1), BLACK);
        }
        panel
            .series
            .push(Series::line("kinetic energy", ke.clone(), BLACK));
        panel
            .series
            .push(Series::points("peaks", peaks.clone(), RED).with_marker(Marker::Circle, true));
        csv_series.push(("kinetic_energy_j".to_string(), ke));
        csv_series.push(("peak_j".to_string(), peaks));
    }
    headroom(&mut panel, 0.12);
    Figure::new(
        11,
        "fig11-kinetic-energy-reference",
        format!(
            "Figure 11. Two periods of the kinetic energy of Newton under Backward Euler (Δt = 0.001 s, 5 Newton iterations), \
             k = 10⁶ N/m, from the release at rest: the kinetic energy peaks twice per period of the rope, so two \
             periods span peaks 1 to 5.{caption_extra}"
        ),
        &Chart::new(COLUMN_WIDTH_MM, 66.0, vec![panel]),
        series_csv("time_s", "value_j", &csv_series),
    )
}

/// Figure 12: the kinetic energy over one period with five marked instants, and the rope at
/// those instants.
pub(super) fn figure12(runs: &FigureRuns) -> Result<Figure> {
    let mut energy = Panel::new(Axis::linear("time (s)"), Axis::linear("kinetic energy (J)"));
    let mut rope = Panel::new(
        Axis::linear("x (m)"),
        Axis::linear("y (m)").range(-3.6, 0.3),
    );
    rope.equal_aspect = true;
    let mut csv = CsvFile::new(&[
        "instant",
        "time_s",
        "kinetic_energy_j",
        "node",
        "x_m",
        "y_m",
    ]);
    // The instants in time order on one sequential scale, not the solvers' hues, which every
    // other figure gives a solver.
    let palette = TIME_ORDER;
    if let Some((_, run)) = runs.get(BE_SOFT) {
        let instants = five_instants(&run.kinetic_energy);
        let end = instants.last().map_or(1.0, |&i| i as f64 * run.dt) + 0.05;
        energy
            .series
            .push(Series::line("", energy_series(run, end), BLACK));
        for (n, &i) in instants.iter().enumerate() {
            let t = i as f64 * run.dt;
            let e = run.kinetic_energy[i];
            let c = palette[n % palette.len()];
            // A marker of its own besides the colour, for grey print and colour-blind readers.
            let (marker, filled) = [
                (Marker::Circle, true),
                (Marker::Triangle, true),
                (Marker::Square, true),
                (Marker::Cross, true),
                (Marker::Circle, false),
            ][n % 5];
            energy
                .series
                .push(Series::points("", vec![(t, e)], c).with_marker(marker, filled));
            // Peaks labelled above, minima (the curve rises on both sides) below.
            let offset = if n % 2 == 1 { 6.0 } else { -12.0 };
            energy.label(
                (t, e),
                (0.0, offset),
                Align::Middle,
                format!("{}", n + 1),
                c,
            );
            if let Some((_, state)) = run.positions.get(i) {
                let what = match n {
                    0 => "release",
                    1 | 3 => "peak",
                    _ => "turning point",
                };
                rope.series.push(
                    Series::line(
                        format!("{}: t = {} s, {what}", n + 1, sig_short(t)),
                        xy(&state.x),
                        c,
                    )
                    .with_marker(marker, filled)
                    .with_marker_scale(0.8),
                );
                for (node, p) in state.x.iter().enumerate() {
                    csv.record(vec![
                        (n + 1).to_string(),
                        full(t),
                        full(e),
                        node.to_string(),
                        full(p.x),
                        full(p.y),
                    ]);
                }
            }
        }
        headroom(&mut energy, 0.12);
        let (lo, hi) = energy.y.range.unwrap_or((0.0, 1.0));
        // Room under the minima for their labels.
        energy.y = energy.y.clone().range(lo - 0.12 * (hi - lo), hi);
    }
    Figure::new(
        12,
        "fig12-energy-and-motion",
        "Figure 12. The kinetic energy over one period (a) and the rope's motion (b, drawn to scale: the same metre on both axes), Backward Euler reference, \
         k = 10³ N/m (the softer rope, whose motion is visible at scale). The thesis's five instants are not given; \
         we mark 1 the release (straight rope at rest), 2 the first kinetic-energy peak (the rope passes its \
         equilibrium going down), 3 the next minimum (lowest turning point), 4 the second peak (equilibrium going \
         up) and 5 the next minimum (highest turning point): one full period. The instants are coloured in \
         time order on one sequential scale (dark to light), not in the solvers' hues."
            .into(),
        &Chart::new(FULL_WIDTH_MM, 80.0, vec![energy, rope]),
        csv.text(),
    )
}

/// The node whose height Figure 13 follows: the middle free node (the lowest at rest).
pub const FIGURE13_NODE: usize = 4;
/// The window of Figure 13, s: four periods of the reference, where its bounces still read.
pub const FIGURE13_WINDOW_S: f64 = 10.0;
/// Figure 13 marks every this many Fast m-s steps (the line joins every step).
pub(super) const FIGURE13_MARKER_EVERY: usize = 5;

/// Figure 13: the rope's motion over the first seconds, Backward Euler against Fast m-s.
pub(super) fn figure13(runs: &FigureRuns) -> Result<Figure> {
    let mut panel = Panel::new(
        Axis::linear("time (s)"),
        Axis::linear(format!("y of node x{} (m)", subscript(FIGURE13_NODE))),
    );
    let fms = runs.get(FMS_SOFT_COARSE);
    let mut csv_series = Vec::new();
    let height = |run: &Run| -> Vec<(f64, f64)> {
        run.positions
            .iter()
            .filter(|(t, _)| *t <= FIGURE13_WINDOW_S + 1e-9)
            .map(|(t, s)| (*t, s.x[FIGURE13_NODE].y))
            .collect()
    };
    let mut extra = String::new();
    match fms {
        Some((spec, run)) => {
            let y = height(run);
            panel.series.push(
                Series::line(
                    format!("Fast m-s (Δt = 0.1 s, {} it.)", spec.iterations),
                    y.clone(),
                    colour(SolverId::FastMassSpring, 0),
                )
                .with_weight(1.5)
                .with_marker(Marker::Triangle, true)
                .with_marker_every(FIGURE13_MARKER_EVERY),
            );
            csv_series.push(("fast_mass_spring".to_string(), y));
            extra = format!(" The Fast m-s run stops at t = {} s.", sig4(run.end_time()));
        }
        None => panel.label(
            (5.0, -2.6),
            (0.0, 0.0),
            Align::Middle,
            "(Fast m-s not run in this report)",
            GREY,
        ),
    }
    if let Some((_, run)) = runs.get(BE_SOFT) {
        let y = decimate(&height(run), MAX_BUCKETS);
        panel.series.push(
            Series::line("Backward Euler (Δt = 0.001 s, 5 it.)", y.clone(), BLACK).with_weight(0.8),
        );
        csv_series.insert(0, ("backward_euler".to_string(), y));
    }
    Figure::new(
        13,
        "fig13-motion-be-vs-fms",
        format!(
            "Figure 13. The rope's motion over the first {} s, Backward Euler against Fast m-s (k = 10³ N/m, \
             Δt = 0.1 s, 1 iteration). The thesis does not say what it plots; we plot the height of node 4, a middle \
             node and the lowest at rest, which shows the bounces directly: the reference oscillates about its rest \
             height while one Fast m-s iteration per step creeps down with hardly a bounce. Markers every {} Fast m-s \
             steps.{extra}",
            sig_short(FIGURE13_WINDOW_S),
            FIGURE13_MARKER_EVERY
        ),
        &Chart::new(FULL_WIDTH_MM, 62.0, vec![panel]),
        series_csv("time_s", "y_m", &csv_series),
    )
}

/// Figure 14: the kinetic-energy peaks against time on a log axis, k = 10⁶, Δt = 0.01, middle
/// iteration counts (damping rates are slopes); Figure 15: the kinetic energy itself, cut at
/// the time Fast m-s comes to rest.
pub(super) fn kinetic_energy_middle(runs: &FigureRuns, number: u8) -> Result<Figure> {
    let envelope = number == 14;
    let fms_end = runs.get(STIFF_MIDDLE[1].1).map(|(_, r)| r.end_time());
    let cut = if envelope {
        None
    } else {
        fms_end.or(Some(2.0))
    };
    let mut panel = if envelope {
        Panel::new(
            Axis::linear("time (s)"),
            Axis::log("kinetic-energy peaks (J)"),
        )
    } else {
        Panel::new(Axis::linear("time (s)"), Axis::linear("kinetic energy (J)"))
    };
    let mut csv_series = Vec::new();
    let mut drawn = Vec::new();
    let mut add = |label: String, key: &str, run: &Run, color: Rgb, line: Line, marker: Marker| {
        let until = cut.unwrap_or(run.end_time());
        let points = if envelope {
            run.peaks.iter().map(|p| (p.time_exact, p.energy)).collect()
        } else {
            decimate(&energy_series(run, until), MAX_BUCKETS)
        };
        // The reference thin, the solvers thicker, so the short runs stand out.
        let weight = if run.dt < 0.01 { 0.8 } else { 1.4 };
        // A marker for each solver besides its dash (the reference is solid like XPBD, the
        // threshold dotted like ADMM): a dozen on a dense curve, one per peak on the envelope.
        let every = if envelope {
            1
        } else {
            (points.len() / 12).max(1)
        };
        drawn.push(
            Series::line(label, points.clone(), color)
                .with_weight(weight)
                .with_line(line)
                .with_marker(marker, true)
                .with_marker_every(every),
        );
        csv_series.push((key.to_string(), points));
    };
    let mut present = Vec::new();
    for ((solver, key), marker) in
        STIFF_MIDDLE
            .into_iter()
            .zip([Marker::Circle, Marker::Triangle, Marker::Square])
    {
        if let Some((spec, run)) = runs.get(key) {
            add(
                format!("{} {} it.", solver.display_name(), spec.iterations),
                solver.id(),
                run,
                colour(solver, 1),
                solver_line(solver),
                marker,
            );
            present.push(format!(
                "{} {} iterations (ends at {} s)",
                solver.display_name(),
                spec.iterations,
                sig4(run.end_time())
            ));
        }
    }
    if let Some((_, run)) = runs.get(BE_STIFF) {
        add(
            "Backward Euler (reference)".into(),
            "backward_euler",
            run,
            BLACK,
            Line::Solid,
            Marker::None,
        );
        // The reference first in the data, last (on top) in the drawing.
        csv_series.rotate_right(1);
    }
    panel.series = drawn;
    if envelope {
        panel.series.push(
            Series::line(
                "stopping threshold",
                vec![
                    (0.0, mass_spring_solvers::model::metrics::STOP_THRESHOLD_J),
                    (
                        panel_end(&panel.series),
                        mass_spring_solvers::model::metrics::STOP_THRESHOLD_J,
                    ),
                ],
                GREY,
            )
            .with_line(Line::Dotted),
        );
    }
    if present.is_empty() {
        panel.label(
            (0.3, 5.0),
            (0.0, 0.0),
            Align::Start,
            "(XPBD, Fast m-s and ADMM not run in this report)",
            GREY,
        );
    }
    let first_peaks: Vec<String> = std::iter::once(
        runs.get(BE_STIFF)
            .map(|(_, r)| (SolverId::BackwardEuler.display_name().to_string(), r)),
    )
    .flatten()
    .chain(STIFF_MIDDLE.iter().filter_map(|(s, key)| {
        runs.get(key)
            .map(|(_, r)| (s.display_name().to_string(), r))
    }))
    .filter_map(|(name, r)| {
        r.peaks
            .first()
            .map(|p| format!("{name} {} J", sig4(p.energy)))
    })
    .collect();
    let what = if envelope {
        "the kinetic energy at each of its peaks (the envelope of the oscillation) over each whole run, on a \
         logarithmic axis, so that a constant damping rate is a straight line; the dotted line is the stopping \
         threshold, 0.001 J"
            .to_string()
    } else {
        format!(
            "the kinetic energy itself, cut at t = {} s, when Fast m-s comes to rest",
            cut.map_or("–".into(), sig4)
        )
    };
    Figure::new(
        number,
        format!("fig{number}-kinetic-energy-k1e6-dt0.01{}", if envelope { "" } else { "-cut" }),
        format!(
            "Figure {number}. Kinetic energy against time, k = 10⁶ N/m, Δt = 0.01 s, the middle iteration count of \
             each solver ({}; XPBD solid with circles, Fast m-s dashed with triangles, ADMM dotted with squares), with the Backward Euler reference \
             (Δt = 0.001 s, thin black): {what}. First peaks: {}. The \
             thesis: the reference peaks at about 6 J and XPBD's first peak exceeds 8 J.",
            if present.is_empty() { "not run".to_string() } else { present.join("; ") },
            if first_peaks.is_empty() { "–".to_string() } else { first_peaks.join(", ") }
        ),
        &Chart::new(FULL_WIDTH_MM, 66.0, vec![panel]),
        series_csv("time_s", "kinetic_energy_j", &csv_series),
    )
}

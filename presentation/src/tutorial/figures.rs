//! The tutorial chapter's figures, in the report's figure style ([`crate::plot`]:
//! printed size, no in-plot titles, (a)/(b) tags, legends outside the data), and the CSV of
//! the points each one draws. Geometry (the pendulum's frames, the falling cloth) is drawn
//! to scale, with equal x and y scales.

use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::{full, short, sig4};
use crate::plot::{
    power_of_ten, Align, Axis, Chart, Entry, Line, Marker, Panel, Rgb, Series, COLUMN_WIDTH_MM,
    FULL_WIDTH_MM,
};
use crate::style::TIME_ORDER;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::model::system::Vec3;
use mass_spring_solvers::particles::Integrator;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::tutorial::{
    AdaptiveRun, AdaptiveStudy, ClothDropRun, ConvergenceSeries, DragFall, EnergyRun, Method,
    PendulumRun, SpringPairRun, FORCE_DT, PAIR_DT, REFERENCE_TOLERANCE,
};

const BLACK: Rgb = Rgb(0, 0, 0);
const GREY: Rgb = Rgb(120, 120, 120);
const RED: Rgb = Rgb(200, 30, 30);
const BLUE: Rgb = Rgb(33, 113, 181);
const GREEN: Rgb = Rgb(35, 139, 69);
const PURPLE: Rgb = Rgb(117, 60, 160);

/// Colour, marker and line of each method: a (marker, line) pair of its own, colour aside.
fn method_style(method: Method) -> (Rgb, Marker, Line) {
    match method {
        Method(SolverId::ExplicitEuler) => (RED, Marker::Triangle, Line::Solid),
        Method(SolverId::SymplecticEuler) => (BLUE, Marker::Circle, Line::Solid),
        Method(SolverId::Rk4) => (GREEN, Marker::Square, Line::Solid),
        Method(SolverId::BackwardEuler) => (BLACK, Marker::Cross, Line::Solid),
        Method(SolverId::Rk45) => (PURPLE, Marker::Circle, Line::Dashed),
        // The study runs only the five above.
        Method(_) => (GREY, Marker::None, Line::Dotted),
    }
}

/// `10⁻¹¹` for an exact power of ten, else four significant digits.
fn typeset(x: f64) -> String {
    let e = x.log10().round();
    if (10f64.powf(e) - x).abs() <= 1e-9 * x {
        power_of_ten(e as i32)
    } else {
        sig4(x)
    }
}

/// Figure T1: global error against h, log-log, one line per method.
pub fn convergence(series: &[ConvergenceSeries]) -> Result<ChapterFigure> {
    let mut panel = Panel::new(Axis::log("h (s)"), Axis::log("phase-plane error (m)"));
    let mut csv = CsvFile::new(&["method", "zeta", "h_s", "error_m"]);
    for s in series {
        let (color, marker, line) = method_style(s.method);
        panel.series.push(
            Series::line(
                format!(
                    "{}: slope {} (expected {})",
                    s.method,
                    sig4(s.slope),
                    s.method.expected_order()
                ),
                s.points.clone(),
                color,
            )
            .with_marker(marker, true)
            .with_line(line),
        );
        for (h, e) in &s.points {
            csv.record(vec![
                s.method.id().to_string(),
                full(s.zeta),
                full(*h),
                full(*e),
            ]);
        }
    }
    ChapterFigure::new(
        "tutorial_convergence",
        &Chart::new(FULL_WIDTH_MM, 70.0, vec![panel]),
        csv.text(),
    )
}

/// The extent of the y values of `runs`, widened by `pad` decades at both ends.
fn log_extent(runs: &[EnergyRun], pad: f64) -> (f64, f64) {
    let (lo, hi) = runs
        .iter()
        .flat_map(|r| r.points.iter().map(|p| p.1))
        .filter(|e| e.is_finite() && *e > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), e| {
            (lo.min(e), hi.max(e))
        });
    if lo.is_finite() {
        (lo / 10f64.powf(pad), hi * 10f64.powf(pad))
    } else {
        (0.1, 10.0)
    }
}

/// Figure T2: energy of the undamped oscillator against time just below and above each
/// limit, one panel per integrator on a common log axis.
pub fn stability_energy(runs: &[EnergyRun]) -> Result<ChapterFigure> {
    let (lo, hi) = log_extent(runs, 0.3);
    let mut panels = Vec::new();
    let mut csv = CsvFile::new(&["integrator", "h_omega", "periods", "energy_ratio"]);
    for integrator in Integrator::ALL {
        let mut panel = Panel::new(
            Axis::linear("t ω / 2π (periods)"),
            Axis::log("E / E₀").range(lo, hi),
        );
        panel.heading = integrator.to_string();
        for (k, run) in runs
            .iter()
            .filter(|r| r.integrator == integrator)
            .enumerate()
        {
            let (color, line) = if k == 0 {
                (BLUE, Line::Solid)
            } else {
                (RED, Line::Dashed)
            };
            panel.series.push(
                Series::line(
                    format!("hω = {}", sig_short(run.h_omega)),
                    run.points.clone(),
                    color,
                )
                .with_line(line),
            );
            for (t, e) in &run.points {
                csv.record(vec![
                    integrator.key().to_string(),
                    full(run.h_omega),
                    full(*t),
                    full(*e),
                ]);
            }
        }
        panels.push(panel);
    }
    ChapterFigure::new(
        "tutorial_stability_energy",
        &Chart::new(FULL_WIDTH_MM, 62.0, panels),
        csv.text(),
    )
}

/// The pair's RK4 stretch is marked every this many samples (0.1 s); the closed form is the
/// line under it.
const PAIR_MARKER_EVERY: usize = 100;

/// Figure T3: (a) the drag fall and (b) the damped spring pair against their closed forms.
pub fn forces(drag: &DragFall, pair: &SpringPairRun) -> Result<ChapterFigure> {
    let mut left = Panel::new(Axis::linear("t (s)"), Axis::linear("downward speed (m/s)"));
    let closed: Vec<(f64, f64)> = drag.samples.iter().map(|s| (s.0, s.2)).collect();
    let ours: Vec<(f64, f64)> = drag.samples.iter().map(|s| (s.0, s.1)).collect();
    let t_end = drag.samples.last().map_or(0.0, |s| s.0);
    left.series.push(
        Series::line(
            format!("terminal speed m g / k_f = {} m/s", sig4(drag.terminal)),
            vec![(0.0, drag.terminal), (t_end, drag.terminal)],
            GREY,
        )
        .with_line(Line::Dashed),
    );
    left.series.push(Series::line("closed form", closed, BLACK));
    left.series.push(
        Series::points(format!("RK4, h = {} s", short(FORCE_DT)), ours, GREEN)
            .with_marker(Marker::Circle, false),
    );
    let mut right = Panel::new(
        Axis::linear("t (s)"),
        Axis::linear("stretch u = |Δx| − r (m)"),
    );
    let p = pair.pair;
    let closed: Vec<(f64, f64)> = pair.samples.iter().map(|s| (s.0, s.2)).collect();
    let ours: Vec<(f64, f64)> = pair.samples.iter().map(|s| (s.0, s.1)).collect();
    let spacing = pair.samples.get(1).map_or(0.0, |s| s.0);
    let envelope = |sign: f64| -> Vec<(f64, f64)> {
        pair.samples
            .iter()
            .map(|s| (s.0, sign * p.stretch * (-p.decay_rate() * s.0).exp()))
            .collect()
    };
    right.series.push(
        Series::line("envelope ±u₀ exp(−k_d t / 2μ)", envelope(1.0), GREY).with_line(Line::Dashed),
    );
    right
        .series
        .push(Series::line("", envelope(-1.0), GREY).with_line(Line::Dashed));
    right
        .series
        .push(Series::line("closed form", closed, BLACK).with_weight(0.7));
    right.series.push(
        Series::points(
            format!(
                "RK4, h = {} s (a marker every {} s)",
                typeset(PAIR_DT),
                sig_short(PAIR_MARKER_EVERY as f64 * spacing)
            ),
            ours,
            GREEN,
        )
        .with_marker(Marker::Circle, false)
        .with_marker_every(PAIR_MARKER_EVERY),
    );
    let mut csv = CsvFile::new(&["study", "time_s", "ours", "closed_form"]);
    for (t, a, b) in &drag.samples {
        csv.record(vec![
            "drag_speed_m_per_s".to_string(),
            full(*t),
            full(*a),
            full(*b),
        ]);
    }
    for (t, a, b) in &pair.samples {
        csv.record(vec![
            "spring_stretch_m".to_string(),
            full(*t),
            full(*a),
            full(*b),
        ]);
    }
    ChapterFigure::new(
        "tutorial_forces",
        &Chart::new(FULL_WIDTH_MM, 72.0, vec![left, right]),
        csv.text(),
    )
}

/// A chain of particles as (x, y) points: the side view.
fn side_view(points: &[Vec3]) -> Vec<(f64, f64)> {
    points.iter().map(|p| (p.x, p.y)).collect()
}

/// The height, mm, of a figure `width_mm` wide whose `columns` × `rows` frameless panels show
/// a `w` × `h` m extent each at equal scales, with room for the tags and a legend row.
fn to_scale_height_mm(width_mm: f64, columns: usize, rows: usize, w: f64, h: f64) -> f64 {
    // A frameless panel's cell loses about 4 mm across to margins and 5 mm down to its tag.
    let panel_w = width_mm / columns as f64 - 4.0;
    rows as f64 * (panel_w * h / w + 5.0) + 8.0
}

/// Figure T4: the pendulum's six frames, one panel each, to scale.
pub fn pendulum_frames(run: &PendulumRun) -> Result<ChapterFigure> {
    let reach = run.params.particles as f64 * run.params.segment_length;
    let x_range = (-reach - 0.3, reach + 0.3);
    let y_range = (-0.6, run.params.pivot_height + 0.3);
    let bar = (-reach, -0.35);
    let chain_style =
        |label: &str| Series::line(label, Vec::new(), BLUE).with_marker(Marker::Circle, true);
    let pivot_style = |label: &str| {
        Series::points(label, Vec::new(), RED)
            .with_marker(Marker::Square, true)
            .with_marker_scale(1.1)
    };
    let floor_style = |label: &str| Series::line(label, Vec::new(), GREY).with_weight(2.0);
    let mut panels = Vec::new();
    let mut csv = CsvFile::new(&["time_s", "particle", "x_m", "y_m"]);
    for (k, (t, x)) in run.frames.iter().enumerate() {
        let mut panel = Panel::new(
            Axis::linear("").range(x_range.0, x_range.1),
            Axis::linear("").range(y_range.0, y_range.1),
        );
        panel.frame = false;
        panel.equal_aspect = true;
        panel.heading = format!("t = {} s", sig_short(*t));
        let mut floor = floor_style("");
        floor.points = vec![(-reach - 0.2, 0.0), (reach + 0.2, 0.0)];
        panel.series.push(floor);
        let mut chain = chain_style("");
        chain.points = side_view(x);
        panel.series.push(chain);
        let mut pivot = pivot_style("");
        pivot.points = side_view(&x[..1]);
        panel.series.push(pivot);
        if k == 0 {
            panel
                .series
                .push(Series::line("", vec![bar, (bar.0 + 1.0, bar.1)], BLACK).with_weight(1.5));
            panel.label(
                (bar.0 + 1.0, bar.1),
                (4.0, -3.0),
                Align::Start,
                "1 m",
                BLACK,
            );
        }
        for (i, p) in x.iter().enumerate() {
            csv.record(vec![full(*t), i.to_string(), full(p.x), full(p.y)]);
        }
        panels.push(panel);
    }
    let columns = 3;
    let rows = panels.len().div_ceil(columns);
    let height = to_scale_height_mm(
        FULL_WIDTH_MM,
        columns,
        rows,
        x_range.1 - x_range.0,
        y_range.1 - y_range.0,
    );
    let mut chart = Chart::new(FULL_WIDTH_MM, height, panels);
    chart.columns = columns;
    chart.legend = [
        ("chain (particles on springs)", chain_style("")),
        ("pivot (anchored)", pivot_style("")),
        ("floor", floor_style("")),
    ]
    .into_iter()
    .map(|(label, s)| Entry {
        label: label.into(),
        style: s.style,
    })
    .collect();
    ChapterFigure::new("tutorial_pendulum_frames", &chart, csv.text())
}

/// A short decimal for labels and captions (`0.5`, `1.432`).
pub fn sig_short(x: f64) -> String {
    let s = sig4(x);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Figure T5: the pendulum's mechanical energy against time, with the steps where the floor
/// acted.
pub fn pendulum_energy(run: &PendulumRun) -> Result<ChapterFigure> {
    let mut panel = Panel::new(Axis::linear("t (s)"), Axis::linear("mechanical energy (J)"));
    panel.series.push(Series::line(
        format!("RK4, h = {} s", short(run.dt)),
        run.energy.clone(),
        BLACK,
    ));
    panel.series.push(
        Series::points(
            "a step in which the floor acted",
            run.contacts.iter().map(|c| (c.0, c.3)).collect(),
            RED,
        )
        .with_marker(Marker::Circle, true)
        .with_marker_scale(0.6),
    );
    let mut csv = CsvFile::new(&[
        "series",
        "time_s",
        "particle",
        "energy_j",
        "energy_before_step_j",
    ]);
    for (t, e) in &run.energy {
        csv.record(vec![
            "energy".to_string(),
            full(*t),
            String::new(),
            full(*e),
            String::new(),
        ]);
    }
    for (t, i, before, after) in &run.contacts {
        csv.record(vec![
            "contact".to_string(),
            full(*t),
            i.to_string(),
            full(*after),
            full(*before),
        ]);
    }
    ChapterFigure::new(
        "tutorial_pendulum_energy",
        &Chart::new(COLUMN_WIDTH_MM, 70.0, vec![panel]),
        csv.text(),
    )
}

/// Figure T6: (a) the centre of mass's height against its closed form, with the first
/// contact; (b) the cloth at the saved frames up to the first contact, side view, to scale.
pub fn cloth_drop(run: &ClothDropRun) -> Result<ChapterFigure> {
    let mut fall = Panel::new(
        Axis::linear("t (s)"),
        Axis::linear("height of the centre of mass (m)"),
    );
    fall.series
        .push(Series::line("RK4, Δt = 1e-3 s", run.centre.clone(), BLUE).with_weight(1.6));
    fall.series.push(
        Series::line("closed form (drag fall)", run.closed_centre.clone(), BLACK)
            .with_line(Line::Dashed),
    );
    fall.series.push(
        Series::line(
            format!("first contact, t = {} s", sig4(run.first_contact)),
            vec![
                (run.first_contact, 0.0),
                (run.first_contact, run.params.height),
            ],
            GREY,
        )
        .with_line(Line::Dotted),
    );
    // (b) The saved frames up to the first contact in side view, to scale: the cloth falls
    // flat and touches the floor flat (at first contact every particle lies at y = 0, so that
    // frame alone drew an empty line). Frames in time order on one sequential scale, each
    // named above its line.
    let mut frames: Vec<&(f64, Vec<Vec3>)> = run
        .frames
        .iter()
        .filter(|(t, _)| *t <= run.first_contact)
        .collect();
    frames.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut side = Panel::new(Axis::linear("x (m)"), Axis::linear("height y (m)"));
    let width_m = (run.params.cloth.nx - 1) as f64 * run.params.cloth.spacing;
    side.series.push(
        Series::line("floor", vec![(-0.1, 0.0), (width_m + 0.1, 0.0)], GREY)
            .with_weight(2.0)
            .with_line(Line::Dashed),
    );
    let palette = TIME_ORDER;
    for (n, (t, x)) in frames.iter().enumerate() {
        let colour = palette[n * (palette.len() - 1) / (frames.len() - 1).max(1)];
        // Every spring in one series, a NaN point between springs.
        let springs: Vec<(f64, f64)> = run
            .springs
            .iter()
            .flat_map(|&(a, b)| [(x[a].x, x[a].y), (x[b].x, x[b].y), (f64::NAN, f64::NAN)])
            .collect();
        side.series
            .push(Series::line("", springs, colour).with_weight(1.2));
        let top = x.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
        let contact = if *t == run.first_contact {
            ", first contact"
        } else {
            ""
        };
        // A frame's time accumulated in steps (0.7000000000000001) printed to the millisecond.
        let time = if *t == run.first_contact {
            sig4(*t)
        } else {
            short((*t * 1e3).round() / 1e3)
        };
        side.label(
            (0.0, top),
            (0.0, 4.0),
            Align::Start,
            format!("t = {time} s{contact}"),
            colour,
        );
    }
    let mut csv = CsvFile::new(&["time_s", "particle", "x_m", "y_m", "z_m"]);
    for (t, x) in &run.frames {
        for (i, p) in x.iter().enumerate() {
            csv.record(vec![
                full(*t),
                i.to_string(),
                full(p.x),
                full(p.y),
                full(p.z),
            ]);
        }
    }
    ChapterFigure::new(
        "tutorial_cloth_drop",
        &Chart::new(FULL_WIDTH_MM, 85.0, vec![fall, side]),
        csv.text(),
    )
}

/// (tolerance, f(run)) of each run.
fn against_tolerance(runs: &[AdaptiveRun], f: impl Fn(&AdaptiveRun) -> f64) -> Vec<(f64, f64)> {
    runs.iter().map(|r| (r.tolerance, f(r))).collect()
}

/// Figure T7: (a) the adaptive integrator's error and (b) its work against the tolerance.
pub fn adaptive(study: &AdaptiveStudy) -> Result<ChapterFigure> {
    let mut error = Panel::new(Axis::log("tolerance T"), Axis::log("error (m)"));
    error.series.push(
        Series::line(
            "error = T",
            study
                .pendulum
                .iter()
                .map(|r| (r.tolerance, r.tolerance))
                .collect(),
            GREY,
        )
        .with_line(Line::Dashed),
    );
    error.series.push(
        Series::line(
            format!(
                "pendulum, against the run at T = {}",
                typeset(REFERENCE_TOLERANCE)
            ),
            against_tolerance(&study.pendulum, |r| r.error),
            PURPLE,
        )
        .with_marker(Marker::Circle, true),
    );
    error.series.push(
        Series::line(
            "dropped particle, against its closed form",
            against_tolerance(&study.drop, |r| r.error),
            GREEN,
        )
        .with_marker(Marker::Square, true),
    );
    let mut work = Panel::new(
        Axis::log("tolerance T"),
        Axis::log("force evaluations, steps"),
    );
    work.series.push(
        Series::line(
            "pendulum: force evaluations",
            against_tolerance(&study.pendulum, |r| r.stats.evaluations as f64),
            PURPLE,
        )
        .with_marker(Marker::Circle, true),
    );
    work.series.push(
        Series::line(
            "pendulum: accepted steps",
            against_tolerance(&study.pendulum, |r| r.stats.accepted as f64),
            PURPLE,
        )
        .with_line(Line::Dashed)
        .with_marker(Marker::Circle, false),
    );
    work.series.push(
        Series::line(
            "dropped particle: force evaluations",
            against_tolerance(&study.drop, |r| r.stats.evaluations as f64),
            GREEN,
        )
        .with_marker(Marker::Square, true),
    );
    let mut csv = CsvFile::new(&[
        "scene",
        "tolerance_m",
        "error_m",
        "accepted",
        "rejected_error",
        "rejected_contact",
        "evaluations",
        "smallest_step_s",
        "largest_step_s",
    ]);
    for (scene, runs) in [
        ("pendulum", &study.pendulum),
        ("dropped_particle", &study.drop),
    ] {
        for r in runs {
            let s = r.stats;
            csv.record(vec![
                scene.to_string(),
                full(r.tolerance),
                full(r.error),
                s.accepted.to_string(),
                s.rejected_error.to_string(),
                s.rejected_contact.to_string(),
                s.evaluations.to_string(),
                full(s.smallest_step),
                full(s.largest_step),
            ]);
        }
    }
    ChapterFigure::new(
        "tutorial_adaptive",
        &Chart::new(FULL_WIDTH_MM, 75.0, vec![error, work]),
        csv.text(),
    )
}

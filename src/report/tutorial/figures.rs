//! The tutorial chapter's figures (SVG, drawn with the report's plot layer) and the CSV of the
//! points each one draws. Geometry (the pendulum's frames, the falling cloth) is drawn to
//! scale.

use super::studies::{
    AdaptiveStudy, ClothDropRun, ConvergenceSeries, DragFall, EnergyRun, Method, PendulumRun,
    SpringPairRun, CONVERGENCE_TIME, FORCE_DT, PAIR_DT, REFERENCE_TOLERANCE,
};
use crate::error::Result;
use crate::particles::Integrator;
use crate::report::format::{full, short, sig, sig4};
use crate::report::plot::{height_to_scale, svg, Axis, Legend, Line, Marker, Panel, Series};
use crate::system::Vec3;
use plotters::style::RGBColor;

/// One figure of the chapter: file stem (`tutorial_convergence`), SVG and CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct TutorialFigure {
    pub stem: &'static str,
    pub svg: String,
    pub csv: String,
}

const PANEL: (u32, u32) = (760, 520);
const HALF: (u32, u32) = (600, 500);
const THIRD: (u32, u32) = (480, 440);

const BLACK: RGBColor = RGBColor(0, 0, 0);
const GREY: RGBColor = RGBColor(150, 150, 150);
const RED: RGBColor = RGBColor(200, 30, 30);
const BLUE: RGBColor = RGBColor(33, 113, 181);
const GREEN: RGBColor = RGBColor(35, 139, 69);
const PURPLE: RGBColor = RGBColor(117, 60, 160);

/// Colour and marker of each method, the same in every figure.
pub fn style(method: Method) -> (RGBColor, Marker) {
    match method {
        Method::Tutorial(Integrator::ExplicitEuler) => (RED, Marker::Triangle),
        Method::Tutorial(Integrator::SymplecticEuler) => (BLUE, Marker::Circle),
        Method::Tutorial(Integrator::Rk4) => (GREEN, Marker::Square),
        Method::BackwardEuler => (BLACK, Marker::Cross),
        Method::DormandPrince => (PURPLE, Marker::Circle),
    }
}

/// Figure: global error against h, log-log.
pub fn convergence(series: &[ConvergenceSeries]) -> Result<TutorialFigure> {
    let mut panel = Panel::new(
        format!("global error at t = {} s", full(CONVERGENCE_TIME)),
        Axis::log("h (s)"),
        Axis::log("phase-plane error (m)"),
    );
    panel.legend = Legend::LowerRight;
    let mut csv = String::from("method,zeta,h_s,error_m\n");
    for s in series {
        let (color, marker) = style(s.method);
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
            .with_marker(marker, true),
        );
        for (h, e) in &s.points {
            csv += &format!(
                "{},{},{},{}\n",
                s.method.id(),
                full(s.zeta),
                full(*h),
                full(*e)
            );
        }
    }
    Ok(TutorialFigure {
        stem: "tutorial_convergence",
        svg: svg(&[panel], PANEL)?,
        csv,
    })
}

/// Figure: energy of the undamped oscillator against time just below and above each limit.
pub fn stability_energy(runs: &[EnergyRun]) -> Result<TutorialFigure> {
    let mut panels = Vec::new();
    let mut csv = String::from("integrator,h_omega,periods,energy_ratio\n");
    for integrator in Integrator::ALL {
        let mut panel = Panel::new(
            integrator.to_string(),
            Axis::linear("t ω / 2π (periods)"),
            Axis::log("E / E₀").range(1e-8, 1e8),
        );
        panel.legend = Legend::UpperLeft;
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
                csv += &format!(
                    "{},{},{},{}\n",
                    integrator.key(),
                    full(run.h_omega),
                    full(*t),
                    full(*e)
                );
            }
        }
        panels.push(panel);
    }
    Ok(TutorialFigure {
        stem: "tutorial_stability_energy",
        svg: svg(&panels, THIRD)?,
        csv,
    })
}

/// Figure: the drag fall and the damped spring pair against their closed forms.
pub fn forces(drag: &DragFall, pair: &SpringPairRun) -> Result<TutorialFigure> {
    let mut left = Panel::new(
        "(a) falling with drag f = −k_f v",
        Axis::linear("t (s)"),
        Axis::linear("downward speed (m/s)"),
    );
    left.legend = Legend::LowerRight;
    let closed: Vec<(f64, f64)> = drag.samples.iter().map(|s| (s.0, s.2)).collect();
    let ours: Vec<(f64, f64)> = drag.samples.iter().map(|s| (s.0, s.1)).collect();
    let t_end = drag.samples.last().map_or(0.0, |s| s.0);
    left.series.push(Series::line(
        "(m g / k_f)(1 − e^(−k_f t / m))",
        closed,
        BLACK,
    ));
    left.series.push(
        Series::line(format!("RK4, h = {} s", short(FORCE_DT)), ours, GREEN)
            .with_line(Line::None)
            .with_marker(Marker::Circle, false),
    );
    left.series.push(
        Series::line(
            format!("terminal m g / k_f = {} m/s", sig4(drag.terminal)),
            vec![(0.0, drag.terminal), (t_end, drag.terminal)],
            GREY,
        )
        .with_line(Line::Dashed),
    );
    let mut right = Panel::new(
        "(b) two particles on a damped spring",
        Axis::linear("t (s)"),
        Axis::linear("stretch |x_a − x_b| − r (m)"),
    );
    let p = pair.pair;
    let closed: Vec<(f64, f64)> = pair.samples.iter().map(|s| (s.0, s.2)).collect();
    let ours: Vec<(f64, f64)> = pair.samples.iter().step_by(5).map(|s| (s.0, s.1)).collect();
    let step = pair.samples.get(1).map_or(0.0, |s| s.0);
    let envelope = |sign: f64| -> Vec<(f64, f64)> {
        pair.samples
            .iter()
            .map(|s| (s.0, sign * p.stretch * (-p.decay_rate() * s.0).exp()))
            .collect()
    };
    right
        .series
        .push(Series::line("closed form", closed, BLACK).with_width(1));
    right.series.push(
        Series::line(
            format!(
                "RK4, h = {} s (every {} s)",
                short(PAIR_DT),
                short(5.0 * step)
            ),
            ours,
            GREEN,
        )
        .with_line(Line::None)
        .with_marker(Marker::Circle, false)
        .with_marker_size(2),
    );
    right
        .series
        .push(Series::line("± u₀ e^(−k_d t / 2μ)", envelope(1.0), GREY).with_line(Line::Dashed));
    right
        .series
        .push(Series::line("", envelope(-1.0), GREY).with_line(Line::Dashed));
    let mut csv = String::from("study,time_s,ours,closed_form\n");
    for (t, a, b) in &drag.samples {
        csv += &format!(
            "drag_speed_m_per_s,{},{},{}\n",
            full(*t),
            full(*a),
            full(*b)
        );
    }
    for (t, a, b) in &pair.samples {
        csv += &format!("spring_stretch_m,{},{},{}\n", full(*t), full(*a), full(*b));
    }
    Ok(TutorialFigure {
        stem: "tutorial_forces",
        svg: svg(&[left, right], HALF)?,
        csv,
    })
}

/// A chain of particles as a polyline with markers, shifted by `offset`.
fn chain(points: &[Vec3], offset: (f64, f64)) -> Vec<(f64, f64)> {
    points
        .iter()
        .map(|p| (p.x + offset.0, p.y + offset.1))
        .collect()
}

/// A horizontal scale bar of `length` m at `at`.
fn scale_bar(panel: &mut Panel, at: (f64, f64), length: f64) {
    panel
        .series
        .push(Series::line("", vec![at, (at.0 + length, at.1)], BLACK).with_width(3));
    panel.label((at.0, at.1 + 0.35), format!("{} m", full(length)), BLACK);
}

/// Figure: the pendulum's six frames, to scale, in two rows.
pub fn pendulum_frames(run: &PendulumRun) -> Result<TutorialFigure> {
    let reach = run.params.particles as f64 * run.params.segment_length;
    let (cell_w, cell_h) = (2.0 * reach + 0.6, run.params.pivot_height + 1.0);
    let mut panel = Panel::new(
        "the pendulum bouncing on the floor (to scale)",
        Axis::linear("").range(-0.3, 3.0 * cell_w - 0.3),
        Axis::linear("").range(-0.6, 2.0 * cell_h - 0.3),
    );
    panel.mesh = false;
    let mut csv = String::from("time_s,particle,x_m,y_m\n");
    for (k, (t, x)) in run.frames.iter().enumerate() {
        let (col, row) = (k % 3, 1 - k / 3);
        let offset = (col as f64 * cell_w + reach + 0.3, row as f64 * cell_h);
        let floor_y = offset.1;
        panel.series.push(
            Series::line(
                "",
                vec![
                    (offset.0 - reach - 0.2, floor_y),
                    (offset.0 + reach + 0.2, floor_y),
                ],
                GREY,
            )
            .with_width(3),
        );
        panel.series.push(
            Series::line(
                if k == 0 { "chain" } else { "" },
                chain(&x[1..], offset),
                BLUE,
            )
            .with_marker(Marker::Circle, true),
        );
        panel.series.push(
            Series::line(
                if k == 0 { "pivot (anchored)" } else { "" },
                chain(&x[..1], offset),
                RED,
            )
            .with_line(Line::None)
            .with_marker(Marker::Square, true),
        );
        panel
            .series
            .push(Series::line("", chain(&x[..2], offset), BLUE).with_width(2));
        panel.label(
            (offset.0 - reach, floor_y + run.params.pivot_height + 0.6),
            format!("({}) t = {} s", k + 1, sig_short(*t)),
            BLACK,
        );
        for (i, p) in x.iter().enumerate() {
            csv += &format!("{},{i},{},{}\n", full(*t), full(p.x), full(p.y));
        }
    }
    scale_bar(&mut panel, (0.0, -0.45), 1.0);
    let width = 1000;
    let height = height_to_scale(&panel, width)?;
    Ok(TutorialFigure {
        stem: "tutorial_pendulum_frames",
        svg: svg(&[panel], (width, height))?,
        csv,
    })
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

/// Figure: the pendulum's mechanical energy against time, with the steps where the floor
/// acted.
pub fn pendulum_energy(run: &PendulumRun) -> Result<TutorialFigure> {
    let mut panel = Panel::new(
        "pendulum: mechanical energy",
        Axis::linear("t (s)"),
        Axis::linear("E = kinetic + gravitational + elastic (J)"),
    );
    panel.series.push(Series::line(
        format!("RK4, h = {} s", short(run.dt)),
        run.energy.clone(),
        BLACK,
    ));
    panel.series.push(
        Series::line(
            "a step in which the floor acted",
            run.contacts.iter().map(|c| (c.0, c.3)).collect(),
            RED,
        )
        .with_line(Line::None)
        .with_marker(Marker::Circle, true)
        .with_marker_size(2),
    );
    let mut csv = String::from("series,time_s,particle,energy_J,energy_before_step_J\n");
    for (t, e) in &run.energy {
        csv += &format!("energy,{},,{},\n", full(*t), full(*e));
    }
    for (t, i, before, after) in &run.contacts {
        csv += &format!(
            "contact,{},{i},{},{}\n",
            full(*t),
            full(*after),
            full(*before)
        );
    }
    Ok(TutorialFigure {
        stem: "tutorial_pendulum_energy",
        svg: svg(&[panel], PANEL)?,
        csv,
    })
}

/// Figure: the cloth falling 10 m, side view to scale, each frame shifted along x.
pub fn cloth_drop(run: &ClothDropRun) -> Result<TutorialFigure> {
    let width_m = (run.params.cloth.nx - 1) as f64 * run.params.cloth.spacing;
    let shift = width_m + 0.6;
    let frames = run.frames.len() as f64;
    let mut panel = Panel::new(
        "the cloth dropped from 10 m (side view, to scale)",
        Axis::linear(format!("x (m), frame k shifted by {} m", sig_short(shift)))
            .range(-0.4, frames * shift),
        Axis::linear("height y (m)").range(-0.5, run.params.height + 0.8),
    );
    panel
        .series
        .push(Series::line("floor", vec![(-0.4, 0.0), (frames * shift, 0.0)], GREY).with_width(3));
    let mut csv = String::from("time_s,particle,x_m,y_m,z_m\n");
    for (k, (t, x)) in run.frames.iter().enumerate() {
        let dx = k as f64 * shift;
        for &(a, b) in &run.springs {
            panel.series.push(
                Series::line("", vec![(x[a].x + dx, x[a].y), (x[b].x + dx, x[b].y)], BLUE)
                    .with_width(1),
            );
        }
        let top = x.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
        panel.label((dx, top + 0.7), format!("t = {} s", sig_short(*t)), BLACK);
        for (i, p) in x.iter().enumerate() {
            csv += &format!(
                "{},{i},{},{},{}\n",
                full(*t),
                full(p.x),
                full(p.y),
                full(p.z)
            );
        }
    }
    let width = 700;
    let height = height_to_scale(&panel, width)?;
    Ok(TutorialFigure {
        stem: "tutorial_cloth_drop",
        svg: svg(&[panel], (width, height))?,
        csv,
    })
}

/// Figure: the adaptive integrator's error and work against the tolerance.
pub fn adaptive(study: &AdaptiveStudy) -> Result<TutorialFigure> {
    let mut error = Panel::new(
        "(a) error against tolerance",
        Axis::log("tolerance T"),
        Axis::log("error (m)"),
    );
    error.legend = Legend::LowerRight;
    let tolerances: Vec<f64> = study.pendulum.iter().map(|r| r.tolerance).collect();
    let points = |runs: &[super::studies::AdaptiveRun],
                  f: &dyn Fn(&super::studies::AdaptiveRun) -> f64| {
        runs.iter().map(|r| (r.tolerance, f(r))).collect::<Vec<_>>()
    };
    error.series.push(
        Series::line(
            format!("pendulum, against T = {}", sig(REFERENCE_TOLERANCE, 1)),
            points(&study.pendulum, &|r| r.error),
            PURPLE,
        )
        .with_marker(Marker::Circle, true),
    );
    error.series.push(
        Series::line(
            "dropped particle, against the closed form",
            points(&study.drop, &|r| r.error),
            GREEN,
        )
        .with_marker(Marker::Square, true),
    );
    error.series.push(
        Series::line(
            "error = T",
            tolerances.iter().map(|&t| (t, t)).collect(),
            GREY,
        )
        .with_line(Line::Dashed),
    );
    let mut work = Panel::new(
        "(b) work against tolerance",
        Axis::log("tolerance T"),
        Axis::log("count"),
    );
    work.series.push(
        Series::line(
            "pendulum: force evaluations",
            points(&study.pendulum, &|r| r.stats.evaluations as f64),
            PURPLE,
        )
        .with_marker(Marker::Circle, true),
    );
    work.series.push(
        Series::line(
            "pendulum: accepted steps",
            points(&study.pendulum, &|r| r.stats.accepted as f64),
            PURPLE,
        )
        .with_line(Line::Dashed)
        .with_marker(Marker::Circle, false),
    );
    work.series.push(
        Series::line(
            "dropped particle: force evaluations",
            points(&study.drop, &|r| r.stats.evaluations as f64),
            GREEN,
        )
        .with_marker(Marker::Square, true),
    );
    let mut csv = String::from(
        "scene,tolerance,error_m,accepted,rejected_error,rejected_contact,evaluations,smallest_step_s,largest_step_s\n",
    );
    for (scene, runs) in [
        ("pendulum", &study.pendulum),
        ("dropped_particle", &study.drop),
    ] {
        for r in runs {
            let s = r.stats;
            csv += &format!(
                "{scene},{},{},{},{},{},{},{},{}\n",
                full(r.tolerance),
                full(r.error),
                s.accepted,
                s.rejected_error,
                s.rejected_contact,
                s.evaluations,
                full(s.smallest_step),
                full(s.largest_step)
            );
        }
    }
    Ok(TutorialFigure {
        stem: "tutorial_adaptive",
        svg: svg(&[error, work], HALF)?,
        csv,
    })
}

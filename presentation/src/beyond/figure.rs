//! Figure B1 (section 10): every newer solver's gap to the converged stage against its
//! iterations, in small multiples by family, with the tolerance line.

use super::*;
use crate::benchmark::families::FAMILIES;
use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::full;
use crate::plot::{Axis, Chart, Line, Panel, Series, FULL_WIDTH_MM};
use crate::style::{coinciding_groups, colour, family_marker, solver_line};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::beyond::{ConvergenceCurve, Start, CONVERGENCE_ITERATIONS};

/// The rows of Figure B1, each with its short heading: the families of the work-precision
/// figures, the damped pair joining the last.
pub(super) fn b1_families() -> Vec<(&'static str, Vec<SolverId>)> {
    let names = ["thesis's solvers", "accelerated", "substeps, VBD, damped"];
    let damped = [SolverId::DampedBackwardEuler, SolverId::DampedAdmm];
    FAMILIES
        .iter()
        .zip(names)
        .enumerate()
        .map(|(i, ((_, members), name))| {
            let mut members = members.to_vec();
            if i + 1 == FAMILIES.len() {
                members.extend(damped);
            }
            (name, members)
        })
        .collect()
}

/// Figure B1 marks every this many iterations of a curve (its marker tells the solvers of a
/// family apart besides colour and dash).
pub(super) const B1_MARKER_EVERY: usize = 20;

/// The tolerance line of Figure B1.
pub(super) const TOLERANCE_GREY: crate::plot::Rgb = crate::plot::Rgb(120, 120, 120);

impl BeyondChapter {
    /// The chapter's figure: the convergence curves at [`CONVERGENCE_DT`],
    /// [`CONVERGENCE_STIFFNESS`], small multiples: a row per family of solvers
    /// (`b1_families`), a column per start, the tolerance [`GAP_TOLERANCE`] drawn in each;
    /// curves that coincide are drawn once and named together.
    pub fn figures(&self) -> Result<Vec<ChapterFigure>> {
        let mut panels = Vec::new();
        let mut csv = CsvFile::new(&["solver", "start", "iteration", "gap_m"]);
        for curve in Start::ALL.iter().flat_map(|&s| self.figure_curves(s)) {
            for (i, g) in curve.gaps.iter().enumerate() {
                if let Some(g) = g {
                    csv.record(vec![
                        curve.spec.id.to_string(),
                        curve.start.id().to_string(),
                        (i + 1).to_string(),
                        full(g.max(GAP_FLOOR)),
                    ]);
                }
            }
        }
        for (family, members) in b1_families() {
            for start in Start::ALL {
                let mut panel = Panel::new(
                    Axis::linear("iterations m"),
                    Axis::log("gap (m)").range(GAP_FLOOR / 3.0, 1e-2),
                );
                panel.heading = format!("{family}, {}", start.label());
                let curves: Vec<&ConvergenceCurve> = self
                    .figure_curves(start)
                    .filter(|c| members.contains(&c.spec.id))
                    .collect();
                let points: Vec<Vec<(f64, f64)>> = curves
                    .iter()
                    .map(|c| {
                        c.gaps
                            .iter()
                            .enumerate()
                            .filter_map(|(i, g)| g.map(|g| ((i + 1) as f64, g.max(GAP_FLOOR))))
                            .collect()
                    })
                    .collect();
                panel.series.push(
                    Series::line(
                        "1e-6 m",
                        vec![
                            (1.0, GAP_TOLERANCE),
                            (CONVERGENCE_ITERATIONS as f64, GAP_TOLERANCE),
                        ],
                        TOLERANCE_GREY,
                    )
                    .with_line(Line::Dotted),
                );
                for group in coinciding_groups(&points) {
                    let id = curves[group[0]].spec.id;
                    let names: Vec<&str> = group
                        .iter()
                        .map(|&i| curves[i].spec.id.display_name())
                        .collect();
                    panel.series.push(
                        Series::line(names.join(" ≈ "), points[group[0]].clone(), colour(id, 0))
                            .with_line(solver_line(id))
                            .with_marker(family_marker(id), true)
                            .with_marker_every(B1_MARKER_EVERY),
                    );
                }
                panels.push(panel);
            }
        }
        let mut chart = Chart::new(FULL_WIDTH_MM, 230.0, panels);
        chart.columns = Start::ALL.len();
        Ok(vec![ChapterFigure::new(
            "beyond_convergence",
            &chart,
            csv.text(),
        )?])
    }

    pub(super) fn figure_curves(&self, start: Start) -> impl Iterator<Item = &ConvergenceCurve> {
        self.curves.iter().filter(move |c| {
            c.start == start && c.dt_s == CONVERGENCE_DT && c.stiffness == CONVERGENCE_STIFFNESS
        })
    }
}

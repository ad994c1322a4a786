//! The continuum chapter's figures: the soft beam's axis under each energy (to scale), Cook's
//! convergence, and the membrane's centre line beside the spring sheet's (to scale).

use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::full;
use crate::plot::{Axis, Chart, Line, Marker, Panel, Rgb, Series, FULL_WIDTH_MM};
use crate::sheet::SheetChapter;
use crate::style::{BLACK, GREY};
use crate::tables::stiffness_label;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::scene::SHEET_NODES_PER_SIDE;
use mass_spring_solvers::studies::continuum::statics::COOK_LITERATURE;
use mass_spring_solvers::studies::continuum::ContinuumStatics;

/// The figures' file stems.
pub const ENERGIES_FIGURE: &str = "continuum_energies";
pub const COOK_FIGURE: &str = "continuum_cook";
pub const MEMBRANE_FIGURE: &str = "continuum_membrane_sheet";

/// Each energy's colour, in [`EnergyKind::ALL`]'s order (Okabe-Ito).
const ENERGY_COLOURS: [Rgb; 5] = [
    Rgb(213, 94, 0),
    Rgb(0, 114, 178),
    Rgb(0, 158, 115),
    Rgb(204, 121, 167),
    Rgb(230, 159, 0),
];

/// Each energy's marker, in [`EnergyKind::ALL`]'s order.
const ENERGY_MARKERS: [Marker; 5] = [
    Marker::Cross,
    Marker::Circle,
    Marker::Triangle,
    Marker::Square,
    Marker::Circle,
];

fn energy_index(energy: EnergyKind) -> usize {
    EnergyKind::ALL
        .iter()
        .position(|&e| e == energy)
        .expect("every energy is in ALL")
}

/// Every figure of the chapter.
pub fn all(s: &ContinuumStatics, sheet: &SheetChapter) -> Result<Vec<ChapterFigure>> {
    Ok(vec![energies(s)?, cook(s)?, membrane_and_sheet(s, sheet)?])
}

/// The soft beam's axis at each energy's equilibrium, to scale.
fn energies(s: &ContinuumStatics) -> Result<ChapterFigure> {
    let mut csv = CsvFile::new(&["energy", "node", "x_m", "y_m"]);
    let mut panel = Panel::new(Axis::linear("x (m)"), Axis::linear("y (m)"));
    panel.equal_aspect = true;
    let rest: Vec<(f64, f64)> = s.soft_beam[0]
        .axis
        .iter()
        .enumerate()
        .map(|(i, _)| (i as f64 / (s.soft_beam[0].axis.len() - 1) as f64, 0.0))
        .collect();
    panel
        .series
        .push(Series::line("rest", rest, GREY).with_line(Line::Dotted));
    for b in &s.soft_beam {
        let k = energy_index(b.energy);
        for (i, p) in b.axis.iter().enumerate() {
            csv.record(vec![
                b.energy.name().into(),
                i.to_string(),
                full(p[0]),
                full(p[1]),
            ]);
        }
        panel.series.push(
            Series::line(
                b.energy.name(),
                b.axis.iter().map(|p| (p[0], p[1])).collect(),
                ENERGY_COLOURS[k],
            )
            .with_marker(ENERGY_MARKERS[k], k % 2 == 0)
            .with_marker_every(4),
        );
    }
    ChapterFigure::new(
        ENERGIES_FIGURE,
        &Chart::new(FULL_WIDTH_MM, 90.0, vec![panel]),
        csv.text(),
    )
}

/// u_y at (48, 52) and at P2 against N, and the literature's value.
fn cook(s: &ContinuumStatics) -> Result<ChapterFigure> {
    let mut csv = CsvFile::new(&["n", "u_y_48_52", "u_y_48_60"]);
    for c in &s.cook {
        csv.record(vec![c.n.to_string(), full(c.mid), full(c.corner)]);
    }
    let mut panel = Panel::new(Axis::log("N (elements a side)"), Axis::linear("u_y"));
    let ends = (s.cook[0].n as f64, s.cook[s.cook.len() - 1].n as f64);
    panel.series.push(
        Series::line(
            format!("literature, (48, 52): {COOK_LITERATURE}"),
            vec![(ends.0, COOK_LITERATURE), (ends.1, COOK_LITERATURE)],
            BLACK,
        )
        .with_line(Line::Dashed),
    );
    panel.series.push(
        Series::line(
            "u_y(48, 52)",
            s.cook.iter().map(|c| (c.n as f64, c.mid)).collect(),
            ENERGY_COLOURS[1],
        )
        .with_marker(Marker::Circle, true),
    );
    panel.series.push(
        Series::line(
            "u_y(48, 60), the corner P2",
            s.cook.iter().map(|c| (c.n as f64, c.corner)).collect(),
            ENERGY_COLOURS[0],
        )
        .with_marker(Marker::Square, false),
    );
    ChapterFigure::new(
        COOK_FIGURE,
        &Chart::new(FULL_WIDTH_MM, 80.0, vec![panel]),
        csv.text(),
    )
}

/// The centre lines of the spring sheet and of the stable neo-Hookean membrane, to scale.
fn membrane_and_sheet(s: &ContinuumStatics, sheet: &SheetChapter) -> Result<ChapterFigure> {
    let n = SHEET_NODES_PER_SIDE;
    let row = (n - 1) / 2;
    let mut csv = CsvFile::new(&["series", "stiffness_n_per_m", "node", "x_m", "y_m"]);
    let mut panel = Panel::new(Axis::linear("x (m)"), Axis::linear("y (m)"));
    panel.equal_aspect = true;
    for (k, (stiffness, _, e)) in sheet
        .equilibria
        .iter()
        .filter(|(_, nodes, _)| *nodes == n)
        .enumerate()
    {
        let springs: Vec<(f64, f64)> = (0..n)
            .map(|i| (e.x[i * n + row].x, e.x[i * n + row].y))
            .collect();
        let Some(m) = s
            .membranes
            .iter()
            .find(|m| m.stiffness == *stiffness && m.energy == EnergyKind::StableNeoHookean)
        else {
            continue;
        };
        let continuum: Vec<(f64, f64)> = m.centre_line.iter().map(|p| (p[0], p[1])).collect();
        for (name, points) in [("spring sheet", &springs), ("membrane", &continuum)] {
            for (i, p) in points.iter().enumerate() {
                csv.record(vec![
                    name.into(),
                    full(*stiffness),
                    i.to_string(),
                    full(p.0),
                    full(p.1),
                ]);
            }
        }
        let label = stiffness_label(*stiffness);
        panel.series.push(
            Series::line(
                format!("spring sheet, k = {label} N/m"),
                springs,
                ENERGY_COLOURS[k],
            )
            .with_marker(Marker::Circle, true),
        );
        panel.series.push(
            Series::line(
                format!("membrane, k = {label} N/m"),
                continuum,
                ENERGY_COLOURS[k],
            )
            .with_line(Line::Dashed)
            .with_marker(Marker::Cross, false),
        );
    }
    ChapterFigure::new(
        MEMBRANE_FIGURE,
        &Chart::new(FULL_WIDTH_MM, 80.0, vec![panel]),
        csv.text(),
    )
}

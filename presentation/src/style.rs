//! Each solver's look in every figure (colour, line style, markers, one (colour, marker, dash)
//! triple per solver) and when two series coincide on a log axis, so that they are drawn once.

use crate::plot::{Line, Marker, Rgb};
use mass_spring_solvers::solvers::registry::SolverId;

/// Two series coincide in a drawing when every pair of their points is closer than this on a
/// log axis, decades (12 %; under a third of a marker on the error plots' ten decades).
pub const COINCIDE_DECADES: f64 = 0.05;

pub const BLACK: Rgb = Rgb(0, 0, 0);
pub const GREY: Rgb = Rgb(120, 120, 120);
pub const RED: Rgb = Rgb(200, 30, 30);
pub const BLUE: Rgb = Rgb(33, 113, 181);
pub const GREEN: Rgb = Rgb(35, 139, 69);

/// Instants in time order, earliest darkest: five steps of viridis, its light yellow end left
/// out (it would vanish on white).
pub const TIME_ORDER: [Rgb; 5] = [
    Rgb(68, 1, 84),
    Rgb(59, 82, 139),
    Rgb(33, 145, 140),
    Rgb(53, 183, 121),
    Rgb(144, 200, 60),
];

/// The colour of a solver at its `index`-th iteration count (0 = fewest, darkest).
pub fn colour(solver: SolverId, index: usize) -> Rgb {
    let shades: [Rgb; 3] = match solver {
        SolverId::BackwardEuler => [BLACK, BLACK, BLACK],
        SolverId::Xpbd => [Rgb(8, 48, 107), Rgb(33, 113, 181), Rgb(107, 174, 214)],
        SolverId::FastMassSpring => [Rgb(127, 39, 4), Rgb(217, 72, 1), Rgb(253, 141, 60)],
        SolverId::AdmmPd => [Rgb(0, 68, 27), Rgb(35, 139, 69), Rgb(116, 196, 118)],
        // The solvers the thesis's figures do not show: one Okabe-Ito colour each.
        other => [OTHER_SOLVERS[registry_index(other) % OTHER_SOLVERS.len()]; 3],
    };
    shades[index.min(2)]
}

/// The marker of a solver in a figure of many solvers: the thesis's four their own, the others
/// by registry order.
pub fn solver_marker(solver: SolverId) -> Marker {
    match solver {
        SolverId::BackwardEuler => Marker::Square,
        SolverId::Xpbd => Marker::Circle,
        SolverId::FastMassSpring => Marker::Triangle,
        SolverId::AdmmPd => Marker::Cross,
        other => [Marker::Circle, Marker::Triangle, Marker::Square][registry_index(other) % 3],
    }
}

/// The line of a solver in a figure of many solvers: solid for Backward Euler and XPBD, dashed
/// for Fast m-s, dotted for ADMM; for the others, with [`colour`], a (colour, line) pair of
/// their own (five colours, then the next line style).
pub fn solver_line(solver: SolverId) -> Line {
    // The thesis's three iterative solvers have a dash of their own besides their hue, so
    // that they stay apart in grey print and under deuteranopia.
    match solver {
        SolverId::FastMassSpring => return Line::Dashed,
        SolverId::AdmmPd => return Line::Dotted,
        _ if SolverId::THESIS_TABLES.contains(&solver) => return Line::Solid,
        _ => {}
    }
    [Line::Solid, Line::Dashed, Line::Dotted][registry_index(solver) / OTHER_SOLVERS.len() % 3]
}

/// A solver's marker in the families of the work-precision figures and Figure B1: with
/// [`solver_line`] a (dash, marker) pair of its own in each family, colour aside.
pub fn family_marker(solver: SolverId) -> Marker {
    [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
    ][registry_index(solver) % 4]
}

/// The colours of the solvers outside the thesis's tables (Okabe-Ito, black and the thesis
/// solvers' hues left out).
const OTHER_SOLVERS: [Rgb; 5] = [
    Rgb(230, 159, 0),
    Rgb(86, 180, 233),
    Rgb(204, 121, 167),
    Rgb(213, 94, 0),
    Rgb(0, 114, 178),
];

/// A solver's position in the registry, which fixes its colour and marker.
fn registry_index(solver: SolverId) -> usize {
    SolverId::ALL
        .iter()
        .position(|&s| s == solver)
        .expect("SolverId::ALL lists every solver")
}

/// The marker of the `index`-th iteration count inside one solver's panel.
pub fn iteration_marker(index: usize) -> Marker {
    [Marker::Circle, Marker::Triangle, Marker::Square][index.min(2)]
}

/// The colour of an evidence class (or reproduction status) in the parity figure: one fixed
/// colour per label (Okabe-Ito), black for a label it does not know.
pub fn class_colour(class: &str) -> Rgb {
    match class {
        "faithful" => Rgb(0, 158, 115),
        "interpretation" => Rgb(86, 180, 233),
        "predicted" => Rgb(0, 114, 178),
        "selected" => Rgb(230, 159, 0),
        "fitted" => Rgb(204, 121, 167),
        "noise-limited" => Rgb(128, 128, 128),
        "unexplained" => Rgb(213, 94, 0),
        _ => BLACK,
    }
}

/// Whether two series coincide in a log-log drawing: same x values, y within
/// [`COINCIDE_DECADES`] at every point.
fn coincide(a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(p, q)| {
            p.0 == q.0
                && p.1 > 0.0
                && q.1 > 0.0
                && (p.1.log10() - q.1.log10()).abs() < COINCIDE_DECADES
        })
}

/// Series that coincide with the first of a group join it, as groups of indices into
/// `series` in order: each group is drawn once and named together.
pub fn coinciding_groups(series: &[Vec<(f64, f64)>]) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, s) in series.iter().enumerate() {
        match groups.iter_mut().find(|g| coincide(&series[g[0]], s)) {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
}

//! What the benchmark's views share (sections 12, 12.7 and 12.8): a case's rows, the families
//! of solvers the work-precision figures group, a front's look and the do-nothing line.

use crate::plot::{Line, Marker, Rgb, Series};
use crate::style::{colour, family_marker, solver_line};
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::sweep::BASELINES;
use mass_spring_solvers::studies::benchmark::Case;

/// The grey of the explicit baselines and the do-nothing line.
pub const BASELINE_GREY: Rgb = Rgb(115, 115, 115);

/// Whether a row belongs to a case.
pub fn of_case(row_scene: &str, row_stiffness: f64, case: Case) -> bool {
    row_scene == case.scene.id() && row_stiffness == case.stiffness
}

/// The families of the work-precision figures' panels, each with the explicit baselines.
pub const FAMILIES: [(&str, &[SolverId]); 3] = [
    (
        "the thesis's solvers",
        &[
            SolverId::BackwardEuler,
            SolverId::Pbd,
            SolverId::Xpbd,
            SolverId::FastMassSpring,
            SolverId::AdmmPd,
        ],
    ),
    (
        "accelerated Projective Dynamics",
        &[
            SolverId::ChebyshevLiu,
            SolverId::ChebyshevAdmm,
            SolverId::AndersonLiu,
            SolverId::AndersonAdmm,
            SolverId::Lbfgs,
        ],
    ),
    (
        "substeps and vertex descent",
        &[SolverId::XpbdSubsteps, SolverId::Vbd],
    ),
];

/// A solver's front in a work-precision figure: its colour, line and marker, or for an
/// explicit baseline grey crosses (RK4 dashed, symplectic Euler dotted).
pub fn front_series(id: SolverId, points: Vec<(f64, f64)>) -> Series {
    if BASELINES.contains(&id) {
        Series::line(id.info().display_name, points, BASELINE_GREY)
            .with_line(if id == SolverId::Rk4 {
                Line::Dashed
            } else {
                Line::Dotted
            })
            .with_marker(Marker::Cross, false)
    } else {
        Series::line(id.info().display_name, points, colour(id, 0))
            .with_line(solver_line(id))
            .with_marker(family_marker(id), true)
    }
}

/// The do-nothing line of a work-precision figure: relative error 1 from cost `lo` to `hi`.
pub fn doing_nothing(lo: f64, hi: f64) -> Series {
    Series::line("doing nothing", vec![(lo, 1.0), (hi, 1.0)], BASELINE_GREY)
        .with_line(Line::Solid)
        .with_weight(0.6)
}

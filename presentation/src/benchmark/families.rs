//! What the benchmark's views share (sections 12, 12.7 and 12.8): a case's rows, the families
//! of solvers the work-precision figures group and the baselines' grey.

use crate::plot::Rgb;
use mass_spring_solvers::solvers::registry::SolverId;
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

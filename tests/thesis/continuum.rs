//! The continuum chapter (section 14), at the tests' size (`ChapterSize::Test`: the stiff
//! beam at r = 1, 2, the energies on the beam at r = 1; Cook N = 2 … 32), computed once with
//! the report's data: every number its prose and tables print is recomputed here from the scenes and Newton directly, not through the study's
//! functions, and each claim of the prose is checked against the recomputed numbers.

use super::report::data;
use mass_spring_report::continuum::{share, ContinuumChapter};
use mass_spring_report::format::sig4;
use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::continuum::scenes::{
    beam, beam_tip_deflection, cook, cook_node, membrane, BEAM_DENSITY, BEAM_LENGTH, BEAM_POISSON,
    BEAM_SIDE,
};
use mass_spring_solvers::model::continuum::statics::static_equilibrium;
use mass_spring_solvers::model::scene::{SHEET_NODES_PER_SIDE, THESIS_GRAVITY};
use mass_spring_solvers::studies::continuum::ChapterSize;

/// The tolerance the recomputation solves to, tighter than the chapter's, so that it is an
/// independent solve and not the same iterate.
const RECOMPUTED: f64 = 1e-10;

/// Beam theory written out again from fem-scenes.md: qL⁴/(8EI) + qL²/(2κGA).
fn theory(youngs: f64) -> f64 {
    let a = BEAM_SIDE * BEAM_SIDE;
    let q = BEAM_DENSITY * THESIS_GRAVITY * a;
    let g = youngs / (2.0 * (1.0 + BEAM_POISSON));
    q * BEAM_LENGTH.powi(4) / (8.0 * youngs * a * a / 12.0)
        + q * BEAM_LENGTH.powi(2) / (2.0 * (5.0 / 6.0) * g * a)
}

/// Relative agreement to 1e-6: equilibria solved to different residuals agree far better.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * b.abs().max(1e-12)
}

/// Notes in `out` a recomputed `value` that `section` does not print.
fn printed(section: &str, out: &mut Vec<String>, value: String, what: &str) {
    if !section.contains(&value) {
        out.push(format!("{what}: {value} not printed"));
    }
}

/// Where the chapter's numbers and the recomputed ones disagree, or where a claim of its prose
/// does not hold on the recomputed numbers; empty if none.
fn disagreements(chapter: &ContinuumChapter) -> Vec<String> {
    let s = &chapter.statics;
    let section = chapter.section(14, &[], &data().sheet);
    let mut out = Vec::new();
    // Cook: u_y at (48, 52) and at P2, rising from below 23.96 at (48, 52).
    let mut mids = Vec::new();
    for c in &s.cook {
        let system = cook(c.n, EnergyKind::Linear, 1.0).unwrap();
        let u = static_equilibrium(&system, RECOMPUTED)
            .unwrap()
            .displacement;
        let mid = u[2 * cook_node(c.n, c.n, c.n / 2) + 1];
        let corner = u[2 * cook_node(c.n, c.n, c.n) + 1];
        if !close(c.mid, mid) || !close(c.corner, corner) {
            out.push(format!(
                "Cook N = {}: {} {} against {mid} {corner}",
                c.n, c.mid, c.corner
            ));
        }
        printed(&section, &mut out, sig4(mid), "Cook's u_y(48, 52)");
        printed(&section, &mut out, sig4(corner), "Cook's u_y(P2)");
        mids.push(mid);
    }
    if mids.windows(2).any(|w| w[1] <= w[0]) || mids.iter().any(|&u| u >= 23.96) {
        out.push(format!("Cook does not rise from below 23.96: {mids:?}"));
    }
    let [.., a, b, c] = mids[..] else {
        unreachable!("the tests' size has five meshes")
    };
    printed(
        &section,
        &mut out,
        format!("{:.2}", ((b - a) / (c - b)).log2()),
        "Cook's order",
    );
    // The stiff beam: below theory, the ratio rising with r.
    let expected = theory(1e9);
    printed(&section, &mut out, sig4(expected), "beam theory");
    let mut ratios = Vec::new();
    for p in &s.stiff_beam {
        let system = beam(p.r, EnergyKind::Linear, 1e9).unwrap();
        let u = static_equilibrium(&system, RECOMPUTED)
            .unwrap()
            .displacement;
        let sag = -beam_tip_deflection(p.r, &u);
        if !close(p.sag, sag) {
            out.push(format!("stiff beam r = {}: {} against {sag}", p.r, p.sag));
        }
        printed(&section, &mut out, sig4(sag), "stiff beam's sag");
        printed(
            &section,
            &mut out,
            sig4(sag / expected),
            "stiff beam's ratio",
        );
        printed(
            &section,
            &mut out,
            share(sag / expected),
            "stiff beam's ratio in the prose",
        );
        ratios.push(sag / expected);
    }
    if ratios.windows(2).any(|w| w[1] <= w[0]) || ratios.iter().any(|&r| r >= 1.0) {
        out.push(format!("the ratio does not rise below 1: {ratios:?}"));
    }
    // The soft beam: each energy's tip (the prose's range is two of them) and the linear
    // energy's volume change, Σ V det F / Σ V − 1.
    for b in &s.soft_beam {
        let system = beam(s.energy_refinement, b.energy, 1e6).unwrap();
        let u = static_equilibrium(&system, RECOMPUTED)
            .unwrap()
            .displacement;
        let tip = beam_tip_deflection(s.energy_refinement, &u);
        if !close(b.tip, tip) {
            out.push(format!(
                "soft beam {}: {} against {tip}",
                b.energy.name(),
                b.tip
            ));
        }
        printed(&section, &mut out, sig4(-tip), "soft beam's sag");
        if b.energy == EnergyKind::Linear {
            let (rest, deformed) = system.elements().iter().fold((0.0, 0.0), |(r, d), e| {
                let j = e.deformation(&u).f().determinant();
                (r + e.measure(), d + e.measure() * j)
            });
            printed(
                &section,
                &mut out,
                share(deformed / rest - 1.0),
                "the linear energy's volume change",
            );
        }
    }
    // The membrane against the spring sheet.
    for (k, n, e) in &data().sheet.equilibria {
        if *n != SHEET_NODES_PER_SIDE {
            continue;
        }
        let system = membrane(*n, EnergyKind::StableNeoHookean, *k).unwrap();
        let u = static_equilibrium(&system, RECOMPUTED)
            .unwrap()
            .displacement;
        let lowest = u
            .iter()
            .skip(1)
            .step_by(3)
            .fold(f64::INFINITY, |m, &y| m.min(y));
        let springs = e.x.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        printed(&section, &mut out, sig4(lowest), "membrane's lowest y");
        printed(
            &section,
            &mut out,
            sig4(lowest / springs),
            "membrane / sheet",
        );
    }
    if s.checks.iter().any(|c| !c.passes()) {
        out.push("a verification check fails".into());
    }
    out
}

/// Every number the chapter prints, recomputed, and every claim of its prose, hold. Wrong
/// implementations it catches (shown below): a Cook value off in its sixth digit, the beam's
/// ratios reordered (a claim that the refined mesh locks more), a failing check.
#[test]
fn the_continuum_chapter_recomputes() {
    let chapter = &data().continuum;
    assert_eq!(chapter.statics.size, ChapterSize::Test);
    let found = disagreements(chapter);
    assert!(found.is_empty(), "{found:#?}");
    let mut wrong = chapter.clone();
    wrong.statics.cook[2].mid *= 1.0 + 1e-5;
    assert!(!disagreements(&wrong).is_empty());
    let mut wrong = chapter.clone();
    wrong.statics.stiff_beam.reverse();
    assert!(!disagreements(&wrong).is_empty());
    let mut wrong = chapter.clone();
    wrong.statics.checks[0].value = 1.0;
    assert!(!disagreements(&wrong).is_empty());
}

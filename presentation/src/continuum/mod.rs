//! The continuum chapter (the thesis's future work, §5: "FEM, por ejemplo", where Liu 2013
//! drops out): the scenes of `docs/fem-scenes.md`, the five energies side by side, the
//! verification checks, Cook's convergence, the stiff beam against beam theory and the
//! membrane beside the spring sheet. The science is
//! [`mass_spring_solvers::studies::continuum`]; this module presents it.

mod figures;

use crate::chapter_figure::ChapterFigure;
use crate::format::{percent, sig, sig4, MarkdownTable};
use crate::output::OutputFile;
use crate::sheet::SheetChapter;
use crate::tables::stiffness_label;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::continuum::scenes::{
    beam, cook, membrane, patch, BEAM_DENSITY, BEAM_LENGTH, BEAM_POISSON, BEAM_SIDE, BEAM_YOUNGS,
    COOK_MAX_ELEMENTS_PER_SIDE, COOK_POISSON, COOK_YOUNGS, MAX_REFINEMENT, MEMBRANE_POISSON,
    PATCH_CELLS,
};
use mass_spring_solvers::model::scene::SHEET_NODES_PER_SIDE;
use mass_spring_solvers::studies::continuum::statics::{
    COOK_LITERATURE, STIFF_BEAM_TOLERANCE, TOLERANCE,
};
use mass_spring_solvers::studies::continuum::{ChapterSize, ContinuumStatics};

pub use figures::{COOK_FIGURE, ENERGIES_FIGURE, MEMBRANE_FIGURE};

/// Every result of the chapter.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuumChapter {
    pub statics: ContinuumStatics,
    /// The scenes' table, its sizes counted from the builders.
    pub scenes: MarkdownTable,
}

impl ContinuumChapter {
    /// Solves the chapter's equilibria at `size` (the report's, or the tests' smaller one).
    pub fn compute(size: ChapterSize) -> Result<Self> {
        let statics = ContinuumStatics::compute(size)?;
        Ok(Self {
            scenes: scenes_table(&statics)?,
            statics,
        })
    }

    /// The chapter's figures: the energies to scale, Cook's convergence, and the membrane
    /// beside the spring sheet (whose equilibria `sheet` holds).
    pub fn figures(&self, sheet: &SheetChapter) -> Result<Vec<ChapterFigure>> {
        figures::all(&self.statics, sheet)
    }

    /// The chapter's files: its figures and their data.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        crate::chapter_figure::chapter_figure_files(figures)
    }

    /// The chapter's section of `REPORT.md`, headed `## {number}.`.
    pub fn section(&self, number: u32, figures: &[ChapterFigure], sheet: &SheetChapter) -> String {
        let mut md = format!("## {number}. The continuum (§5: FEM, where Liu drops out)\n\n");
        md += "The thesis's future work asks to raise the dimension of the problem and notes \
               that leaving mass-spring systems (\"FEM, por ejemplo\") drops Liu 2013 from the \
               comparison: its local step projects springs only. The sheet of section 11 raised \
               the dimension and kept the springs; this chapter takes the step the thesis names. \
               `docs/fem-scenes.md` fixes the scenes, the energies and their conventions; \
               `src/model/continuum/` implements them, and Newton's static equilibrium (a \
               projected Hessian far from the minimum, the exact one near it, a backtracking \
               line search) is their ground truth. This chapter presents the statics; the \
               continuum also runs under the four optimization integrators (Newton's stages, \
               `src/integrators/continuum.rs`, tested in `tests/continuum/dynamics.rs`), whose \
               results and the other solvers on elements are the next step.\n\n";
        md += &format!("### {number}.1 The scenes\n\n");
        md += &self.scenes.render();
        md += "\nEach is built by `mss --scene beam|membrane|cook|patch` and read from a scene \
               file (`scenes/continuum-*.toml`, every field checked before any work).\n\n";
        md += &self.energies(number, figures);
        md += &self.verification(number);
        md += &self.cook(number, figures);
        md += &self.beam_theory(number);
        md += &self.membrane_and_sheet(number, figures, sheet);
        md
    }

    /// The energies side by side: the soft beam's sag and volume change, the membrane's sag
    /// and area change.
    fn energies(&self, number: u32, figures: &[ChapterFigure]) -> String {
        let s = &self.statics;
        let mut md = format!("### {number}.2 The five energies side by side\n\n");
        let nonlinear: Vec<f64> = s
            .soft_beam
            .iter()
            .filter(|b| b.energy != EnergyKind::Linear)
            .map(|b| -b.tip)
            .collect();
        let (lo, hi) = nonlinear
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            });
        let linear = s
            .soft_beam
            .iter()
            .find(|b| b.energy == EnergyKind::Linear)
            .expect("every energy runs on the beam");
        md += &format!(
            "The soft beam (E = 1e6 Pa, r = {}) sags by a large fraction of its \
             length, where the energies part ways. Each equilibrium is Newton's to a residual of \
             {TOLERANCE:e} of the largest nodal weight or better (the column). The four \
             rotation-invariant energies' tips sag between {} and {} m; the linear energy, not \
             rotation-invariant, swells the beam by {} of its volume as it bends (a rotation \
             reads to it as a stretch; Figure C1) — the negative control of the table, and the reason \
             the linear energy stays in the small-strain regime below.\n\n",
            s.energy_refinement,
            sig4(lo),
            sig4(hi),
            share(linear.volume_change),
        );
        let mut t = MarkdownTable::new(&[
            "energy",
            "tip sag (m)",
            "volume change",
            "Newton iterations",
            "residual reached",
        ]);
        for b in &s.soft_beam {
            t.row(vec![
                b.energy.name().into(),
                sig4(-b.tip),
                percent(b.volume_change),
                b.equilibrium.iterations.to_string(),
                order_of(b.equilibrium.relative_residual),
            ]);
        }
        md += &t.render();
        md += "\n";
        md += &figure_md(
            figures,
            ENERGIES_FIGURE,
            "C1",
            &format!(
                "The soft beam's axis (the mean position of each cross-section's nodes) at \
                 each energy's equilibrium, to scale (the same metre on both axes), r = {}, \
                 E = 1e6 Pa; the rest axis is y = 0.",
                s.energy_refinement
            ),
        );
        md += "The membrane (the sheet's twin, section 11) under the four energies defined on \
               membranes (the linear one has no stiffness across a flat membrane's plane):\n\n";
        let mut t = MarkdownTable::new(&[
            "k (N/m)",
            "energy",
            "lowest node y (m)",
            "area change",
            "Newton iterations",
            "residual reached",
        ]);
        for m in &s.membranes {
            t.row(vec![
                stiffness_label(m.stiffness),
                m.energy.name().into(),
                sig4(m.lowest),
                percent(m.area_change),
                m.equilibrium.iterations.to_string(),
                order_of(m.equilibrium.relative_residual),
            ]);
        }
        md += &t.render();
        md += "\n";
        md
    }

    /// The verification table.
    fn verification(&self, number: u32) -> String {
        let s = &self.statics;
        let passed = s.checks.iter().filter(|c| c.passes()).count();
        let mut md = format!("### {number}.3 Verification\n\n");
        md += &format!(
            "Each check computed at report time by the functions the tests call \
             (`src/studies/continuum/statics.rs`); values at round-off are shown by their order \
             of magnitude. {passed} of {} pass. The energies' stresses and Hessians against \
             finite differences, their linearisation at rest, the clamp against a numeric \
             eigen-clamp and the uniaxial closed forms are tested in `tests/continuum/` and not \
             repeated here.\n\n",
            s.checks.len()
        );
        let mut t = MarkdownTable::new(&["check", "tolerance", "value reached", "passes"]);
        for c in &s.checks {
            t.row(vec![
                c.check.clone(),
                if c.tolerance == 0.0 {
                    "0".into()
                } else {
                    format!("{:e}", c.tolerance)
                },
                order_of(c.value),
                if c.passes() { "yes" } else { "**no**" }.into(),
            ]);
        }
        md += &t.render();
        md += "\n";
        md
    }

    /// Cook's convergence.
    fn cook(&self, number: u32, figures: &[ChapterFigure]) -> String {
        let s = &self.statics;
        let last = s.cook.last().expect("Cook runs at several meshes");
        let mut md = format!("### {number}.4 Cook's membrane\n\n");
        md += &format!(
            "The classic check of plane elements under shear and bending, with the linear \
             energy. u_y at (48, 52) rises from below towards the literature's converged value, \
             about {COOK_LITERATURE}, and reaches {} at N = {} ({} below it); its observed \
             order from the last three meshes is {:.2} (linear triangles converge slowly here, \
             as they lock in bending). u_y at the corner P2 = (48, 60) rises too, and passes \
             {COOK_LITERATURE}: the corner's limit is not the mid-point's (Figure C2).\n\n",
            sig4(last.mid),
            last.n,
            share(1.0 - last.mid / COOK_LITERATURE),
            s.cook_order,
        );
        let mut t = MarkdownTable::new(&["N", "u_y(48, 52)", "u_y(48, 60)", "residual reached"]);
        for c in &s.cook {
            t.row(vec![
                c.n.to_string(),
                sig4(c.mid),
                sig4(c.corner),
                order_of(c.relative_residual),
            ]);
        }
        md += &t.render();
        md += "\n";
        md += &figure_md(
            figures,
            COOK_FIGURE,
            "C2",
            &format!(
                "Cook's membrane: u_y at (48, 52) and at P2 = (48, 60) against the mesh N \
                 (log axis), with the literature's converged value at (48, 52), \
                 {COOK_LITERATURE} (dashed)."
            ),
        );
        md
    }

    /// The stiff beam against beam theory.
    fn beam_theory(&self, number: u32) -> String {
        let s = &self.statics;
        let mut md = format!("### {number}.5 The beam against beam theory\n\n");
        let first = &s.stiff_beam[0];
        let last = s
            .stiff_beam
            .last()
            .expect("the beam runs at several meshes");
        md += &format!(
            "The stiff beam (E = 1e9 Pa, the linear energy: a sag of about a millimetre, the \
             linear regime) against Euler-Bernoulli's sag under its own weight plus \
             Timoshenko's shear term, {} m. Linear tets lock in bending: the tip sags {} of \
             theory at r = {} and {} at r = {}, the ratio rising as the mesh is refined. That \
             gap is mesh error against the continuum, not a solver's error (a solver's error is \
             against Newton on the same mesh and energy). Residuals to {STIFF_BEAM_TOLERANCE:e} \
             of the largest weight: on the finer meshes the round-off of the elastic forces, \
             which grow against the nodes' weights as the mesh is refined, keeps Newton above \
             {TOLERANCE:e}.\n\n",
            sig4(s.theory),
            share(first.ratio),
            first.r,
            share(last.ratio),
            last.r,
        );
        let mut t = MarkdownTable::new(&[
            "r",
            "tip sag (m)",
            "beam theory (m)",
            "ratio",
            "residual reached",
        ]);
        for b in &s.stiff_beam {
            t.row(vec![
                b.r.to_string(),
                sig4(b.sag),
                sig4(s.theory),
                sig4(b.ratio),
                order_of(b.relative_residual),
            ]);
        }
        md += &t.render();
        md += "\n";
        md
    }

    /// The membrane's rest state beside the spring sheet's.
    fn membrane_and_sheet(
        &self,
        number: u32,
        figures: &[ChapterFigure],
        sheet: &SheetChapter,
    ) -> String {
        let s = &self.statics;
        let mut md = format!("### {number}.6 The membrane beside the spring sheet\n\n");
        md += "The membrane's Y = 8k/3 and ν = 1/3 match the spring net's C₁₁₂₂ and C₁₂₁₂; \
               the net's C₁₁₁₁ is 2k where the isotropic membrane's is 3k (a square spring net \
               is not isotropic), so the two sheets' shapes are compared side by side (Figure C3), \
               not as an error of one against the other.\n\n";
        let mut t = MarkdownTable::new(&[
            "k (N/m)",
            "spring sheet: lowest y (m)",
            "membrane, stable neo-Hookean: lowest y (m)",
            "membrane / sheet",
        ]);
        for (k, n, e) in &sheet.equilibria {
            if *n != SHEET_NODES_PER_SIDE {
                continue;
            }
            let Some(m) = s
                .membranes
                .iter()
                .find(|m| m.stiffness == *k && m.energy == EnergyKind::StableNeoHookean)
            else {
                continue;
            };
            let lowest = e.x.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            t.row(vec![
                stiffness_label(*k),
                sig4(lowest),
                sig4(m.lowest),
                sig4(m.lowest / lowest),
            ]);
        }
        md += &t.render();
        md += "\n";
        md += &figure_md(
            figures,
            MEMBRANE_FIGURE,
            "C3",
            "The centre line (the row nearest the middle) of the spring sheet and of the \
             stable neo-Hookean membrane at rest, at each stiffness, to scale.",
        );
        md
    }
}

/// The scenes' table, their sizes counted from the builders.
fn scenes_table(s: &ContinuumStatics) -> Result<MarkdownTable> {
    let mut t = MarkdownTable::new(&["scene", "mesh", "nodes", "elements", "what it tests"]);
    let r = s.energy_refinement;
    let beam_r = beam(r, EnergyKind::Linear, BEAM_YOUNGS[1])?;
    t.row(vec![
        "beam".into(),
        format!("r = {r} (up to {MAX_REFINEMENT})"),
        beam_r.node_count().to_string(),
        format!("{} tets", beam_r.elements().len()),
        format!(
            "a {BEAM_LENGTH} m × {BEAM_SIDE} m × {BEAM_SIDE} m cantilever clamped at x = 0 under \
             its weight; ρ = {BEAM_DENSITY} kg/m³, ν = {BEAM_POISSON}, E = {:e} Pa (soft) and \
             {:e} Pa (stiff)",
            BEAM_YOUNGS[0], BEAM_YOUNGS[1]
        ),
    ]);
    let m = membrane(SHEET_NODES_PER_SIDE, EnergyKind::StableNeoHookean, 1e3)?;
    t.row(vec![
        "membrane".into(),
        format!("n = {SHEET_NODES_PER_SIDE}"),
        m.node_count().to_string(),
        format!("{} triangles", m.elements().len()),
        format!(
            "the sheet of section 11 with its springs replaced by plane-stress triangles, \
             Y = 8k/3, ν = {}",
            sig4(MEMBRANE_POISSON)
        ),
    ]);
    let finest = s.cook.last().map_or(2, |c| c.n);
    let c = cook(finest, EnergyKind::Linear, COOK_YOUNGS)?;
    t.row(vec![
        "cook".into(),
        format!(
            "N = {} … {finest} (up to {COOK_MAX_ELEMENTS_PER_SIDE})",
            s.cook[0].n
        ),
        c.node_count().to_string(),
        format!("{} triangles", c.elements().len()),
        format!(
            "Cook's membrane, plane stress, E = {COOK_YOUNGS}, ν = {}, a unit shear load on its \
             right edge",
            sig4(COOK_POISSON)
        ),
    ]);
    let p = patch(EnergyKind::Linear)?;
    t.row(vec![
        "patch".into(),
        format!("{PATCH_CELLS} × {PATCH_CELLS} × {PATCH_CELLS} cubes"),
        p.node_count().to_string(),
        format!("{} tets", p.elements().len()),
        "the affine patch test: the boundary moved by x = AX + b, the interior free".into(),
    ]);
    Ok(t)
}

/// A positive fraction as a share in percent with two significant digits (`60 %`, `0.78 %`).
pub fn share(x: f64) -> String {
    format!("{} %", sig(100.0 * x, 2))
}

/// A value at round-off shown by its order of magnitude (`< 1e-11`), per the project's rule
/// for round-off-level quantities; `0` as such.
pub fn order_of(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("< 1e{}", x.abs().log10().floor() as i32 + 1)
    }
}

/// A figure's Markdown: the image, its caption (keyed `C1`, `C2`, … by `key`, which the
/// report's navigation numbers) and its data.
fn figure_md(figures: &[ChapterFigure], stem: &str, key: &str, caption: &str) -> String {
    figures
        .iter()
        .find(|f| f.stem == stem)
        .map(|f| {
            format!(
                "![Figure {key}](figures/{s}.svg)\n\n*Figure {key}. {caption}* Data: \
                 [`data/{s}.csv`](data/{s}.csv).\n\n",
                s = f.stem
            )
        })
        .unwrap_or_default()
}

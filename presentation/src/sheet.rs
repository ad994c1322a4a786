//! The sheet chapter (the thesis's future work, §5: "a higher dimensionality of the problem"):
//! the 10 × 10 sheet of `docs/sheet-scene.md`: its exact equilibrium, the benchmark's view of
//! it (section 12's protocol), and the thesis's conclusions revisited: does the ranking of the
//! solvers on the rope hold one dimension up?

use crate::benchmark::{
    errors_below_one, jackknife, mean_with_interval, BenchmarkChapter, ASYMPTOTIC_ERROR,
    ASYMPTOTIC_SLOPE, BOOTSTRAP_RESAMPLES, ROUND_OFF_SPREAD, TAU_TIE, TAU_TIE_BESIDE,
};
use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::{full, sig4, MarkdownTable};
use crate::output::OutputFile;
use crate::plot::{Axis, Chart, Line, Marker, Panel, Rgb, Series, FULL_WIDTH_MM};
use crate::style::colour;
use crate::tables::stiffness_label;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::model::scene::{SHEET_NODES_PER_SIDE, THESIS_STIFFNESSES};
use mass_spring_solvers::model::sheet_equilibrium::{report_equilibria, Equilibrium};
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::beyond::GridScene;

/// The colour of the stiff sheet's profiles in Figure S1 (the soft one's is Backward Euler's).
const PROFILE_BLUE: Rgb = Rgb(0, 114, 178);

/// Every result of the chapter.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetChapter {
    /// The exact equilibria of `sheet_equilibrium.csv`: (stiffness, n, equilibrium).
    pub equilibria: Vec<(f64, usize, Equilibrium)>,
}

impl SheetChapter {
    /// Solves the exact equilibria.
    pub fn compute() -> Result<Self> {
        Ok(Self {
            equilibria: report_equilibria()?,
        })
    }

    /// The chapter's figure: the exact rest states of the 10 × 10 sheet at both stiffnesses,
    /// the edge and centre-line profiles seen along z (x against y), to scale.
    pub fn figures(&self) -> Result<Vec<ChapterFigure>> {
        let mut csv = CsvFile::new(&["stiffness_n_per_m", "node", "x_m", "y_m", "z_m"]);
        let n = SHEET_NODES_PER_SIDE;
        // Node i·n + j sits at x = i, z = j (m) at rest: the edge is j = 0, the centre line
        // the row nearest the middle (the sheet is symmetric about it).
        let rows = [("edge", 0), ("centre line", (n - 1) / 2)];
        let mut panel = Panel::new(Axis::linear("x (m)"), Axis::linear("y (m)"));
        panel.equal_aspect = true;
        for (k, (stiffness, _, e)) in self
            .equilibria
            .iter()
            .filter(|(_, nodes, _)| *nodes == n)
            .enumerate()
        {
            for (i, p) in e.x.iter().enumerate() {
                csv.record(vec![
                    full(*stiffness),
                    i.to_string(),
                    full(p.x),
                    full(p.y),
                    full(p.z),
                ]);
            }
            for (r, (name, j)) in rows.iter().enumerate() {
                let points: Vec<(f64, f64)> = (0..n)
                    .map(|i| (e.x[i * n + j].x, e.x[i * n + j].y))
                    .collect();
                panel.series.push(
                    Series::line(
                        format!("k = {} N/m, {name}", stiffness_label(*stiffness)),
                        points,
                        [colour(SolverId::BackwardEuler, 0), PROFILE_BLUE][k % 2],
                    )
                    .with_line([Line::Solid, Line::Dashed][r])
                    .with_marker([Marker::Circle, Marker::Cross][k % 2], r == 0),
                );
            }
        }
        Ok(vec![ChapterFigure::new(
            "sheet_rest_states",
            &Chart::new(FULL_WIDTH_MM, 80.0, vec![panel]),
            csv.text(),
        )?])
    }

    /// The chapter's files: the figure and `data/sheet_equilibrium.csv`.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files = crate::chapter_figure::chapter_figure_files(figures);
        files.push(OutputFile::text(
            "data/sheet_equilibrium.csv",
            equilibrium_csv(&self.equilibria),
        ));
        files
    }

    /// The chapter's section of `REPORT.md`, headed `## {number}.`, with the benchmark's views
    /// of the sheet.
    pub fn section(
        &self,
        number: u32,
        figures: &[ChapterFigure],
        benchmark: &BenchmarkChapter,
    ) -> String {
        let mut md =
            format!("## {number}. The sheet: the thesis's experiment one dimension up (§5)\n\n");
        md += &format!(
            "The thesis's second line of future work is a problem of higher dimension, staying \
             with mass-spring systems so that Liu 2013 stays in the comparison. The sheet of \
             `docs/sheet-scene.md` is the rope woven into a {n} × {n} net: 9 m × 9 m, 1 kg a node, \
             structural and both shear springs at rest length, the four corners fixed, flat and \
             taut at rest, g = 9.81 m/s², k = {} N/m. Every solver of the registry that runs \
             springs and gravity runs it in the benchmark of section 12, at the settings of \
             section 10.\n\n",
            THESIS_STIFFNESSES.map(stiffness_label).join(" and "),
            n = SHEET_NODES_PER_SIDE,
        );
        md += crate::integrators::UNDER_BACKWARD_EULER;
        md += "\n\n";

        md += &format!("### {number}.1 The exact equilibrium\n\n");
        md +=
            "The minimiser of spring plus gravity energy with the corners fixed, by Newton with a \
               backtracking line search from a sagged start (the flat start has no transverse \
               stiffness), every linear solve through the crate's scalar banded LDLᵀ; `data/\
               sheet_equilibrium.csv` has every node at full precision. The tests check the \
               residual with an independent force routine, a positive smallest Hessian eigenvalue, \
               the symmetries x ↦ 9 − x and z ↦ 9 − z, and independence of the start. \
               Figure S1 draws both rest states to scale.\n\n";
        let mut t = MarkdownTable::new(&[
            "k (N/m)",
            "n",
            "largest free-node force (N)",
            "Newton iterations",
            "lowest node y (m)",
        ]);
        for (k, n, e) in &self.equilibria {
            let lowest = e.x.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            t.row(vec![
                stiffness_label(*k),
                n.to_string(),
                sig4(e.residual),
                e.iterations.to_string(),
                sig4(lowest),
            ]);
        }
        md += &t.render();
        md += "\n";
        if let Some(f) = figures.iter().find(|f| f.stem == "sheet_rest_states") {
            md += &format!(
                "![sheet_rest_states](figures/{s}.svg)\n\n*Figure S1. The exact rest states of \
                 the {n} × {n} sheet, to scale (the same metre on both axes), seen along z: the \
                 height of the nodes of one edge (z = 0, solid, filled markers) and of the centre \
                 line (the row nearest the middle, dashed, hollow markers) against x, at each stiffness; the sheet is symmetric \
                 in x and z, so the other edges and the view along x are the same curves.* Data, \
                 every node: [`data/{s}.csv`](data/{s}.csv).\n\n",
                s = f.stem,
                n = SHEET_NODES_PER_SIDE
            );
        }

        md += &format!("### {number}.2 The sheet in the benchmark\n\n");
        md += &benchmark.scene_view_intro(GridScene::Sheet, 12);
        for case in benchmark
            .cases()
            .into_iter()
            .filter(|c| c.scene == GridScene::Sheet)
        {
            md += &format!("**{}**\n\n", case.label());
            md += &benchmark.scene_view(case).render();
            md += "\n";
        }

        md += &format!("### {number}.3 Conclusions revisited: does the ranking hold?\n\n");
        let cells = benchmark.rankings();
        md += &format!(
            "For each stiffness, time step and setting of the thesis's grid, the solvers with three \
             settings ranked by their relative physical error on the rope and on the sheet; τ is \
             Kendall's τ-b between the two orders (1: the same order, 0: unrelated, -1: reversed), two \
             errors within a relative {TAU_TIE:e} of each other tied (round-off: in a 1-iteration cell \
             several solvers compute the same first iteration) and solvers tied on both scenes merged \
             as one computation. Cells where every solver's error agrees to round-off (a relative spread \
             below {ROUND_OFF_SPREAD:e}) rank nothing and are left out: {} cells remain. The interval is \
             the 2.5-97.5 % range of the mean τ over {BOOTSTRAP_RESAMPLES} bootstrap resamples of \
             the cells.\n\n",
            cells.len()
        );
        let mut t = MarkdownTable::new(&[
            ">k (N/m)",
            ">dt (s)",
            ">setting",
            "best three on the rope",
            "best three on the sheet",
            ">τ",
            ">before the asymptotic regime, rope / sheet",
        ]);
        let top = |r: &[SolverId]| {
            r.iter()
                .take(3)
                .map(|id| id.info().display_name)
                .collect::<Vec<_>>()
                .join(", ")
        };
        for c in &cells {
            t.row(vec![
                stiffness_label(c.stiffness),
                full(c.dt_s),
                (c.setting + 1).to_string(),
                top(&c.rope),
                top(&c.sheet),
                c.tau.map_or("–".into(), |tau| format!("{tau:.2}"))
                    + if c.pre_asymptotic() { " ‡" } else { "" },
                format!(
                    "{} of {} / {} of {}",
                    c.before_asymptotic.0,
                    c.rope.len(),
                    c.before_asymptotic.1,
                    c.sheet.len()
                ),
            ]);
        }
        md += &t.render();
        md += "\n";
        let settled: Vec<f64> = cells
            .iter()
            .filter(|c| !c.pre_asymptotic())
            .filter_map(|c| c.tau)
            .collect();
        md += &format!(
            "‡: more than half of the ranked solvers on the rope or on the sheet are before the \
             asymptotic regime (section 12.4's rule: a local slope below {ASYMPTOTIC_SLOPE} or an \
             error above {ASYMPTOTIC_ERROR} of doing nothing's; the sheet's slopes read to its \
             long runs at 0.005 s), so τ there ranks errors that do not yet fall with the step: \
             {} of the {} cells. The majority rule was written with these cells in view (an \
             interpretation, not a pre-registration). {}\n\n",
            cells.iter().filter(|c| c.pre_asymptotic()).count(),
            cells.len(),
            settled_taus(&settled)
        );
        let taus: Vec<f64> = cells.iter().filter_map(|c| c.tau).collect();
        md += &match mean_with_interval(&taus) {
            Some((mean, lo, hi)) => format!(
                "Mean τ-b = {mean:.2}, 95 % bootstrap interval [{lo:.2}, {hi:.2}] over {} cells: {}, \
                 in cells most of which ({}) rank errors before the asymptotic regime.\n\n",
                taus.len(),
                if lo > 0.0 {
                    "the rope's ranking carries over to the sheet more than by chance"
                } else {
                    "the data cannot tell the rope's ranking from an unrelated one on the sheet"
                },
                cells.iter().filter(|c| c.pre_asymptotic()).count()
            ),
            None => "No cell ranks the solvers on both scenes.\n\n".into(),
        };
        let beside: Vec<f64> = cells
            .iter()
            .filter_map(|c| c.tau_at(TAU_TIE_BESIDE))
            .collect();
        let jack = jackknife(&cells);
        let (below, ranked) = errors_below_one(&cells);
        if let (Some((mean_beside, _, _)), Some(lo), Some(hi)) = (
            mean_with_interval(&beside),
            jack.iter().min_by(|a, b| a.1.total_cmp(&b.1)),
            jack.iter().max_by(|a, b| a.1.total_cmp(&b.1)),
        ) {
            md += &format!(
                "With ties at a relative {TAU_TIE_BESIDE:e} instead, mean τ-b = {mean_beside:.2} over {} \
                 cells. Leaving one solver out of every cell at a time (a jackknife: resampling solvers with \
                 replacement would tie a solver with its copy by construction), the mean τ-b lies between \
                 {:.2} (without {}) and {:.2} (without {}). Of the {ranked} errors ranked, {below} are below 1 \
                 (a relative physical error under 100 %); the others rank solvers that miss the motion.\n\n",
                beside.len(),
                lo.1,
                lo.0.display_name(),
                hi.1,
                hi.0.display_name(),
            );
        }
        md
    }
}

/// The fewest cells whose mean τ gets a bootstrap interval: over fewer, the interval is the
/// range of a handful of values and says nothing.
pub const FEWEST_FOR_INTERVAL: usize = 5;

/// The τ of the cells in the asymptotic regime: their mean and bootstrap interval over at
/// least [`FEWEST_FOR_INTERVAL`] of them, else the values themselves.
fn settled_taus(settled: &[f64]) -> String {
    if settled.is_empty() {
        return "No cell is in the asymptotic regime on both scenes.".into();
    }
    if settled.len() < FEWEST_FOR_INTERVAL {
        return format!(
            "The other {} read τ = {} (too few for an interval).",
            settled.len(),
            settled
                .iter()
                .map(|t| format!("{t:.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    match mean_with_interval(settled) {
        Some((mean, lo, hi)) => format!(
            "Over the other {}, mean τ = {mean:.2} [{lo:.2}, {hi:.2}].",
            settled.len()
        ),
        None => String::new(),
    }
}

/// `sheet_equilibrium.csv`: one row per node (i, j) of every equilibrium, every coordinate at
/// full precision.
pub fn equilibrium_csv(equilibria: &[(f64, usize, Equilibrium)]) -> String {
    let mut csv = CsvFile::new(&["stiffness_n_per_m", "n", "i", "j", "x_m", "y_m", "z_m"]);
    for (k, n, eq) in equilibria {
        for i in 0..*n {
            for j in 0..*n {
                let p = eq.x[i * n + j];
                csv.record(vec![
                    full(*k),
                    n.to_string(),
                    i.to_string(),
                    j.to_string(),
                    full(p.x),
                    full(p.y),
                    full(p.z),
                ]);
            }
        }
    }
    csv.text()
}

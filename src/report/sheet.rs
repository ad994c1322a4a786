//! The sheet chapter (the thesis's future work, §5: "a higher dimensionality of the problem"):
//! the grid of Tables 2-7 on the 10 × 10 sheet of `docs/sheet-scene.md` for every solver, its
//! exact equilibrium, and the thesis's conclusions revisited: does the ranking of the solvers
//! on the rope hold one dimension up?

use crate::beyond::{
    grid_rows, grid_solvers, kendall_tau, ranking, run_grid, GridResult, GridRow, GridScene,
    GRID_DTS, GRID_MAX_TIME, SHEET_MAX_TIME,
};
use crate::error::Result;
use crate::registry::SolverId;
use crate::report::beyond::{grid_csv, grid_table};
use crate::report::figures::colour;
use crate::report::format::{full, sig4, MarkdownTable};
use crate::report::output::OutputFile;
use crate::report::plot::{Axis, Chart, Marker, Panel, Series, FULL_WIDTH_MM};
use crate::report::tables::stiffness_label;
use crate::report::ChapterFigure;
use crate::scene::{SHEET_NODES_PER_SIDE, THESIS_STIFFNESSES};
use crate::sheet_equilibrium::{equilibrium_csv, report_equilibria, Equilibrium};
use crate::system::Vec3;

/// A ranking "holds" one dimension up when Kendall's τ between the rope's and the sheet's is
/// at least this (about four pairs in five in the same order).
pub const RANKING_HOLDS_TAU: f64 = 0.6;

/// The horizontal coordinate of a view.
type Projection = fn(&Vec3) -> f64;

/// A gap to the reference below this (summed over nodes, m) counts as converged to its step.
pub const CLOSE_GAP: f64 = 1e-6;

/// Every result of the chapter.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetChapter {
    /// The sheet's grid.
    pub grid: Vec<GridResult>,
    /// The exact equilibria of `sheet_equilibrium.csv`: (stiffness, n, equilibrium).
    pub equilibria: Vec<(f64, usize, Equilibrium)>,
}

/// One (stiffness, dt) cell of the rankings' comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct RankingCell {
    pub stiffness: f64,
    pub dt_s: f64,
    pub rope: Vec<(SolverId, f64)>,
    pub sheet: Vec<(SolverId, f64)>,
    pub tau: Option<f64>,
}

impl SheetChapter {
    /// Runs the sheet's grid and solves the exact equilibria.
    pub fn compute(progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        Self::compute_rows(&grid_rows(GridScene::Sheet), progress)
    }

    /// The chapter with only `rows` of the grid run (the tests run a part of it).
    pub fn compute_rows(
        rows: &[GridRow],
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Self> {
        Ok(Self {
            grid: run_grid(rows, progress)?,
            equilibria: report_equilibria()?,
        })
    }

    /// The solvers ranked: every grid solver but the reference's method.
    fn ranked_solvers() -> Vec<SolverId> {
        grid_solvers()
            .into_iter()
            .filter(|id| !matches!(id, SolverId::BackwardEuler | SolverId::DampedBackwardEuler))
            .collect()
    }

    /// The rankings on the rope (`rope`: the rope's grid, section 10) and on the sheet, per
    /// stiffness and time step.
    pub fn rankings(&self, rope: &[GridResult]) -> Vec<RankingCell> {
        let solvers = Self::ranked_solvers();
        let mut cells = Vec::new();
        for stiffness in THESIS_STIFFNESSES {
            for dt_s in GRID_DTS {
                let rope = ranking(rope, GridScene::Rope, stiffness, dt_s, &solvers);
                let sheet = ranking(&self.grid, GridScene::Sheet, stiffness, dt_s, &solvers);
                let ids = |r: &[(SolverId, f64)]| r.iter().map(|(id, _)| *id).collect::<Vec<_>>();
                let tau = kendall_tau(&ids(&rope), &ids(&sheet));
                cells.push(RankingCell {
                    stiffness,
                    dt_s,
                    rope,
                    sheet,
                    tau,
                });
            }
        }
        cells
    }

    /// The chapter's figure: the exact rest states of the 10 × 10 sheet at both stiffnesses,
    /// (a) seen along z (x against y), (b) seen along x (z against y), to scale.
    pub fn figures(&self) -> Result<Vec<ChapterFigure>> {
        let mut csv = String::from("stiffness,node,x_m,y_m,z_m\n");
        let views: [(&str, Projection); 2] = [("x (m)", |p| p.x), ("z (m)", |p| p.z)];
        let mut panels = Vec::new();
        for (view, (label, horizontal)) in views.iter().enumerate() {
            let mut panel = Panel::new(Axis::linear(*label), Axis::linear("y (m)"));
            panel.equal_aspect = true;
            for (k, (stiffness, _, e)) in self
                .equilibria
                .iter()
                .filter(|(_, n, _)| *n == SHEET_NODES_PER_SIDE)
                .enumerate()
            {
                let points: Vec<(f64, f64)> = e.x.iter().map(|p| (horizontal(p), p.y)).collect();
                if view == 0 {
                    for (i, p) in e.x.iter().enumerate() {
                        csv += &format!(
                            "{},{i},{},{},{}\n",
                            full(*stiffness),
                            full(p.x),
                            full(p.y),
                            full(p.z)
                        );
                    }
                }
                let legend = if view == 1 {
                    format!("k = {} N/m", stiffness_label(*stiffness))
                } else {
                    String::new()
                };
                panel.series.push(
                    Series::points(legend, points, colour(SolverId::BackwardEuler, 0))
                        .with_marker([Marker::Circle, Marker::Cross][k % 2], k == 0),
                );
            }
            panels.push(panel);
        }
        Ok(vec![ChapterFigure::new(
            "sheet_rest_states",
            &Chart::new(FULL_WIDTH_MM, 70.0, panels),
            csv,
        )?])
    }

    /// The chapter's files: the figure, `data/sheet_results.csv` and
    /// `data/sheet_equilibrium.csv`.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files = crate::report::chapter_figure_files(figures);
        files.push(OutputFile::text(
            "data/sheet_results.csv",
            grid_csv(self.grid.iter()),
        ));
        files.push(OutputFile::text(
            "data/sheet_equilibrium.csv",
            equilibrium_csv(&self.equilibria),
        ));
        files
    }

    /// The chapter's section of `REPORT.md`, headed `## {number}.`; `rope` is the rope's grid
    /// of section 10, for the rankings.
    pub fn section(&self, number: u32, figures: &[ChapterFigure], rope: &[GridResult]) -> String {
        let mut md =
            format!("## {number}. The sheet: the thesis's experiment one dimension up (§5)\n\n");
        md += &format!(
            "The thesis's second line of future work is a problem of higher dimension, staying \
             with mass-spring systems so that Liu 2013 stays in the comparison. The sheet of \
             `docs/sheet-scene.md` is the rope woven into a {n} × {n} net: 9 m × 9 m, 1 kg a node, \
             structural and both shear springs at rest length, the four corners fixed, flat and \
             taut at rest, g = 9.81 m/s², k = {} N/m. Every solver of the registry that runs \
             springs and gravity runs it at dt = {} s in the settings of section 10 (the thesis's \
             four at the counts of Tables 1-7). Every sheet run, the reference's (Backward Euler, \
             dt = 1e-3 s, 5 Newton iterations) included, stops at the thesis's rule or at \
             t = {} s, whichever comes first: the thesis's runs last minutes at this size, and this \
             window fits the chapter in its budget. Peaks and T/2 are those of the window; the \
             gaps are summed node distances at the run's end, to the reference's state at the same \
             time and to the exact static equilibrium below.\n\n",
            THESIS_STIFFNESSES.map(stiffness_label).join(" and "),
            GRID_DTS.map(full).join(", "),
            full(SHEET_MAX_TIME),
            n = SHEET_NODES_PER_SIDE,
        );
        md += crate::report::integrators::UNDER_BACKWARD_EULER;
        md += "\n\n";

        md += &format!("### {number}.1 The exact equilibrium\n\n");
        md +=
            "The minimiser of spring plus gravity energy with the corners fixed, by Newton with a \
               backtracking line search from a sagged start (the flat start has no transverse \
               stiffness), every linear solve through the crate's scalar banded LDLᵀ; `data/\
               sheet_equilibrium.csv` has every node at full precision. The tests check the \
               residual with an independent force routine, a positive smallest Hessian eigenvalue, \
               the symmetries x ↦ 9 − x and z ↦ 9 − z, and independence of the start.\n\n";
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
                 the {n} × {n} sheet, to scale: (a) seen along z, (b) seen along x.* Data: \
                 [`data/{s}.csv`](data/{s}.csv).\n\n",
                s = f.stem,
                n = SHEET_NODES_PER_SIDE
            );
        }

        md += &format!("### {number}.2 The grid of Tables 2-7 on the sheet\n\n");
        for id in grid_solvers() {
            md += &format!("**`{}`** ({})\n\n", id.id(), id.info().summary);
            md += &grid_table(self.grid.iter().filter(|r| r.row.spec.id == id)).render();
            md += "\n";
        }

        md += &format!("### {number}.3 Conclusions revisited: does the ranking hold?\n\n");
        md += &format!(
            "For each stiffness and time step, the solvers ranked by the gap to the reference \
             each reaches at its best setting, on the rope (in its {} s window) and on the sheet \
             (in its {} s window), Backward Euler left out (it is the reference's method); τ is \
             Kendall's rank correlation between the two orders (1: the same order). The ranking \
             holds where τ ≥ {}.\n\n",
            full(GRID_MAX_TIME),
            full(SHEET_MAX_TIME),
            full(RANKING_HOLDS_TAU),
        );
        let cells = self.rankings(rope);
        let mut t = MarkdownTable::new(&[
            "k (N/m)",
            "dt (s)",
            "best three on the rope",
            "best three on the sheet",
            "within 1e-6 m (rope / sheet)",
            "τ",
        ]);
        let close = |r: &[(SolverId, f64)]| r.iter().filter(|(_, gap)| *gap < CLOSE_GAP).count();
        let top = |r: &[(SolverId, f64)]| {
            r.iter()
                .take(3)
                .map(|(id, gap)| format!("`{id}` ({})", sig4(*gap)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        for c in &cells {
            t.row(vec![
                stiffness_label(c.stiffness),
                full(c.dt_s),
                top(&c.rope),
                top(&c.sheet),
                format!("{} / {}", close(&c.rope), close(&c.sheet)),
                c.tau.map_or("-".into(), |tau| format!("{tau:.2}")),
            ]);
        }
        md += &t.render();
        md += "\n";
        let holds = cells
            .iter()
            .filter(|c| c.tau.is_some_and(|t| t >= RANKING_HOLDS_TAU))
            .count();
        let taus: Vec<f64> = cells.iter().filter_map(|c| c.tau).collect();
        let mean = taus.iter().sum::<f64>() / taus.len().max(1) as f64;
        md += &format!(
            "The rope's ranking holds on the sheet in {holds} of {} cells (mean τ = {mean:.2}). \
             Where several solvers end within {} m of the reference (they converge to its step: \
             at dt = 1e-3 s the fixed-point solvers do), their order is that of their leftover \
             iteration error, not of their physics, and τ there says little.\n\n",
            cells.len(),
            full(CLOSE_GAP)
        );
        md
    }
}

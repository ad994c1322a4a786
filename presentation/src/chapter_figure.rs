//! A chapter's figure (its stem, layout, SVG and the CSV of the points it draws) and the
//! output files of a chapter's figures.

use crate::output::OutputFile;
use crate::plot::{layout, Chart, Layout};
use mass_spring_solvers::error::Result;

/// One figure of a chapter (the tutorial's, beyond the thesis): file stem
/// (`tutorial_convergence`), layout, SVG and CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct ChapterFigure {
    pub stem: &'static str,
    /// Every text box, data mark and axes rectangle, for the figure test.
    pub layout: Layout,
    pub svg: String,
    pub csv: String,
}

impl ChapterFigure {
    pub fn new(stem: &'static str, chart: &Chart, csv: String) -> Result<Self> {
        let layout = layout(chart)?;
        Ok(Self {
            stem,
            svg: layout.svg(),
            layout,
            csv,
        })
    }
}

/// The files of a chapter's figures: `figures/<stem>.svg` and `data/<stem>.csv` each.
pub fn chapter_figure_files(figures: &[ChapterFigure]) -> Vec<OutputFile> {
    figures
        .iter()
        .flat_map(|f| figure_files(f.stem, &f.svg, &f.csv))
        .collect()
}

/// The figures of the chapters after the thesis's, for `REPORT.md`.
pub struct ChapterFigures<'a> {
    pub tutorial: &'a [ChapterFigure],
    pub beyond: &'a [ChapterFigure],
    pub sheet: &'a [ChapterFigure],
    pub work_precision: &'a [ChapterFigure],
    pub integrators: &'a [ChapterFigure],
    pub continuum: &'a [ChapterFigure],
}

/// A figure's two files: `figures/<stem>.svg` and the points it draws, `data/<stem>.csv`.
pub fn figure_files(stem: &str, svg: &str, csv: &str) -> [OutputFile; 2] {
    [
        OutputFile::text(format!("figures/{stem}.svg"), svg.to_string()),
        OutputFile::text(format!("data/{stem}.csv"), csv.to_string()),
    ]
}

//! The benchmark's work-precision figures in counted flops, one per case ([`work_figure`]), and
//! the chapter's data files.

use super::*;
use crate::benchmark::fronts::work_figure;
use crate::chapter_figure::ChapterFigure;
use crate::output::OutputFile;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::studies::benchmark::sweep::BASELINES;
use mass_spring_solvers::studies::benchmark::Case;
use mass_spring_solvers::studies::beyond::GridScene;

impl BenchmarkChapter {
    /// The work-precision figures in counted flops, one per case ([`work_figure`]).
    pub fn figures(&self) -> Result<Vec<ChapterFigure>> {
        self.cases()
            .into_iter()
            .map(|case| {
                work_figure(
                    stem(case),
                    ("flops over the window", "flops"),
                    self.truth_floor(case),
                    |id, integrator| self.front_under(case, id, integrator),
                )
            })
            .collect()
    }

    /// Whether a work-precision figure of `case` draws any explicit baseline (none is drawn
    /// where every one is unstable at every time step, the stiff sheet).
    pub fn baselines_drawn(&self, case: Case) -> bool {
        BASELINES.iter().any(|&id| !self.front(case, id).is_empty())
    }

    /// The exact motion's own error on a case, relative to its amplitude, as the figures cut
    /// at it: its halving gap (the change when RK4's step is halved, which bounds the coarser
    /// motion's error and is about 15 times the exact motion's own), over the amplitude.
    pub fn truth_floor(&self, case: Case) -> Option<f64> {
        let truth = self.truth(case)?;
        Some(truth.halving_gap_m / truth.amplitude_rms_m)
    }

    /// The figures and the data files.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files: Vec<OutputFile> = figures
            .iter()
            .flat_map(|f| crate::chapter_figure::figure_files(f.stem, &f.svg, &f.csv))
            .collect();
        files.push(OutputFile::text("data/benchmark.csv", rows_csv(&self.rows)));
        files.push(OutputFile::text(
            "data/benchmark_references.csv",
            rows_csv(&self.references),
        ));
        if !self.protocol.is_empty() {
            files.push(OutputFile::text(
                "data/benchmark_thesis_protocol.csv",
                rows_csv(&self.protocol),
            ));
        }
        files.push(OutputFile::text(
            "data/benchmark_own_start.csv",
            rows_csv(&self.own_start),
        ));
        files.push(OutputFile::text(
            "data/benchmark_truths.csv",
            rows_csv(&self.truths),
        ));
        files
    }
}

/// The figure's file stem of a case.
pub fn stem(case: Case) -> &'static str {
    match (case.scene, case.stiffness == 1e3) {
        (GridScene::Rope, true) => "benchmark_rope_k1e3",
        (GridScene::Rope, false) => "benchmark_rope_k1e6",
        (GridScene::Sheet, true) => "benchmark_sheet_k1e3",
        (GridScene::Sheet, false) => "benchmark_sheet_k1e6",
    }
}

//! What the report is made of, gathered once per process: the runs' results, the forensic
//! reproduction, every chapter's data, and what it reads from the crate's files (equation tags,
//! quoted code, dependency versions), with where the repository is.

use crate::benchmark::BenchmarkChapter;
use crate::beyond::BeyondChapter;
use crate::continuum::ContinuumChapter;
use crate::integrators::IntegratorsChapter;
use crate::rest_state::Catenary;
use crate::runs::FigureRuns;
use crate::sheet::SheetChapter;
use crate::traceability;
use crate::traceability::{PaperTag, Quote, Tag};
use crate::tutorial::TutorialChapter;
use crate::versions::Versions;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::ResultSet;
use mass_spring_solvers::studies::forensics::Forensics;
use std::path::{Path, PathBuf};

/// The workspace's root directory, the science crate's (where `src/`, `Cargo.toml` and
/// `Cargo.lock` are); this crate lives in its `presentation/`.
pub fn crate_root() -> PathBuf {
    let presentation = Path::new(env!("CARGO_MANIFEST_DIR"));
    presentation.parent().unwrap_or(presentation).to_path_buf()
}

/// The science crate's package name, which names the repository's root manifest.
const SCIENCE_PACKAGE: &str = "mass-spring-solvers";

/// The repository of this crate that holds `start` (the nearest ancestor, `start` included,
/// whose `Cargo.toml` names the package), found at run time: the report's default output
/// directory is its `report/`, wherever the binary was built.
pub fn repository_containing(start: &Path) -> Option<PathBuf> {
    let package = format!("name = \"{SCIENCE_PACKAGE}\"");
    start.ancestors().find_map(|dir| {
        let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).ok()?;
        let names_us = manifest.split("[package]").nth(1).is_some_and(|p| {
            p.lines()
                .take_while(|l| !l.trim_start().starts_with('['))
                .any(|l| l.trim() == package)
        });
        names_us.then(|| dir.to_path_buf())
    })
}

/// What the report reads from the crate's files: equation tags, the quoted step function of
/// each solver, and the dependency versions.
#[derive(Debug, Clone, PartialEq)]
pub struct Sources {
    pub tags: Vec<Tag>,
    /// The tags of the papers after the thesis (`[Wang 2015, Eq. 12]`).
    pub paper_tags: Vec<PaperTag>,
    pub quotes: Vec<(SolverId, Quote)>,
    pub versions: Versions,
}

impl Sources {
    /// Reads the crate at `root`; quotes the step functions of `solvers`. A missing region
    /// marker is an error naming the file and the marker.
    pub fn read(root: &Path, solvers: &[SolverId]) -> Result<Self> {
        let quotes = solvers
            .iter()
            .map(|&s| traceability::solver_step(root, s).map(|q| (s, q)))
            .collect::<Result<_>>()?;
        Ok(Self {
            tags: traceability::scan(root)?,
            paper_tags: traceability::scan_papers(root)?,
            quotes,
            versions: Versions::read(root)?,
        })
    }
}

/// The solvers that appear in a result set, in table order.
pub fn solvers_in(results: &ResultSet) -> Vec<SolverId> {
    SolverId::THESIS_TABLES
        .into_iter()
        .filter(|s| results.rows.iter().any(|m| m.published.solver == *s))
        .collect()
}

/// Everything the report shows.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportData {
    pub results: ResultSet,
    /// The forensic reproduction of `results` (issue 5); None leaves its sections out.
    pub forensics: Option<Forensics>,
    pub runs: FigureRuns,
    pub catenary: Catenary,
    /// The tutorial's chapter.
    pub tutorial: TutorialChapter,
    /// The chapter after the thesis's: the newer solvers.
    pub beyond: BeyondChapter,
    /// The sheet: the thesis's experiment one dimension up.
    pub sheet: SheetChapter,
    /// The timing study: accuracy against counted work.
    /// The benchmark's chapter (work and precision).
    pub benchmark: BenchmarkChapter,
    /// The optimization integrators.
    pub integrators: IntegratorsChapter,
    /// The continuum (its statics).
    pub continuum: ContinuumChapter,
    pub sources: Sources,
}

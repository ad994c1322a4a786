//! Tables 1-12 of thesis §4.3-4.4, each published row beside ours, with the deviation, a
//! status mark under the reproduction rule ([`mass_spring_solvers::studies::experiments::reproduces`]), $`T/2`$
//! under both conventions, and the reproduction summary with the best explanation of every
//! row that is not reproduced.
//!
//! Published values are shown exactly as the thesis prints them (with a decimal point),
//! ours with [`SIGNIFICANT_DIGITS`] significant digits.

use crate::format::{
    counted, full, opt4, percent, rest_error, sci3, sig, sig4, signed, MarkdownTable,
    ROUND_OFF_REST_ERROR_M, SIGNIFICANT_DIGITS,
};
use mass_spring_solvers::model::metrics::STOP_THRESHOLD_J;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{
    peak_tolerance, published_rows, Measured, PublishedRow, ResultSet, HALF_PERIOD_TOLERANCE,
    PUBLISHED_CSV,
};
use std::sync::OnceLock;

pub use mass_spring_solvers::studies::experiments::rule::{ERROR_CHECK_ABOVE, ERROR_RATIO_RANGE};

/// Mark of a reproduced row.
pub const PASS: &str = "✓";
/// Mark of a row that is not reproduced.
pub const FAIL: &str = "✗";
/// Mark of a row that was not run (its solver is not part of this report).
pub const NOT_RUN: &str = "not run";

/// A published row's numbers as printed in the thesis.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Printed {
    pub error: String,
    pub ke_peaks: String,
    pub half_period_s: String,
    pub period_rel_error: String,
}

fn same_experiment(a: &PublishedRow, b: &PublishedRow) -> bool {
    a.table == b.table
        && a.solver == b.solver
        && a.dt_s == b.dt_s
        && a.iterations == b.iterations
        && a.stiffness == b.stiffness
}

/// The printed values of a published row, from the embedded `thesis_results.csv`.
pub fn printed(row: &PublishedRow) -> &'static Printed {
    static PRINTED: OnceLock<Vec<Printed>> = OnceLock::new();
    let all = PRINTED.get_or_init(|| {
        csv::Reader::from_reader(PUBLISHED_CSV.as_bytes())
            .records()
            .map(|r| {
                let r = r.expect("data/thesis_results.csv is embedded at build time and parses");
                let field = |i: usize| r.get(i).unwrap_or("").to_string();
                Printed {
                    error: field(5),
                    ke_peaks: field(6),
                    half_period_s: field(7),
                    period_rel_error: field(8),
                }
            })
            .collect()
    });
    let index = published_rows()
        .iter()
        .position(|p| same_experiment(p, row))
        .expect("every row comes from the published table");
    &all[index]
}

/// Our measurement of a published row, if it was run.
pub fn measured<'a>(results: &'a ResultSet, row: &PublishedRow) -> Option<&'a Measured> {
    results
        .rows
        .iter()
        .find(|m| same_experiment(&m.published, row))
}

/// The published rows of one of Tables 1-7.
pub fn published_table(table: u8) -> impl Iterator<Item = &'static PublishedRow> {
    published_rows().iter().filter(move |r| r.table == table)
}

/// `1e3`, `1e6`.
pub fn stiffness_label(k: f64) -> String {
    format!("{k:e}")
}

/// The name of a solver as in the thesis.
pub fn solver_name(kind: SolverId) -> &'static str {
    match kind {
        SolverId::BackwardEuler => {
            "Newton-Raphson on the Backward Euler step (the thesis's implicit reference)"
        }
        SolverId::Xpbd => "XPBD (Extended Position-Based Dynamics)",
        SolverId::FastMassSpring => "Fast Simulation of Mass-Spring Systems (Liu 2013)",
        SolverId::AdmmPd => "ADMM ⊇ Projective Dynamics (Overby 2017)",
        other => other.info().summary,
    }
}

/// The integrator of the thesis's minimizing solvers, named in the titles of the tables that
/// show their runs (issue 23).
const BE: &str = "Backward Euler";
/// The same for the tables that show every solver.
const IMPLICIT: &str = "the implicit solvers under Backward Euler";

/// The title of Tables 1-12.
pub fn title(table: u8) -> String {
    let k = published_table(table)
        .next()
        .map_or(String::new(), |r| stiffness_label(r.stiffness));
    match table {
        1 => "Table 1. Reference values, Backward Euler, k = 1e3 and 1e6 N/m".into(),
        2 | 3 => format!("Table {table}. XPBD, k = {k} N/m"),
        4 | 5 => format!(
            "Table {table}. Fast Simulation of Mass-Spring Systems, k = {k} N/m, under {BE}"
        ),
        6 | 7 => format!("Table {table}. ADMM ⊇ Projective Dynamics, k = {k} N/m, under {BE}"),
        8 => "Table 8. Abbreviation of each solver".into(),
        9 => format!(
            "Table 9. Rest-state error of the coarsest approximations, k = 1e3 N/m, dt = 0.1 s, \
             {IMPLICIT}"
        ),
        10 => format!("Table 10. Kinetic energy at dt = 0.1 s, k = 1e3 N/m, {IMPLICIT}"),
        11 => format!("Table 11. Kinetic energy at dt = 0.1 s, k = 1e6 N/m, {IMPLICIT}"),
        12 => format!("Table 12. Kinetic energy at dt = 0.001 s, k = 1e6 N/m, {IMPLICIT}"),
        _ => format!("Table {table}"),
    }
}

/// Relative T/2 deviation of ours from the published value (thesis convention).
pub fn half_period_deviation(m: &Measured) -> Option<f64> {
    m.half_period_thesis
        .map(|t| (t - m.published.half_period_s) / m.published.half_period_s)
}

/// Ours/published rest-state error.
pub fn error_ratio(m: &Measured) -> Option<f64> {
    m.error_sum
        .zip(m.published.error)
        .map(|(ours, published)| ours / published)
}

/// Whether the rest-state error is checked (published above [`ERROR_CHECK_ABOVE`]) and, if
/// so, whether ours is within [`ERROR_RATIO_RANGE`].
pub fn error_within_band(m: &Measured) -> Option<bool> {
    let published = m.published.error?;
    (published > ERROR_CHECK_ABOVE).then(|| {
        error_ratio(m).is_some_and(|r| (ERROR_RATIO_RANGE.0..=ERROR_RATIO_RANGE.1).contains(&r))
    })
}

/// Whether a faithful run counts as reproduced: the rule of evidence's decision
/// ([`Forensics::reproduces`]: the reproduction rule and the fitted rest-error band) where the
/// forensic chapter was computed, the reproduction rule alone in a partial report.
pub fn reproduced(m: &Measured, forensics: Option<&Forensics>) -> bool {
    forensics.map_or_else(|| m.reproduces(), |f| f.reproduces(m))
}

/// The status cell: ✓ (marginal), ✗, or ✗ with the rest error that contradicts a row the
/// reproduction rule passes.
fn status(m: Option<&Measured>, forensics: Option<&Forensics>) -> String {
    match m {
        None => NOT_RUN.into(),
        Some(m) if !reproduced(m, forensics) && m.reproduces() => format!("{FAIL} rest error"),
        Some(m) if m.marginal() => format!("{PASS} marginal"),
        Some(m) if m.reproduces() => PASS.into(),
        Some(_) => FAIL.into(),
    }
}

fn peaks_cell(m: &Measured) -> String {
    if m.hit_time_limit {
        format!("{} (time limit)", m.peaks)
    } else {
        m.peaks.to_string()
    }
}

fn ratio_cell(m: &Measured) -> String {
    match (error_ratio(m), error_within_band(m)) {
        (Some(r), Some(true)) => format!("{} {PASS}", sig4(r)),
        (Some(r), Some(false)) => format!("{} {FAIL}", sig4(r)),
        (Some(r), None) => format!("{} (floor)", sig4(r)),
        (None, _) => "–".into(),
    }
}

fn dash() -> String {
    "–".into()
}

/// The free nodes of the thesis rope, over which its rest-state error is summed
/// (measurement convention 7 of `docs/thesis-scene.md`).
fn rope_free_nodes() -> usize {
    let rope = mass_spring_solvers::model::scene::thesis_rope(1e3).expect("the thesis rope builds");
    rope.nodes().iter().filter(|n| !n.fixed).count()
}

/// How the thesis's rest-state error adds up, for every sentence that shows it.
pub fn summed_over_free_nodes() -> String {
    format!("summed over {} free nodes", rope_free_nodes())
}

/// The header of a column of the thesis's rest-state error: `which` (`pub.`, `ours`) with
/// its unit and its sum, right-aligned.
pub fn summed_error_header(which: &str) -> String {
    format!(">error {which} (m, Σ {} nodes)", rope_free_nodes())
}

/// One of Tables 1-7: every published row beside ours, the verdict first; T/2 and errors
/// published and ours side by side (the published T/2 as printed; errors in one scientific
/// format, 3 significant digits). The exact convention's T/2 and the relative T errors are in
/// `data/results.csv`.
pub fn results_table(
    results: &ResultSet,
    forensics: Option<&Forensics>,
    table: u8,
) -> MarkdownTable {
    let reference = table == 1;
    let mut header: Vec<String> = ["status", ">dt (s)", ">iter."].map(String::from).to_vec();
    if reference {
        header.push(">k (N/m)".into());
    }
    header.extend(
        [
            ">peaks pub.",
            ">peaks ours",
            ">T/2 pub. (s)",
            ">T/2 ours (s)",
            ">T/2 dev.",
        ]
        .map(String::from),
    );
    if !reference {
        header.extend([summed_error_header("pub."), summed_error_header("ours")]);
    }
    let mut t = MarkdownTable::new(&header);
    for row in published_table(table) {
        let p = printed(row);
        let m = measured(results, row);
        let mut cells = vec![
            status(m, forensics),
            full(row.dt_s),
            row.iterations.to_string(),
        ];
        if reference {
            cells.push(stiffness_label(row.stiffness));
        }
        let or_dash = |f: &dyn Fn(&Measured) -> String| m.map_or_else(dash, f);
        cells.push(p.ke_peaks.clone());
        cells.push(or_dash(&peaks_cell));
        cells.push(p.half_period_s.clone());
        cells.push(or_dash(&|m| opt4(m.half_period_thesis)));
        cells.push(or_dash(&|m| {
            half_period_deviation(m).map_or_else(dash, percent)
        }));
        if !reference {
            cells.push(row.error.map_or_else(dash, sci3));
            cells.push(or_dash(&|m| {
                m.error_sum.map_or_else(dash, |e| {
                    if e < ROUND_OFF_REST_ERROR_M {
                        rest_error(e)
                    } else {
                        sci3(e)
                    }
                })
            }));
        }
        t.row(cells);
    }
    t
}

/// The $`i`$-th iteration count (ascending) of a solver in the published tables.
pub fn iteration_count(solver: SolverId, index: usize) -> Option<usize> {
    let mut counts: Vec<usize> = published_rows()
        .iter()
        .filter(|r| r.solver == solver)
        .map(|r| r.iterations)
        .collect();
    counts.sort_unstable();
    counts.dedup();
    counts.get(index).copied()
}

/// The published rows a view (Tables 9-12) shows: per iteration index, XPBD, Fast m-s and
/// ADMM at `stiffness` and `dt`.
pub fn view_rows(stiffness: f64, dt: f64, indices: &[usize]) -> Vec<&'static PublishedRow> {
    let solvers = [SolverId::Xpbd, SolverId::FastMassSpring, SolverId::AdmmPd];
    indices
        .iter()
        .flat_map(|&i| solvers.iter().map(move |&s| (s, i)))
        .filter_map(|(s, i)| {
            let iterations = iteration_count(s, i)?;
            published_rows().iter().find(|r| {
                r.solver == s
                    && r.stiffness == stiffness
                    && r.dt_s == dt
                    && r.iterations == iterations
            })
        })
        .collect()
}

/// The rows of Tables 9-12: (stiffness, dt, iteration indices).
pub fn view_selection(table: u8) -> Option<(f64, f64, &'static [usize])> {
    match table {
        9 | 10 => Some((1e3, 0.1, &[0, 1])),
        11 => Some((1e6, 0.1, &[0, 1, 2])),
        12 => Some((1e6, 0.001, &[0, 1])),
        _ => None,
    }
}

/// Table 8: the abbreviations, and the colours of the figures.
pub fn table8() -> MarkdownTable {
    let mut t = MarkdownTable::new(&["abbreviation", "solver", "colour in the figures"]);
    for kind in [
        SolverId::Xpbd,
        SolverId::FastMassSpring,
        SolverId::AdmmPd,
        SolverId::BackwardEuler,
    ] {
        let colour = match kind {
            SolverId::BackwardEuler => "black (reference)",
            SolverId::Xpbd => "blue, darker for fewer iterations",
            SolverId::FastMassSpring => "orange, darker for fewer iterations",
            SolverId::AdmmPd => "green, darker for fewer iterations",
            _ => "one colour of its own",
        };
        t.row(vec![
            kind.display_name().into(),
            solver_name(kind).into(),
            colour.into(),
        ]);
    }
    t
}

/// The glossary of solver names: every solver of the registry, its one display name, its
/// identifier in the data files and on the command line, and the paper or section it follows.
pub fn solver_glossary() -> MarkdownTable {
    let mut t = MarkdownTable::new(&["name in this report", "code id", "what it is", "source"]);
    for id in SolverId::ALL {
        let info = id.info();
        t.row(vec![
            info.display_name.into(),
            format!("`{}`", info.id),
            info.summary.into(),
            info.source.into(),
        ]);
    }
    t
}

/// Table 9: rest-state error, published beside ours.
pub fn table9(results: &ResultSet) -> MarkdownTable {
    let (k, dt, indices) = view_selection(9).expect("table 9 is a view");
    let mut t = MarkdownTable::new(&[
        "solver",
        ">dt (s)",
        ">iter.",
        ">k (N/m)",
        &summed_error_header("pub."),
        &summed_error_header("ours"),
        ">ours/pub.",
    ]);
    for row in view_rows(k, dt, indices) {
        let m = measured(results, row);
        t.row(vec![
            row.solver.display_name().into(),
            full(row.dt_s),
            row.iterations.to_string(),
            stiffness_label(row.stiffness),
            printed(row).error.clone(),
            m.map_or_else(dash, |m| opt4(m.error_sum)),
            m.map_or_else(dash, ratio_cell),
        ]);
    }
    t
}

/// Tables 10-12: peaks, T/2 and relative T error, published beside ours.
pub fn kinetic_view(
    results: &ResultSet,
    forensics: Option<&Forensics>,
    table: u8,
) -> MarkdownTable {
    let (k, dt, indices) = view_selection(table).expect("tables 10-12 are views");
    let mut t = MarkdownTable::new(&[
        "status",
        "solver",
        ">dt (s)",
        ">iter.",
        ">peaks pub.",
        ">peaks ours",
        ">T/2 pub. (s)",
        ">T/2 ours (s)",
        ">rel. T err. pub.",
        ">rel. T err. ours",
    ]);
    for row in view_rows(k, dt, indices) {
        let p = printed(row);
        let m = measured(results, row);
        t.row(vec![
            status(m, forensics),
            row.solver.display_name().into(),
            full(row.dt_s),
            row.iterations.to_string(),
            p.ke_peaks.clone(),
            m.map_or_else(dash, peaks_cell),
            p.half_period_s.clone(),
            m.map_or_else(dash, |m| opt4(m.half_period_thesis)),
            p.period_rel_error.clone(),
            m.map_or_else(dash, |m| opt4(m.period_rel_error)),
        ]);
    }
    t
}

/// Any of Tables 1-12 as Markdown, with its title as a bold caption line.
pub fn render_table(results: &ResultSet, forensics: Option<&Forensics>, table: u8) -> String {
    let body = match table {
        1..=7 => results_table(results, forensics, table),
        8 => table8(),
        9 => table9(results),
        10..=12 => kinetic_view(results, forensics, table),
        _ => MarkdownTable::new(&["–"]),
    };
    format!("**{}**\n\n{}", title(table), body.render())
}

/// Counts of a group of rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tally {
    pub rows: usize,
    pub run: usize,
    pub reproduced: usize,
    /// Rows whose rest-state error is checked, and how many are within the band.
    pub error_checked: usize,
    pub error_within: usize,
}

impl Tally {
    fn add(&mut self, m: Option<&Measured>, forensics: Option<&Forensics>) {
        self.rows += 1;
        if let Some(m) = m {
            self.run += 1;
            self.reproduced += usize::from(reproduced(m, forensics));
            if let Some(within) = error_within_band(m) {
                self.error_checked += 1;
                self.error_within += usize::from(within);
            }
        }
    }
}

/// The tally of one of Tables 1-7 or of a view (10-12).
pub fn tally(results: &ResultSet, forensics: Option<&Forensics>, table: u8) -> Tally {
    let rows: Vec<&PublishedRow> = match view_selection(table) {
        Some((k, dt, indices)) => view_rows(k, dt, indices),
        None => published_table(table).collect(),
    };
    let mut t = Tally::default();
    for row in rows {
        t.add(measured(results, row), forensics);
    }
    t
}

/// The reproduction summary: rows reproduced per table, and the rest-state error check.
pub fn summary(results: &ResultSet, forensics: Option<&Forensics>) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "table",
        "solver",
        ">k (N/m)",
        ">rows",
        ">run",
        ">reproduced",
        ">error within 0.8-1.25 (rows with published error > 0.1)",
    ]);
    let mut total = Tally::default();
    for table in 1..=7u8 {
        let first = published_table(table).next().expect("tables 1-7 have rows");
        let k = if table == 1 {
            "1e3, 1e6".to_string()
        } else {
            stiffness_label(first.stiffness)
        };
        let n = tally(results, forensics, table);
        total.rows += n.rows;
        total.run += n.run;
        total.reproduced += n.reproduced;
        total.error_checked += n.error_checked;
        total.error_within += n.error_within;
        t.row(summary_cells(
            table.to_string(),
            first.solver.display_name(),
            k,
            n,
        ));
    }
    t.row(summary_cells("1-7".into(), "all", "both".into(), total));
    for table in 10..=12u8 {
        let (k, _, _) = view_selection(table).expect("views");
        t.row(summary_cells(
            table.to_string(),
            "view",
            stiffness_label(k),
            tally(results, forensics, table),
        ));
    }
    t
}

fn summary_cells(table: String, solver: &str, k: String, n: Tally) -> Vec<String> {
    let error = if n.error_checked == 0 {
        "–".to_string()
    } else {
        format!("{} of {}", n.error_within, n.error_checked)
    };
    vec![
        table,
        solver.to_string(),
        k,
        n.rows.to_string(),
        n.run.to_string(),
        format!("{} of {}", n.reproduced, n.run),
        error,
    ]
}

use mass_spring_solvers::studies::forensics::evidence::REST_ERROR_BAND;
pub use mass_spring_solvers::studies::forensics::NOISE_PEAK_J;
use mass_spring_solvers::studies::forensics::{Forensics, RowEvidence};

/// The best explanation of a row that is not reproduced, as the cells of section 5's table:
/// the peaks and T/2 against the published ones, what our run did (decided from our run, not
/// from the published numbers), then what section 6 found for the row (`evidence`, when the
/// forensic chapter was computed).
pub fn explain(m: &Measured, forensics: Option<&Forensics>) -> [String; 4] {
    let p = &m.published;
    let evidence: Option<&RowEvidence> = forensics.and_then(|f| f.evidence_of(p));
    let tolerance = peak_tolerance(p.ke_peaks);
    let peaks = format!(
        "{} against {} ({}, ±{tolerance})",
        m.peaks,
        p.ke_peaks,
        signed(m.peaks as i64 - p.ke_peaks as i64)
    );
    let half_period = match half_period_deviation(m) {
        Some(d) => format!(
            "{} s against {} s ({}, ±{} %)",
            sig4(m.half_period_thesis.unwrap_or(f64::NAN)),
            printed(p).half_period_s,
            percent(d),
            100.0 * HALF_PERIOD_TOLERANCE
        ),
        None => "no peak: no T/2".into(),
    };
    // A run's length is its last peak's stamp, peaks × T/2, ours and the published one's.
    let lengths = m
        .half_period_thesis
        .map(|t| (t * m.peaks as f64, p.half_period_s * p.ke_peaks as f64));
    let contradicted = forensics
        .filter(|f| m.reproduces() && !f.reproduces(m))
        .zip(p.error);
    let ours = if let Some((f, published)) = contradicted {
        let [at_981, at_98] = f.rest_errors_of(m);
        format!(
            "meets the reproduction rule, but its rest error is {}× the published ({}× against the reference \
             at 9.8 m/s²), outside the fitted band [{}, {}] of section 6",
            sig(at_981 / published, 3),
            sig(at_98 / published, 3),
            REST_ERROR_BAND[0],
            REST_ERROR_BAND[1],
        )
    } else if m.hit_time_limit {
        format!(
            "reached the time limit ({} s) before a peak fell below {STOP_THRESHOLD_J} J",
            sig4(m.end_time)
        )
    } else if let Some(e) = m
        .last_peak_energy
        .filter(|&e| m.peaks == 1 && e < STOP_THRESHOLD_J)
    {
        format!(
            "its first peak ({} J) is already below the {STOP_THRESHOLD_J} J threshold, so it stops \
             after one peak",
            sig4(e)
        )
    } else if m.last_peak_energy.is_some_and(|e| e < NOISE_PEAK_J) {
        format!(
            "its last peak (below {NOISE_PEAK_J:e} J) is round-off (forensic finding 1): after the real peaks \
             the rope creeps to rest and a noise wiggle is detected as a peak, so T/2 is set by arithmetic \
             details"
        )
    } else {
        let (more, fewer) = (
            "more peaks than the published",
            "fewer peaks than the published",
        );
        let count = if m.peaks > p.ke_peaks { more } else { fewer };
        match lengths {
            Some((ours, published)) => format!(
                "{count}, {} ({} s against {} s to the last peak)",
                if ours > published {
                    "over a longer run"
                } else if ours < published {
                    "over a shorter run"
                } else {
                    "over as long a run"
                },
                sig(ours, 3),
                sig(published, 3)
            ),
            None => count.to_string(),
        }
    };
    let found = match (evidence, p.solver) {
        (Some(e), _) if e.evidence.reproduced() => format!(
            "reproduced as {}: {} (configuration `{}` in `data/reproduction.csv`)",
            e.evidence.id(),
            e.configuration.summary(),
            e.configuration.id()
        ),
        (Some(e), _) => format!("classed {}", e.evidence.id()),
        (None, SolverId::Xpbd) => "not expected: an independent prototype and a third-party XPBD \
             kernel reproduce every published XPBD row"
            .into(),
        (None, SolverId::BackwardEuler) => {
            "not expected: round-off alone moves the k = 1e3 peak count by about ±2".into()
        }
        (None, _) => "the forensic chapter was not computed for this partial report".into(),
    };
    [peaks, half_period, capitalise(&ours), found]
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().collect::<String>() + c.as_str())
        .unwrap_or_default()
}

/// Every row of Tables 1-7 that is run and not reproduced, with its explanation, as a
/// Markdown table (one row each: the row, its peaks and T/2 against the published ones, what
/// our run did, what section 6 found).
pub fn explanations(results: &ResultSet, forensics: Option<&Forensics>) -> String {
    let mut t = MarkdownTable::new(&[
        "row",
        "peaks, ours against pub. (dev., tolerance)",
        "T/2 ours against pub. (dev., tolerance)",
        "our run",
        "section 6",
    ]);
    for table in 1..=7u8 {
        for row in published_table(table) {
            if let Some(m) = measured(results, row).filter(|m| !reproduced(m, forensics)) {
                let mut cells = vec![format!(
                    "Table {table}, {} dt = {} s, {}, k = {}",
                    row.solver.display_name(),
                    full(row.dt_s),
                    counted(row.iterations, "iteration"),
                    stiffness_label(row.stiffness),
                )];
                cells.extend(explain(m, forensics));
                t.row(cells);
            }
        }
    }
    if t.is_empty() {
        "Every row that was run is reproduced.\n".into()
    } else {
        t.render()
    }
}

/// The rounding of the report's numbers, stated once.
pub fn rounding_note() -> String {
    format!(
        "Our numbers are rounded to {SIGNIFICANT_DIGITS} significant digits; published peaks and T/2 are as \
         printed in the thesis (decimal comma written as a point)."
    )
}

//! Section 6's evidence: every row's class and what it rests on, the counts, the headline.

use crate::format::{full, opt4, opt_rest_error, percent, rest_error, sig4, MarkdownTable};
use crate::tables::{
    half_period_deviation, printed, published_table, stiffness_label, ERROR_RATIO_RANGE,
};
use mass_spring_solvers::studies::experiments::{Measured, PublishedRow};
use mass_spring_solvers::studies::forensics::evidence::Choice;
use mass_spring_solvers::studies::forensics::{Evidence, Forensics, RowEvidence};

/// `T7 0.1/1`: a row's table, time step and iterations.
pub fn row_label(row: &PublishedRow) -> String {
    let k = if row.table == 1 {
        format!(" (k = {})", stiffness_label(row.stiffness))
    } else {
        String::new()
    };
    format!("T{} {}/{}{k}", row.table, full(row.dt_s), row.iterations)
}

/// The tables 1-7 that have at least one row in the forensic results.
pub(super) fn tables_run(f: &Forensics) -> Vec<u8> {
    (1..=7u8)
        .filter(|&t| f.evidence.iter().any(|e| e.measured.published.table == t))
        .collect()
}

pub(super) fn count_cells(counts: [usize; 7]) -> Vec<String> {
    let total: usize = counts.iter().sum();
    std::iter::once(total.to_string())
        .chain(counts.iter().map(|c| c.to_string()))
        .collect()
}

/// Rows per evidence class, per table and in total, then the observations (twins once): the
/// top of the report.
pub fn counts_table(f: &Forensics) -> MarkdownTable {
    let mut header = vec!["table", ">rows"];
    let ids: Vec<String> = Evidence::ALL
        .iter()
        .map(|s| format!(">{}", s.id()))
        .collect();
    header.extend(ids.iter().map(String::as_str));
    let mut t = MarkdownTable::new(&header);
    for table in tables_run(f) {
        let first = published_table(table).next().expect("tables 1-7 have rows");
        let k = if table == 1 {
            "1e3, 1e6".to_string()
        } else {
            stiffness_label(first.stiffness)
        };
        let mut cells = vec![format!(
            "Table {table} ({}, k = {k})",
            first.solver.display_name()
        )];
        cells.extend(count_cells(f.counts(Some(table))));
        t.row(cells);
    }
    let mut cells = vec!["all rows".to_string()];
    cells.extend(count_cells(f.counts(None)));
    t.row(cells);
    let mut cells = vec!["observations (twins once)".to_string()];
    cells.extend(count_cells(f.observation_counts()));
    t.row(cells);
    t
}

/// `15 faithful, 19 interpretation, ...`.
pub(super) fn class_list(counts: [usize; 7]) -> String {
    Evidence::ALL
        .iter()
        .zip(counts)
        .map(|(e, n)| format!("{n} {}", e.id()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The headline sentence: the class counts, over rows and over observations.
pub fn headline(f: &Forensics) -> String {
    let rows = f.counts(None);
    let observations = f.observation_counts();
    let total: usize = rows.iter().sum();
    let distinct: usize = observations.iter().sum();
    format!(
        "**Evidence for the {total} published rows**, one written rule: {}. Counted as \
         observations, with the {} twin pairs (rows whose published numbers and our runs coincide) taken \
         once, the {distinct} observations are {}. Each row takes the weakest class of the choices it rests \
         on (section 6.1): a convention identified on the rows it affects makes them interpretation, a value chosen with a row in view (the scene on Table 1, calibration) makes it fitted.",
        class_list(rows),
        f.twins.pairs.len(),
        class_list(observations),
    )
}

/// The rows a choice weakens (to a class below faithful).
pub fn rows_resting_on(f: &Forensics, choice: Choice) -> Vec<&PublishedRow> {
    f.evidence
        .iter()
        .filter(|e| e.effects.iter().any(|c| c.choice == choice))
        .map(|e| &e.measured.published)
        .collect()
}

/// The choices the rule weighs: what was chosen, the other reading, how it was identified,
/// the class it gives and the rows that rest on it.
pub fn choices_table(f: &Forensics) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "scope",
        "choice",
        "other reading run",
        "how it was identified",
        "class it gives",
        ">rows resting on it",
        "which",
    ]);
    for choice in Choice::ALL {
        let rows = rows_resting_on(f, choice);
        let class = f
            .evidence
            .iter()
            .flat_map(|e| &e.effects)
            .find(|c| c.choice == choice)
            .map_or("–", |c| c.evidence.id());
        t.row(vec![
            choice.scope().into(),
            choice.chosen().into(),
            choice.other_reading().into(),
            choice.provenance().into(),
            class.into(),
            rows.len().to_string(),
            label_list(&rows),
        ]);
    }
    t
}

pub(super) fn peaks_cell(m: &Measured) -> String {
    if m.hit_time_limit {
        format!("{} (cut at {} s)", m.peaks, sig4(m.end_time))
    } else {
        m.peaks.to_string()
    }
}

/// `+0.48 % (marginal)`.
pub(super) fn deviation_cell(m: &Measured) -> String {
    match half_period_deviation(m) {
        None => "–".into(),
        Some(d) if m.marginal() => format!("{} (marginal)", percent(d)),
        Some(d) => percent(d),
    }
}

/// The class of every row, with the numbers of the configuration that produced them, and its
/// notes (what it rests on, its twin, what else was measured) numbered below the table.
pub fn evidence_table(f: &Forensics) -> (MarkdownTable, String) {
    let mut t = MarkdownTable::new(&[
        "row",
        "evidence",
        "configuration",
        ">peaks pub.",
        ">peaks ours",
        ">T/2 pub. (s)",
        ">T/2 ours (s)",
        ">T/2 dev.",
        &crate::tables::summed_error_header("ours"),
        ">note",
    ]);
    let mut notes = String::new();
    let mut n = 0;
    for e in &f.evidence {
        let m = &e.measured;
        let row = &m.published;
        let p = printed(row);
        let note = row_note(f, e);
        let reference = if note.is_empty() {
            "–".to_string()
        } else {
            n += 1;
            notes += &format!("{n}. {}: {note}\n", row_label(row));
            format!("[{n}]")
        };
        t.row(vec![
            row_label(row),
            e.evidence.id().into(),
            e.configuration.short_label(),
            p.ke_peaks.clone(),
            peaks_cell(m),
            p.half_period_s.clone(),
            opt4(m.half_period_thesis),
            deviation_cell(m),
            opt_rest_error(m.error_sum),
            reference,
        ]);
    }
    (t, notes)
}

/// What a row rests on and what else was measured: each weakening choice with the other
/// reading's outcome, the twin, the note of its selection.
pub(super) fn row_note(f: &Forensics, e: &RowEvidence) -> String {
    let mut parts: Vec<String> = e
        .effects
        .iter()
        .map(|c| {
            format!(
                "{} ({}): {}",
                short_choice(c.choice),
                c.evidence.id(),
                c.note
            )
        })
        .collect();
    if let Some(twin) = f.twins.twin_of(&e.measured.published) {
        parts.push(format!("twin of {}", row_label(twin)));
    }
    if !e.note.is_empty() {
        parts.push(e.note.clone());
    }
    parts.join("; ")
}

/// A choice in two or three words, for the notes.
pub(super) fn short_choice(c: Choice) -> &'static str {
    match c {
        Choice::SceneFit => "scene fit",
        Choice::PeakStamp => "peak time stamp",
        Choice::Clock => "f32 clock",
        Choice::Gravity => "gravity",
        Choice::ReferenceGravity => "reference's gravity",
        Choice::LiuFirstIterate => "first iterate",
        Choice::LiuHypothesis => "Fast m-s hypothesis",
        Choice::AdmmStart => "ADMM start",
    }
}

pub(super) fn label_list(rows: &[&PublishedRow]) -> String {
    if rows.is_empty() {
        "none".into()
    } else {
        rows.iter()
            .map(|r| row_label(r))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

pub(super) fn ratio_cell(ours: f64, published: Option<f64>) -> String {
    match published {
        _ if ours < crate::format::ROUND_OFF_REST_ERROR_M => rest_error(ours),
        Some(p) => {
            let r = ours / p;
            let within = (ERROR_RATIO_RANGE.0..=ERROR_RATIO_RANGE.1).contains(&r);
            format!(
                "{} ({}{})",
                sig4(ours),
                sig4(r),
                if within { " ✓" } else { "" }
            )
        }
        None => rest_error(ours),
    }
}

//! The forensic chapter of the report: how each of the 56 published rows arose, with the
//! strength of the evidence for it.
//!
//! From [`Forensics`] (computed by [`mass_spring_solvers::studies::forensics`]): the evidence-class counts shown at
//! the top of the report, the rule of evidence and the choices it weighs, the class of every
//! row with the configuration that produced our numbers, the time conventions' other readings,
//! Liu's open point and fitted hypothesis with its parameters' intervals, the ADMM candidates,
//! and the gravity-mismatch study of the rest-state error floors. Everything here only
//! formats; every number in the prose comes from the runs.

use crate::format::{
    full, opt4, opt_rest_error, percent, rest_error, sci3, short, sig, sig4, MarkdownTable,
};
use crate::tables::{
    half_period_deviation, printed, published_table, stiffness_label, ERROR_CHECK_ABOVE,
    ERROR_RATIO_RANGE,
};
use mass_spring_solvers::model::metrics::STOP_THRESHOLD_J;
use mass_spring_solvers::model::scene::THESIS_GRAVITY;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{
    better_time_convention, published_rows, same_experiment, Measured, PublishedRow, ResultSet,
    TimeConvention, MARGINAL_HALF_PERIOD,
};
use mass_spring_solvers::studies::forensics::configurations::{
    LiuHypothesis, LIU_DAMPING_GRID, VARIANT_MAX_ITERATIONS, VARIANT_TIME_FACTOR,
};
use mass_spring_solvers::studies::forensics::evidence::{
    Choice, ADMM_CANDIDATES_TRIED, ADMM_PROTOTYPE_CANDIDATES,
};
use mass_spring_solvers::studies::forensics::gravity::{Hypothesis, DISTINCT_ERROR_M, PROVENANCE};
use mass_spring_solvers::studies::forensics::liu_fit::{
    peaks_within_tolerance, DAMPING_BISECTIONS, THRESHOLD_FLOOR_J,
};
use mass_spring_solvers::studies::forensics::{
    AdmmCandidate, ConfigurationId, Evidence, Forensics, RowEvidence, MISMATCHED_GRAVITY,
};

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
fn tables_run(f: &Forensics) -> Vec<u8> {
    (1..=7u8)
        .filter(|&t| f.evidence.iter().any(|e| e.measured.published.table == t))
        .collect()
}

fn count_cells(counts: [usize; 7]) -> Vec<String> {
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
fn class_list(counts: [usize; 7]) -> String {
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
         on (section 6.1): a scene or convention identified on the rows it affects makes them interpretation, a value chosen with a row in view makes it fitted.",
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

fn peaks_cell(m: &Measured) -> String {
    if m.hit_time_limit {
        format!("{} (cut at {} s)", m.peaks, sig4(m.end_time))
    } else {
        m.peaks.to_string()
    }
}

/// `+0.48 % (marginal)`.
fn deviation_cell(m: &Measured) -> String {
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
fn row_note(f: &Forensics, e: &RowEvidence) -> String {
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
fn short_choice(c: Choice) -> &'static str {
    match c {
        Choice::SceneFit => "scene fit",
        Choice::PeakStamp => "peak time stamp",
        Choice::Clock => "f32 clock",
        Choice::Gravity => "gravity",
        Choice::LiuFirstIterate => "first iterate",
        Choice::LiuHypothesis => "Fast m-s hypothesis",
        Choice::AdmmStart => "ADMM start",
    }
}

/// `0.42 %`: a magnitude as a percentage.
fn unsigned_percent(x: f64) -> String {
    percent(x).trim_start_matches('+').to_string()
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// Per table, which T/2 convention of ours lies closer to the published values (the faithful
/// runs, rows with both T/2).
pub fn time_convention_table(faithful: &ResultSet) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "table",
        "solver",
        ">rows",
        ">f32 detection-step closer",
        ">exact closer",
        ">median |dev.| f32 detection-step",
        ">median |dev.| exact",
        "fits better",
    ]);
    for table in 1..=7u8 {
        let rows: Vec<&Measured> = faithful
            .table(table)
            .filter(|m| m.half_period_thesis.is_some() && m.half_period_exact.is_some())
            .collect();
        if rows.is_empty() {
            continue;
        }
        let closer = |c: TimeConvention| {
            rows.iter()
                .filter(|m| {
                    better_time_convention(&m.published, m.half_period_thesis, m.half_period_exact)
                        == Some(c)
                })
                .count()
        };
        let dev = |t: fn(&Measured) -> Option<f64>| {
            median(
                rows.iter()
                    .filter_map(|m| t(m).map(|x| (x / m.published.half_period_s - 1.0).abs()))
                    .collect(),
            )
        };
        let (thesis, exact) = (
            closer(TimeConvention::Thesis),
            closer(TimeConvention::Exact),
        );
        let (dev_thesis, dev_exact) = (dev(|m| m.half_period_thesis), dev(|m| m.half_period_exact));
        t.row(vec![
            table.to_string(),
            rows[0].published.solver.display_name().into(),
            rows.len().to_string(),
            thesis.to_string(),
            exact.to_string(),
            dev_thesis.map_or("–".into(), unsigned_percent),
            dev_exact.map_or("–".into(), unsigned_percent),
            match thesis.cmp(&exact) {
                std::cmp::Ordering::Greater => TimeConvention::Thesis.id().into(),
                std::cmp::Ordering::Less => TimeConvention::Exact.id().into(),
                std::cmp::Ordering::Equal => "neither".into(),
            },
        ]);
    }
    t
}

fn label_list(rows: &[&PublishedRow]) -> String {
    if rows.is_empty() {
        "none".into()
    } else {
        rows.iter()
            .map(|r| row_label(r))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// What happened in a failed run, without the solver's name: `diverged at step 35 (t = 3.5 s)`.
fn short_error(e: &str) -> String {
    let what = e
        .find(" diverged at ")
        .or_else(|| e.find(" step "))
        .map_or(e, |i| &e[i + 1..]);
    what.split(':').next().unwrap_or(what).trim().to_string()
}

/// Every ADMM configuration tried (the faithful one first), with the rows it reproduces.
pub fn variants_table(f: &Forensics, faithful: &ResultSet) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "configuration",
        "departure from Algorithm 4",
        ">rows run",
        ">reproduced",
        ">of the faithful misses",
        "rows reproduced",
        "runs that failed or were cut",
    ]);
    let faithful_rows: Vec<&Measured> = faithful
        .rows
        .iter()
        .filter(|m| m.published.solver == SolverId::AdmmPd)
        .collect();
    let misses: Vec<&PublishedRow> = faithful_rows
        .iter()
        .filter(|m| !m.reproduces())
        .map(|m| &m.published)
        .collect();
    let mut add =
        |id: ConfigurationId, rows: Vec<&Measured>, failed: Vec<(&PublishedRow, &str)>| {
            let reproduced: Vec<&PublishedRow> = rows
                .iter()
                .filter(|m| m.reproduces())
                .map(|m| &m.published)
                .collect();
            let misses_reproduced = reproduced
                .iter()
                .filter(|r| misses.iter().any(|m| same_experiment(m, r)))
                .count();
            let mut trouble: Vec<String> = failed
                .iter()
                .map(|(r, e)| format!("{} {}", row_label(r), short_error(e)))
                .collect();
            let limited: Vec<&PublishedRow> = rows
                .iter()
                .filter(|m| m.hit_time_limit)
                .map(|m| &m.published)
                .collect();
            if !limited.is_empty() {
                trouble.push(format!("cut: {}", label_list(&limited)));
            }
            let departure = match id {
                ConfigurationId::Admm(c) => format!("{} ({})", c.variant().label(), c.origin()),
                _ => "none (Algorithm 4 as printed)".to_string(),
            };
            t.row(vec![
                id.id(),
                departure,
                (rows.len() + failed.len()).to_string(),
                reproduced.len().to_string(),
                format!("{misses_reproduced} of {}", misses.len()),
                label_list(&reproduced),
                if trouble.is_empty() {
                    "–".into()
                } else {
                    trouble.join("; ")
                },
            ]);
        };
    add(ConfigurationId::Faithful, faithful_rows, Vec::new());
    for candidate in AdmmCandidate::ALL {
        if let Some(run) = f.run(ConfigurationId::Admm(candidate)) {
            add(
                run.id,
                run.rows.iter().collect(),
                run.failed.iter().map(|(r, e)| (r, e.as_str())).collect(),
            );
        }
    }
    t
}

/// How many ADMM rows the start x⁰ = x_n + dt·v_n reproduces, of how many.
pub fn admm_start_inertial_count(f: &Forensics) -> (usize, usize) {
    let admm_rows = published_rows()
        .iter()
        .filter(|r| r.solver == SolverId::AdmmPd)
        .count();
    let reproduced = f
        .run(ConfigurationId::Admm(AdmmCandidate::StartInertial))
        .map_or(0, |r| r.rows.iter().filter(|m| m.reproduces()).count());
    (reproduced, admm_rows)
}

/// Liu's open point: the rows each reading of the first iterate reproduces.
pub fn liu_readings_table(f: &Forensics, faithful: &ResultSet) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "table",
        "first iterate",
        ">rows",
        ">reproduced",
        "rows reproduced",
    ]);
    let y = f.run(ConfigurationId::LiuStartInertial);
    for table in [4u8, 5] {
        let x_n: Vec<&Measured> = faithful.table(table).collect();
        let y_rows: Vec<&Measured> = y
            .map(|r| {
                r.rows
                    .iter()
                    .filter(|m| m.published.table == table)
                    .collect()
            })
            .unwrap_or_default();
        for (name, rows) in [("x_n (default)", x_n), ("y = x_n + dt·v_n", y_rows)] {
            let reproduced: Vec<&PublishedRow> = rows
                .iter()
                .filter(|m| m.reproduces())
                .map(|m| &m.published)
                .collect();
            t.row(vec![
                table.to_string(),
                name.into(),
                rows.len().to_string(),
                reproduced.len().to_string(),
                label_list(&reproduced),
            ]);
        }
    }
    t
}

/// Liu started at y with one iteration, on the ADMM one-iteration rows.
pub fn liu_as_admm_table(f: &Forensics) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "ADMM row",
        ">peaks pub.",
        ">peaks Fast m-s (y, 1 it.)",
        ">T/2 pub. (s)",
        ">T/2 Fast m-s (s)",
        ">T/2 dev.",
        "meets the rule",
    ]);
    for m in &f.liu_as_admm {
        let p = printed(&m.published);
        t.row(vec![
            row_label(&m.published),
            p.ke_peaks.clone(),
            peaks_cell(m),
            p.half_period_s.clone(),
            opt4(m.half_period_thesis),
            half_period_deviation(m).map_or("–".into(), percent),
            if m.reproduces() { "✓" } else { "✗" }.into(),
        ]);
    }
    t
}

/// The k = 1e3 rows the damping scan is read on: those whose peak count the damping moves.
fn damping_scan_rows(f: &Forensics) -> Vec<&PublishedRow> {
    f.liu
        .grid
        .first()
        .map(|p| {
            p.rows
                .iter()
                .filter(|m| m.published.stiffness < 1e5 && m.published.ke_peaks > 2)
                .map(|m| &m.published)
                .collect()
        })
        .unwrap_or_default()
}

/// The damping scan: each damping value's peak counts on the k = 1e3 rows (no exemption, the
/// printed threshold), and how many of them are within tolerance.
pub fn damping_scan(f: &Forensics) -> Vec<(f64, Vec<usize>, usize)> {
    let rows = damping_scan_rows(f);
    (0..LIU_DAMPING_GRID.len())
        .map(|damping| {
            let point = f.liu.point(LiuHypothesis {
                damping,
                ..LiuHypothesis::PRINTED
            });
            let measured: Vec<&Measured> = rows
                .iter()
                .map(|r| point.row(r).expect("the grid holds every Fast m-s row"))
                .collect();
            (
                LIU_DAMPING_GRID[damping],
                measured.iter().map(|m| m.peaks).collect(),
                measured
                    .iter()
                    .filter(|m| peaks_within_tolerance(m))
                    .count(),
            )
        })
        .collect()
}

fn damping_scan_table(f: &Forensics) -> MarkdownTable {
    let rows = damping_scan_rows(f);
    let labels: Vec<String> = rows.iter().map(|r| format!(">{}", row_label(r))).collect();
    let mut header = vec!["c (s⁻¹)"];
    header.extend(labels.iter().map(String::as_str));
    header.push(">peak counts within tolerance");
    let mut t = MarkdownTable::new(&header);
    let mut published = vec!["published".to_string()];
    published.extend(rows.iter().map(|r| r.ke_peaks.to_string()));
    published.push("–".into());
    t.row(published);
    for (c, peaks, within) in damping_scan(f) {
        let mut cells = vec![short(c)];
        cells.extend(peaks.iter().map(|p| p.to_string()));
        cells.push(format!("{within} of {}", rows.len()));
        t.row(cells);
    }
    t
}

/// The fitted point's intervals in words: the damping interval bracketed by runs, the
/// threshold interval at k = 1e6 with the factor it means.
pub fn intervals_text(f: &Forensics) -> String {
    let fit = &f.liu;
    let h = fit.in_sample;
    let (lo, hi) = fit.damping.inside();
    let fitted = h.velocity_damping();
    let half_width = 0.5 * (hi - lo);
    let mut s = format!(
        "**Damping.** With the fit's exemption and threshold, every row the fit reproduces stays reproduced \
         for c in [{}, {}] s⁻¹ ({} runs of the rows that fail at the grid's neighbours, {DAMPING_BISECTIONS} \
         halvings of each bracket; the nearest values tried where a row fails: {} and {} s⁻¹). The rows pin c to \
         ±{} s⁻¹ around {}: a blind grid of spacing 0.01 s⁻¹ would hold an admissible value by chance in about \
         {} % of placements.",
        sig(lo, 5),
        sig(hi, 5),
        fit.damping_probes.iter().map(|p| p.rows.len()).sum::<usize>(),
        sig(fit.damping.low.outside, 5),
        sig(fit.damping.high.outside, 5),
        sig(half_width, 2),
        short(fitted),
        sig(100.0 * (hi - lo) / 0.01, 2),
    );
    s += &match fit.threshold {
        Some((low, high)) => format!(
            " **Threshold.** At k = 1e6, with the fitted damping, the rows stay reproduced for thresholds in \
             ({}, {}] J{}, read off runs continued to {THRESHOLD_FLOOR_J:e} J: the kinetic energy multiplied by \
             {} to {} before the printed {STOP_THRESHOLD_J} J test.",
            sig(low, 3),
            sig(high, 3),
            if low <= THRESHOLD_FLOOR_J {
                " (the lower end is where the runs stopped, not a measured end)"
            } else {
                ""
            },
            sig(STOP_THRESHOLD_J / high, 3),
            sig(STOP_THRESHOLD_J / low, 3),
        ),
        None => " **Threshold.** No k = 1e6 row is reproduced by the fit.".into(),
    };
    s
}

fn ratio_cell(ours: f64, published: Option<f64>) -> String {
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

/// The gravity hypotheses counted: per stiffness, the floor observations within the band
/// against our reference runs (with their distinct values) and against the exact equilibria.
pub fn gravity_counts_table(f: &Forensics) -> MarkdownTable {
    let g = &f.gravity;
    let band = format!(
        "{}-{}",
        short(ERROR_RATIO_RANGE.0),
        short(ERROR_RATIO_RANGE.1)
    );
    let ours = format!(">within {band} of the published floor, against our reference");
    let distinct = format!(">distinct values among them (to {DISTINCT_ERROR_M:e} m)");
    let exact = format!(">within {band}, against the exact equilibrium");
    let mut t = MarkdownTable::new(&[
        "hypothesis",
        ">k (N/m)",
        ">floor observations",
        ours.as_str(),
        distinct.as_str(),
        exact.as_str(),
    ]);
    for c in &g.counts {
        t.row(vec![
            c.hypothesis.label().into(),
            stiffness_label(c.stiffness),
            c.rows.to_string(),
            c.within.to_string(),
            c.distinct.to_string(),
            c.within_exact.to_string(),
        ]);
    }
    t
}

/// The hypothesis with the most floor observations within the band at stiffness `k`, against
/// our reference (`exact` false) or the exact equilibria; ties give None.
pub fn gravity_leader(f: &Forensics, k: f64, exact: bool) -> Option<Hypothesis> {
    let within = |h: Hypothesis| {
        let c = f.gravity.count(h, k);
        if exact {
            c.within_exact
        } else {
            c.within
        }
    };
    let best = Hypothesis::ALL.into_iter().map(within).max()?;
    let mut leaders = Hypothesis::ALL.into_iter().filter(|h| within(*h) == best);
    let first = leaders.next()?;
    leaders.next().is_none().then_some(first)
}

/// The conclusion of the gravity study, from the numbers.
pub fn gravity_verdict(f: &Forensics) -> String {
    let g = &f.gravity;
    let mut s = String::new();
    let mut leaders = Vec::new();
    let mut margins_shrink = false;
    for r in &g.residuals {
        let k = r.stiffness;
        let (solver, reference) = (
            g.count(Hypothesis::SolverMismatched, k),
            g.count(Hypothesis::ReferenceMismatched, k),
        );
        s += &format!(
            "At k = {}, our reference stopped {} m (sum of distances) from the exact 9.81 m/s² equilibrium, {} % \
             of the {} m shift between the 9.81 and 9.8 equilibria. Of the {} floor observations, the solvers \
             at 9.8 m/s² put {} within the band and the reference at 9.8 m/s² puts {}; against the exact \
             equilibria, {} and {}. ",
            stiffness_label(k),
            sig(r.residual, 3),
            sig(100.0 * r.residual / r.shift, 2),
            sig(r.shift, 3),
            solver.rows,
            solver.within,
            reference.within,
            solver.within_exact,
            reference.within_exact,
        );
        leaders.push((gravity_leader(f, k, false), gravity_leader(f, k, true)));
        let margin = |a: usize, b: usize| a as i64 - b as i64;
        margins_shrink |= margin(solver.within_exact, reference.within_exact)
            < margin(solver.within, reference.within);
    }
    let first = leaders.first().and_then(|(ours, _)| *ours);
    let one_leader = first.is_some()
        && leaders
            .iter()
            .all(|(ours, exact)| *ours == first && *exact == first);
    s += &match (one_leader, first) {
        (true, Some(h)) => format!(
            "The same hypothesis leads at both stiffnesses and against both references: {}{}. ",
            h.label(),
            if margins_shrink {
                ", though by less against the exact equilibria: part of its lead comes from where our \
                 reference stopped"
            } else {
                ""
            }
        ),
        _ => "No one hypothesis leads at both stiffnesses against both references. ".to_string(),
    };
    s += "The floors are therefore at most **consistent with** a gravity mismatch: the study was not designed \
          before its run, and a floor depends on where each reference run stopped in its residual oscillation, \
          which for the thesis's reference no published number fixes. ";
    let broken = g.broken_by_mismatch();
    s += &format!(
        "The mismatch and the reproduced rows conflict at the 0.5 % edge: with the solvers at {} m/s², {} of the {} \
         rows reproduced at {} m/s² no longer meet the rule (peaks and T/2){}; under the rule of evidence \
         (section 6.1) those rows are interpretation.",
        short(MISMATCHED_GRAVITY),
        broken.len(),
        g.rows.iter().filter(|r| r.reproduced_at_981).count(),
        short(THESIS_GRAVITY),
        if broken.is_empty() {
            String::new()
        } else {
            format!(
                ": {}",
                label_list(&broken.iter().map(|r| &r.published).collect::<Vec<_>>())
            )
        }
    );
    s
}

/// The gravity study, every solver row: the published error beside ours with both runs at
/// 9.81 m/s², with the reference at 9.8, and with the solver at 9.8 (sum of distances;
/// ours/published in brackets, ✓ within the band).
pub fn gravity_table(f: &Forensics) -> MarkdownTable {
    let g = short(MISMATCHED_GRAVITY);
    let g0 = short(THESIS_GRAVITY);
    let same = format!(">both at {g0}");
    let reference = format!(">reference at {g}");
    let solver = format!(">solver at {g}");
    let peaks = format!("solver at {g}: peaks, T/2");
    let mut t = MarkdownTable::new(&[
        "row",
        "configuration",
        &crate::tables::summed_error_header("pub."),
        same.as_str(),
        reference.as_str(),
        solver.as_str(),
        peaks.as_str(),
    ]);
    for r in &f.gravity.rows {
        let row = &r.published;
        let m = &r.solver_mismatched_run;
        let floor = if r.is_floor() { " (floor)" } else { "" };
        t.row(vec![
            row_label(row),
            r.configuration.short_label(),
            format!("{}{floor}", row.error.map_or("–".into(), sci3)),
            ratio_cell(r.same_gravity.sum, row.error),
            ratio_cell(r.reference_mismatched.sum, row.error),
            ratio_cell(r.solver_mismatched.sum, row.error),
            format!(
                "{}, {}{}",
                m.peaks,
                opt4(m.half_period_thesis),
                if m.reproduces() { " ✓" } else { " ✗" }
            ),
        ]);
    }
    t
}

/// How many of the faithful ADMM misses oscillate longer than published (more peaks) and how
/// many stop earlier.
pub fn admm_misses_by_direction(faithful: &ResultSet) -> (usize, usize) {
    let misses: Vec<&Measured> = faithful
        .rows
        .iter()
        .filter(|m| m.published.solver == SolverId::AdmmPd && !m.reproduces())
        .collect();
    let longer = misses
        .iter()
        .filter(|m| m.published.ke_peaks > m.peaks)
        .count();
    (longer, misses.len() - longer)
}

/// The forensic section of REPORT.md (without its heading), for the faithful result set
/// `faithful` that `f` was computed from.
pub fn section(f: &Forensics) -> String {
    let mut md = headline(f);
    md += "\n\n";
    md += &counts_table(f).render();
    md += "\n";
    md += "**The rule of evidence** (one rule, `mass_spring_solvers::studies::forensics::evidence`). A row's reproduction rests on the \
           printed algorithm and on *choices*: values at points the thesis leaves open (the scene fitted on Table \
           1, conventions 4 and 5 of `docs/thesis-scene.md`, the gravity, Liu's first iterate) and departures from \
           the printed algorithm (the Fast m-s hypothesis, the ADMM start). Each choice gives the row a class, strongest \
           first: **faithful** (every reading of the choice we ran reproduces the row: it does not rest on it); \
           **interpretation** (a point the text leaves open, resolved one way, where the other reading does not \
           reproduce the row, its outcome given, or where the choice was identified on this row); **predicted** \
           (a value chosen with neither this row nor its twin in view, at any time in this repository's history \
           or documents, reproduces it, and the history shows the test before the data); **selected** (a \
           departure chosen from several candidates tried on the same rows); **fitted** (a value chosen with \
           this row or its twin in view, whatever a later split does). A row takes the weakest class any of its \
           choices gives it. Before any of this, the noise test: a row whose match rests on a kinetic-energy peak \
           below 1e-15 J (forensic finding 1), or whose T/2 spans more than the 0.5 % tolerance across runs that \
           have its peak count and agree to round-off before their last peak, is **noise-limited**; a row none \
           reproduces is noise-limited by the same test on the run with its exact peak count, else \
           **unexplained**. Twins, rows whose published numbers and our runs coincide, count once in every \
           count. A run cut at its time limit never counts as reproduced. The departures are labelled \
           configurations of `mass_spring_solvers::studies::forensics`; the faithful solvers and the results of sections 4-5 know \
           nothing of them. The machine-readable form is [`data/reproduction.csv`](data/reproduction.csv).\n\n";
    md += &format!(
        "The scene itself (anchors, taut start, gravity, the two time conventions) is the specification every \
         configuration runs on, the faithful one included: a row on which a scene-level choice was identified, \
         or which fails under its other reading, is interpretation; the other rows were not used to choose it. \
         The twin pairs: {}.\n\n",
        f.twins
            .pairs
            .iter()
            .map(|(a, b)| format!("{} = {}", row_label(a), row_label(b)))
            .collect::<Vec<_>>()
            .join(", ")
    );
    md += "### 6.1 The choices and the rows that rest on them\n\n";
    md += &choices_table(f).render();
    md += "\nThe evidence of every row, the time conventions' other readings, the Fast m-s hypothesis with its \
           parameters' intervals, every ADMM candidate and the gravity study are in appendix A.\n\n";
    md
}

/// The forensic chapter's details (the report's appendix A, without its heading): every row's
/// evidence (followed by `parity_figure`, ours against published, as Markdown), the time
/// conventions, the Liu hypothesis, the ADMM candidates, the gravity study.
pub fn appendix(f: &Forensics, faithful: &ResultSet, parity_figure: &str) -> String {
    let mut md = String::new();
    md += "### A.1 Evidence for every row\n\n";
    md += &format!(
        "Our numbers are those of the configuration named; errors against our faithful reference of the same \
         stiffness, as the sum of per-node distances (measurement convention 7 of `docs/thesis-scene.md`; below {:e} m they are the round-off of \
         converged solves and are printed as that bound). \"marginal\" marks a row that passes with a T/2 \
         deviation above {} %.\n\n",
        crate::format::ROUND_OFF_REST_ERROR_M,
        short(100.0 * MARGINAL_HALF_PERIOD)
    );
    let (table, notes) = evidence_table(f);
    md += &table.render();
    md += "\n";
    md += &notes;
    md += "\n";
    md += parity_figure;
    md += "### A.2 The time conventions and their other readings\n\n";
    md += "Convention 4 stamps a peak at the step that detects it; its other reading stamps it at its own sample. \
           Convention 5 accumulates time in f32; its other reading in f64. At dt = 1e-3 s either reading moves T/2 \
           by a few thousandths of a percent to a few tenths, so Table 1 cannot identify the peak time stamp; the \
           rows that can are listed in section 6.1. Per table, the faithful runs: how many rows' published T/2 lies \
           closer to our f32 detection-step value and how many to our exact value (the 0.5 % tolerance is wider \
           than the gap between the two at dt = 1e-3).\n\n";
    md += &time_convention_table(faithful).render();
    md += "\n### A.3 Fast m-s: the open first iterate and the fitted hypothesis\n\n";
    md += "Algorithm 3 does not say where each step's iteration starts. Both readings were run on every Fast m-s row; \
           a row reproduced by one only is an interpretation.\n\n";
    md += &liu_readings_table(f, faithful).render();
    md += "\nStarted at y with one iteration, Fast m-s's step is almost ADMM's with the start x⁰ = x_n + dt·v_n (appendix \
           A.4). Run on the ADMM one-iteration rows, measured against the published ADMM numbers:\n\n";
    md += &liu_as_admm_table(f).render();
    let reproduced = f.liu_as_admm.iter().filter(|m| m.reproduces()).count();
    md += &format!(
        "\n{reproduced} of the {} published ADMM one-iteration rows meet the rule with Fast m-s started at y.\n\n",
        f.liu_as_admm.len()
    );
    let fitted_rows = rows_resting_on(f, Choice::LiuHypothesis);
    md += &format!(
        "Forensic findings 2-4 form one hypothesis with three free parameters: the first peak exempt from the \
         stopping threshold, a velocity damping c after each step, and a stopping threshold at k = 1e6. Its \
         values, c = 0.05 s⁻¹ and 1e-4 J, were fitted on the Fast m-s rows' peak counts (findings 3 and 4 of \
         `docs/thesis-scene.md`, in the repository's first commit); the grid of {} points (c in {{{}}} s⁻¹, \
         threshold 1e-3 or 1e-4 J at k = 1e6, exemption or not) was laid around them later. So every row it \
         reproduces is **fitted**, {} rows ({}), and no split of the same rows can make one predicted. The fit: exact peak \
         counts first, then counts within tolerance, then rows meeting the full rule, twins once; ties go to the \
         least departure. The damping scan on the k = 1e3 rows whose peak count it moves (no exemption, printed \
         threshold):\n\n",
        LiuHypothesis::grid().len(),
        LIU_DAMPING_GRID.iter().map(|c| short(*c)).collect::<Vec<_>>().join(", "),
        fitted_rows.len(),
        label_list(&fitted_rows),
    );
    md += &damping_scan_table(f).render();
    let in_sample = f.liu.point(f.liu.in_sample);
    md += &format!(
        "\nThe fit picks **{}**: {} of {} peak counts within tolerance, {} rows meeting the full rule (twins once). \
         How tightly the rows pin its parameters:\n\n{}\n\n",
        f.liu.in_sample.label(),
        f.twins
            .observations(&in_sample.rows, |m| &m.published)
            .filter(|m| peaks_within_tolerance(m))
            .count(),
        f.twins
            .observations(&in_sample.rows, |m| &m.published)
            .count(),
        f.liu.reproduced(&f.twins).len(),
        intervals_text(f),
    );
    md += "The exemption is a yes-or-no choice fitted on Table 5's one-iteration rows at dt = 0.1 and 0.01 s \
           (finding 2), whose first peak is already below the threshold; both end on a round-off peak, so the \
           exemption reproduces no row outside the noise-limited ones. Every grid run is in \
           [`data/liu_grid.csv`](data/liu_grid.csv).\n";
    md += "\n### A.4 ADMM: every candidate tried\n\n";
    let (n, of) = admm_start_inertial_count(f);
    let (longer, earlier) = admm_misses_by_direction(faithful);
    md += &format!(
        "Of the {} ADMM rows the faithful method misses, {longer} published runs oscillate longer than ours (more \
         peaks) and {earlier} stop earlier (forensic finding 6). {} labelled departures from Algorithm 4 \
         (`forensics::admm_variants`) were run on the ADMM rows, after {} others tried with an independent \
         prototype ({}), none of which reproduced a row: {ADMM_CANDIDATES_TRIED} candidates in all. All but the \
         start x⁰ = x_n + dt·v_n skip rows costing more than {VARIANT_MAX_ITERATIONS:e} solver iterations \
         (Table 6's dt = 0.001 s rows with 20 and 50 iterations, which the faithful method already reproduces), \
         and every run stops at {} times the published run's duration (a run still going then cannot reproduce \
         its row). Algorithm 4 line 2.1 prints the start x̃, the prediction with gravity; the start \
         x_n + dt·v_n leaves gravity out of the first iterate only. It reproduces **{n} of the {of}** ADMM rows: \
         a departure *selected* from {ADMM_CANDIDATES_TRIED} candidates on the rows it explains, not read off the \
         text.\n\n",
        longer + earlier,
        AdmmCandidate::ALL.len(),
        ADMM_PROTOTYPE_CANDIDATES.len(),
        ADMM_PROTOTYPE_CANDIDATES.join(", "),
        short(VARIANT_TIME_FACTOR),
    );
    md += &variants_table(f, faithful).render();
    md += &format!(
        "\n### A.5 The rest-state error floors: gravity mismatch\n\n\
         Forensic finding 5: the small published errors (at most {}) are floors, and a reference and solvers \
         run at different gravities ({} and {} m/s²) give errors of their size. Provenance: {PROVENANCE}. So \
         this is a description, not a test: every solver row runs under the configuration of its evidence \
         class, with the reference or the solvers at {} m/s², and the table counts the floor rows within \
         {}-{} of the published error (sum of per-node distances, measurement convention 7 of `docs/thesis-scene.md`; twins once). Ours/published \
         in brackets, ✓ within the band; both norms and the errors to the exact equilibria in \
         [`data/gravity-mismatch.csv`](data/gravity-mismatch.csv).\n\n",
        short(ERROR_CHECK_ABOVE),
        short(THESIS_GRAVITY),
        short(MISMATCHED_GRAVITY),
        short(MISMATCHED_GRAVITY),
        short(ERROR_RATIO_RANGE.0),
        short(ERROR_RATIO_RANGE.1),
    );
    md += &gravity_counts_table(f).render();
    md += "\n";
    md += &gravity_verdict(f);
    md += "\n\n";
    md += &gravity_table(f).render();
    md += "\n";
    md
}

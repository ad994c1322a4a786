//! The forensic sections of the report (issue 5): how each of the 56 published rows arose.
//!
//! From [`Forensics`] (computed by [`crate::experiments`]): the status counts shown at the top
//! of the report, the status of every row with the configuration that produced our numbers,
//! the "as published" configuration of each solver with its options (fitted ones marked), the
//! table of every ADMM variant tried with the rows it reproduces, and the gravity-mismatch
//! analysis of the rest-state error floors. Everything here only formats: the same data gives
//! the same bytes.

use crate::experiments::{
    ConfigurationId, Forensics, GravityRow, Measured, PublishedRow, ResultSet, RowStatus,
    SolverKind, Status, MISMATCHED_GRAVITY, NOISE_PEAK_J, VARIANT_MAX_ITERATIONS,
    VARIANT_TIME_FACTOR,
};
use crate::report::format::{full, opt4, percent, short, sig4, MarkdownTable};
use crate::report::tables::{
    half_period_deviation, printed, published_table, stiffness_label, ERROR_CHECK_ABOVE,
    ERROR_RATIO_RANGE,
};
use crate::scene::THESIS_GRAVITY;

/// `T7 0.1/1`: a row's table, time step and iterations.
pub fn row_label(row: &PublishedRow) -> String {
    format!("T{} {}/{}", row.table, full(row.dt_s), row.iterations)
}

/// The tables 1-7 that have at least one row in the forensic results.
fn tables_run(f: &Forensics) -> Vec<u8> {
    (1..=7u8)
        .filter(|&t| f.statuses.iter().any(|s| s.measured.published.table == t))
        .collect()
}

fn count_cells(counts: [usize; 4]) -> Vec<String> {
    let total: usize = counts.iter().sum();
    std::iter::once(total.to_string())
        .chain(counts.iter().map(|c| c.to_string()))
        .collect()
}

/// Rows per status, per table and in total (the top of the report).
pub fn counts_table(f: &Forensics) -> MarkdownTable {
    let mut header = vec!["table", "solver", ">k (N/m)", ">rows"];
    let ids: Vec<String> = Status::ALL.iter().map(|s| format!(">{}", s.id())).collect();
    header.extend(ids.iter().map(String::as_str));
    let mut t = MarkdownTable::new(&header);
    for table in tables_run(f) {
        let first = published_table(table).next().expect("tables 1-7 have rows");
        let k = if table == 1 {
            "1e3, 1e6".to_string()
        } else {
            stiffness_label(first.stiffness)
        };
        let mut cells = vec![table.to_string(), first.solver.abbreviation().into(), k];
        cells.extend(count_cells(f.counts(Some(table))));
        t.row(cells);
    }
    let mut cells = vec!["all".to_string(), "all".into(), "both".into()];
    cells.extend(count_cells(f.counts(None)));
    t.row(cells);
    t
}

/// The note of a status row: the round-off peak, or what was tried.
fn status_note(s: &RowStatus) -> String {
    let m = &s.measured;
    match s.status {
        Status::NoiseLimited => format!(
            "peaks exact; the last peak ({} J) is round-off (finding 1), so T/2 is set by noise",
            sig4(s.noise_peak_energy.unwrap_or(f64::NAN))
        ),
        Status::Unexplained => {
            let tried: Vec<&str> = s.tried.iter().map(|c| c.id()).collect();
            format!("tried: {}", tried.join(", "))
        }
        Status::Faithful | Status::Variant => match m.last_peak_energy {
            Some(e) if e < NOISE_PEAK_J => format!(
                "the last peak ({} J) is round-off: T/2 matches within the rule by chance",
                sig4(e)
            ),
            _ => String::new(),
        },
    }
}

fn peaks_cell(m: &Measured) -> String {
    if m.hit_time_limit {
        format!("{} (time limit)", m.peaks)
    } else {
        m.peaks.to_string()
    }
}

/// The status of every row, with the numbers of the configuration that produced them.
pub fn status_table(f: &Forensics) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "table",
        "solver",
        ">dt (s)",
        ">iter.",
        ">k (N/m)",
        "status",
        "configuration",
        ">peaks pub.",
        ">peaks ours",
        ">T/2 pub. (s)",
        ">T/2 ours (s)",
        ">T/2 dev.",
        ">error pub.",
        ">error ours (Σ|Δ|₁)",
        ">error ours (Σ|Δ|)",
        "note",
    ]);
    for s in &f.statuses {
        let m = &s.measured;
        let row = &m.published;
        let p = printed(row);
        t.row(vec![
            row.table.to_string(),
            row.solver.abbreviation().into(),
            full(row.dt_s),
            row.iterations.to_string(),
            stiffness_label(row.stiffness),
            s.status.id().into(),
            s.configuration.id().into(),
            p.ke_peaks.clone(),
            peaks_cell(m),
            p.half_period_s.clone(),
            opt4(m.half_period_thesis),
            half_period_deviation(m).map_or_else(|| "–".into(), percent),
            if p.error.is_empty() {
                "–".into()
            } else {
                p.error.clone()
            },
            opt4(m.error_l1),
            opt4(m.error_sum),
            status_note(s),
        ]);
    }
    t
}

/// The "as published" configuration of each solver and the options it sets.
pub fn as_published_table() -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "solver",
        "configuration",
        "option",
        "value",
        "fitted",
        "evidence",
    ]);
    for solver in SolverKind::ALL {
        let id = ConfigurationId::as_published(solver);
        let options = id.options();
        if options.is_empty() {
            t.row(vec![
                solver.abbreviation().into(),
                id.id().into(),
                "none".into(),
                "–".into(),
                "–".into(),
                "the faithful method reproduces every published row".into(),
            ]);
        }
        for o in options {
            t.row(vec![
                solver.abbreviation().into(),
                id.id().into(),
                format!("`{}`", o.option),
                o.value.into(),
                if o.fitted { "fitted" } else { "no" }.into(),
                o.why.into(),
            ]);
        }
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

/// Every ADMM configuration tried (the faithful one of `faithful` first), with the rows it
/// reproduces.
pub fn variants_table(f: &Forensics, faithful: &ResultSet) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[
        "configuration",
        "departure from Algorithm 4",
        ">rows run",
        ">reproduced",
        ">of the faithful misses",
        "rows reproduced",
        "runs that failed or hit the time limit",
    ]);
    let admm_statuses: Vec<&RowStatus> = f
        .statuses
        .iter()
        .filter(|s| s.measured.published.solver == SolverKind::AdmmPd)
        .collect();
    let misses: Vec<&PublishedRow> = admm_statuses
        .iter()
        .filter(|s| s.status != Status::Faithful)
        .map(|s| &s.measured.published)
        .collect();
    let faithful_rows: Vec<&Measured> = faithful
        .rows
        .iter()
        .filter(|m| m.published.solver == SolverKind::AdmmPd)
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
                .filter(|r| misses.iter().any(|m| same_row(m, r)))
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
                trouble.push(format!("time limit: {}", label_list(&limited)));
            }
            let departure = match id {
                ConfigurationId::Faithful => "none (Algorithm 4 as written)".to_string(),
                _ => id.admm_variant().label(),
            };
            t.row(vec![
                id.id().into(),
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
    for id in ConfigurationId::ADMM_VARIANTS {
        if let Some(run) = f.run(id) {
            add(
                id,
                run.rows.iter().collect(),
                run.failed.iter().map(|(r, e)| (r, e.as_str())).collect(),
            );
        }
    }
    t
}

fn same_row(a: &PublishedRow, b: &PublishedRow) -> bool {
    a.table == b.table && a.dt_s == b.dt_s && a.iterations == b.iterations && a.solver == b.solver
}

/// What happened in a failed run, without the solver's name: `diverged at step 35 (t = 3.5 s)`.
fn short_error(e: &str) -> String {
    let what = e
        .find(" diverged at ")
        .or_else(|| e.find(" step "))
        .map_or(e, |i| &e[i + 1..]);
    what.split(':').next().unwrap_or(what).trim().to_string()
}

/// Whether a published error is a floor (at most [`ERROR_CHECK_ABOVE`]).
fn is_floor(row: &PublishedRow) -> bool {
    row.error.is_some_and(|e| e <= ERROR_CHECK_ABOVE)
}

fn ratio_cell(ours: f64, published: Option<f64>) -> String {
    match published {
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
        None => sig4(ours),
    }
}

/// The gravity-mismatch hypothesis, every solver row: the published error beside ours with
/// both runs at 9.81 m/s², with the reference at 9.8, and with the solver at 9.8 (sum of
/// absolute coordinate differences; ours/published in brackets, ✓ within the band).
pub fn gravity_table(f: &Forensics) -> MarkdownTable {
    let g = short(MISMATCHED_GRAVITY);
    let g0 = short(THESIS_GRAVITY);
    let same = format!(">both at {g0}");
    let reference = format!(">reference at {g}");
    let solver = format!(">solver at {g}");
    let mut t = MarkdownTable::new(&[
        "table",
        "solver",
        ">dt (s)",
        ">iter.",
        ">k (N/m)",
        "configuration",
        ">error pub.",
        same.as_str(),
        reference.as_str(),
        solver.as_str(),
        "solver at 9.8: peaks, T/2",
    ]);
    for r in &f.gravity {
        let row = &r.published;
        let m = &r.solver_mismatched_run;
        let published = printed(row).error.clone();
        let floor = if is_floor(row) { " (floor)" } else { "" };
        t.row(vec![
            row.table.to_string(),
            row.solver.abbreviation().into(),
            full(row.dt_s),
            row.iterations.to_string(),
            stiffness_label(row.stiffness),
            r.configuration.id().into(),
            format!("{published}{floor}"),
            ratio_cell(r.same_gravity.l1, row.error),
            ratio_cell(r.reference_mismatched.l1, row.error),
            ratio_cell(r.solver_mismatched.l1, row.error),
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

/// One hypothesis of the gravity analysis: its name and how it reads a row's error.
struct Hypothesis {
    name: String,
    l1: fn(&GravityRow) -> f64,
    sum: fn(&GravityRow) -> f64,
}

fn hypotheses() -> [Hypothesis; 3] {
    let (g0, g) = (short(THESIS_GRAVITY), short(MISMATCHED_GRAVITY));
    [
        Hypothesis {
            name: format!("reference and solvers at {g0} m/s² (no mismatch)"),
            l1: |r| r.same_gravity.l1,
            sum: |r| r.same_gravity.sum,
        },
        Hypothesis {
            name: format!("reference at {g}, solvers at {g0} m/s²"),
            l1: |r| r.reference_mismatched.l1,
            sum: |r| r.reference_mismatched.sum,
        },
        Hypothesis {
            name: format!("reference at {g0}, solvers at {g} m/s²"),
            l1: |r| r.solver_mismatched.l1,
            sum: |r| r.solver_mismatched.sum,
        },
    ]
}

/// Ours/published over the floor rows: how many within the band, the median, the range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RatioStats {
    pub rows: usize,
    pub within: usize,
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

fn ratio_stats(f: &Forensics, error: fn(&GravityRow) -> f64) -> Option<RatioStats> {
    let mut ratios: Vec<f64> = f
        .gravity
        .iter()
        .filter(|r| is_floor(&r.published))
        .filter_map(|r| r.published.error.map(|p| error(r) / p))
        .collect();
    if ratios.is_empty() {
        return None;
    }
    ratios.sort_by(f64::total_cmp);
    let n = ratios.len();
    let median = if n % 2 == 1 {
        ratios[n / 2]
    } else {
        0.5 * (ratios[n / 2 - 1] + ratios[n / 2])
    };
    Some(RatioStats {
        rows: n,
        within: ratios
            .iter()
            .filter(|r| (ERROR_RATIO_RANGE.0..=ERROR_RATIO_RANGE.1).contains(*r))
            .count(),
        median,
        min: ratios[0],
        max: ratios[n - 1],
    })
}

/// The floor rows under each hypothesis and norm: rows within the band, median and range of
/// ours/published.
pub fn gravity_summary(f: &Forensics) -> MarkdownTable {
    let band = format!(
        ">within {}-{}",
        short(ERROR_RATIO_RANGE.0),
        short(ERROR_RATIO_RANGE.1)
    );
    let mut t = MarkdownTable::new(&[
        "hypothesis",
        "norm",
        ">floor rows",
        band.as_str(),
        ">median ours/pub.",
        ">range",
    ]);
    for h in hypotheses() {
        for (norm, error) in [("Σ|Δ|₁ (coordinates)", h.l1), ("Σ|Δ| (distances)", h.sum)] {
            if let Some(s) = ratio_stats(f, error) {
                t.row(vec![
                    h.name.clone(),
                    norm.into(),
                    s.rows.to_string(),
                    s.within.to_string(),
                    sig4(s.median),
                    format!("{}-{}", sig4(s.min), sig4(s.max)),
                ]);
            }
        }
    }
    t
}

/// The conclusion of the gravity analysis, from the numbers.
pub fn gravity_verdict(f: &Forensics) -> String {
    let [same, reference, solver] = hypotheses().map(|h| ratio_stats(f, h.l1));
    let (Some(same), Some(reference), Some(solver)) = (same, reference, solver) else {
        return "No floor rows were run.".into();
    };
    let still = f
        .gravity
        .iter()
        .filter(|r| r.solver_mismatched_run.reproduces())
        .count();
    let as_published = f
        .gravity
        .iter()
        .filter(|r| {
            f.status(&r.published).is_some_and(|s| {
                s.status != Status::Unexplained && s.status != Status::NoiseLimited
            })
        })
        .count();
    let (g0, g) = (short(THESIS_GRAVITY), short(MISMATCHED_GRAVITY));
    let mut s = format!(
        "Of the {} rows whose published error is a floor (at most {}), {} come within {}-{} of the published \
         value with every run at {g0} m/s², {} with the reference at {g} m/s², and {} with the reference at \
         {g0} m/s² and the solvers at {g} m/s² (median ours/published {}, {} and {}; sum of absolute \
         coordinate differences). ",
        solver.rows,
        short(ERROR_CHECK_ABOVE),
        same.within,
        short(ERROR_RATIO_RANGE.0),
        short(ERROR_RATIO_RANGE.1),
        reference.within,
        solver.within,
        sig4(same.median),
        sig4(reference.median),
        sig4(solver.median),
    );
    let best = [&same, &reference, &solver]
        .into_iter()
        .max_by_key(|s| s.within)
        .expect("three hypotheses");
    if best == &solver && 4 * solver.within >= 3 * solver.rows {
        s += &format!(
            "**The mismatch explains the floors**, in one direction only: the thesis's solvers most likely ran \
             with g = {g} m/s² and its Backward Euler reference with {g0} m/s² (the reverse assignment leaves \
             the floors unexplained). "
        );
    } else if best == &reference && 4 * reference.within >= 3 * reference.rows {
        s += &format!(
            "**The mismatch explains the floors**, in one direction only: the thesis's reference most likely \
             ran with g = {g} m/s² and its solvers with {g0} m/s². "
        );
    } else {
        s += "The mismatch does **not** explain the floors convincingly. ";
    }
    s += &format!(
        "With the solvers at {g} m/s², {still} of the {} solver rows still meet the reproduction rule \
         (peaks and T/2) under their \"as published\" configuration ({as_published} have the status \
         faithful or variant at {g0} m/s²).",
        f.gravity.len()
    );
    s
}

/// The forensic section of REPORT.md (without its heading), for the faithful result set
/// `faithful` that `f` was computed from.
pub fn section(f: &Forensics, faithful: &ResultSet) -> String {
    let mut md = String::new();
    md += "Every published row gets the first status that applies: **faithful** (the faithful configuration \
           meets the reproduction rule), **variant** (a named configuration does), **noise-limited** (the \
           peak count is exact but T/2 is set by a round-off peak, forensic finding 1 of \
           `docs/thesis-scene.md`: the peak's energy is shown), **unexplained** (with what was tried). The \
           configurations are labelled options of this crate, never the default; the faithful results of \
           sections 4-5 are unchanged by them. The machine-readable form is \
           [`data/reproduction.csv`](data/reproduction.csv) (`our_error` is the sum of absolute \
           coordinate differences, the norm the published errors match best).\n\n";
    md += "### 6.1 The \"as published\" configuration of each solver\n\n";
    md += "What each solver needs beyond the faithful method to give its published numbers. \"Fitted\" marks a \
           value chosen to match the published numbers; the others are read off them or are a discrete \
           choice the thesis leaves open.\n\n";
    md += &as_published_table().render();
    md += "\n### 6.2 Status of every row\n\n";
    md += "Our numbers are those of the configuration named; errors against our faithful reference of the same \
           stiffness, as the sum of absolute coordinate differences (Σ|Δ|₁, the norm the published errors \
           match within 0.98-1.01 on every XPBD row above 0.1) and as the sum of distances (Σ|Δ|, the \
           norm of sections 4-5).\n\n";
    md += &status_table(f).render();
    md += "\n### 6.3 ADMM: every variant tried\n\n";
    md += &format!(
        "The published ADMM rows at dt = 0.1 and 0.01 s keep oscillating longer than the faithful method \
         (forensic finding 6). Each labelled variant of `admm::AdmmVariant` below was run on the ADMM rows; \
         the variants other than the \"as published\" one skip rows costing more than \
         {VARIANT_MAX_ITERATIONS:e} solver iterations (Table 6's dt = 0.001 s rows with 20 and 50 iterations, \
         which the faithful method already reproduces) and stop at {} times the published run's duration (a run still going then cannot reproduce its \
         row). A documented negative result is a result.\n\n",
        short(VARIANT_TIME_FACTOR)
    );
    md += &variants_table(f, faithful).render();
    md += "\nTried earlier with an independent prototype and not re-implemented here (all failed, issue 5): z \
           carried across steps, Overby's x-first order, the velocity from x̃, the ½(p + v) shortcut of Eq 56 \
           with another ω, z = p. The start point x⁰ = x_n + dt·v_n reproduces every published ADMM row; with \
           one iteration it is, up to where gravity enters the first projection, Liu's first iterate y.\n";
    md += &format!(
        "\n### 6.4 The rest-state error floors: gravity mismatch\n\n\
         Forensic finding 5, run in full: every solver row under its \"as published\" configuration, against \
         our Backward Euler reference, with the reference or the solvers at g = {} m/s² instead of {} m/s². \
         Errors as Σ|Δ|₁; ours/published in brackets, ✓ within {}-{}; \"(floor)\" marks a published error of \
         at most {}. All numbers with both norms are in [`data/gravity-mismatch.csv`](data/gravity-mismatch.csv).\n\n",
        short(MISMATCHED_GRAVITY),
        short(THESIS_GRAVITY),
        short(ERROR_RATIO_RANGE.0),
        short(ERROR_RATIO_RANGE.1),
        short(ERROR_CHECK_ABOVE),
    );
    md += &gravity_summary(f).render();
    md += "\n";
    md += &gravity_verdict(f);
    md += "\n\n";
    md += &gravity_table(f).render();
    md += "\n";
    md
}

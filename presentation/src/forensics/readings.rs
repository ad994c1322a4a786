//! The readings of the thesis's open points, each on the rows it concerns: the time
//! convention, the ADMM variants, Liu's readings, the damping scan and the intervals.

use super::evidence::*;

use crate::format::{opt4, percent, short, sig, MarkdownTable};
use crate::tables::{half_period_deviation, printed};
use mass_spring_solvers::model::metrics::STOP_THRESHOLD_J;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{
    better_time_convention, published_rows, same_experiment, Measured, PublishedRow, ResultSet,
    TimeConvention,
};
use mass_spring_solvers::studies::forensics::configurations::{LiuHypothesis, LIU_DAMPING_GRID};
use mass_spring_solvers::studies::forensics::liu_fit::{
    peaks_within_tolerance, DAMPING_BISECTIONS, THRESHOLD_FLOOR_J,
};
use mass_spring_solvers::studies::forensics::{AdmmCandidate, ConfigurationId, Forensics};

/// `0.42 %`: a magnitude as a percentage.
pub(super) fn unsigned_percent(x: f64) -> String {
    percent(x).trim_start_matches('+').to_string()
}

pub(super) fn median(mut v: Vec<f64>) -> Option<f64> {
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

/// What happened in a failed run, without the solver's name: `diverged at step 35 (t = 3.5 s)`.
pub(super) fn short_error(e: &str) -> String {
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
        .filter(|m| !f.reproduces(m))
        .map(|m| &m.published)
        .collect();
    let mut add =
        |id: ConfigurationId, rows: Vec<&Measured>, failed: Vec<(&PublishedRow, &str)>| {
            let reproduced: Vec<&PublishedRow> = rows
                .iter()
                .filter(|m| f.reproduces(m))
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
        .map_or(0, |r| r.rows.iter().filter(|m| f.reproduces(m)).count());
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
                .filter(|m| f.reproduces(m))
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
pub(super) fn damping_scan_rows(f: &Forensics) -> Vec<&PublishedRow> {
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

pub(super) fn damping_scan_table(f: &Forensics) -> MarkdownTable {
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

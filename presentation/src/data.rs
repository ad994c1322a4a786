//! The machine-readable files of `report/data/`: the 56 results in the columns of
//! `thesis_results.csv`, Table 1 alone, the exact catenary, the forensic reproduction (evidence
//! class per row, every named configuration's runs, the Liu grid, the gravity-mismatch errors)
//! and (written by
//! the figures) one CSV per figure. Numbers are written as the shortest decimal that
//! round-trips the `f64`.

use crate::forensics::row_label;
use crate::format::{full, full_opt};
use crate::rest_state::Catenary;
use crate::tables::half_period_deviation;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{
    better_time_convention, Measured, PublishedRow, ResultSet,
};
use mass_spring_solvers::studies::forensics::Forensics;

/// The columns of `results.csv` and `table1.csv`: those of `thesis_results.csv` (the published
/// table's own names; thesis convention for `half_period_s`) plus the exact-convention
/// half-period.
pub const RESULTS_HEADER: &[&str] = &[
    "table",
    "solver",
    "dt_s",
    "iterations",
    "stiffness",
    "error",
    "ke_peaks",
    "half_period_s",
    "period_rel_error",
    "half_period_exact_s",
];

fn row(m: &Measured) -> Vec<String> {
    let p = &m.published;
    vec![
        p.table.to_string(),
        p.solver.id().to_string(),
        full(p.dt_s),
        p.iterations.to_string(),
        full(p.stiffness),
        full_opt(m.error_sum),
        m.peaks.to_string(),
        full_opt(m.half_period_thesis),
        full_opt(m.period_rel_error),
        full_opt(m.half_period_exact),
    ]
}

/// `results.csv`: every measured row, in the thesis's order.
pub fn results_csv(results: &ResultSet) -> String {
    write_csv(RESULTS_HEADER, results.rows.iter().map(row))
}

/// `table1.csv`: the Backward Euler reference rows (Table 1).
pub fn table1_csv(results: &ResultSet) -> String {
    write_csv(
        RESULTS_HEADER,
        results
            .rows
            .iter()
            .filter(|m| m.published.table == 1 && m.published.solver == SolverId::BackwardEuler)
            .map(row),
    )
}

/// `catenary.csv`: the exact static equilibrium of the discrete elastic chain of the thesis
/// rope, for every stiffness available.
pub fn catenary_csv(catenary: &Catenary) -> Option<String> {
    let mut csv = CsvFile::new(&["stiffness_n_per_m", "node", "x_m", "y_m"]);
    let mut any = false;
    for (k, nodes) in catenary.all() {
        any = true;
        for (i, p) in nodes.iter().enumerate() {
            csv.record(vec![full(k), i.to_string(), full(p.x), full(p.y)]);
        }
    }
    any.then(|| csv.text())
}

/// A CSV file being built, record by record, and written with `csv::Writer` at the end: every
/// data file of the report goes through it or [`write_csv`], so that a field holding a comma
/// is quoted and every file reads back with a strict reader.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvFile {
    header: Vec<&'static str>,
    records: Vec<Vec<String>>,
}

impl CsvFile {
    /// An empty file with these columns.
    pub fn new(header: &[&'static str]) -> Self {
        Self {
            header: header.to_vec(),
            records: Vec::new(),
        }
    }

    /// Appends a record; it must have one field per column.
    pub fn record(&mut self, fields: Vec<String>) {
        debug_assert_eq!(fields.len(), self.header.len(), "{:?}", self.header);
        self.records.push(fields);
    }

    /// The file's text.
    pub fn text(&self) -> String {
        write_csv(&self.header, self.records.iter().cloned())
    }
}

/// A CSV file of `header` and `records`, written with `csv::Writer` (fields quoted where they
/// hold a comma, a quote or a line break).
pub fn write_csv(header: &[&str], records: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut writer = csv::Writer::from_writer(Vec::new());
    writer
        .write_record(header)
        .expect("writing to memory cannot fail");
    for record in records {
        writer
            .write_record(&record)
            .expect("writing to memory cannot fail");
    }
    String::from_utf8(writer.into_inner().expect("writing to memory cannot fail"))
        .expect("every field is UTF-8")
}

/// The columns of `reproduction.csv`: one row per published row with its evidence class, the
/// configuration that produced our numbers, the choices it rests on and its twin.
pub const REPRODUCTION_HEADER: &[&str] = &[
    "table",
    "solver",
    "dt_s",
    "iterations",
    "stiffness_n_per_m",
    "evidence",
    "configuration",
    "rests_on",
    "twin_of",
    "published_peaks",
    "our_peaks",
    "published_half_period_s",
    "our_half_period_s",
    "half_period_rel_dev",
    "marginal",
    "better_time_convention",
    "published_error_m",
    "our_error_m",
];

fn experiment(p: &PublishedRow) -> Vec<String> {
    vec![
        p.table.to_string(),
        p.solver.id().to_string(),
        full(p.dt_s),
        p.iterations.to_string(),
        full(p.stiffness),
    ]
}

/// `reproduction.csv`: the evidence class of every row run, in the thesis's order.
/// `our_error_m` is the sum of per-node distances to our reference (convention 7);
/// `better_time_convention` is the T/2 convention of ours closer to the published value.
pub fn reproduction_csv(forensics: &Forensics) -> String {
    write_csv(
        REPRODUCTION_HEADER,
        forensics.evidence.iter().map(|e| {
            let m = &e.measured;
            let p = &m.published;
            let mut r = experiment(p);
            r.extend([
                e.evidence.id().to_string(),
                e.configuration.id(),
                if e.effects.is_empty() {
                    String::new()
                } else {
                    e.rests_on()
                },
                forensics.twins.twin_of(p).map_or(String::new(), row_label),
                p.ke_peaks.to_string(),
                m.peaks.to_string(),
                full(p.half_period_s),
                full_opt(m.half_period_thesis),
                full_opt(half_period_deviation(m)),
                m.marginal().to_string(),
                better_time_convention(p, m.half_period_thesis, m.half_period_exact)
                    .map_or("", |c| c.id())
                    .to_string(),
                full_opt(p.error),
                full_opt(m.error_sum),
            ]);
            r
        }),
    )
}

/// The columns of `configurations.csv`: every run of a named configuration other than the
/// faithful one and the Liu grid (`outcome` is `ran` or the error of a failed run).
pub const CONFIGURATIONS_HEADER: &[&str] = &[
    "configuration",
    "table",
    "solver",
    "dt_s",
    "iterations",
    "stiffness_n_per_m",
    "outcome",
    "peaks",
    "half_period_s",
    "half_period_rel_dev",
    "error_l1_m",
    "error_m",
    "last_peak_energy_j",
    "hit_time_limit",
    "reproduces",
];

/// `configurations.csv`: the runs of every named configuration, configuration by
/// configuration, rows in the thesis's order.
pub fn configurations_csv(forensics: &Forensics) -> String {
    let mut records = Vec::new();
    for run in &forensics.runs {
        for m in &run.rows {
            let mut r = vec![run.id.id()];
            r.extend(experiment(&m.published));
            r.extend([
                "ran".to_string(),
                m.peaks.to_string(),
                full_opt(m.half_period_thesis),
                full_opt(half_period_deviation(m)),
                full_opt(m.error_l1),
                full_opt(m.error_sum),
                full_opt(m.last_peak_energy),
                m.hit_time_limit.to_string(),
                m.reproduces().to_string(),
            ]);
            records.push(r);
        }
        for (row, error) in &run.failed {
            let mut r = vec![run.id.id()];
            r.extend(experiment(row));
            r.push(error.clone());
            r.extend(std::iter::repeat_n(String::new(), 7));
            r.push("false".into());
            records.push(r);
        }
    }
    write_csv(CONFIGURATIONS_HEADER, records)
}

/// The columns of `liu_grid.csv`: every run of the Liu hypothesis, the grid's points and the
/// probes of its intervals.
pub const LIU_GRID_HEADER: &[&str] = &[
    "configuration",
    "role",
    "table",
    "dt_s",
    "iterations",
    "stiffness_n_per_m",
    "exempt_first_peak",
    "damping_per_s",
    "threshold_j",
    "peaks",
    "half_period_s",
    "error_m",
    "last_peak_energy_j",
    "reproduces",
];

/// `liu_grid.csv`: every grid point on every Liu row, then the damping probes.
pub fn liu_grid_csv(forensics: &Forensics) -> String {
    let fit = &forensics.liu;
    let record = |id: String,
                  role: &str,
                  h: mass_spring_solvers::studies::forensics::LiuHypothesis,
                  c: f64,
                  m: &Measured| {
        let p = &m.published;
        vec![
            id,
            role.to_string(),
            p.table.to_string(),
            full(p.dt_s),
            p.iterations.to_string(),
            full(p.stiffness),
            h.exempt_first_peak.to_string(),
            full(c),
            full(h.threshold(p.stiffness)),
            m.peaks.to_string(),
            full_opt(m.half_period_thesis),
            full_opt(m.error_sum),
            full_opt(m.last_peak_energy),
            m.reproduces().to_string(),
        ]
    };
    let mut records = Vec::new();
    for point in &fit.grid {
        let role = if point.hypothesis == fit.in_sample {
            "grid, fitted"
        } else {
            "grid"
        };
        for m in &point.rows {
            records.push(record(
                point.hypothesis.id(),
                role,
                point.hypothesis,
                point.hypothesis.velocity_damping(),
                m,
            ));
        }
    }
    let h = fit.in_sample;
    for probe in &fit.damping_probes {
        for m in &probe.rows {
            records.push(record(
                h.probe_id(probe.damping, h.threshold(1e6)),
                "damping probe",
                h,
                probe.damping,
                m,
            ));
        }
    }
    write_csv(LIU_GRID_HEADER, records)
}

/// The columns of `gravity-mismatch.csv`: per solver row, the published error and ours (sum of
/// per-node distances, and the sum of coordinate differences) under each hypothesis, against
/// our reference runs and against the exact equilibria.
pub const GRAVITY_HEADER: &[&str] = &[
    "table",
    "solver",
    "dt_s",
    "iterations",
    "stiffness_n_per_m",
    "configuration",
    "published_error_m",
    "error_same_gravity_m",
    "error_l1_same_gravity_m",
    "error_reference_9_8_m",
    "error_l1_reference_9_8_m",
    "error_solver_9_8_m",
    "error_l1_solver_9_8_m",
    "error_to_exact_same_gravity_m",
    "error_to_exact_reference_9_8_m",
    "error_to_exact_solver_9_8_m",
    "solver_9_8_peaks",
    "solver_9_8_half_period_s",
];

/// `gravity-mismatch.csv`: the gravity-mismatch hypothesis for every solver row.
pub fn gravity_csv(forensics: &Forensics) -> String {
    write_csv(
        GRAVITY_HEADER,
        forensics.gravity.rows.iter().map(|g| {
            let mut r = experiment(&g.published);
            r.extend([
                g.configuration.id(),
                full_opt(g.published.error),
                full(g.same_gravity.sum),
                full(g.same_gravity.l1),
                full(g.reference_mismatched.sum),
                full(g.reference_mismatched.l1),
                full(g.solver_mismatched.sum),
                full(g.solver_mismatched.l1),
                full(g.to_exact.same_gravity),
                full(g.to_exact.reference_mismatched),
                full(g.to_exact.solver_mismatched),
                g.solver_mismatched_run.peaks.to_string(),
                full_opt(g.solver_mismatched_run.half_period_thesis),
            ]);
            r
        }),
    )
}

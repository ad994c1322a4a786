//! The benchmark's long runs (issue 47, item 8): what does not fit `make report`'s budget,
//! computed by `make report-long` into the committed `report/long/`, deterministic, read by
//! `make report` as it reads `report/timing/`, and shown beside the runs of the report.

use super::*;
use crate::format::{full, sig, MarkdownTable};
use mass_spring_solvers::studies::benchmark::sweep::{long_configurations, SHEET_NEWTON_DTS};
use std::path::Path;

/// The long runs' file in `report/long/`.
pub const LONG_CSV: &str = "benchmark_long.csv";

/// The long runs committed in `dir` (`report/long/`), empty if it has no [`LONG_CSV`]; an
/// error naming the file and the record if it is malformed.
pub fn load(dir: &Path) -> Result<Vec<Row>> {
    let path = dir.join(LONG_CSV);
    if !path.exists() {
        return Ok(Vec::new());
    }
    super::wall::read_csv(&path)
}

impl BenchmarkChapter {
    /// Section 12.2's view of the long runs: each solver's relative physical error on the
    /// sheet at its first setting, from dt = 0.01 s (this report's) down to 0.001 s
    /// (`report/long/`), and the slope over that decade; empty without long runs.
    pub fn long_section(&self) -> String {
        if self.long.is_empty() {
            return String::new();
        }
        let mut md = format!(
            "The sheet's other solvers at the small steps, from `make report-long` \
             ([`long/{LONG_CSV}`](long/{LONG_CSV}), committed and checked by CI): each solver's \
             first setting under Backward Euler, its relative physical error at dt = 0.01 s (this \
             report's run) and at {} s, and the fitted slope over that decade.\n\n",
            SHEET_NEWTON_DTS.map(full).join(", ")
        );
        let mut header = vec![
            "case".to_string(),
            "solver".to_string(),
            ">0.01 s".to_string(),
        ];
        header.extend(SHEET_NEWTON_DTS.map(|dt| format!(">{} s", full(dt))));
        header.push(">slope".into());
        let header: Vec<&str> = header.iter().map(String::as_str).collect();
        let mut t = MarkdownTable::new(&header);
        for case in self.cases() {
            let ids =
                super::start::distinct(long_configurations(case).into_iter().map(|c| c.spec.id));
            for id in ids {
                let error_at = |rows: &[Row], dt: f64| {
                    rows.iter()
                        .filter(|r| families::of_case(&r.scene, r.stiffness_n_per_m, case))
                        .find(|r| {
                            r.kind == "dynamics"
                                && r.solver == id.id()
                                && r.dt_s == dt
                                && r.iterations == first_setting(id)
                                && r.count_mode()
                                && (r.integrator.is_empty() || r.integrator == "backward-euler")
                        })
                        .and_then(|r| r.physical_rel)
                };
                let mut points: Vec<(f64, f64)> = Vec::new();
                let mut cells = vec![case.label(), id.info().display_name.to_string()];
                for (dt, rows) in std::iter::once((0.01, &self.rows))
                    .chain(SHEET_NEWTON_DTS.iter().map(|&dt| (dt, &self.long)))
                {
                    let e = error_at(rows, dt);
                    if let Some(e) = e {
                        points.push((dt, e));
                    }
                    cells.push(e.map_or("–".into(), |e| sig(e, 3)));
                }
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                cells.push(log_slope(&points).map_or("–".into(), |s| sig(s, 2)));
                t.row(cells);
            }
        }
        md += &t.render();
        md + "\n"
    }
}

//! Tables 1-3: the 18 XPBD rows of the faithful result set and the two references they are
//! measured against.
//!
//! Run with `cargo test --test thesis tables_xpbd -- --nocapture` to see the measured tables.

use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{Measured, ResultSet};
use mass_spring_solvers::studies::forensics::faithful_results;

/// Prints Tables 1-3 (the rows of the other tables are left out).
fn print_tables(tables: &ResultSet) {
    println!("\nTables 1-3, thesis convention (ours / published)");
    println!(
        "{:>5} {:<14} {:>6} {:>5} {:>7} | {:>5} {:>5} | {:>8} {:>8} {:>7} | {:>10} {:>6} {:>10} {:>6} {:>10} | {:>8}",
        "table", "solver", "dt", "iter", "k", "peaks", "pub", "T/2", "pub", "dT %", "error",
        "ratio", "error L1", "ratio", "pub", "end (s)"
    );
    for row in tables.rows.iter().filter(|r| r.published.table <= 3) {
        let p = &row.published;
        let t = row.half_period_thesis.unwrap_or(f64::NAN);
        let (error, ratio, error_l1, ratio_l1) = match (p.error, row.error_sum, row.error_l1) {
            (Some(e), Some(sum), Some(l1)) => (
                format!("{sum:.3e}"),
                format!("{:.3}", sum / e),
                format!("{l1:.3e}"),
                format!("{:.3}", l1 / e),
            ),
            _ => ("-".into(), "-".into(), "-".into(), "-".into()),
        };
        println!(
            "{:>5} {:<14} {:>6} {:>5} {:>7.0e} | {:>5} {:>5} | {:>8.4} {:>8.4} {:>+7.3} | {:>10} {:>6} {:>10} {:>6} {:>10} | {:>8.1}",
            p.table,
            p.solver.id(),
            p.dt_s,
            p.iterations,
            p.stiffness,
            row.peaks,
            p.ke_peaks,
            t,
            p.half_period_s,
            100.0 * (t - p.half_period_s) / p.half_period_s,
            error,
            ratio,
            error_l1,
            ratio_l1,
            p.error.map_or("-".into(), |e| format!("{e:.2e}")),
            row.end_time
        );
    }
}

fn xpbd_rows() -> impl Iterator<Item = &'static Measured> {
    faithful_results()
        .rows
        .iter()
        .filter(|r| r.published.solver == SolverId::Xpbd)
}

#[test]
fn tables_2_3_peak_counts_and_half_periods_reproduce() {
    print_tables(faithful_results());
    assert_eq!(xpbd_rows().count(), 18);
    let failures: Vec<_> = xpbd_rows()
        .filter(|row| !row.reproduces() || row.hit_time_limit)
        .map(|row| {
            let p = &row.published;
            format!(
                "table {} dt {} iter {}: {} peaks (pub {}), T/2 {:?} (pub {})",
                p.table,
                p.dt_s,
                p.iterations,
                row.peaks,
                p.ke_peaks,
                row.half_period_thesis,
                p.half_period_s
            )
        })
        .collect();
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The rows whose published rest-state error exceeds 0.1 (11 of 18), with our error under
/// `norm` divided by the published one.
fn error_ratios(norm: fn(&Measured) -> Option<f64>) -> Vec<(String, f64)> {
    xpbd_rows()
        .filter(|r| r.published.error.unwrap() > 0.1)
        .map(|r| {
            let p = &r.published;
            let name = format!("k {:e} dt {} iter {}", p.stiffness, p.dt_s, p.iterations);
            (name, norm(r).unwrap() / p.error.unwrap())
        })
        .collect()
}

/// Scene convention 7, the sum of per-node Euclidean distances, against the published errors
/// above 0.1. Ten of the eleven rows fall within 0.8-1.25; k = 1e3, dt = 0.1, 50 iterations
/// gives 0.77: that run stops inside a residual oscillation during which this error swings
/// between 0.73 and 0.88 of the published value from one step to the next.
#[test]
fn tables_2_3_rest_errors_above_0_1_match() {
    let ratios = error_ratios(|r| r.error_sum);
    assert_eq!(ratios.len(), 11);
    let outside: Vec<_> = ratios
        .iter()
        .filter(|(_, q)| !(0.8..=1.25).contains(q))
        .collect();
    assert!(outside.len() <= 1, "{outside:#?}");
    assert!(
        ratios.iter().all(|(_, q)| (0.75..=1.25).contains(q)),
        "{ratios:#?}"
    );
}

/// The published "error" is matched much more closely by the vector 1-norm of the position
/// difference, summed over nodes and coordinates: every one of the 11 rows within 3 %, where the
/// Euclidean sum reads 2-23 % low.
#[test]
fn tables_2_3_rest_errors_match_the_one_norm() {
    let ratios = error_ratios(|r| r.error_l1);
    assert!(
        ratios.iter().all(|(_, q)| (0.97..=1.03).contains(q)),
        "{ratios:#?}"
    );
}

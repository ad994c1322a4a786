//! Tables 4-7: the 36 Liu 2013 and ADMM-PD rows of the faithful result set, printed and checked
//! row by row against the reproduction rule.
//!
//! Run with `cargo test --test thesis tables_liu_admm -- --nocapture` to see the measured tables.

use crate::asserted::{outcome, Outcome};
use mass_spring_solvers::studies::experiments::Measured;
use mass_spring_solvers::studies::forensics::{faithful_results, forensic_results, Evidence};

fn label(m: &Measured) -> String {
    let p = &m.published;
    format!(
        "T{} dt={} it={} k={:e}",
        p.table, p.dt_s, p.iterations, p.stiffness
    )
}

/// Prints Table `table` and asserts each row's outcome as `tests/asserted/` states it: whether
/// it reproduces, or, for a noise-limited row, only that its class is noise-limited (whether
/// such a row passes moves with the last bits of its start: `tests/thesis/round_off.rs`).
fn check_table(table: u8) {
    println!(
        "{:<28} {:>6} {:>6} {:>10} {:>10} {:>8} {:>9} {:>9} {:>10} ok",
        "row", "peaks", "pub", "T/2", "pub T/2", "dev %", "error", "pub err", "last KE J"
    );
    let mut rows: Vec<&Measured> = faithful_results().table(table).collect();
    assert_eq!(rows.len(), 9);
    rows.sort_by(|a, b| {
        let (a, b) = (&a.published, &b.published);
        a.iterations
            .cmp(&b.iterations)
            .then(b.dt_s.total_cmp(&a.dt_s))
    });
    for m in rows {
        let p = &m.published;
        let t = m.half_period_thesis.unwrap_or(f64::NAN);
        let error = m.error_sum.expect("a solver row has a rest-state error");
        let published_error = p.error.expect("Tables 4-7 publish an error");
        println!(
            "{:<28} {:>6} {:>6} {:>10.4} {:>10.4} {:>8.2} {:>9.2e} {:>9.2e} {:>10.1e} {}{}",
            label(m),
            m.peaks,
            p.ke_peaks,
            t,
            p.half_period_s,
            100.0 * (t - p.half_period_s) / p.half_period_s,
            error,
            published_error,
            m.last_peak_energy.unwrap_or(f64::NAN),
            if m.reproduces() { "yes" } else { "no" },
            if m.hit_time_limit {
                " (time limit)"
            } else {
                ""
            },
        );
        assert!(
            published_error <= 0.1,
            "no row of Tables 4-7 has a published error above 0.1"
        );
        let asserted = outcome(table, p.dt_s, p.iterations);
        if asserted == Outcome::NoiseLimited {
            let class = forensic_results().evidence_of(p).unwrap().evidence;
            assert_eq!(class, Evidence::NoiseLimited, "{}", label(m));
        } else {
            assert_eq!(
                m.reproduces(),
                asserted == Outcome::Reproduces,
                "{}",
                label(m)
            );
        }
    }
}

/// Faithful Liu at k = 1e3 reproduces 3 of the 8 rows that are not noise-limited. 0.1/1 is a
/// round-off row (finding 1: 2 peaks, exact; its T/2 is set by a noise peak near 1e-26 J,
/// -2.2 %), asserted as noise-limited only. The misses, per the forensic findings of
/// `docs/thesis-scene.md`: 0.001/1 (118 vs 87 peaks), 0.01/30 and 0.01/70 (74 vs
/// 61) and 0.001/30 and 0.001/70 (725 vs 227) are the 0.05 s⁻¹ velocity damping of finding 3
/// (our converged rows equal Backward Euler's 725 peaks; their T/2 still matches within 0.1 %
/// except the 725-peak rows, +0.52 %).
#[test]
fn table_4_liu_k_1e3() {
    check_table(4);
}

/// Faithful Liu at k = 1e6 reproduces none of the 4 rows that are not noise-limited; the other
/// 5 are asserted as noise-limited only. 0.1/1 and 0.01/1 stop at their first peak, which is
/// below 1e-3 J (finding 2: the thesis exempted it; 1 vs 2 peaks); 0.001/1 (+1.2 %), 0.1/30
/// (-7.6 %) and 0.1/70 (+2.3 %) are round-off rows with exact peak counts (finding 1): their
/// second peak is noise below 1e-19 J, whose timing, and so T/2, moves with any change in the
/// last bits of the arithmetic (0.001/1 passes from 7 of the 8 nudged starts, 0.1/70 matched
/// within 0.5 % by chance with a Cholesky global solve); 0.01/30 (4 vs 5), 0.01/70 (16 vs 20), 0.001/30
/// and 0.001/70 (175 vs 184) are finding 4's effective 1e-4 J threshold with finding 3's
/// damping.
#[test]
fn table_5_liu_k_1e6() {
    check_table(5);
}

/// Faithful ADMM-PD at k = 1e3 reproduces 8 of 9 rows; the miss, 0.1/1 (10 vs 11 peaks, T/2
/// +17 %), is the large-dt ADMM behaviour of finding 6.
#[test]
fn table_6_admm_k_1e3() {
    check_table(6);
}

/// Faithful ADMM-PD at k = 1e6 reproduces the 3 rows at dt = 1e-3 (they equal Backward Euler
/// when converged); the six rows at dt = 0.1 and 0.01 stop much earlier than published (4 to 36
/// peaks against 7 to 49), the unexplained behaviour of finding 6.
#[test]
fn table_7_admm_k_1e6() {
    check_table(7);
}

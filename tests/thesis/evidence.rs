//! The rule of evidence (`forensics::evidence`), tested claim by claim: each test recomputes
//! its claim from the runs or from the CSV files the report writes, with its own code, and has
//! a negative case beside it, a plausible wrong hypothesis that the same check rejects.

use mass_spring_report::data::{
    gravity_csv, liu_grid_csv, reproduction_csv, GRAVITY_HEADER, LIU_GRID_HEADER,
    REPRODUCTION_HEADER,
};
use mass_spring_solvers::model::metrics::STOP_THRESHOLD_J;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{
    published_rows, reproduces, same_experiment, Measured, PublishedRow,
};
use mass_spring_solvers::studies::forensics::evidence::{
    classify, round_off_spread, Choice, SceneReadings, Selection, ADMM_CANDIDATES_TRIED,
    ROUND_OFF_AGREEMENT,
};
use mass_spring_solvers::studies::forensics::gravity::Hypothesis;
use mass_spring_solvers::studies::forensics::liu_fit::{stop_under, THRESHOLD_FLOOR_J};
use mass_spring_solvers::studies::forensics::{
    faithful_results, forensic_results, AdmmCandidate, ConfigurationId, Evidence, RowEvidence,
    NOISE_PEAK_J,
};
use std::collections::HashMap;

/// The Table 1 reference's final positions at stiffness `k`: at 9.81 m/s² (`g` = 0, the
/// faithful run) or at 9.8 (`g` = 1, the gravity study's).
fn reference_positions(g: usize, k: f64) -> &'static [mass_spring_solvers::model::system::Vec3] {
    if g == 0 {
        &faithful_results().reference(k).final_positions
    } else {
        &forensic_results()
            .gravity
            .mismatched_references
            .iter()
            .find(|m| m.published.stiffness == k)
            .unwrap()
            .final_positions
    }
}

fn label(p: &PublishedRow) -> String {
    format!(
        "T{} {}/{} k={:e}",
        p.table, p.dt_s, p.iterations, p.stiffness
    )
}

fn evidence_of(row: &PublishedRow) -> &'static RowEvidence {
    forensic_results()
        .evidence_of(row)
        .expect("every row has a class")
}

fn rests_on(e: &RowEvidence, choice: Choice) -> bool {
    e.effects.iter().any(|c| c.choice == choice)
}

/// A CSV file the report writes, read back strictly (no flexible records), as maps from
/// column name to field.
fn read_strictly(text: &str, header: &[&str]) -> Vec<HashMap<String, String>> {
    let mut reader = csv::ReaderBuilder::new()
        .flexible(false)
        .from_reader(text.as_bytes());
    let names: Vec<String> = reader
        .headers()
        .expect("a header")
        .iter()
        .map(String::from)
        .collect();
    assert_eq!(names, header, "the header the report documents");
    reader
        .records()
        .map(|r| {
            let r = r.expect("every record parses with the header's width");
            names
                .iter()
                .cloned()
                .zip(r.iter().map(String::from))
                .collect()
        })
        .collect()
}

fn number(field: &str) -> f64 {
    field.parse().unwrap_or(f64::NAN)
}

/// The rows reproduced under the selected configuration whose reproduction `breaks` under
/// another reading, recomputed from the selected runs.
fn broken_by(breaks: impl Fn(&Measured) -> bool) -> Vec<PublishedRow> {
    forensic_results()
        .evidence
        .iter()
        .filter(|e| e.measured.reproduces() && e.evidence != Evidence::NoiseLimited)
        .filter(|e| breaks(&e.measured))
        .map(|e| e.measured.published.clone())
        .collect()
}

fn resting_on(choice: Choice) -> Vec<PublishedRow> {
    forensic_results()
        .evidence
        .iter()
        .filter(|e| rests_on(e, choice))
        .map(|e| e.measured.published.clone())
        .collect()
}

// ---------------------------------------------------------------------------------------------
// The scene-level choices.

/// Convention 4: the rows whose reproduction fails when each peak is stamped at its own
/// sample are exactly those that rest on it, 14 of them (9 otherwise faithful; a tenth, T7
/// 0.001/1, is selected since its printed-method rest error contradicts it). Negative case:
/// the other reading as the thesis's convention is rejected by the published numbers
/// themselves, since every dt = 0.1 s XPBD row stamped at its sample is one step short.
#[test]
fn convention_4_weakens_exactly_the_rows_the_other_stamp_breaks() {
    let broken = broken_by(|m| !reproduces(&m.published, m.peaks, m.half_period_sample_stamp));
    assert_eq!(broken, resting_on(Choice::PeakStamp));
    assert_eq!(
        broken.len(),
        14,
        "{:?}",
        broken.iter().map(label).collect::<Vec<_>>()
    );
    let otherwise_faithful = broken
        .iter()
        .filter(|r| {
            let e = evidence_of(r);
            e.effects
                .iter()
                .all(|c| c.evidence == Evidence::Interpretation)
                && e.configuration == ConfigurationId::Faithful
        })
        .count();
    assert_eq!(otherwise_faithful, 9);
    for r in &broken {
        assert_eq!(
            evidence_of(r).evidence.max(Evidence::Interpretation),
            evidence_of(r).evidence
        );
    }
    // Negative case: stamped at the sample, each XPBD dt = 0.1 s row reads exactly one step
    // (0.1 s) short of the published stamp, peaks × T/2.
    for m in faithful_results()
        .rows
        .iter()
        .filter(|m| m.published.solver == SolverId::Xpbd && m.published.dt_s == 0.1)
    {
        let p = &m.published;
        let published_stamp = p.half_period_s * p.ke_peaks as f64;
        let sample_stamp = m.half_period_sample_stamp.unwrap() * m.peaks as f64;
        assert!(
            (published_stamp - sample_stamp - 0.1).abs() < 2e-3,
            "{}: published stamp {published_stamp}, sample stamp {sample_stamp}",
            label(p)
        );
        assert!(!reproduces(p, m.peaks, m.half_period_sample_stamp));
    }
}

/// Convention 5: the rows an f64 clock breaks are those that rest on the f32 clock: the long
/// k = 1e3 runs at dt = 1e-3 s. Negative case: with the f64 clock the k = 1e3 reference reads
/// more than the tolerance short of Table 1.
#[test]
fn convention_5_weakens_exactly_the_rows_an_f64_clock_breaks() {
    let broken = broken_by(|m| !reproduces(&m.published, m.peaks, m.half_period_f64_clock));
    assert_eq!(broken, resting_on(Choice::Clock));
    assert!(!broken.is_empty());
    for r in &broken {
        assert_eq!(r.dt_s, 1e-3, "{}", label(r));
        assert_eq!(r.stiffness, 1e3, "{}", label(r));
    }
    let reference = faithful_results().reference(1e3);
    let t = reference.half_period_f64_clock.unwrap();
    assert!(
        (t / reference.published.half_period_s - 1.0).abs() > 0.005,
        "f64 clock: {t}"
    );
}

/// The scene was fitted on Table 1, so both Table 1 rows rest on it, are fitted (calibration:
/// they cannot test the scene), and no other row rests on it. Negative case, a constructed
/// row: a faithful Table 2 row stays faithful under the rule, and the same run relabelled as a
/// Table 1 row flips to fitted (tried once against the rule before issue 49, which gave the
/// relabelled row interpretation: this test failed).
#[test]
fn table_1_is_calibration_and_no_other_row_rests_on_the_scene_fit() {
    let rows = resting_on(Choice::SceneFit);
    assert_eq!(rows.len(), 2);
    assert!(rows.iter().all(|r| r.table == 1));
    assert!(rows
        .iter()
        .all(|r| evidence_of(r).evidence == Evidence::Fitted));
    let table_2 = forensic_results()
        .evidence
        .iter()
        .find(|e| e.evidence == Evidence::Faithful && e.measured.published.table == 2)
        .expect("a faithful Table 2 row");
    let selection = |table: u8| {
        let mut measured = table_2.measured.clone();
        measured.published.table = table;
        Selection {
            configuration: table_2.configuration,
            measured,
            evidence: Evidence::Faithful,
            effects: Vec::new(),
            note: String::new(),
        }
    };
    let no_gravity_reading = SceneReadings { gravity_9_8: None };
    assert_eq!(
        classify(selection(2), &no_gravity_reading).evidence,
        Evidence::Faithful
    );
    assert_eq!(
        classify(selection(1), &no_gravity_reading).evidence,
        Evidence::Fitted
    );
}

/// The headline's count of the rows not used to fit the scene, recomputed from
/// `reproduction.csv` read strictly: the rows outside Table 1 that the printed equations
/// reproduce (class faithful or interpretation).
/// Negative case: counting Table 1's calibration rows as well gives a larger count (the
/// headline's old 34 of 56), which the same check rejects.
#[test]
fn the_rows_not_used_to_fit_the_scene_are_counted_apart() {
    let f = forensic_results();
    let records = read_strictly(&reproduction_csv(f), REPRODUCTION_HEADER);
    let reproduced = |r: &&HashMap<String, String>| {
        [Evidence::Faithful, Evidence::Interpretation]
            .iter()
            .any(|e| e.id() == r["evidence"])
    };
    let tested: Vec<_> = records.iter().filter(|r| r["table"] != "1").collect();
    let count = tested.iter().filter(|r| reproduced(r)).count();
    // Table 1's rows read as the printed equations' reproductions, as before issue 49.
    let with_calibration = count + records.iter().filter(|r| r["table"] == "1").count();
    let (rows, headline) = f.rows_not_used_to_fit_the_scene();
    assert_eq!((rows, headline), (tested.len(), count));
    assert_eq!(rows, 54);
    assert!(with_calibration > count, "{with_calibration} {count}");
}

/// Rest errors as evidence, recomputed with this file's code from the faithful runs' final
/// positions and the two references (9.81 m/s² and the gravity study's 9.8): the rows the
/// printed method reproduces by the rule whose ours/published lies outside [0.1, 10] against
/// both are the ones the report names, and none of them keeps the printed method's class
/// (each is reproduced by another configuration, whose rest error lies inside the band).
/// Negative case: read against the 9.81 reference alone, the converged rows that sit below a
/// published floor are contradicted too, a larger set that the same check rejects.
#[test]
fn rest_errors_contradict_the_rows_outside_the_band_at_both_gravities() {
    use mass_spring_solvers::model::metrics::rest_error_sum;
    let f = forensic_results();
    let outside = |m: &Measured, readings: &[usize]| {
        let p = m.published.error.unwrap();
        readings.iter().all(|&g| {
            let ratio = rest_error_sum(
                &m.final_positions,
                reference_positions(g, m.published.stiffness),
            ) / p;
            !(0.1..=10.0).contains(&ratio)
        })
    };
    let candidates = || {
        faithful_results()
            .rows
            .iter()
            .filter(|m| m.published.error.is_some() && m.reproduces())
    };
    let ours: Vec<String> = candidates()
        .filter(|m| outside(m, &[0, 1]))
        .map(|m| label(&m.published))
        .collect();
    let reported: Vec<String> = f
        .contradicted_by_rest_error([0.1, 10.0])
        .iter()
        .map(|(m, _)| label(&m.published))
        .collect();
    assert_eq!(ours, reported);
    assert!(!ours.is_empty());
    for (m, _) in f.contradicted_by_rest_error([0.1, 10.0]) {
        let e = evidence_of(&m.published);
        assert_ne!(
            e.configuration,
            ConfigurationId::Faithful,
            "{}",
            label(&m.published)
        );
        assert!(e.evidence.reproduced() && e.evidence != Evidence::Faithful);
    }
    let one_reading = candidates().filter(|m| outside(m, &[0])).count();
    assert!(one_reading > ours.len(), "{one_reading} {}", ours.len());
    // The band's reading of the reference at either gravity is a scene-level choice: a
    // faithful run the 9.81 reference alone contradicts rests on it, so its row is no longer
    // faithful (referee of issue 49). Recomputed: every reproduced row classed on the
    // printed method whose rest error lies outside the band at 9.81 and inside at 9.8 names
    // the choice, and none is faithful; negative case: such rows exist.
    let mut resting = 0;
    for m in candidates().filter(|m| outside(m, &[0]) && !outside(m, &[1])) {
        let e = evidence_of(&m.published);
        if e.configuration != ConfigurationId::Faithful {
            continue;
        }
        resting += 1;
        assert!(
            e.effects
                .iter()
                .any(|c| c.choice == Choice::ReferenceGravity),
            "{}",
            label(&m.published)
        );
        assert_ne!(e.evidence, Evidence::Faithful, "{}", label(&m.published));
    }
    assert!(resting > 0);
}

/// The tolerance sweep of section 6, recomputed from the faithful runs with this file's own
/// rule (peaks within max(1, round(0.005 × published)), T/2 within the tolerance, not cut at
/// its time limit) over all rows, the 54 outside Table 1, and those that also identified
/// neither time convention (the dt = 0.1 s rows of Tables 2-7; the k = 1e3 reference and
/// Table 2's dt = 0.001 s rows). Negative case: the counts grow with the tolerance (the +0.48 %
/// rows of Table 6 pass at 0.5 % and fail at 0.4 %), so a table that printed one count for
/// every tolerance would fail.
#[test]
fn the_tolerance_sweep_counts_come_from_the_runs() {
    let rows = &faithful_results().rows;
    let passes = |m: &Measured, tolerance: f64| {
        let p = &m.published;
        let peak_tolerance = ((0.005 * p.ke_peaks as f64).round() as usize).max(1);
        !m.hit_time_limit
            && m.peaks.abs_diff(p.ke_peaks) <= peak_tolerance
            && m.half_period_thesis
                .is_some_and(|t| (t - p.half_period_s).abs() <= tolerance * p.half_period_s)
    };
    let identified = |p: &PublishedRow| {
        (p.dt_s == 0.1 && p.table >= 2)
            || (p.table == 1 && p.stiffness == 1e3)
            || (p.table == 2 && p.dt_s == 0.001)
    };
    let section = mass_spring_report::forensics::section(forensic_results(), faithful_results());
    let mut counts = Vec::new();
    for (tolerance, label) in [(0.004, "0.4"), (0.005, "0.5"), (0.006, "0.6")] {
        let all = rows.iter().filter(|m| passes(m, tolerance)).count();
        let tested = rows
            .iter()
            .filter(|m| m.published.table != 1 && passes(m, tolerance))
            .count();
        let unused = rows
            .iter()
            .filter(|m| m.published.table != 1 && !identified(&m.published) && passes(m, tolerance))
            .count();
        let line = format!("| {label} % | {all} | {tested} | {unused} |");
        assert!(section.contains(&line), "{line}");
        counts.push(all);
    }
    assert!(counts[0] < counts[1], "{counts:?}");
}

/// Gravity: the rows whose selected configuration at 9.8 m/s² fails the rule, recomputed from
/// `gravity-mismatch.csv`, are those that rest on 9.81. Negative case: the same rows at
/// 9.81 m/s² (the runs they are classed on) pass.
#[test]
fn gravity_weakens_exactly_the_rows_9_8_breaks() {
    let f = forensic_results();
    let records = read_strictly(&gravity_csv(f), GRAVITY_HEADER);
    let mut broken = Vec::new();
    for r in &records {
        let row = published_rows()
            .iter()
            .find(|p| {
                p.table.to_string() == r["table"]
                    && number(&r["dt_s"]) == p.dt_s
                    && r["iterations"] == p.iterations.to_string()
            })
            .unwrap();
        let e = evidence_of(row);
        let peaks: usize = r["solver_9_8_peaks"].parse().unwrap();
        let t = r["solver_9_8_half_period_s"].parse().ok();
        if e.evidence.reproduced() && !reproduces(row, peaks, t) {
            broken.push(row.clone());
            assert!(e.measured.reproduces(), "{}: passes at 9.81", label(row));
        }
    }
    let resting: Vec<PublishedRow> = resting_on(Choice::Gravity)
        .into_iter()
        .filter(|r| r.table != 1)
        .collect();
    assert_eq!(broken, resting);
    assert_eq!(
        broken.len(),
        3,
        "{:?}",
        broken.iter().map(label).collect::<Vec<_>>()
    );
}

// ---------------------------------------------------------------------------------------------
// The solver-level choices.

/// Every row the Liu hypothesis reproduces is fitted, never predicted: its values were chosen
/// with the Liu rows in view. No row is predicted.
#[test]
fn the_liu_hypothesis_fits_and_predicts_nothing() {
    let f = forensic_results();
    assert_eq!(f.counts(None)[Evidence::Predicted as usize], 0);
    let h = f.liu.in_sample;
    assert_eq!(h.velocity_damping(), 0.05);
    assert!(h.exempt_first_peak && h.low_threshold);
    let fitted = resting_on(Choice::LiuHypothesis);
    assert!(!fitted.is_empty());
    for r in &fitted {
        let e = evidence_of(r);
        assert_eq!(e.evidence, Evidence::Fitted, "{}", label(r));
        assert_eq!(e.configuration, ConfigurationId::Liu(h), "{}", label(r));
        // The printed method, either reading, misses it.
        assert!(!faithful_results()
            .rows
            .iter()
            .find(|m| same_experiment(&m.published, r))
            .unwrap()
            .reproduces());
    }
}

/// The damping interval, recomputed from `liu_grid.csv`: every probe inside it passes, and each
/// end is bracketed by a probe where some row fails. Negative case: the wider interval
/// 0.05 ± 0.001 s⁻¹ holds a failing probe.
#[test]
fn the_damping_interval_is_bracketed_by_runs() {
    let f = forensic_results();
    let records = read_strictly(&liu_grid_csv(f), LIU_GRID_HEADER);
    let mut probes: HashMap<String, (f64, bool)> = HashMap::new();
    for r in records.iter().filter(|r| r["role"] == "damping probe") {
        let entry = probes
            .entry(r["damping_per_s"].clone())
            .or_insert((number(&r["damping_per_s"]), true));
        entry.1 &= r["reproduces"] == "true";
    }
    let (lo, hi) = f.liu.damping.inside();
    assert!(lo < 0.05 && 0.05 < hi, "[{lo}, {hi}]");
    for (c, passes) in probes.values() {
        if (lo..=hi).contains(c) {
            assert!(passes, "a probe inside the interval fails: c = {c}");
        }
    }
    for outside in [f.liu.damping.low.outside, f.liu.damping.high.outside] {
        let (_, passes) = probes
            .values()
            .find(|(c, _)| *c == outside)
            .expect("each end is bracketed by a probe");
        assert!(!passes, "c = {outside} should fail");
        assert!((outside - if outside < 0.05 { lo } else { hi }).abs() < 1e-4);
    }
    assert!(
        probes
            .values()
            .any(|(c, passes)| (c - 0.05).abs() <= 0.001 && !passes),
        "0.05 ± 0.001 holds a failing probe"
    );
}

/// The threshold interval at k = 1e6, recomputed from the runs continued to the floor with
/// this test's own stopping logic: inside it every reproduced k = 1e6 row passes, just
/// outside it one fails. Negative case: the printed 1e-3 J threshold fails.
#[test]
fn the_threshold_interval_is_read_off_the_runs() {
    let f = forensic_results();
    let (low, high) = f.liu.threshold.expect("k = 1e6 rows are reproduced");
    assert!(low < 1e-4 && 1e-4 <= high, "({low}, {high}]");
    assert!(low > THRESHOLD_FLOOR_J);
    let exempt = f.liu.in_sample.exempt_first_peak;
    let all_pass = |threshold: f64| {
        f.liu.threshold_runs.iter().all(|(row, peaks)| {
            // The first peak below the threshold stops the run (the first one exempt).
            let stop = peaks
                .iter()
                .skip(usize::from(exempt))
                .position(|p| p.energy < threshold)
                .map(|i| i + 1 + usize::from(exempt))
                .unwrap_or(peaks.len());
            let t = peaks[stop - 1].time_thesis / stop as f64;
            assert_eq!((stop, Some(t)), stop_under(peaks, threshold, exempt));
            reproduces(row, stop, Some(t))
        })
    };
    assert!(!f.liu.threshold_runs.is_empty());
    for t in [low * 1.0001, 1e-4, high] {
        assert!(all_pass(t), "threshold {t:e}");
    }
    assert!(!all_pass(low * 0.9999) || low <= THRESHOLD_FLOOR_J);
    assert!(!all_pass(high * 1.0001));
    assert!(!all_pass(STOP_THRESHOLD_J), "the printed threshold");
}

/// The ADMM start is selected, from the candidates of the history: 8 run here and 5 tried
/// with the prototype. It reproduces all 18 ADMM rows, and no other candidate reproduces a
/// row the faithful method misses; 9 rows rest on it, 2 of them (T6 0.1/20, T7 0.001/1)
/// because the printed method's rest error contradicts them.
#[test]
fn the_admm_start_is_selected_from_13() {
    assert_eq!(ADMM_CANDIDATES_TRIED, 13);
    let f = forensic_results();
    let selected = resting_on(Choice::AdmmStart);
    assert_eq!(selected.len(), 9);
    for r in &selected {
        let e = evidence_of(r);
        assert_eq!(e.evidence, Evidence::Selected, "{}", label(r));
        assert_eq!(
            e.configuration,
            ConfigurationId::Admm(AdmmCandidate::StartInertial)
        );
    }
    let run = f
        .run(ConfigurationId::Admm(AdmmCandidate::StartInertial))
        .unwrap();
    assert_eq!(run.rows.len(), 18);
    assert!(run.rows.iter().all(Measured::reproduces));
}

// ---------------------------------------------------------------------------------------------
// The noise test and the twins.

/// T5 0.01/1 matches on noise: its reproducing run's last peak is round-off, so it is
/// noise-limited, not reproduced. Negative case: T5 0.01/30, reproduced with a real last peak,
/// is not noise-limited.
#[test]
fn a_row_that_matches_on_noise_is_noise_limited() {
    let row = |dt: f64, iterations: usize| {
        published_rows()
            .iter()
            .find(|r| r.table == 5 && r.dt_s == dt && r.iterations == iterations)
            .unwrap()
    };
    let noise = evidence_of(row(0.01, 1));
    assert_eq!(noise.evidence, Evidence::NoiseLimited);
    assert!(noise.measured.reproduces(), "it meets the rule, on noise");
    assert!(noise.measured.last_peak_energy.unwrap() < NOISE_PEAK_J);
    let real = evidence_of(row(0.01, 30));
    assert_eq!(real.evidence, Evidence::Fitted);
    assert!(real.measured.last_peak_energy.unwrap() > 1e-6);
    for e in &forensic_results().evidence {
        if e.evidence.reproduced() {
            assert!(
                e.measured.last_peak_energy.unwrap() >= NOISE_PEAK_J,
                "{} rests on a noise peak",
                label(&e.measured.published)
            );
        }
    }
}

/// The second noise criterion: runs of one motion (the same first peak to round-off and the
/// same peak count) whose T/2 spread exceeds the tolerance. Negative case: a spread within the
/// tolerance, or runs of another motion, do not count.
#[test]
fn a_t2_spread_across_one_motion_is_noise() {
    let base = faithful_results()
        .rows
        .iter()
        .find(|m| m.peaks == 2 && m.first_peak_energy.is_some())
        .unwrap();
    let with = |t: f64, first: f64| Measured {
        half_period_thesis: Some(t),
        first_peak_energy: Some(first),
        ..base.clone()
    };
    let t0 = base.half_period_thesis.unwrap();
    let e0 = base.first_peak_energy.unwrap();
    let same_motion_far = with(t0 * 1.02, e0 * (1.0 + 0.1 * ROUND_OFF_AGREEMENT));
    assert!(round_off_spread(base, [&same_motion_far]) > 0.005);
    let same_motion_near = with(t0 * 1.001, e0);
    assert!(round_off_spread(base, [&same_motion_near]) < 0.005);
    let other_motion = with(t0 * 1.02, e0 * 1.01);
    assert_eq!(round_off_spread(base, [&other_motion]), 0.0);
}

/// Twins, recomputed from the published table and our faithful runs with this test's own
/// criterion: 7 pairs, each one observation. Negative case: T5 0.001/30 and 0.001/70 print the
/// same peaks and T/2 but different errors, so they are not twins.
#[test]
fn twins_count_once() {
    let f = forensic_results();
    let rows = &faithful_results().rows;
    let mut pairs = Vec::new();
    for (i, a) in rows.iter().enumerate() {
        for b in &rows[i + 1..] {
            let (p, q) = (&a.published, &b.published);
            let printed_alike = p.table == q.table
                && p.dt_s == q.dt_s
                && (p.error, p.ke_peaks, p.half_period_s, p.period_rel_error)
                    == (q.error, q.ke_peaks, q.half_period_s, q.period_rel_error);
            let ours_alike = a.peaks == b.peaks
                && a.half_period_thesis == b.half_period_thesis
                && a.final_positions
                    .iter()
                    .zip(&b.final_positions)
                    .all(|(x, y)| (x - y).norm() < 1e-7);
            if printed_alike && ours_alike {
                pairs.push((p.clone(), q.clone()));
            }
        }
    }
    assert_eq!(pairs, f.twins.pairs);
    assert_eq!(pairs.len(), 7);
    let rows_total: usize = f.counts(None).iter().sum();
    let observations: usize = f.observation_counts().iter().sum();
    assert_eq!(rows_total - observations, pairs.len());
    for (a, b) in &pairs {
        assert_eq!(evidence_of(a).evidence, evidence_of(b).evidence);
    }
    let t5 = |it: usize| {
        published_rows()
            .iter()
            .find(|r| r.table == 5 && r.dt_s == 1e-3 && r.iterations == it)
            .unwrap()
    };
    assert_eq!(t5(30).ke_peaks, t5(70).ke_peaks);
    assert!(f.twins.twin_of(t5(30)).is_none());
}

// ---------------------------------------------------------------------------------------------
// The counts the report prints.

/// The headline counts, recomputed from `reproduction.csv` read strictly: the classes per row,
/// and as observations with each twin pair once.
#[test]
fn the_headline_counts_come_from_the_rows() {
    let f = forensic_results();
    let records = read_strictly(&reproduction_csv(f), REPRODUCTION_HEADER);
    assert_eq!(records.len(), published_rows().len());
    let mut counts = [0usize; 7];
    let mut twinned = 0;
    for r in &records {
        let class = Evidence::ALL
            .iter()
            .position(|e| e.id() == r["evidence"])
            .expect("a known class");
        counts[class] += 1;
        twinned += usize::from(!r["twin_of"].is_empty());
    }
    assert_eq!(counts, f.counts(None));
    assert_eq!(twinned, 2 * f.twins.pairs.len());
    let observations: usize = f.observation_counts().iter().sum();
    assert_eq!(observations, records.len() - twinned / 2);
}

/// The gravity counts, recomputed from `gravity-mismatch.csv`: per hypothesis and stiffness,
/// the floor observations within 0.8-1.25 of the published error. Negative case: with the
/// published floors shifted by one row (a shuffled assignment), the leading hypothesis loses
/// most of its rows.
#[test]
fn the_gravity_counts_come_from_the_csv() {
    let f = forensic_results();
    let records = read_strictly(&gravity_csv(f), GRAVITY_HEADER);
    let twin_seconds: Vec<String> = f
        .twins
        .pairs
        .iter()
        .map(|(_, b)| format!("{} {} {}", b.table, b.dt_s, b.iterations))
        .collect();
    let floors: Vec<&HashMap<String, String>> = records
        .iter()
        .filter(|r| number(&r["published_error_m"]) <= 0.1)
        .filter(|r| {
            !twin_seconds.contains(&format!(
                "{} {} {}",
                r["table"],
                number(&r["dt_s"]),
                r["iterations"]
            ))
        })
        .collect();
    let column = |h: Hypothesis| match h {
        Hypothesis::NoMismatch => "error_same_gravity_m",
        Hypothesis::ReferenceMismatched => "error_reference_9_8_m",
        Hypothesis::SolverMismatched => "error_solver_9_8_m",
    };
    let in_band = |ours: f64, published: f64| (0.8..=1.25).contains(&(ours / published));
    for k in [1e3, 1e6] {
        let at_k: Vec<&&HashMap<String, String>> = floors
            .iter()
            .filter(|r| number(&r["stiffness_n_per_m"]) == k)
            .collect();
        for h in Hypothesis::ALL {
            let within = at_k
                .iter()
                .filter(|r| in_band(number(&r[column(h)]), number(&r["published_error_m"])))
                .count();
            let c = f.gravity.count(h, k);
            assert_eq!((c.rows, c.within), (at_k.len(), within), "{h:?} k = {k:e}");
        }
        // Negative case: each row's error against the next row's published floor.
        let h = Hypothesis::SolverMismatched;
        let shuffled = (0..at_k.len())
            .filter(|&i| {
                in_band(
                    number(&at_k[i][column(h)]),
                    number(&at_k[(i + 1) % at_k.len()]["published_error_m"]),
                )
            })
            .count();
        assert!(
            shuffled < f.gravity.count(h, k).within,
            "k = {k:e}: shuffled {shuffled}"
        );
    }
}

/// One decision of "reproduced" everywhere: recomputed with this file's rule (the reproduction
/// rule, and ours/published rest error inside the band against the reference at 9.81 or at
/// 9.8 m/s²) from the faithful runs' final positions, section 5's total, Tables 6-7's marks,
/// appendix A.4's faithful misses and the headline's count over the rows outside Table 1 all
/// read it; the band-and-gravity table of section 6 and its Tables 2-3 sentence are recomputed
/// the same way.
/// Negative cases: the rule alone (section 5's old "34 of 56") gives a larger total, which the
/// summary check rejects; the 9.81-only reading gives a smaller count than either gravity at the
/// rule's band, so a table that printed one column twice would fail.
#[test]
fn every_reproduced_count_reads_the_rule_of_evidence() {
    use mass_spring_report::tables;
    use mass_spring_solvers::model::metrics::rest_error_sum;
    let f = forensic_results();
    let faithful = faithful_results();
    let passes = |m: &Measured, band: [f64; 2], readings: &[usize]| {
        m.reproduces()
            && m.published.error.is_none_or(|p| {
                readings.iter().any(|&g| {
                    let ratio = rest_error_sum(
                        &m.final_positions,
                        reference_positions(g, m.published.stiffness),
                    ) / p;
                    (band[0]..=band[1]).contains(&ratio)
                })
            })
    };
    let band = [0.1, 10.0];
    let ours: Vec<&Measured> = faithful
        .rows
        .iter()
        .filter(|m| passes(m, band, &[0, 1]))
        .collect();
    let by_rule = faithful.rows.iter().filter(|m| m.reproduces()).count();
    assert!(ours.len() < by_rule, "{} {by_rule}", ours.len());
    let summary = tables::summary(faithful, Some(f)).render();
    let total = format!("| 1-7 | all | both | 56 | 56 | {} of 56 |", ours.len());
    assert!(summary.contains(&total), "{total}\n{summary}");
    assert!(!summary.contains(&format!("{by_rule} of 56")));
    // The headline's count: the rows outside Table 1 reproduced by the same decision.
    let tested = ours.iter().filter(|m| m.published.table != 1).count();
    assert_eq!(f.rows_not_used_to_fit_the_scene().1, tested);
    // Tables 6-7 mark each row the band fails "✗ rest error", and only those.
    for table in [6, 7] {
        let text = tables::results_table(faithful, Some(f), table).render();
        let failed_by_band = faithful
            .table(table)
            .filter(|m| m.reproduces() && !passes(m, band, &[0, 1]))
            .count();
        assert_eq!(
            text.matches("✗ rest error").count(),
            failed_by_band,
            "{text}"
        );
    }
    // Appendix A.4: the faithful ADMM misses under the same decision.
    let admm_misses = faithful
        .rows
        .iter()
        .filter(|m| m.published.solver == SolverId::AdmmPd && !passes(m, band, &[0, 1]))
        .count();
    let appendix = mass_spring_report::forensics::appendix(f, faithful, "");
    let faithful_line = format!(
        "| faithful | none (Algorithm 4 as printed) | 18 | {} | 0 of {admm_misses} |",
        18 - admm_misses
    );
    assert!(appendix.contains(&faithful_line), "{faithful_line}");
    // Section 6's table of bands and gravity readings, over the 54 rows outside Table 1.
    let section = mass_spring_report::forensics::section(f, faithful);
    let outside_1 = || faithful.rows.iter().filter(|m| m.published.table != 1);
    let mut either_at_rule = 0;
    let mut only_981_at_rule = 0;
    for (band, label) in [
        ([0.1, 10.0], "[0.1, 10] (the rule's)"),
        ([0.2, 5.0], "[0.2, 5]"),
        ([0.05, 20.0], "[0.05, 20]"),
    ] {
        let either = outside_1().filter(|m| passes(m, band, &[0, 1])).count();
        let only_981 = outside_1().filter(|m| passes(m, band, &[0])).count();
        let line = format!("| {label} | {either} | {only_981} |");
        assert!(section.contains(&line), "{line}");
        if label.ends_with("(the rule's)") {
            (either_at_rule, only_981_at_rule) = (either, only_981);
        }
    }
    assert!(only_981_at_rule < either_at_rule);
    let from_2_3 = ours
        .iter()
        .filter(|m| matches!(m.published.table, 2 | 3))
        .count();
    let sentence = format!(
        "Of the {tested} rows reproduced at the rule's band, {from_2_3} are rows of Tables 2-3"
    );
    assert!(section.contains(&sentence), "{sentence}");
    let rest = format!(
        "{} of the 36 rows of Tables 4-7 are reproduced",
        tested - from_2_3
    );
    assert!(section.contains(&rest), "{rest}");
    // The rows that neither fitted the scene nor identified a time convention (convention 4 on
    // the dt = 0.1 s rows of Tables 2-7, convention 5 on the k = 1e3 reference and Table 2's
    // dt = 0.001 s rows), and those of them reproduced.
    let identified = |p: &PublishedRow| {
        (p.dt_s == 0.1 && p.table >= 2)
            || (p.table == 1 && p.stiffness == 1e3)
            || (p.table == 2 && p.dt_s == 0.001)
    };
    let unused = outside_1().filter(|m| !identified(&m.published)).count();
    let unused_ours: Vec<&&Measured> = ours
        .iter()
        .filter(|m| m.published.table != 1 && !identified(&m.published))
        .collect();
    let unused_2_3 = unused_ours
        .iter()
        .filter(|m| matches!(m.published.table, 2 | 3))
        .count();
    let sentence = format!(
        "Of the {unused} rows that neither fitted the scene nor identified a time convention, {} are \
         reproduced at the rule's band ({unused_2_3} of them from Tables 2-3)",
        unused_ours.len()
    );
    assert!(section.contains(&sentence), "{sentence}");
}

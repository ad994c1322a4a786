//! The forensic reproduction: labelled departures that never touch the faithful solvers, the
//! evidence class of all 56 published rows, the tests of every claim the forensic chapter
//! makes (each checks the claim, not its digits), the out-of-sample tests of the fitted
//! hypotheses, and snapshots of the chapter's tables.
//!
//! One result set per process: the faithful rows come from
//! [`experiments::faithful_results`], the forensic configurations from
//! [`forensics::forensic_results`]. Snapshots (four significant digits) live in
//! `snapshots/`; review a change with `cargo insta review`.

use mass_spring_solvers::admm::{default_omega, dual_update, z_minimisation, AdmmPd};
use mass_spring_solvers::backward_euler::{converged_step, BackwardEuler, ConvergedStepOptions};
use mass_spring_solvers::experiments::{
    faithful_results, published_rows, Configuration, Measured, PublishedRow,
};
use mass_spring_solvers::fast_mass_spring::{FastMassSpring, FirstIterate};
use mass_spring_solvers::forensics::configurations::LIU_DAMPING_GRID;
use mass_spring_solvers::forensics::gravity::Hypothesis;
use mass_spring_solvers::forensics::{
    forensic_results, AdmmCandidate, AdmmVariant, ConfigurationId, Evidence, FixedNodes,
    LiuHypothesis, StartPoint, VariantAdmm, Weights, NOISE_PEAK_J,
};
use mass_spring_solvers::projective::{finish_step, reduction_matrix, to_columns, GlobalSolve};
use mass_spring_solvers::registry::SolverId;
use mass_spring_solvers::report::data::{reproduction_csv, REPRODUCTION_HEADER};
use mass_spring_solvers::report::forensics::{
    admm_start_inertial_count, counts_table, damping_scan, evidence_table, gravity_split_table,
    gravity_table, gravity_verdict, leave_one_out_table, liu_as_admm_table, time_convention_table,
    variants_table,
};
use mass_spring_solvers::report::format::sig4;
use mass_spring_solvers::report::tables::explanations;
use mass_spring_solvers::scene::thesis_rope;
use mass_spring_solvers::{MassSpringSystem, Result, State, TimeStepper, Vec3};

fn snapshot(name: &str, text: &str) {
    insta::with_settings!({snapshot_path => "../../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!(name, text);
    });
}

fn label(p: &PublishedRow) -> String {
    format!(
        "T{} {} {}/{} k={:e}",
        p.table,
        p.solver.id(),
        p.dt_s,
        p.iterations,
        p.stiffness
    )
}

/// The published row of a table, dt and iteration count.
fn row(table: u8, dt: f64, iterations: usize) -> &'static PublishedRow {
    published_rows()
        .iter()
        .find(|r| r.table == table && r.dt_s == dt && r.iterations == iterations)
        .expect("a published row")
}

// ---------------------------------------------------------------------------------------------
// The faithful ADMM is unchanged by the variants.

/// Algorithm 4 exactly as `AdmmPd::step` computed it before the labelled variants existed
/// (the same operations in the same order), from the crate's public building blocks.
fn algorithm_4_step(system: &MassSpringSystem, dt: f64, iterations: usize, state: &mut State) {
    let n = system.len();
    let omega = default_omega(system);
    let omega2: Vec<f64> = omega.iter().map(|w| w * w).collect();
    let dt2_omega2: Vec<f64> = omega2.iter().map(|w2| dt * dt * w2).collect();
    let a = GlobalSolve::new(system, dt, &omega2).unwrap();
    let d = reduction_matrix(system);
    let mut x_n = vec![0.0; 3 * n];
    to_columns(&state.x, &mut x_n);
    let mut x = vec![0.0; 3 * n];
    let mut m_x_tilde = vec![0.0; 3 * n];
    for (i, node) in system.nodes().iter().enumerate() {
        let x_tilde = if node.fixed {
            state.x[i]
        } else {
            state.x[i] + dt * state.v[i] + dt * dt / node.mass * system.external_force(i)
        };
        for c in 0..3 {
            x[c * n + i] = x_tilde[c];
            m_x_tilde[c * n + i] = node.mass * x_tilde[c];
        }
    }
    let s = system.springs().len();
    let mut z = vec![Vec3::zeros(); s];
    let mut u_bar = vec![Vec3::zeros(); s];
    for _ in 0..iterations {
        for (i, spring) in system.springs().iter().enumerate() {
            let d_x = d.apply_row(i, &x);
            z[i] = z_minimisation(
                d_x + u_bar[i],
                spring.rest_length,
                spring.stiffness,
                omega[i],
            );
            u_bar[i] = dual_update(u_bar[i], d_x, z[i]);
        }
        x.copy_from_slice(&m_x_tilde);
        for i in 0..s {
            d.add_row_transposed(i, dt2_omega2[i] * (z[i] - u_bar[i]), &mut x);
        }
        a.solve(&mut x, &x_n);
    }
    finish_step(state, &x, dt);
}

fn bits(state: &State) -> Vec<u64> {
    state
        .x
        .iter()
        .chain(&state.v)
        .flat_map(|p| p.iter().map(|c| c.to_bits()).collect::<Vec<_>>())
        .collect()
}

/// `AdmmPd::new` and the forensic `VariantAdmm` with `AdmmVariant::PRINTED` give, bit for
/// bit, the steps of Algorithm 4 written out here from the crate's public building blocks.
#[test]
fn faithful_admm_is_bit_identical_to_algorithm_4() {
    for (k, dt, iterations, steps) in [
        (1e3, 0.1, 1, 200),
        (1e3, 0.01, 20, 300),
        (1e6, 0.01, 1, 300),
        (1e6, 0.001, 50, 300),
    ] {
        let system = thesis_rope(k).unwrap();
        let mut new = AdmmPd::new(&system, dt, iterations).unwrap();
        let mut faithful = VariantAdmm::new(&system, dt, iterations, AdmmVariant::PRINTED).unwrap();
        assert_eq!(new.name(), format!("ADMM-PD ({iterations} iterations)"));
        let (mut a, mut b, mut c) = (
            system.initial_state(),
            system.initial_state(),
            system.initial_state(),
        );
        for step in 0..steps {
            new.step(&mut a).unwrap();
            faithful.step(&mut b).unwrap();
            algorithm_4_step(&system, dt, iterations, &mut c);
            assert!(
                bits(&a) == bits(&c) && bits(&b) == bits(&c),
                "k {k}, dt {dt}, {iterations} iterations: step {step} differs"
            );
        }
        assert!(a.kinetic_energy(&system) > 0.0, "the rope moved");
    }
}

fn max_distance(a: &State, b: &State) -> f64 {
    a.x.iter()
        .zip(&b.x)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// A moving state of the k = 1e6 rope (300 Backward Euler steps from rest).
fn moving_state(system: &MassSpringSystem) -> State {
    let mut be = BackwardEuler::reference(system).unwrap();
    let mut state = system.initial_state();
    for _ in 0..300 {
        be.step(&mut state).unwrap();
    }
    state
}

/// Every variant that still minimises Eq (20) converges to the Backward Euler step (the
/// independent oracle); the fixed-node overwrite solves another problem and does not, and the
/// stale right-hand side equals one iteration bit for bit.
#[test]
fn admm_variants_converge_where_they_should() {
    let system = thesis_rope(1e6).unwrap();
    let state = moving_state(&system);
    let dt = 1e-3;
    let oracle = converged_step(&system, &state, dt, ConvergedStepOptions::default()).unwrap();
    let base = AdmmVariant::PRINTED;
    let one_step = |variant: AdmmVariant, iterations: usize, from: &State| {
        let mut s = from.clone();
        VariantAdmm::new(&system, dt, iterations, variant)
            .unwrap()
            .step(&mut s)
            .unwrap();
        s
    };
    let converging = [
        (
            "x⁰ = x_n + dt·v_n",
            AdmmVariant {
                start: StartPoint::Inertial,
                ..base
            },
        ),
        (
            "x⁰ = x_n",
            AdmmVariant {
                start: StartPoint::Previous,
                ..base
            },
        ),
        (
            "fixed DOFs removed",
            AdmmVariant {
                fixed_nodes: FixedNodes::Eliminated,
                ..base
            },
        ),
    ];
    for (name, variant) in converging {
        let e = max_distance(&one_step(variant, 400, &state), &oracle);
        println!("{name}: 400 iterations, {e:.1e} m from the Backward Euler step");
        assert!(e < 1e-10, "{name}: {e:e} m");
    }
    // Other weights converge to the same step, slowly when ω² is far from k: on the k = 1e3
    // rope, ω² = k² and ω² = √k are 1e3 times too large and too small.
    let soft = thesis_rope(1e3).unwrap();
    let soft_state = moving_state(&soft);
    let soft_oracle =
        converged_step(&soft, &soft_state, dt, ConvergedStepOptions::default()).unwrap();
    for (name, weights, iterations) in [
        ("ω = k", Weights::Stiffness, 100_000),
        ("ω² = √k", Weights::FourthRootStiffness, 100_000),
    ] {
        let mut s = soft_state.clone();
        VariantAdmm::new(&soft, dt, iterations, AdmmVariant { weights, ..base })
            .unwrap()
            .step(&mut s)
            .unwrap();
        let e = max_distance(&s, &soft_oracle);
        println!("{name} (k = 1e3): {iterations} iterations, {e:.1e} m");
        assert!(e < 1e-10, "{name}: {e:e} m");
    }
    // The carried dual needs a previous step: from its converged dual, the next step converges.
    let carried = AdmmVariant {
        carry_dual: true,
        ..base
    };
    let mut solver = VariantAdmm::new(&system, dt, 400, carried).unwrap();
    let mut s = state.clone();
    solver.step(&mut s).unwrap();
    let oracle2 = converged_step(&system, &s, dt, ConvergedStepOptions::default()).unwrap();
    solver.step(&mut s).unwrap();
    let e = max_distance(&s, &oracle2);
    println!("ū carried: {e:.1e} m");
    assert!(e < 1e-10, "ū carried: {e:e} m");

    let overwritten = AdmmVariant {
        fixed_nodes: FixedNodes::Overwritten,
        ..base
    };
    let e = max_distance(&one_step(overwritten, 400, &state), &oracle);
    println!("fixed nodes overwritten: {e:.1e} m");
    assert!(
        e > 1e-6,
        "overwriting the fixed nodes solves another problem"
    );
    let stale = AdmmVariant {
        stale_rhs: true,
        ..base
    };
    assert_eq!(
        bits(&one_step(stale, 20, &state)),
        bits(&one_step(stale, 1, &state))
    );
    assert!(VariantAdmm::new(&system, dt, 1, overwritten)
        .unwrap()
        .name()
        .contains("variant: fixed nodes overwritten"));
}

// ---------------------------------------------------------------------------------------------
// The faithful solvers carry no forensic option.

/// `AdmmPd::new` and `FastMassSpring::new` take the system, dt and the iteration count, and
/// nothing else; their modules name no forensic departure.
#[test]
fn faithful_constructors_take_no_forensic_option() {
    let _: fn(&MassSpringSystem, f64, usize) -> Result<AdmmPd> = AdmmPd::new;
    let _: fn(&MassSpringSystem, f64, usize) -> Result<FastMassSpring> = FastMassSpring::new;
    let root = env!("CARGO_MANIFEST_DIR");
    for (file, words) in [
        (
            "src/admm.rs",
            &[
                "variant",
                "carry_dual",
                "stale_rhs",
                "with_omega",
                "StartPoint",
            ][..],
        ),
        (
            "src/fast_mass_spring.rs",
            &["variant", "damping", "threshold"][..],
        ),
    ] {
        let code: String = std::fs::read_to_string(format!("{root}/{file}"))
            .unwrap()
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        for word in words {
            assert!(
                !code.contains(word),
                "{file} names `{word}` outside its docs"
            );
        }
    }
    // Liu's open point is an interpretation the report names, and the default is x_n.
    assert_eq!(FirstIterate::default(), FirstIterate::Previous);
}

/// Liu started at y is a different first iterate, not a different fixed point: one step of
/// many iterations reaches the same converged Backward Euler step from either start.
#[test]
fn liu_first_iterate_changes_the_path_not_the_fixed_point() {
    let system = thesis_rope(1e6).unwrap();
    let state = moving_state(&system);
    let dt = 1e-3;
    let oracle = converged_step(&system, &state, dt, ConvergedStepOptions::default()).unwrap();
    let step = |first: FirstIterate, iterations: usize| {
        let mut s = state.clone();
        FastMassSpring::new(&system, dt, iterations)
            .unwrap()
            .with_first_iterate(first)
            .step(&mut s)
            .unwrap();
        s
    };
    for first in [FirstIterate::Previous, FirstIterate::Inertial] {
        let e = max_distance(&step(first, 400), &oracle);
        assert!(e < 1e-10, "{first:?}: {e:e} m");
    }
    assert_ne!(
        bits(&step(FirstIterate::Previous, 1)),
        bits(&step(FirstIterate::Inertial, 1))
    );
}

// ---------------------------------------------------------------------------------------------
// Evidence classes.

/// Every row has the class its numbers justify.
#[test]
fn every_row_has_a_justified_class() {
    let f = forensic_results();
    assert_eq!(f.evidence.len(), published_rows().len());
    assert_eq!(f.counts(None).iter().sum::<usize>(), published_rows().len());
    let y = f.run(ConfigurationId::LiuStartInertial).unwrap();
    for e in &f.evidence {
        let m = &e.measured;
        let row = &m.published;
        let name = label(row);
        let faithful = faithful_results()
            .rows
            .iter()
            .find(|f| &f.published == row)
            .unwrap();
        assert_eq!(e.evidence.reproduced(), m.reproduces(), "{name}");
        match e.evidence {
            Evidence::Faithful => {
                assert_eq!(e.configuration, ConfigurationId::Faithful, "{name}");
                if row.solver == SolverId::FastMassSpring {
                    assert!(y.row(row).unwrap().reproduces(), "{name}: both readings");
                }
            }
            Evidence::Interpretation => {
                assert_eq!(row.solver, SolverId::FastMassSpring, "{name}");
                assert_ne!(
                    faithful.reproduces(),
                    y.row(row).unwrap().reproduces(),
                    "{name}: exactly one reading reproduces it"
                );
            }
            Evidence::Predicted => {
                let left_out = f.liu.left_out(row).unwrap();
                assert_eq!(e.configuration, ConfigurationId::Liu(left_out.hypothesis));
                assert!(!faithful.reproduces(), "{name}");
            }
            Evidence::Selected => {
                assert!(
                    matches!(e.configuration, ConfigurationId::Admm(_)),
                    "{name}"
                );
                assert!(!faithful.reproduces(), "{name}");
            }
            Evidence::Fitted => {
                assert_eq!(e.configuration, ConfigurationId::Liu(f.liu.in_sample));
                assert!(
                    !f.liu.left_out(row).unwrap().measured.reproduces(),
                    "{name}"
                );
            }
            Evidence::NoiseLimited => {
                assert_eq!(m.peaks, row.ke_peaks, "{name}");
                assert!(m.last_peak_energy.unwrap() < NOISE_PEAK_J, "{name}");
            }
            Evidence::Unexplained => {
                assert!(!faithful.reproduces(), "{name}");
            }
        }
    }
}

/// A run cut at its time limit never counts as reproduced, whatever its numbers.
#[test]
fn a_run_cut_at_its_time_limit_is_never_reproduced() {
    let m = faithful_results()
        .rows
        .iter()
        .find(|m| m.reproduces())
        .unwrap();
    let cut = Measured {
        hit_time_limit: true,
        ..m.clone()
    };
    assert!(!cut.reproduces() && !cut.marginal());
}

// ---------------------------------------------------------------------------------------------
// The claims of the forensic chapter, each checked.

/// "c = 0.05 s⁻¹ gives every damped k = 1e3 peak count; 0, 0.04 and 0.06 do not": the scan
/// runs all four.
#[test]
fn only_c_0_05_gives_every_k_1e3_peak_count() {
    let scan = damping_scan(forensic_results());
    assert_eq!(scan.len(), LIU_DAMPING_GRID.len());
    let all: Vec<f64> = scan
        .iter()
        .filter(|(_, peaks, within)| *within == peaks.len())
        .map(|(c, _, _)| *c)
        .collect();
    assert_eq!(all, [0.05], "{scan:?}");
}

/// The Liu hypothesis left out one row at a time: the fit on the other 17 rows picks the same
/// damping and threshold, and predicts every row that is not a round-off row. (With another
/// damping grid, e.g. without 0.05, this fails.)
#[test]
fn liu_hypothesis_predicts_the_left_out_rows() {
    let f = forensic_results();
    assert_eq!(f.liu.left_out.len(), 18);
    assert_eq!(f.liu.in_sample.velocity_damping(), 0.05);
    assert!(f.liu.in_sample.low_threshold && f.liu.in_sample.exempt_first_peak);
    let round_off = |r: &PublishedRow| r.ke_peaks <= 2 && r.half_period_s > 5.0;
    for l in &f.liu.left_out {
        let r = &l.measured.published;
        assert_eq!(l.hypothesis.velocity_damping(), 0.05, "{}", label(r));
        if !round_off(r) {
            assert!(l.measured.reproduces(), "{} is not predicted", label(r));
        }
    }
    // In sample, every peak count is exact.
    let in_sample = f.liu.point(f.liu.in_sample);
    for m in &in_sample.rows {
        assert_eq!(m.peaks, m.published.ke_peaks, "{}", label(&m.published));
    }
}

/// "x⁰ = x_n + dt·v_n reproduces every published ADMM row": run on all 18.
#[test]
fn admm_start_inertial_reproduces_all_18_rows() {
    let f = forensic_results();
    let run = f
        .run(ConfigurationId::Admm(AdmmCandidate::StartInertial))
        .unwrap();
    assert_eq!(run.rows.len(), 18);
    assert!(run.rows.iter().all(|m| m.reproduces()));
    assert_eq!(admm_start_inertial_count(f), (18, 18));
    // The other candidates reproduce none of the rows the faithful method misses.
    for candidate in AdmmCandidate::ALL.into_iter().skip(1) {
        let run = f.run(ConfigurationId::Admm(candidate)).unwrap();
        for m in run.rows.iter().filter(|m| m.reproduces()) {
            let faithful = faithful_results()
                .rows
                .iter()
                .find(|f| f.published == m.published)
                .unwrap();
            assert!(
                faithful.reproduces(),
                "{candidate:?} {}",
                label(&m.published)
            );
        }
    }
}

/// "Liu started at y with one iteration gives the published ADMM one-iteration rows".
#[test]
fn liu_from_y_gives_the_admm_one_iteration_rows() {
    let f = forensic_results();
    assert_eq!(f.liu_as_admm.len(), 6);
    for m in &f.liu_as_admm {
        assert_eq!(m.published.solver, SolverId::AdmmPd);
        assert!(m.reproduces(), "{}", label(&m.published));
    }
    assert_eq!(row(6, 0.1, 1).ke_peaks, 11);
}

/// The gravity study's design: selected on the k = 1e3 floors, tested on the k = 1e6 floors,
/// with the sum-of-distances norm; the selected assignment passes its pre-set criterion, and
/// the reverse assignment and no mismatch do not.
#[test]
fn gravity_mismatch_is_tested_out_of_sample() {
    let g = &forensic_results().gravity;
    assert_eq!(g.selected, Hypothesis::SolverMismatched);
    assert!(g.supported);
    let test = |h: Hypothesis| g.test.iter().find(|c| c.hypothesis == h).unwrap();
    assert!(test(Hypothesis::NoMismatch).within * 2 < test(Hypothesis::NoMismatch).rows);
    assert!(
        test(Hypothesis::ReferenceMismatched).within * 2
            < test(Hypothesis::ReferenceMismatched).rows
    );
    let rows: usize = g.selection[0].rows + g.test[0].rows;
    assert_eq!(rows, g.rows.iter().filter(|r| r.is_floor()).count());
    assert!(gravity_verdict(forensic_results()).contains("predicted out of sample"));
}

/// Table 6's dt = 1e-3 rows pass marginally, and their published T/2 lies closer to our exact
/// convention than to the f32 one (the tolerance cannot tell the two apart).
#[test]
fn table_6_dt_1e3_rows_are_marginal_and_fit_the_exact_convention() {
    use mass_spring_solvers::experiments::{better_time_convention, TimeConvention};
    for iterations in [1, 20, 50] {
        let m = faithful_results()
            .rows
            .iter()
            .find(|m| &m.published == row(6, 1e-3, iterations))
            .unwrap();
        assert!(m.marginal(), "T6 0.001/{iterations}");
        assert_eq!(
            better_time_convention(&m.published, m.half_period_thesis, m.half_period_exact),
            Some(TimeConvention::Exact)
        );
    }
}

/// The explanation of a row is decided from our run: Table 5's one-iteration rows at dt = 0.1
/// and 0.01 stop at a first peak already below the threshold.
#[test]
fn explanations_start_from_our_run() {
    let text = explanations(faithful_results(), Some(forensic_results()));
    for dt in ["0.1", "0.01"] {
        let line = text
            .lines()
            .find(|l| l.starts_with(&format!("- Table 5, Fast m-s dt = {dt} s, 1 iterations")))
            .unwrap();
        assert!(line.contains("Our first peak"), "{line}");
        assert!(!line.contains("round-off"), "{line}");
    }
}

/// `reproduction.csv` has the columns of issue 8 and one line per published row.
#[test]
fn reproduction_csv_has_the_issue_columns() {
    let csv = reproduction_csv(forensic_results());
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(
        header.join(","),
        "table,solver,dt_s,iterations,stiffness,evidence,configuration,free_choices,published_peaks,\
         our_peaks,published_half_period_s,our_half_period_s,half_period_rel_dev,marginal,\
         better_time_convention,published_error,our_error"
    );
    assert_eq!(REPRODUCTION_HEADER, header.join(","));
    let records: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert_eq!(records.len(), published_rows().len());
    for r in records {
        assert_eq!(r.len(), 17, "{r:?}");
        assert!(Evidence::ALL.iter().any(|e| e.id() == &r[5]), "{r:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Snapshots.

#[test]
fn evidence_tables_match_their_snapshot() {
    let f = forensic_results();
    snapshot(
        "forensics-evidence",
        &format!(
            "{}\n{}\n{}\n{}\n{}",
            counts_table(f).render(),
            evidence_table(f).render(),
            time_convention_table(faithful_results()).render(),
            liu_as_admm_table(f).render(),
            leave_one_out_table(f).render()
        ),
    );
}

fn opt(x: Option<f64>) -> String {
    x.map_or("-".to_string(), sig4)
}

fn numbers(m: &Measured) -> String {
    format!(
        "{} {} {} {} | {} {} | {} | {}",
        m.peaks,
        opt(m.half_period_thesis),
        opt(m.half_period_exact),
        opt(m.period_rel_error),
        opt(m.error_l1),
        opt(m.error_sum),
        opt(m.last_peak_energy),
        m.hit_time_limit
    )
}

/// Every ADMM candidate on every row it ran, and the candidates table.
#[test]
fn admm_variants_match_their_snapshot() {
    let f = forensic_results();
    let mut text = variants_table(f, faithful_results()).render();
    for candidate in AdmmCandidate::ALL {
        let run = f.run(ConfigurationId::Admm(candidate)).unwrap();
        text += &format!("\n{}\n", candidate.id());
        for m in &run.rows {
            let p = &m.published;
            text += &format!(
                "  T{} {}/{} | {}{}\n",
                p.table,
                p.dt_s,
                p.iterations,
                numbers(m),
                if m.reproduces() { " ✓" } else { "" }
            );
        }
        for (p, e) in &run.failed {
            text += &format!("  T{} {}/{} | failed: {e}\n", p.table, p.dt_s, p.iterations);
        }
    }
    snapshot("forensics-admm-variants", &text);
}

/// The Liu grid: every point's numbers on every Liu row.
#[test]
fn liu_grid_matches_its_snapshot() {
    let f = forensic_results();
    let mut text = String::new();
    for h in LiuHypothesis::grid() {
        text += &format!("{}\n", h.id());
        for m in &f.liu.point(h).rows {
            let p = &m.published;
            text += &format!(
                "  T{} {}/{} | {}\n",
                p.table,
                p.dt_s,
                p.iterations,
                numbers(m)
            );
        }
    }
    snapshot("forensics-liu-grid", &text);
}

#[test]
fn gravity_mismatch_matches_its_snapshot() {
    let f = forensic_results();
    snapshot(
        "forensics-gravity",
        &format!(
            "{}\n{}\n\n{}",
            gravity_split_table(f).render(),
            gravity_verdict(f),
            gravity_table(f).render()
        ),
    );
}

/// The faithful configuration is the default of `run_all`'s result set.
#[test]
fn the_faithful_configuration_is_the_default() {
    assert_eq!(faithful_results().configuration, Configuration::faithful());
    for r in published_rows() {
        assert_eq!(
            ConfigurationId::Faithful.configuration(r),
            Configuration::faithful()
        );
    }
}

//! The forensic reproduction (issue 5): labelled variants that never change the faithful
//! results, the status of all 56 published rows, the "as published" numbers, the ADMM
//! variants and the gravity-mismatch analysis of the error floors.
//!
//! One result set per process: the faithful rows come from
//! [`experiments::faithful_results`], the forensic configurations from
//! [`experiments::forensic_results`]. Snapshots (four significant digits) live in
//! `snapshots/`; review a change with `cargo insta review`, or accept it with
//! `INSTA_UPDATE=always cargo test --test forensics`.

use mass_spring_solvers::admm::{
    default_omega, dual_update, z_minimisation, AdmmPd, AdmmVariant, FixedNodes, StartPoint,
    Weights,
};
use mass_spring_solvers::backward_euler::{converged_step, BackwardEuler, ConvergedStepOptions};
use mass_spring_solvers::experiments::{
    faithful_results, forensic_results, published_rows, Configuration, ConfigurationId, Measured,
    PublishedRow, SolverKind, Status, NOISE_PEAK_J,
};
use mass_spring_solvers::projective::{finish_step, reduction_matrix, to_columns, GlobalSolve};
use mass_spring_solvers::report::data::{reproduction_csv, REPRODUCTION_HEADER};
use mass_spring_solvers::report::forensics::{
    as_published_table, counts_table, gravity_summary, gravity_table, gravity_verdict,
    status_table, variants_table,
};
use mass_spring_solvers::report::format::sig4;
use mass_spring_solvers::scene::thesis_rope;
use mass_spring_solvers::{MassSpringSystem, State, TimeStepper, Vec3};

fn snapshot(name: &str, text: &str) {
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
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

/// `AdmmPd::new` (and `with_variant(FAITHFUL)`) give, bit for bit, the steps of Algorithm 4
/// as computed before the variants were added.
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
        let mut faithful =
            AdmmPd::with_variant(&system, dt, iterations, AdmmVariant::FAITHFUL).unwrap();
        assert_eq!(new.name(), format!("ADMM-PD ({iterations} iterations)"));
        assert_eq!(faithful.name(), new.name());
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
    let base = AdmmVariant::FAITHFUL;
    let one_step = |variant: AdmmVariant, iterations: usize, from: &State| {
        let mut s = from.clone();
        AdmmPd::with_variant(&system, dt, iterations, variant)
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
        AdmmPd::with_variant(&soft, dt, iterations, AdmmVariant { weights, ..base })
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
    let mut solver = AdmmPd::with_variant(&system, dt, 400, carried).unwrap();
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
    assert!(AdmmPd::with_variant(&system, dt, 1, overwritten)
        .unwrap()
        .name()
        .contains("variant: fixed nodes overwritten"));
}

// ---------------------------------------------------------------------------------------------
// Named configurations.

/// The faithful configuration is the default of every row and of `run_all`; every other named
/// configuration departs from it on each row it concerns.
#[test]
fn named_configurations_are_labelled_and_never_the_default() {
    assert_eq!(AdmmVariant::default(), AdmmVariant::FAITHFUL);
    assert_eq!(faithful_results().configuration, Configuration::faithful());
    for row in published_rows() {
        assert_eq!(
            ConfigurationId::Faithful.configuration(row),
            Configuration::faithful()
        );
        for id in ConfigurationId::ALL.into_iter().skip(1) {
            if id.solver() == Some(row.solver) {
                assert_ne!(id.configuration(row), Configuration::faithful(), "{id:?}");
                assert!(!id.options().is_empty(), "{id:?} lists its options");
            }
        }
    }
    // The fitted options are marked.
    let fitted: Vec<&str> = ConfigurationId::LiuAsPublished
        .options()
        .into_iter()
        .filter(|o| o.fitted)
        .map(|o| o.option)
        .collect();
    assert_eq!(fitted, ["velocity_damping", "stop.threshold"]);
    for solver in SolverKind::ALL {
        let id = ConfigurationId::as_published(solver);
        assert!(id == ConfigurationId::Faithful || id.is_as_published());
    }
}

// ---------------------------------------------------------------------------------------------
// Statuses.

/// Every row has a status that its numbers justify; an unexplained row lists every
/// configuration that concerns it.
#[test]
fn every_row_has_a_justified_status() {
    let f = forensic_results();
    assert_eq!(f.statuses.len(), published_rows().len());
    assert_eq!(f.counts(None).iter().sum::<usize>(), published_rows().len());
    for s in &f.statuses {
        let m = &s.measured;
        let name = label(&m.published);
        match s.status {
            Status::Faithful => {
                assert_eq!(s.configuration, ConfigurationId::Faithful, "{name}");
                assert!(m.reproduces(), "{name}");
            }
            Status::Variant => {
                assert_ne!(s.configuration, ConfigurationId::Faithful, "{name}");
                assert!(m.reproduces(), "{name}");
            }
            Status::NoiseLimited => {
                assert_eq!(m.peaks, m.published.ke_peaks, "{name}");
                let e = s
                    .noise_peak_energy
                    .expect("the noise peak's energy is shown");
                assert!(e < NOISE_PEAK_J, "{name}: {e:e} J");
            }
            Status::Unexplained => {
                for id in ConfigurationId::ALL {
                    if id == ConfigurationId::Faithful || id.concerns(&m.published) {
                        assert!(s.tried.contains(&id), "{name}: {id:?} not tried");
                    }
                }
            }
        }
    }
}

/// With the "as published" Liu configuration, every Liu row that is not noise-limited has
/// exactly the published peak count; the noise-limited rows' counts are recorded.
#[test]
fn liu_as_published_peak_counts_are_exact() {
    let f = forensic_results();
    let run = f.run(ConfigurationId::LiuAsPublished).unwrap();
    assert_eq!(run.rows.len(), 18);
    assert!(run.failed.is_empty());
    let mut noise_limited = Vec::new();
    for m in &run.rows {
        let status = f.status(&m.published).unwrap();
        if status.status == Status::NoiseLimited {
            noise_limited.push(format!("{}: {} peaks", label(&m.published), m.peaks));
            continue;
        }
        assert_eq!(
            m.peaks,
            m.published.ke_peaks,
            "{}: {} peaks against {} published",
            label(&m.published),
            m.peaks,
            m.published.ke_peaks
        );
    }
    println!("noise-limited Liu rows: {noise_limited:?}");
}

/// The faithful Liu still equals Backward Euler when converged: its converged rows (70
/// iterations at dt = 1e-3) give the reference's peaks and rest state. (The single-step
/// convergence to the Backward Euler step is `liu_and_admm_converge_to_the_backward_euler_step`
/// in `tests/projective.rs`.)
#[test]
fn faithful_converged_liu_equals_backward_euler() {
    let results = faithful_results();
    for k in [1e3, 1e6] {
        let reference = results.reference(k);
        let liu = results
            .rows
            .iter()
            .find(|m| {
                m.published.solver == SolverKind::FastMassSpring
                    && m.published.stiffness == k
                    && m.published.dt_s == 1e-3
                    && m.published.iterations == 70
            })
            .unwrap();
        assert_eq!(liu.peaks, reference.peaks, "k = {k}");
        let error = liu.error_sum.unwrap();
        assert!(error < 1e-6, "k = {k}: {error:e} m from the reference");
    }
}

/// `reproduction.csv` has exactly the columns of issue 5 and one line per published row.
#[test]
fn reproduction_csv_has_the_issue_columns() {
    let csv = reproduction_csv(forensic_results());
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "table,solver,dt_s,iterations,stiffness,status,configuration,published_peaks,our_peaks,\
         published_half_period_s,our_half_period_s,half_period_rel_dev,published_error,our_error"
    );
    assert_eq!(REPRODUCTION_HEADER.split(',').count(), 14);
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), published_rows().len());
    for line in rows {
        assert_eq!(line.split(',').count(), 14, "{line}");
        let status = line.split(',').nth(5).unwrap();
        assert!(Status::ALL.iter().any(|s| s.id() == status), "{line}");
    }
}

// ---------------------------------------------------------------------------------------------
// Snapshots.

#[test]
fn status_table_matches_its_snapshot() {
    let f = forensic_results();
    snapshot(
        "forensics-status",
        &format!("{}\n{}", counts_table(f).render(), status_table(f).render()),
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

/// Every row under its solver's "as published" configuration, four significant digits.
#[test]
fn as_published_numbers_match_their_snapshot() {
    let f = forensic_results();
    let mut text = String::from(
        "table solver dt iter k | configuration | peaks T/2(thesis) T/2(exact) relT | error_l1 error_sum | last peak J | limit\n",
    );
    for row in published_rows() {
        let id = ConfigurationId::as_published(row.solver);
        let m = match id {
            ConfigurationId::Faithful => faithful_results()
                .rows
                .iter()
                .find(|m| &m.published == row)
                .unwrap(),
            _ => f.run(id).unwrap().row(row).unwrap(),
        };
        text += &format!(
            "{} {} {} {} {:e} | {} | {}\n",
            row.table,
            row.solver.id(),
            row.dt_s,
            row.iterations,
            row.stiffness,
            id.id(),
            numbers(m)
        );
    }
    text += "\n";
    text += &as_published_table().render();
    snapshot("forensics-as-published", &text);
}

/// Every ADMM variant on every row it ran, and the variants table.
#[test]
fn admm_variants_match_their_snapshot() {
    let f = forensic_results();
    let mut text = variants_table(f, faithful_results()).render();
    for id in ConfigurationId::ADMM_VARIANTS {
        let run = f.run(id).unwrap();
        text += &format!("\n{}\n", id.id());
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

#[test]
fn gravity_mismatch_matches_its_snapshot() {
    let f = forensic_results();
    snapshot(
        "forensics-gravity",
        &format!(
            "{}\n{}\n\n{}",
            gravity_summary(f).render(),
            gravity_verdict(f),
            gravity_table(f).render()
        ),
    );
}

//! The report's tutorial chapter (section 9) against closed forms and stated bounds: each
//! number the chapter prints comes from [`TutorialChapter::compute`], and each of its five
//! points is checked here against an oracle that does not come from the code under test.

use mass_spring_report::tutorial::TutorialChapter;
use mass_spring_solvers::particles::{AdaptiveStepper, Integrator, ParticleSystem};
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::tutorial::{
    self as studies, expected_limit, log_log_slope, spectral_radius, Method, Oscillator, Scheme,
    DROP, GROWTH_THRESHOLD,
};
use mass_spring_solvers::{TimeStepper, Vec3};
use std::sync::OnceLock;

/// The chapter, computed once per test process.
fn chapter() -> &'static TutorialChapter {
    static CHAPTER: OnceLock<TutorialChapter> = OnceLock::new();
    CHAPTER.get_or_init(|| TutorialChapter::compute().expect("the tutorial's studies run"))
}

// ---------------------------------------------------------------------------------------------
// 1. Convergence orders
// ---------------------------------------------------------------------------------------------

#[test]
fn every_method_converges_at_its_order_against_the_closed_form() {
    let series = &chapter().convergence;
    assert_eq!(series.len(), Method::ALL.len());
    for s in series {
        let expected = f64::from(s.method.expected_order());
        println!("{}: slope {:.4} (expected {expected})", s.method, s.slope);
        assert!(
            (s.slope - expected).abs() <= 0.1,
            "{}: fitted slope {} is not {expected}",
            s.method,
            s.slope
        );
        // Each halving of h divides the error by about 2^order, not only on average.
        for w in s.points.windows(2) {
            let local = (w[0].1 / w[1].1).ln() / (w[0].0 / w[1].0).ln();
            assert!(
                (local - expected).abs() <= 0.15,
                "{}: local slope {local} between h = {} and {}",
                s.method,
                w[0].0,
                w[1].0
            );
        }
    }
    // The tutorial's "Euler es un Runge-Kutta de orden 2": explicit Euler is first order.
    let euler = series
        .iter()
        .find(|s| s.method == Method(SolverId::ExplicitEuler))
        .unwrap();
    assert!(euler.slope < 1.5);
}

#[test]
fn the_oscillator_closed_form_solves_its_equation() {
    // The oracle itself: u'' + (k_d/m) u' + (k/m) u = 0 and the initial conditions, checked by
    // finite differences of the closed form.
    let o = Oscillator::standard(0.1);
    assert_eq!(o.exact(0.0), (o.u0, o.v0));
    let d = 1e-4;
    for t in [0.1, 0.37, 0.9] {
        let (u, v) = o.exact(t);
        let (u_plus, v_plus) = o.exact(t + d);
        let (u_minus, v_minus) = o.exact(t - d);
        let acceleration = (u_plus - 2.0 * u + u_minus) / (d * d);
        let residual = o.mass * acceleration + o.damping * v + o.stiffness * u;
        assert!(residual.abs() < 1e-5, "residual {residual} at t = {t}");
        assert!(((u_plus - u_minus) / (2.0 * d) - v).abs() < 1e-6);
        assert!(((v_plus - v_minus) / (2.0 * d) - acceleration).abs() < 1e-4);
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Stability
// ---------------------------------------------------------------------------------------------

/// The closed-form spectral radius of each integrator's one-step map at hω = x.
fn closed_form_radius(integrator: Integrator, x: f64) -> f64 {
    match integrator {
        Integrator::ExplicitEuler => (1.0 + x * x).sqrt(),
        Integrator::SymplecticEuler => {
            // Trace 2 - x², determinant 1.
            let half_trace = 1.0 - 0.5 * x * x;
            if half_trace.abs() <= 1.0 {
                1.0
            } else {
                half_trace.abs() + (half_trace * half_trace - 1.0).sqrt()
            }
        }
        Integrator::Rk4 => (1.0 - x.powi(6) / 72.0 + x.powi(8) / 576.0).sqrt(),
    }
}

#[test]
fn the_measured_amplification_matches_the_closed_form() {
    for integrator in Integrator::ALL {
        for x in [0.1, 0.5, 1.0, 1.9, 2.1, 2.7, 2.9, 3.5] {
            let measured = spectral_radius(integrator, x).unwrap();
            let closed = closed_form_radius(integrator, x);
            assert!(
                (measured - closed).abs() < 1e-9 * closed.max(1.0),
                "{integrator} at hω = {x}: {measured} vs {closed}"
            );
        }
    }
}

#[test]
fn the_stability_limits_are_0_2_and_2_sqrt_2() {
    for l in &chapter().limits {
        println!(
            "{}: {} (closed form {})",
            l.integrator, l.measured, l.expected
        );
        assert_eq!(l.expected, expected_limit(l.integrator));
        match l.integrator {
            // Zero to within the resolution: growth x²/2 per step below the threshold.
            Integrator::ExplicitEuler => {
                assert!(l.measured <= 1.01 * (2.0 * GROWTH_THRESHOLD).sqrt())
            }
            Integrator::SymplecticEuler => assert!((l.measured - 2.0).abs() < 1e-8),
            Integrator::Rk4 => assert!((l.measured - 8f64.sqrt()).abs() < 1e-8),
        }
    }
}

#[test]
fn energy_stays_bounded_below_each_limit_and_explodes_above() {
    for run in &chapter().energy {
        let x = run.h_omega;
        let rho = closed_form_radius(run.integrator, x);
        let steps = |periods: f64| (periods * std::f64::consts::TAU / x).round();
        let (t_end, e_end) = *run.points.last().unwrap();
        println!(
            "{} hω = {x}: E/E0 = {e_end:.3e} after {t_end:.2} periods",
            run.integrator
        );
        match run.integrator {
            // E_n = (1 + h²ω²)^n E_0 exactly.
            Integrator::ExplicitEuler => {
                for &(t, e) in &run.points {
                    let closed = (1.0 + x * x).powf(steps(t));
                    assert!(
                        (e / closed - 1.0).abs() < 1e-6,
                        "hω = {x}, t = {t}: {e} vs {closed}"
                    );
                }
            }
            // Below the limit symplectic Euler conserves v² + ω²u² − hω²uv, which bounds
            // E/E_0 by (1 + hω/2)/(1 − hω/2).
            Integrator::SymplecticEuler if x < 2.0 => {
                let bound = (1.0 + x / 2.0) / (1.0 - x / 2.0);
                assert!(run.points.iter().all(|p| p.1 <= bound * (1.0 + 1e-9)));
                assert!((t_end - studies::ENERGY_PERIODS).abs() < 1.0);
            }
            // RK4's map is normal: the energy never grows where |R| <= 1.
            Integrator::Rk4 if x < 8f64.sqrt() => {
                for w in run.points.windows(2) {
                    assert!(w[1].1 <= w[0].1 * (1.0 + 1e-12));
                }
            }
            // Above the limit: growth at (nearly) the rate ρ^(2n) of the closed form.
            _ => {
                let rate = e_end.ln() / steps(t_end);
                println!(
                    "  growth per step {rate:.4} vs 2 ln ρ = {:.4}",
                    2.0 * rho.ln()
                );
                assert!(rho > 1.0 && rate >= 0.8 * 2.0 * rho.ln(), "{rate} vs {rho}");
                assert!(e_end > 100.0);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Forces
// ---------------------------------------------------------------------------------------------

#[test]
fn drag_follows_the_exponential_and_reaches_the_terminal_velocity() {
    let d = &chapter().drag;
    let (m, g, k_f) = studies::DRAG;
    let closed = |t: f64| m * g / k_f * (1.0 - (-k_f * t / m).exp());
    for (t, ours, printed) in &d.samples {
        assert!((printed - closed(*t)).abs() < 1e-12);
        assert!((ours - closed(*t)).abs() < 1e-9, "t = {t}: {ours}");
    }
    assert!(d.max_error < 1e-9);
    assert!((d.terminal - m * g / k_f).abs() < 1e-12);
    assert!((d.final_speed - m * g / k_f).abs() < 1e-7 * d.terminal);
}

#[test]
fn the_damped_spring_decays_and_rings_as_the_damped_oscillator() {
    let p = &chapter().pair;
    let (ma, mb) = (p.pair.mass_a, p.pair.mass_b);
    let mu = ma * mb / (ma + mb);
    let decay = p.pair.damping / (2.0 * mu);
    let frequency = (p.pair.stiffness / mu - decay * decay).sqrt();
    println!(
        "decay {} vs {decay}, frequency {} vs {frequency}",
        p.measured_decay, p.measured_frequency
    );
    assert!((p.measured_decay - decay).abs() < 1e-6 * decay);
    assert!((p.measured_frequency - frequency).abs() < 1e-6 * frequency);
    assert!(p.max_error < 1e-9, "{}", p.max_error);
    assert!(p.max_momentum < 1e-10);
}

#[test]
fn each_gravity_acts_on_its_own_particles() {
    let particles = &chapter().gravities;
    assert!(particles.iter().any(|p| p.gravities.len() > 1));
    let distinct: std::collections::BTreeSet<_> =
        particles.iter().map(|p| p.gravities.clone()).collect();
    assert_eq!(distinct.len(), particles.len());
    for p in particles {
        assert!((p.ours - p.closed).norm() < 1e-9, "{p:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Collisions
// ---------------------------------------------------------------------------------------------

#[test]
fn each_bounce_keeps_e_squared_of_the_energy() {
    let (height, e, g) = DROP;
    for run in &chapter().bounces {
        assert_eq!(run.kept.len(), studies::BOUNCES, "{}", run.scheme);
        for (n, kept) in run.kept.iter().enumerate() {
            // The apex before bounce n+1 is e^(2n)·h; a contact seen up to one step late at
            // depth d <= |v| h leaves with v² + 2 g d: a relative energy error up to 2 g h/|v|.
            let v = (2.0 * g * height * e.powi(2 * n as i32)).sqrt();
            let bound = match run.scheme {
                Scheme::Fixed(_, h) => 1.5 * e * e * 2.0 * g * h / v,
                Scheme::Adaptive(tolerance) => 1e3 * tolerance,
            };
            println!(
                "{}: bounce {} kept {kept} (bound {bound:.2e})",
                run.scheme,
                n + 1
            );
            assert!(
                (kept - e * e).abs() <= bound,
                "{} bounce {}: {kept} vs e² = {}",
                run.scheme,
                n + 1,
                e * e
            );
        }
    }
}

#[test]
fn the_pendulum_bounces_and_only_loses_energy() {
    let p = &chapter().pendulum;
    assert_eq!(p.frames.len(), studies::PENDULUM_FRAMES.len());
    assert!(!p.contacts.is_empty());
    let e0 = p.energy[0].1;
    // At rest, springs at their rest length: the energy is gravity's, m g y over every node
    // (the anchored pivot's is constant).
    let params = &p.params;
    let nodes = (params.particles + 1) as f64;
    assert!(
        (e0 - nodes * params.particle_mass * params.gravity * params.pivot_height).abs() < 1e-9
    );
    for w in p.energy.windows(2) {
        // Drag, damping and the floor only take energy; a contact resolved one step late may
        // give back at most m g |v| h.
        assert!(w[1].1 <= w[0].1 + 1e-3, "energy rose at t = {}", w[1].0);
    }
    let last = p.energy.last().unwrap().1;
    let lost_at_floor: f64 = p.contacts.iter().map(|c| c.2 - c.3).sum();
    assert!(lost_at_floor > 0.0 && lost_at_floor < e0 - last);
    for (_, x) in &p.frames {
        assert!(x.iter().all(|x| x.y >= 0.0));
        assert_eq!(x[0], Vec3::new(0.0, params.pivot_height, 0.0));
    }
}

#[test]
fn the_cloth_falls_as_its_centre_of_mass_closed_form_and_lands() {
    let c = &chapter().cloth;
    assert!(c.max_centre_error < 1e-9, "{}", c.max_centre_error);
    assert!((c.first_contact - c.closed_contact).abs() <= c.dt + 1e-12);
    // Without drag the fall from 10 m takes sqrt(2h/g); drag only delays it.
    let free_fall = (2.0 * c.params.height / c.params.cloth.gravity).sqrt();
    assert!(c.closed_contact >= free_fall && c.closed_contact < free_fall * 1.01);
    assert!(c.lowest >= 0.0);
    assert!(c.final_highest < 0.1 * c.params.height);
}

// ---------------------------------------------------------------------------------------------
// 5. The adaptive integrator
// ---------------------------------------------------------------------------------------------

#[test]
fn the_bouncing_closed_form_is_right() {
    let (h, e, g): (f64, f64, f64) = (1.0, 0.5, 9.81);
    let fall = (2.0 * h / g).sqrt();
    // At the contact the particle has already bounced: on the floor, rising at e·g·t.
    let (y, v) = studies::bouncing_exact(h, e, g, fall);
    assert!(y.abs() < 1e-12 && (v - e * g * fall).abs() < 1e-12);
    let (y, v) = studies::bouncing_exact(h, e, g, 0.5 * fall);
    assert!((y - 0.75 * h).abs() < 1e-12 && (v + 0.5 * g * fall).abs() < 1e-12);
    // The first rebound's apex: e²h, at rest.
    let apex = fall + e * fall;
    let (y, v) = studies::bouncing_exact(h, e, g, apex);
    assert!((y - e * e * h).abs() < 1e-12 && v.abs() < 1e-12);
}

#[test]
fn the_adaptive_error_follows_the_tolerance() {
    let a = &chapter().adaptive;
    for r in &a.drop {
        println!("drop: T = {:e}, error {:e}", r.tolerance, r.error);
        assert!(
            r.error <= r.tolerance,
            "dropped particle at T = {}",
            r.tolerance
        );
    }
    for r in &a.pendulum {
        println!(
            "pendulum: T = {:e}, error {:e}, {:?}",
            r.tolerance, r.error, r.stats
        );
        assert!(
            r.error <= 50.0 * r.tolerance,
            "pendulum at T = {}",
            r.tolerance
        );
        assert!(r.stats.rejected_contact > 0);
    }
    let points = |f: &dyn Fn(&studies::AdaptiveRun) -> f64| {
        a.pendulum
            .iter()
            .map(|r| (r.tolerance, f(r)))
            .collect::<Vec<_>>()
    };
    let error_slope = log_log_slope(&points(&|r| r.error));
    let steps_slope = log_log_slope(&points(&|r| r.stats.accepted as f64));
    assert!((0.8..=1.3).contains(&error_slope), "{error_slope}");
    // A fifth-order method: steps ∝ T^(-1/5).
    assert!((-0.25..=-0.15).contains(&steps_slope), "{steps_slope}");
}

#[test]
fn the_adaptive_integrator_meets_its_tolerance_on_the_oscillator() {
    let o = Oscillator::standard(0.1);
    for tolerance in [1e-4, 1e-6, 1e-8, 1e-10] {
        let mut stepper =
            AdaptiveStepper::new(ParticleSystem::from_system(o.system()), 1.0, tolerance).unwrap();
        let mut state = stepper.system().initial_state();
        stepper.step(&mut state).unwrap();
        let error = o.error(&state, 1.0);
        println!("T = {tolerance:e}: error {error:e}, {:?}", stepper.stats());
        assert!(error <= 10.0 * tolerance, "T = {tolerance}: {error}");
    }
}

// ---------------------------------------------------------------------------------------------
// The report's section and `mss --solver rk45`
// ---------------------------------------------------------------------------------------------

#[test]
fn the_section_shows_every_figure_and_data_file() {
    let c = chapter();
    let figures = c.figures().unwrap();
    let md = c.section(9, &figures);
    for f in &figures {
        assert!(
            md.contains(&format!("figures/{}.svg", f.stem)),
            "{}",
            f.stem
        );
        assert!(f.svg.starts_with("<svg") && f.csv.lines().count() > 1);
    }
    for file in c.files(&figures) {
        let name = file.path.to_string_lossy().into_owned();
        assert!(
            name.starts_with("figures/tutorial_") || name.starts_with("data/tutorial_"),
            "{name}"
        );
        if name.ends_with(".csv") {
            assert!(md.contains(&name) || figures.iter().any(|f| name.contains(f.stem)));
        }
    }
    assert!(md.contains("step rejection"));
}

#[test]
fn the_chapter_is_deterministic() {
    let again = TutorialChapter::compute().unwrap();
    assert!(&again == chapter());
    let (a, b) = (again.figures().unwrap(), chapter().figures().unwrap());
    assert_eq!(again.section(9, &a), chapter().section(9, &b));
    assert_eq!(again.files(&a), chapter().files(&b));
}

//! The report's chapter on the particle-system tutorial (seed 004): each of its claims and
//! examples run with the crate's integrators and checked against a closed form or a stated
//! bound ([`studies`]), drawn ([`figures`]) and written as a section of `REPORT.md` with its
//! data in `data/tutorial_*.csv`. Nothing here is typed in: every number is computed by
//! [`TutorialChapter::compute`].

pub mod figures;
pub use mass_spring_solvers::studies::tutorial as studies;

use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::{full, short, sig, sig4, MarkdownTable};
use crate::output::OutputFile;
use figures::sig_short;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::particles::adaptive::{MAX_GROWTH, MAX_SHRINK, SAFETY};
use mass_spring_solvers::particles::Integrator;
use mass_spring_solvers::solvers::registry::SolverId;
use studies::{
    AdaptiveStudy, BounceRun, ClothDropRun, ConvergenceSeries, DragFall, EnergyRun,
    GravityParticle, PendulumRun, SpringPairRun, StabilityLimit,
};

/// Every result of the chapter.
#[derive(Debug, Clone, PartialEq)]
pub struct TutorialChapter {
    pub convergence: Vec<ConvergenceSeries>,
    pub limits: Vec<StabilityLimit>,
    pub energy: Vec<EnergyRun>,
    pub drag: DragFall,
    pub pair: SpringPairRun,
    pub gravities: Vec<GravityParticle>,
    pub bounces: Vec<BounceRun>,
    pub pendulum: PendulumRun,
    pub cloth: ClothDropRun,
    pub adaptive: AdaptiveStudy,
}

impl TutorialChapter {
    /// Runs every study (about a second).
    pub fn compute() -> Result<Self> {
        Ok(Self {
            convergence: studies::convergence()?,
            limits: studies::stability_limits()?,
            energy: studies::energy_runs()?,
            drag: studies::drag_fall()?,
            pair: studies::spring_pair()?,
            gravities: studies::several_gravities()?,
            bounces: studies::bounces()?,
            pendulum: studies::pendulum()?,
            cloth: studies::cloth_drop()?,
            adaptive: studies::adaptive()?,
        })
    }

    /// The chapter's figures, in the order the section shows them.
    pub fn figures(&self) -> Result<Vec<ChapterFigure>> {
        Ok(vec![
            figures::convergence(&self.convergence)?,
            figures::stability_energy(&self.energy)?,
            figures::forces(&self.drag, &self.pair)?,
            figures::pendulum_frames(&self.pendulum)?,
            figures::pendulum_energy(&self.pendulum)?,
            figures::cloth_drop(&self.cloth)?,
            figures::adaptive(&self.adaptive)?,
        ])
    }

    /// The chapter's files: `figures/tutorial_*.svg` and `data/tutorial_*.csv`.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files = crate::chapter_figure::chapter_figure_files(figures);
        files.push(OutputFile::text(
            "data/tutorial_stability.csv",
            self.stability_csv(),
        ));
        files.push(OutputFile::text(
            "data/tutorial_gravities.csv",
            self.gravities_csv(),
        ));
        files.push(OutputFile::text(
            "data/tutorial_bounces.csv",
            self.bounces_csv(),
        ));
        files
    }

    fn stability_csv(&self) -> String {
        let mut csv = CsvFile::new(&["integrator", "largest_stable_h_omega", "closed_form"]);
        for l in &self.limits {
            csv.record(vec![
                l.integrator.key().to_string(),
                full(l.measured),
                full(l.expected),
            ]);
        }
        csv.text()
    }

    fn gravities_csv(&self) -> String {
        let mut csv = CsvFile::new(&[
            "particle",
            "gravities",
            "x_m",
            "y_m",
            "z_m",
            "closed_x_m",
            "closed_y_m",
            "closed_z_m",
        ]);
        for (i, p) in self.gravities.iter().enumerate() {
            csv.record(vec![
                i.to_string(),
                p.gravities.join(" + ").to_string(),
                full(p.ours.x),
                full(p.ours.y),
                full(p.ours.z),
                full(p.closed.x),
                full(p.closed.y),
                full(p.closed.z),
            ]);
        }
        csv.text()
    }

    fn bounces_csv(&self) -> String {
        let mut csv = CsvFile::new(&["scheme", "bounce", "energy_kept", "restitution_squared"]);
        let e2 = studies::DROP.1.powi(2);
        for run in &self.bounces {
            for (n, kept) in run.kept.iter().enumerate() {
                csv.record(vec![
                    run.scheme.to_string(),
                    (n + 1).to_string(),
                    full(*kept),
                    full(e2),
                ]);
            }
        }
        csv.text()
    }

    /// The chapter's section of `REPORT.md`, headed `## {number}.`.
    pub fn section(&self, number: u32, figures: &[ChapterFigure]) -> String {
        let figure = |stem: &str, caption: String| {
            figures
                .iter()
                .find(|f| f.stem == stem)
                .map(|f| {
                    format!(
                        "![{stem}](figures/{s}.svg)\n\n*{caption}* Data: [`data/{s}.csv`](data/{s}.csv).\n\n",
                        s = f.stem
                    )
                })
                .unwrap_or_default()
        };
        let mut md = format!("## {number}. The particle-system tutorial, verified\n\n");
        md += "The tutorial that goes with the thesis (seed 004, \"Simulación física. Métodos numéricos\", after \
               Baraff and Witkin) builds a particle system: particles with force accumulators, gravity, drag and \
               damped springs as force objects, explicit Euler and RK4, a floor, a falling cloth and a bouncing \
               pendulum (`src/particles/`). Each of its claims and examples is run here and set against a closed \
               form or a stated bound; `tests/tutorial_chapter.rs` fails when one does not hold. Every number \
               below is computed when the report is generated.\n\n";
        md += &self.convergence_md(number);
        md += &figure(
            "tutorial_convergence",
            format!(
                "Figure T1. Global error at t = {} s against the step h, log-log, on the oscillator of {}.1; the legend \
                 gives each fitted slope and the expected order.",
                full(studies::CONVERGENCE_TIME),
                number
            ),
        );
        md += &self.stability_md(number);
        md += &figure(
            "tutorial_stability_energy",
            format!(
                "Figure T2. Energy of the undamped oscillator over time (in periods), each integrator just below \
                 (solid) and just above (dashed) its limit; explicit Euler, stable at no step, at hω = {}. Runs \
                 stop when the energy exceeds {} times the initial one; the spring's rest length, {} m, keeps it \
                 linear.",
                studies::energy_h_omegas(Integrator::ExplicitEuler)
                    .map(short)
                    .join(" and "),
                sig(studies::ENERGY_CAP, 1),
                sig(studies::ENERGY_REST_LENGTH, 1)
            ),
        );
        md += &self.forces_md(number);
        md += &figure(
            "tutorial_forces",
            "Figure T3. (a) The falling particle's speed with drag against the closed form and the terminal \
             velocity; (b) the stretch of the two-particle damped spring against the damped-oscillator solution \
             and its envelope."
                .into(),
        );
        md += &self.collisions_md(number, &figure);
        md += &self.adaptive_md(number);
        md += &figure(
            "tutorial_adaptive",
            format!(
                "Figure T7. The adaptive integrator: (a) the error at the end of the run against the tolerance, \
                 for the pendulum (against the run at tolerance {}) and for the dropped particle (against its \
                 closed-form bouncing trajectory); (b) force evaluations and accepted steps.",
                sig(studies::REFERENCE_TOLERANCE, 1)
            ),
        );
        md
    }

    fn convergence_md(&self, number: u32) -> String {
        let osc = studies::Oscillator::standard(studies::CONVERGENCE_ZETA);
        let mut md = format!("### {number}.1 Convergence orders\n\n");
        md += &format!(
            "One particle of {} kg on a spring of k = {} N/m (ω = {} rad/s) to an anchor, no gravity, released \
             with stretch {} m and speed {} m/s: its stretch obeys m ü = −k u − k_d u̇ exactly, whose solution is \
             closed-form. The error is the phase-plane distance $\\sqrt{{e_u^2 + (e_v/\\omega)^2}}$ at t = {} s; \
             the slope is the least-squares fit of log error against log h over {} halvings of h. The \
             oscillator is damped (ζ = {}, the tutorial's spring damping) for every method but Backward Euler, \
             whose springs (the thesis's) have no damping; it runs the undamped one.\n\n",
            full(osc.mass),
            full(osc.stiffness),
            full(osc.omega()),
            full(osc.u0),
            full(osc.v0),
            full(studies::CONVERGENCE_TIME),
            self.convergence.first().map_or(0, |s| s.points.len() - 1),
            full(studies::CONVERGENCE_ZETA)
        );
        let mut t = MarkdownTable::new(&[
            "method",
            "ζ",
            "h (s)",
            "error at largest h (m)",
            "error at smallest h (m)",
            "fitted slope",
            "expected order",
        ]);
        for s in &self.convergence {
            let (first, last) = (s.points[0], s.points[s.points.len() - 1]);
            t.row(vec![
                s.method.to_string(),
                full(s.zeta),
                format!("{} … {}", sig(first.0, 3), sig(last.0, 3)),
                sig4(first.1),
                sig4(last.1),
                sig4(s.slope),
                s.method.expected_order().to_string(),
            ]);
        }
        md += &t.render();
        let euler = self
            .convergence
            .iter()
            .find(|s| s.method == studies::Method(SolverId::ExplicitEuler))
            .map_or(f64::NAN, |s| s.slope);
        md += &format!(
            "\nThe tutorial's \"Euler es un Runge-Kutta de orden 2\" does not hold (Figure T1): explicit Euler's error falls \
             with slope {} — it is the one-stage Runge-Kutta method, of order 1 (the order-2 ones are midpoint and \
             Heun). Dormand-Prince 5 is the fifth-order solution of the adaptive pair of {number}.5, here with a \
             fixed step, which checks its tableau.\n\n",
            sig4(euler)
        );
        md
    }

    fn stability_md(&self, number: u32) -> String {
        let mut md = format!("### {number}.2 Stability\n\n");
        md += &format!(
            "On the undamped oscillator each integrator is a linear map of (u, v/ω) per step. Its 2×2 matrix is \
             measured by stepping the crate's integrator once from two perturbations of the rest state, and the \
             largest stable hω found by bisection ({} halvings of [{}, {}]) on its spectral radius ρ: stable when \
             ρ ≤ 1 + {}. The closed forms: explicit Euler's factor $\\sqrt{{1 + h^2\\omega^2}}$ exceeds 1 at every \
             h > 0; symplectic Euler's eigenvalues leave the unit circle at hω = 2; RK4's factor on the imaginary \
             axis, $|R(iy)|^2 = 1 - y^6/72 + y^8/576$, exceeds 1 beyond y = 2√2.\n\n",
            studies::BISECTION_STEPS,
            full(studies::STABILITY_SEARCH.0),
            full(studies::STABILITY_SEARCH.1),
            sig(studies::GROWTH_THRESHOLD, 1)
        );
        let mut t = MarkdownTable::new(&[
            "integrator",
            "largest stable hω, measured",
            "closed form",
            "difference",
        ]);
        for l in &self.limits {
            t.row(vec![
                l.integrator.to_string(),
                sig(l.measured, 10),
                sig(l.expected, 10),
                sig(l.measured - l.expected, 2),
            ]);
        }
        md += &t.render();
        md += &format!(
            "\nExplicit Euler's measured limit (Figure T2) is the bisection's resolution, not a stable range: its growth per \
             step, $\\sqrt{{1 + h^2\\omega^2}} - 1 \\approx h^2\\omega^2/2$, is below the threshold {} only for hω \
             < {}. Data: [`data/tutorial_stability.csv`](data/tutorial_stability.csv).\n\n",
            sig(studies::GROWTH_THRESHOLD, 1),
            sig((2.0 * studies::GROWTH_THRESHOLD).sqrt(), 2)
        );
        md
    }

    fn forces_md(&self, number: u32) -> String {
        let (m, g, k_f) = studies::DRAG;
        let d = &self.drag;
        let p = &self.pair;
        let mut md = format!("### {number}.3 Forces against their closed forms\n\n");
        md += &format!(
            "**Drag** (Figure T3 (a)). A particle of {} kg falling from rest under g = {} m/s² with drag f = −k_f v, k_f = {} N·s/m \
             (RK4, h = {} s): its speed follows $\\frac{{mg}}{{k_f}}(1 - e^{{-k_f t/m}})$ to within {} m/s over \
             {} s, and at t = 20 m/k_f it is {} m/s against the terminal velocity m g / k_f = {} m/s.\n\n",
            full(m),
            full(g),
            full(k_f),
            full(studies::FORCE_DT),
            sig(d.max_error, 2),
            full(20.0 * m / k_f),
            sig(d.final_speed, 10),
            full(d.terminal)
        );
        md += &format!(
            "**The damped spring** (Figure T3 (b)). Two free particles of {} and {} kg joined by the tutorial's spring (k_s = {} \
             N/m, k_d = {} N·s/m, rest length {} m), released at rest {} m stretched, no gravity (RK4, h = {} s, \
             {} s). The stretch obeys μ ü = −k_s u − k_d u̇ with the reduced mass μ = {} kg; the decay rate and \
             the frequency are measured from the stretch's maxima (a least-squares fit of their logarithm, and \
             their mean spacing):\n\n",
            full(p.pair.mass_a),
            full(p.pair.mass_b),
            full(p.pair.stiffness),
            full(p.pair.damping),
            full(p.pair.rest_length),
            full(p.pair.stretch),
            full(studies::PAIR_DT),
            full(studies::PAIR_TIME),
            full(p.pair.reduced_mass())
        );
        let mut t = MarkdownTable::new(&["quantity", "measured", "closed form"]);
        t.row(vec![
            "decay rate k_d / 2μ (1/s)".into(),
            sig(p.measured_decay, 8),
            sig(p.pair.decay_rate(), 8),
        ]);
        t.row(vec![
            "damped frequency √(k_s/μ − (k_d/2μ)²) (rad/s)".into(),
            sig(p.measured_frequency, 8),
            sig(p.pair.damped_frequency(), 8),
        ]);
        t.row(vec![
            "largest |stretch − closed form| (m)".into(),
            sig(p.max_error, 2),
            "0".into(),
        ]);
        t.row(vec![
            "largest |total momentum| (kg·m/s)".into(),
            sig(p.max_momentum, 2),
            "0".into(),
        ]);
        md += &t.render();
        md += &format!(
            "\n**Several gravities.** The tutorial lets several gravity objects act on different sets of \
             particles of one system. Four unconnected particles of 1 kg, three gravity objects (RK4, h = {} s, \
             {} s); each particle against $x_0 + v_0 t + \\frac12 \\sum g\\,t^2$ over the gravities acting on \
             it (RK4 is exact on these parabolas; the differences are rounding):\n\n",
            full(studies::FORCE_DT),
            full(studies::GRAVITIES_TIME)
        );
        let v = |x: mass_spring_solvers::model::system::Vec3| {
            format!("({}, {}, {})", sig4(x.x), sig4(x.y), sig4(x.z))
        };
        let mut t = MarkdownTable::new(&[
            "particle",
            "gravities acting",
            "x₀ (m)",
            "v₀ (m/s)",
            "x(t) ours (m)",
            "|ours − closed form| (m)",
        ]);
        for (i, p) in self.gravities.iter().enumerate() {
            t.row(vec![
                i.to_string(),
                p.gravities.join(" + "),
                v(p.start),
                v(p.velocity),
                v(p.ours),
                sig((p.ours - p.closed).norm(), 2),
            ]);
        }
        md += &t.render();
        md += "\nData: [`data/tutorial_gravities.csv`](data/tutorial_gravities.csv).\n\n";
        md
    }

    fn collisions_md(&self, number: u32, figure: &dyn Fn(&str, String) -> String) -> String {
        let (height, e, g) = studies::DROP;
        let mut md = format!("### {number}.4 Collisions\n\n");
        md += &format!(
            "The floor (`particles::ground`) puts a particle found below it back on it and reverses its normal \
             velocity scaled by the restitution e, after each step. A particle of 1 kg dropped from {} m (g = {} \
             m/s², e = {}) keeps $e^2$ = {} of its energy at each bounce; the energy after each bounce over the \
             energy after the previous one (the initial m g h for the first):\n\n",
            full(height),
            full(g),
            full(e),
            full(e * e)
        );
        let mut header = vec!["scheme".to_string()];
        header.extend((1..=studies::BOUNCES).map(|n| format!("bounce {n}")));
        header.push("largest |kept − e²|".into());
        let mut t = MarkdownTable::new(&header);
        for run in &self.bounces {
            let mut row = vec![run.scheme.to_string()];
            row.extend(run.kept.iter().map(|k| sig(*k, 6)));
            row.push(sig(
                run.kept
                    .iter()
                    .map(|k| (k - e * e).abs())
                    .fold(0.0, f64::max),
                2,
            ));
            t.row(row);
        }
        md += &t.render();
        md += "\nWith a fixed step the contact is seen up to one step late, so the energy kept is e² to first \
               order in h (compare RK4's two rows); the adaptive \
               integrator of the last row bounds the penetration by its tolerance. Data: \
               [`data/tutorial_bounces.csv`](data/tutorial_bounces.csv).\n\n";
        let p = &self.pendulum;
        let pp = &p.params;
        let lost_at_floor: f64 = p.contacts.iter().map(|c| c.2 - c.3).sum();
        let (e_start, e_end) = (
            p.energy.first().map_or(f64::NAN, |x| x.1),
            p.energy.last().map_or(f64::NAN, |x| x.1),
        );
        let first_contact = p.contacts.first().map_or(f64::NAN, |c| c.0);
        md += &format!(
            "**The pendulum** of the tutorial's six frames (Figure T4; its energy in Figure T5): {} particles of {} kg on damped springs ({} m, k_s = {} \
             N/m, k_d = {} N·s/m) hanging from a pivot {} m above the floor, released horizontal at rest, with \
             drag k_f = {} N·s/m and restitution {} ({}, h = {} s). The chain is longer than the pivot is high, so \
             it strikes the floor (first at t = {} s) and bounces. Over {} s its mechanical energy falls from {} \
             J to {} J; the {} steps in which the floor acted took {} J of it, the drag and the springs' damping \
             the rest.\n\n",
            pp.particles,
            full(pp.particle_mass),
            full(pp.segment_length),
            full(pp.stiffness),
            full(pp.damping),
            full(pp.pivot_height),
            full(pp.drag),
            full(pp.restitution),
            p.integrator,
            full(p.dt),
            sig4(first_contact),
            full(studies::PENDULUM_TIME),
            sig4(e_start),
            sig4(e_end),
            p.contacts.len(),
            sig4(lost_at_floor)
        );
        md += &figure(
            "tutorial_pendulum_frames",
            format!(
                "Figure T4. The pendulum at t = {} s, drawn to scale (the bar is 1 m), as the tutorial's sequence \
                 of six frames; grey: the floor.",
                p.frames
                    .iter()
                    .map(|f| sig_short(f.0))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        );
        md += &figure(
            "tutorial_pendulum_energy",
            "Figure T5. The pendulum's mechanical energy (kinetic + gravitational + elastic) against time; red: \
             the steps in which the floor acted, at the energy after the step."
                .into(),
        );
        let c = &self.cloth;
        let cp = &c.params;
        md += &format!(
            "**The cloth falling 10 m** (Figure T6). The tutorial's example: a {}×{} cloth (a particle per vertex of a \
             triangle mesh, {} kg each, a spring per edge, k_s = {} N/m, k_d = {} N·s/m) dropped flat from {} m \
             onto the floor (restitution {}) with a light drag k_f = {} N·s/m (RK4, h = {} s). The springs' \
             forces cancel in the sum, so until the first contact the centre of mass falls exactly as one \
             particle with drag, $y_c = y_0 - v_t(t - \\tau(1 - e^{{-t/\\tau}}))$ with τ = m/k_f: it does so \
             to within {} m. The first particle reaches the floor at t = {} s (the closed form: {} s, to within \
             one step); no particle ever goes below the floor (lowest: {} m); at t = {} s the highest particle is \
             {} m above the floor and the kinetic energy is {} J.\n\n",
            cp.cloth.nx,
            cp.cloth.ny,
            full(cp.cloth.particle_mass),
            full(cp.cloth.stiffness),
            full(cp.cloth.damping),
            full(cp.height),
            full(cp.restitution),
            full(cp.drag),
            full(c.dt),
            sig(c.max_centre_error, 2),
            sig4(c.first_contact),
            sig4(c.closed_contact),
            sig4(c.lowest),
            full(studies::CLOTH_TIME),
            sig(c.final_highest, 3),
            sig(c.final_kinetic, 3)
        );
        md += &figure(
            "tutorial_cloth_drop",
            format!(
                "Figure T6. The cloth drop: (a) the height of the centre of mass against time, \
                 simulated and in closed form, which agree to {} m until the first contact (dotted, \
                 {} s; the closed form reaches the floor at {} s); (b) the cloth in side view \
                 (every spring projected on the x-y plane), to scale, at t = {} s and at the first \
                 contact, each frame named above it: it falls flat and lands flat.",
                sig(c.max_centre_error, 2),
                sig4(c.first_contact),
                sig4(c.closed_contact),
                studies::CLOTH_FRAMES
                    .iter()
                    .filter(|&&t| t <= c.first_contact)
                    .map(|t| short(*t))
                    .collect::<Vec<_>>()
                    .join(", "),
            ),
        );
        md
    }

    fn adaptive_md(&self, number: u32) -> String {
        let a = &self.adaptive;
        let mut md = format!("### {number}.5 Adaptive step size\n\n");
        md += &format!(
            "The tutorial ends by promising another article on adaptive step size. `particles::adaptive` \
               implements the embedded Runge-Kutta pair of Dormand and Prince, 5(4): seven stages per step give a \
               fifth-order solution, which is kept, and a fourth-order one; their difference estimates the local \
               error. A step is accepted when that estimate is within T (1 + |y|) for every position and velocity \
               component, T the tolerance, and the next step is h·min({}, max({}, {} err^(−1/5))). **Bounces are \
               handled by step rejection**, not event location: the floor is not in the differential equation, so \
               a step that leaves a particle more than T (1 + |floor height|) below the floor is rejected and \
               retried with half the step; the accepted step then ends at most that deep past the contact, where \
               the floor responds as for the fixed-step integrators. `mss --solver rk45 --tolerance T` runs it.\n\n",
            short(MAX_GROWTH),
            short(MAX_SHRINK),
            short(SAFETY)
        );
        md += &format!(
            "Below: the pendulum of {number}.4 for {} s (error: the largest distance of a particle from the run at \
             tolerance {}, which took {} steps) and the dropped particle of {number}.4 for {} s (error: against \
             the closed-form bouncing trajectory).\n\n",
            full(studies::ADAPTIVE_TIME),
            sig(studies::REFERENCE_TOLERANCE, 1),
            a.reference.accepted,
            full(studies::DROP_TIME)
        );
        let mut t = MarkdownTable::new(&[
            "tolerance T",
            "pendulum: accepted",
            "rejected (error)",
            "rejected (floor)",
            "force evaluations",
            "steps (s)",
            "error (m)",
            "dropped particle: evaluations",
            "error (m)",
        ]);
        for (p, d) in a.pendulum.iter().zip(&a.drop) {
            t.row(vec![
                sig(p.tolerance, 1),
                p.stats.accepted.to_string(),
                p.stats.rejected_error.to_string(),
                p.stats.rejected_contact.to_string(),
                p.stats.evaluations.to_string(),
                format!(
                    "{} … {}",
                    sig(p.stats.smallest_step, 2),
                    sig(p.stats.largest_step, 2)
                ),
                sig(p.error, 2),
                d.stats.evaluations.to_string(),
                sig(d.error, 2),
            ]);
        }
        md += &t.render();
        let slope = |runs: &[studies::AdaptiveRun], f: &dyn Fn(&studies::AdaptiveRun) -> f64| {
            studies::log_log_slope(&runs.iter().map(|r| (r.tolerance, f(r))).collect::<Vec<_>>())
        };
        md += &format!(
            "\nOn the pendulum the error falls with the tolerance (Figure T7; fitted slope {}) and the accepted steps grow \
             as T to the power {} (a fifth-order method: −1/5 expected away from contacts). For comparison, RK4 \
             with a fixed step: {}.\n\n",
            sig(slope(&a.pendulum, &|r| r.error), 3),
            sig(slope(&a.pendulum, &|r| r.stats.accepted as f64), 3),
            a.rk4
                .iter()
                .map(|(h, evaluations, error)| format!(
                    "h = {} s, {evaluations} evaluations, error {} m",
                    short(*h),
                    sig(*error, 2)
                ))
                .collect::<Vec<_>>()
                .join("; ")
        );
        md
    }
}

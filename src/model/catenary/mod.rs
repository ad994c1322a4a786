//! Analytic reference solutions for the hanging rope of thesis section 3.1 (Figure 2).
//!
//! The thesis verifies its Backward-Euler mass-spring solver on a rope of 10 nodes of 1 kg
//! joined by 9 springs of rest length $`l_0 = 1`$ m, node 0 fixed at $`(0, 0)`$ m, node 9 fixed at
//! $`(9, 0)`$ m, gravity $`g = 9.81\,\mathrm{m/s^2}`$ along $`-y`$ and stiffness $`k = 10^3`$ or
//! $`10^6`$ N/m. The rest length of the rope equals the anchor span, so the rope can only sag by
//! stretching: an inextensible catenary has no solution there, and both references below are
//! extensible.
//!
//! # Discrete elastic chain ([`ElasticChain`] → [`ChainEquilibrium`])
//!
//! The exact static equilibrium of the simulated system itself, where a converged Backward-Euler
//! run must come to rest. No load acts horizontally, so every spring carries the same horizontal
//! tension $`H`$, while the vertical component grows by the weight of each free node: spring $`j`$
//! (joining nodes $`j`$ and $`j+1`$) carries $`V_j = V_0 + g\sum_{i=1}^{j} m_i`$. A linear spring
//! under tension $`T_j = \sqrt{H^2 + V_j^2}`$ has length $`l_{0,j} + T_j/k_j`$ along
//! $`(H, V_j)/T_j`$, so the equilibrium is the root $`(H, V_0)`$ of the closure condition
//! ```math
//! \sum_{j=0}^{N-2} \left(\frac{l_{0,j}}{T_j} + \frac{1}{k_j}\right)
//! \begin{pmatrix} H \\ V_j \end{pmatrix} = B - A .
//! ```
//!
//! # Continuous elastic catenary ([`ElasticCatenary`])
//!
//! Irvine's closed form for a cable of unstretched length $`L`$, weight $`w`$ per unit unstretched
//! length and axial stiffness $`EA`$. In the Lagrangian coordinate $`s \in [0, L]`$ the tension is
//! $`(H, V(s))`$ with $`V(s) = V_0 + w s`$, and
//! ```math
//! \begin{aligned}
//! x(s) &= x_A + \frac{H s}{EA} + \frac{H}{w}\left[\operatorname{asinh}\frac{V(s)}{H} -
//!   \operatorname{asinh}\frac{V_0}{H}\right],\\
//! y(s) &= y_A + \frac{V_0 s + w s^2/2}{EA} + \frac{1}{w}\left[\sqrt{H^2 + V(s)^2} -
//!   \sqrt{H^2 + V_0^2}\right].
//! \end{aligned}
//! ```
//!
//! The thesis rope corresponds to $`L = 9`$ m, $`w = m g / l_0`$ and $`EA = k l_0`$. The chain with
//! $`N`$ nodes, $`l_0 = L/(N-1)`$, $`k = EA/l_0`$ and free-node weight $`w l_0`$ is the
//! midpoint-rule discretisation of the integrals above (with $`V_0`$ shifted by $`w l_0/2`$, each
//! spring carries the exact tension of the cable at its midpoint), so its node $`i`$ converges to
//! the cable point $`s_i = i\,l_0`$ at second order in $`l_0`$;
//! [`ElasticCatenary::max_node_distance`] measures that gap.
//!
//! # Solving
//!
//! Both closure conditions are the gradient of the strictly convex complementary energy
//! $`\Pi^*(H, V_0) = \sum_j \left(l_{0,j} T_j + T_j^2/(2k_j)\right) - H\,\Delta x - V_0\,\Delta y`$
//! (an integral over $`s`$ for the cable), so their 2×2 Jacobians are symmetric positive definite
//! and the root is unique. Newton's method uses those analytic Jacobians, starting from a
//! shallow elastic cable. It is globalised by keeping $`H`$ on the curve where the horizontal
//! closure holds (increasing and concave in $`H`$) and bracketing $`V_0`$, along which the vertical
//! residual is monotone; a plain damped Newton step in $`(H, V_0)`$ can instead be drawn into the
//! kink of $`\Pi^*`$ at $`H = 0`$ where a spring goes slack. The closure residual ends at most
//! $`10^{-13}`$ of the stretched length, for stiffnesses from 1 N/m to $`10^9`$ N/m.
//!
//! The chain model assumes every spring is in tension. A spring can only go slack when $`H = 0`$,
//! with the rest of the chain hanging in two vertical strands, so this holds whenever the
//! horizontal anchor span exceeds every rest length. When it fails, or when a nearly degenerate
//! geometry leaves rounding above the tolerance, the solve returns
//! [`CatenaryError::NoConvergence`].

// H, V0, EA, L and W are the symbols of the thesis and of Irvine; snake_case would hide them.
#![allow(non_snake_case)]

use std::fmt;

use nalgebra::{Matrix2, Vector2, Vector3};

/// Gravitational acceleration of the thesis experiments, $`g = 9.81\,\mathrm{m/s^2}`$ along $`-y`$.
pub const THESIS_GRAVITY: f64 = 9.81;

/// Largest closure residual accepted, relative to the stretched cable length; a few ulps per
/// spring is the best the closure sum can do.
const RELATIVE_TOLERANCE: f64 = 1e-13;
/// Budget of Newton steps, on $`H`$ and $`V_0`$ together; typical solves take under 30.
const MAX_NEWTON_ITERATIONS: usize = 500;
/// Newton stops once its step is this small relative to the unknowns: a few ulps.
const RESOLUTION: f64 = 4.0 * f64::EPSILON;
/// Enough doublings to sweep the whole `f64` range when bracketing the starting tension.
const MAX_BRACKET_DOUBLINGS: usize = 2200;
/// The starting tension only has to be in the right ballpark.
const GUESS_BISECTIONS: usize = 60;

/// Why a catenary could not be built or solved.
#[derive(Debug, Clone, PartialEq)]
pub enum CatenaryError {
    /// A parameter is non-finite or outside its allowed range.
    InvalidParameter {
        /// Name of the offending field or argument.
        field: &'static str,
        /// Entry of a per-node or per-spring field, if the field is a list.
        index: Option<usize>,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A chain needs two anchors and at least one free node.
    TooFewNodes {
        /// The node count asked for.
        node_count: usize,
    },
    /// A per-spring or per-node list does not match the number of springs in `rest_lengths`.
    LengthMismatch {
        /// Name of the offending list.
        field: &'static str,
        /// Its length.
        found: usize,
        /// The length the chain needs.
        expected: usize,
    },
    /// Newton's method did not reach the residual tolerance (see the module documentation for
    /// when a chain has no all-tension equilibrium).
    NoConvergence {
        /// Which model was being solved.
        problem: &'static str,
        /// Newton steps spent.
        iterations: usize,
        /// Closure residual relative to the stretched cable length when it gave up.
        relative_residual: f64,
    },
}

impl fmt::Display for CatenaryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidParameter {
                field,
                index,
                value,
                allowed,
            } => {
                write!(f, "invalid {field}")?;
                if let Some(index) = index {
                    write!(f, "[{index}]")?;
                }
                write!(f, ": {value} (allowed: {allowed})")
            }
            Self::TooFewNodes { node_count } => write!(
                f,
                "invalid node_count: {node_count} (allowed: >= 3, two anchors and at least one \
                 free node)"
            ),
            Self::LengthMismatch {
                field,
                found,
                expected,
            } => write!(
                f,
                "invalid {field}: {found} entries (allowed: exactly {expected}, to match \
                 rest_lengths)"
            ),
            Self::NoConvergence {
                problem,
                iterations,
                relative_residual,
            } => write!(
                f,
                "{problem} did not converge in {iterations} Newton steps (closure residual \
                 {relative_residual:e} of the stretched length; allowed: <= \
                 {RELATIVE_TOLERANCE:e})"
            ),
        }
    }
}

impl std::error::Error for CatenaryError {}

mod chain;
mod continuous;
pub use chain::{ChainEquilibrium, ElasticChain};
pub use continuous::ElasticCatenary;

fn require_positive(
    field: &'static str,
    index: Option<usize>,
    value: f64,
) -> Result<(), CatenaryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CatenaryError::InvalidParameter {
            field,
            index,
            value,
            allowed: "finite and > 0",
        })
    }
}

fn validate_anchors(anchor_a: &Vector3<f64>, anchor_b: &Vector3<f64>) -> Result<(), CatenaryError> {
    for (field, value) in [
        ("anchor_a.x", anchor_a.x),
        ("anchor_a.y", anchor_a.y),
        ("anchor_b.x", anchor_b.x),
        ("anchor_b.y", anchor_b.y),
    ] {
        if !value.is_finite() {
            return Err(CatenaryError::InvalidParameter {
                field,
                index: None,
                value,
                allowed: "finite",
            });
        }
    }
    for (field, value) in [("anchor_a.z", anchor_a.z), ("anchor_b.z", anchor_b.z)] {
        if value != 0.0 {
            return Err(CatenaryError::InvalidParameter {
                field,
                index: None,
                value,
                allowed: "exactly 0 (the rope hangs in the x-y plane)",
            });
        }
    }
    // With no horizontal span H vanishes and the closed forms, which divide by H, break down.
    if anchor_b.x <= anchor_a.x {
        return Err(CatenaryError::InvalidParameter {
            field: "anchor_b.x",
            index: None,
            value: anchor_b.x,
            allowed: "> anchor_a.x",
        });
    }
    Ok(())
}

/// Starting $`(H, V_0)`$ from a shallow (parabolic) elastic cable along the chord: its tension
/// $`T`$ makes the stretch $`C T`$ plus the sag's extra length $`W_\perp^2 D / (24 T^2)`$ cover the
/// gap between the chord length $`D`$ and the unstretched length $`L`$, where $`C`$ is the total
/// compliance and $`W_\perp`$ the weight component normal to the chord.
fn shallow_cable_guess(chord: Vector2<f64>, L: f64, W: f64, C: f64) -> Vector2<f64> {
    let D = chord.norm();
    let W_normal = W * chord.x / D;
    // Increasing in T from -inf to +inf, so one root, bracketed by doubling and halving.
    let length_surplus = |T: f64| L + C * T - D - W_normal * W_normal * D / (24.0 * T * T);
    let (mut lower, mut upper) = (W, W);
    for _ in 0..MAX_BRACKET_DOUBLINGS {
        if length_surplus(upper) >= 0.0 {
            break;
        }
        upper *= 2.0;
    }
    for _ in 0..MAX_BRACKET_DOUBLINGS {
        if length_surplus(lower) <= 0.0 {
            break;
        }
        lower *= 0.5;
    }
    // Tensions span decades between k = 1 N/m and stiff chains, so bisect geometrically.
    for _ in 0..GUESS_BISECTIONS {
        let middle = lower.sqrt() * upper.sqrt();
        if length_surplus(middle) < 0.0 {
            lower = middle;
        } else {
            upper = middle;
        }
    }
    let T = lower.sqrt() * upper.sqrt();
    Vector2::new(T * chord.x / D, T * chord.y / D - W / 2.0)
}

/// Closure residual $`r = \sum_j d_j - (B - A)`$ and its Jacobian at one $`(H, V_0)`$.
struct Evaluation {
    residual: Vector2<f64>,
    jacobian: Matrix2<f64>,
    /// Stretched length of the cable, the scale of the residual.
    length_scale: f64,
}

struct NewtonSolution {
    unknowns: Vector2<f64>,
    iterations: usize,
    relative_residual: f64,
}

/// Solves the closure $`r(H, V_0) = 0`$ by Newton's method on $`V_0`$ along the curve where the
/// horizontal closure $`r_x = 0`$ holds, with $`H`$ kept on that curve by
/// [`balance_horizontal_tension`].
///
/// A plain damped Newton step in $`(H, V_0)`$ can be drawn into a point $`H = 0`$,
/// $`V_0 = -g\sum_{i \le j} m_i`$ where spring $`j`$ would be slack, because the complementary
/// energy has a cone-shaped kink there. On the curve $`H > 0`$, so no spring is ever slack, and
/// the vertical residual increases with $`V_0`$ at the rate
/// $`\partial_{V_0} r_y - (\partial_{V_0} r_x)^2 / \partial_H r_x`$ (the Schur complement of the
/// symmetric positive definite Jacobian), so the root can be bracketed and Newton falls back to
/// bisection whenever it would leave the bracket.
fn solve_closure(
    problem: &'static str,
    guess: Vector2<f64>,
    evaluate: impl Fn(f64, f64) -> Evaluation,
) -> Result<NewtonSolution, CatenaryError> {
    let mut V0 = guess.y;
    let (mut H, mut current, mut iterations) = balance_horizontal_tension(&evaluate, guess.x, V0);
    // V0 values known to give a negative and a positive vertical residual.
    let (mut below, mut above) = (f64::NEG_INFINITY, f64::INFINITY);
    while iterations < MAX_NEWTON_ITERATIONS {
        let vertical = current.residual.y;
        if vertical < 0.0 {
            below = V0;
        } else if vertical > 0.0 {
            above = V0;
        } else {
            break;
        }
        let J = current.jacobian;
        let slope = J[(1, 1)] - J[(0, 1)] * J[(1, 0)] / J[(0, 0)];
        let newton = V0 - vertical / slope;
        // Rounding can leave a bracket end at the root itself, hence the closed interval; the
        // comparisons also reject a NaN step.
        let next = if newton >= below && newton <= above {
            newton
        } else if below.is_finite() && above.is_finite() {
            0.5 * (below + above)
        } else {
            // No usable slope and only one side known: step outwards by the tension scale.
            V0 - vertical.signum() * (V0.abs() + H)
        };
        let resolved = (next - V0).abs() <= RESOLUTION * (V0.abs() + H);
        let (next_H, next_evaluation, horizontal_steps) =
            balance_horizontal_tension(&evaluate, H, next);
        iterations += 1 + horizontal_steps;
        // Within tolerance, a step that does not shrink the residual only stirs rounding noise.
        if current.residual.norm() <= RELATIVE_TOLERANCE * current.length_scale
            && next_evaluation.residual.norm() >= current.residual.norm()
        {
            break;
        }
        (V0, H, current) = (next, next_H, next_evaluation);
        if resolved {
            break;
        }
    }

    let relative_residual = current.residual.norm() / current.length_scale;
    if relative_residual <= RELATIVE_TOLERANCE {
        Ok(NewtonSolution {
            unknowns: Vector2::new(H, V0),
            iterations,
            relative_residual,
        })
    } else {
        Err(CatenaryError::NoConvergence {
            problem,
            iterations,
            relative_residual,
        })
    }
}

/// Solves the horizontal closure $`r_x(H) = 0`$ at fixed $`V_0`$ by Newton's method from `H`,
/// returning the root, the evaluation there and the number of steps.
///
/// $`r_x`$ is increasing and concave in $`H`$ and starts at $`r_x(0^+) = -\Delta x < 0`$, so a
/// Newton step from left of the root stays left and climbs to it monotonically, while a step
/// from the right lands left of it, or is replaced by halving $`H`$ if it would cross zero.
fn balance_horizontal_tension(
    evaluate: &impl Fn(f64, f64) -> Evaluation,
    mut H: f64,
    V0: f64,
) -> (f64, Evaluation, usize) {
    let mut current = evaluate(H, V0);
    let mut steps = 0;
    while steps < MAX_NEWTON_ITERATIONS {
        let horizontal = current.residual.x;
        if horizontal == 0.0 {
            break;
        }
        let newton = H - horizontal / current.jacobian[(0, 0)];
        let next = if newton > 0.0 { newton } else { 0.5 * H };
        let trial = evaluate(next, V0);
        // Left of the root Newton climbs monotonically towards it; a step that crosses it or
        // does not shrink |r_x| is rounding noise, so keep the better end and stop.
        if horizontal < 0.0 && !(trial.residual.x < 0.0 && trial.residual.x > horizontal) {
            if trial.residual.x.abs() < horizontal.abs() {
                (H, current) = (next, trial);
                steps += 1;
            }
            break;
        }
        let resolved = (next - H).abs() <= RESOLUTION * H;
        (H, current) = (next, trial);
        steps += 1;
        if resolved {
            break;
        }
    }
    (H, current, steps)
}

/// A catenary that cannot be found is bad input, or a Newton iteration that did not converge.
impl From<CatenaryError> for crate::error::Error {
    fn from(e: CatenaryError) -> Self {
        match e {
            CatenaryError::NoConvergence { .. } => crate::error::Error::NotConverged {
                what: "catenary".into(),
                detail: e.to_string(),
            },
            _ => crate::error::Error::Input(e.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error;

    type TestResult = Result<(), Box<dyn Error>>;

    /// Largest net force on a free node, recomputed from the positions alone, over its weight.
    fn max_relative_imbalance(chain: &ElasticChain, equilibrium: &ChainEquilibrium) -> f64 {
        let spring_force = |from: Vector3<f64>, to: Vector3<f64>, l0: f64, k: f64| {
            let d = to - from;
            let length = d.norm();
            k * (length - l0) * d / length
        };
        let positions = &equilibrium.positions;
        (1..chain.node_count() - 1)
            .map(|node| {
                let weight = chain.free_node_masses[node - 1] * chain.gravity;
                let net = spring_force(
                    positions[node],
                    positions[node + 1],
                    chain.rest_lengths[node],
                    chain.stiffnesses[node],
                ) + spring_force(
                    positions[node],
                    positions[node - 1],
                    chain.rest_lengths[node - 1],
                    chain.stiffnesses[node - 1],
                ) + Vector3::new(0.0, -weight, 0.0);
                net.norm() / weight
            })
            .fold(0.0, f64::max)
    }

    fn asymmetric_chain() -> ElasticChain {
        ElasticChain {
            anchor_a: Vector3::new(-1.0, 2.0, 0.0),
            anchor_b: Vector3::new(6.5, -1.5, 0.0),
            free_node_masses: vec![1.0, 0.5, 2.0, 1.5, 0.8, 1.2, 3.0],
            rest_lengths: vec![1.0, 1.2, 0.8, 1.5, 1.0, 0.9, 1.1, 1.3],
            stiffnesses: vec![1e3, 5e3, 2e3, 1e4, 3e3, 1e3, 8e3, 2e3],
            gravity: THESIS_GRAVITY,
        }
    }

    #[test]
    fn discrete_equilibrium_balances_every_free_node() -> TestResult {
        let mut cases = vec![(
            "asymmetric non-uniform chain".to_string(),
            asymmetric_chain(),
        )];
        for k in [1e3, 1e6] {
            cases.push((
                format!("thesis rope k = {k:e}"),
                ElasticChain::thesis_rope(k)?,
            ));
            let mut uneven = ElasticChain::thesis_rope(k)?;
            uneven.anchor_b = Vector3::new(8.0, 2.5, 0.0);
            cases.push((format!("thesis rope k = {k:e}, B at (8, 2.5)"), uneven));
        }
        for (name, chain) in cases {
            let equilibrium = chain.solve_equilibrium()?;
            let imbalance = max_relative_imbalance(&chain, &equilibrium);
            println!(
                "{name}: H = {:.12} N, V0 = {:.12} N, {} Newton iterations, \
                 residual {:.1e}, max |net force|/(m g) = {imbalance:.1e}",
                equilibrium.H,
                equilibrium.V0,
                equilibrium.newton_iterations,
                equilibrium.relative_residual
            );
            assert!(imbalance < 1e-9, "{name}: imbalance {imbalance:e}");
        }
        Ok(())
    }

    #[test]
    fn thesis_rope_is_symmetric_with_known_sags() -> TestResult {
        for (k, expected_sag, tolerance) in [(1e3, 1.47, 5e-3), (1e6, 0.143, 5e-4)] {
            let equilibrium = ElasticChain::thesis_rope(k)?.solve_equilibrium()?;
            let positions = &equilibrium.positions;
            for (node, mirror) in positions.iter().zip(positions.iter().rev()) {
                assert!(
                    (node.x + mirror.x - 9.0).abs() < 1e-12,
                    "x mirror at k = {k}"
                );
                assert!((node.y - mirror.y).abs() < 1e-12, "y mirror at k = {k}");
            }
            let sag = -positions.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            println!(
                "thesis rope k = {k:e}: lowest-node sag = {sag:.15} m, H = {:.15} N, V0 = {:.15} N",
                equilibrium.H, equilibrium.V0
            );
            assert!(
                (sag - expected_sag).abs() < tolerance,
                "k = {k}: sag {sag} m, expected about {expected_sag} m"
            );
        }
        Ok(())
    }

    #[test]
    fn continuous_catenary_meets_its_end_conditions() -> TestResult {
        let cases = [
            ElasticCatenary::thesis_rope(1e3)?,
            ElasticCatenary::thesis_rope(1e6)?,
            ElasticCatenary::solve(
                Vector3::new(-1.0, 2.0, 0.0),
                Vector3::new(6.5, -1.5, 0.0),
                11.0,
                15.0,
                2e4,
            )?,
        ];
        for catenary in cases {
            let start_gap = (catenary.position(0.0) - catenary.anchor_a).norm();
            let end_gap = (catenary.position(catenary.L) - catenary.anchor_b).norm();
            println!(
                "continuous EA = {:e}: H = {:.12} N, V0 = {:.12} N, |x(L) - B| = {end_gap:.1e} m, \
                 {} Newton iterations",
                catenary.EA, catenary.H, catenary.V0, catenary.newton_iterations
            );
            assert!(start_gap == 0.0, "x(0) misses A by {start_gap:e} m");
            assert!(end_gap < 1e-12, "x(L) misses B by {end_gap:e} m");
        }
        Ok(())
    }

    #[test]
    fn continuous_catenary_becomes_inextensible_as_ea_grows() -> TestResult {
        let (span, L, w) = (9.0, 12.0, THESIS_GRAVITY);
        // Classic catenary y = a cosh(x/a): bisect L = 2 a sinh(span / (2a)), decreasing in a.
        let (mut lower, mut upper) = (1e-2_f64, 1e3_f64);
        for _ in 0..200 {
            let a = 0.5 * (lower + upper);
            if 2.0 * a * (span / (2.0 * a)).sinh() > L {
                lower = a;
            } else {
                upper = a;
            }
        }
        let a = 0.5 * (lower + upper);
        let inextensible = |s: f64| {
            let from_middle = s - L / 2.0;
            Vector3::new(
                span / 2.0 + a * (from_middle / a).asinh(),
                a.hypot(from_middle) - a * (span / (2.0 * a)).cosh(),
                0.0,
            )
        };
        let inextensible_sag = a * ((span / (2.0 * a)).cosh() - 1.0);

        let mut previous_gap = f64::NAN;
        for EA in [1e6, 1e8, 1e10, 1e12] {
            let catenary =
                ElasticCatenary::solve(Vector3::zeros(), Vector3::new(span, 0.0, 0.0), L, w, EA)?;
            let gap = (0..=24)
                .map(|i| {
                    let s = L * i as f64 / 24.0;
                    (catenary.position(s) - inextensible(s)).norm()
                })
                .fold(0.0, f64::max);
            let sag = -catenary.position(L / 2.0).y;
            println!(
                "EA = {EA:e}: sag {sag:.12} m vs inextensible {inextensible_sag:.12} m, \
                 max shape gap {gap:.3e} m"
            );
            // The stretch, and so the gap, is proportional to 1/EA.
            if previous_gap.is_finite() {
                let ratio = previous_gap / gap;
                assert!(
                    (70.0..130.0).contains(&ratio),
                    "gap ratio {ratio} per 100x EA"
                );
            }
            previous_gap = gap;
        }
        assert!(
            previous_gap < 1e-7,
            "EA = 1e12 still {previous_gap:e} m away"
        );
        Ok(())
    }

    fn least_squares_slope(points: &[(f64, f64)]) -> f64 {
        let count = points.len() as f64;
        let mean_x = points.iter().map(|p| p.0).sum::<f64>() / count;
        let mean_y = points.iter().map(|p| p.1).sum::<f64>() / count;
        let covariance: f64 = points
            .iter()
            .map(|(x, y)| (x - mean_x) * (y - mean_y))
            .sum();
        let variance: f64 = points.iter().map(|(x, _)| (x - mean_x).powi(2)).sum();
        covariance / variance
    }

    #[test]
    fn discrete_chain_converges_to_catenary_at_second_order() -> TestResult {
        for EA in [1e3, 1e6] {
            let catenary = ElasticCatenary::thesis_rope(EA)?;
            let mut log_points = Vec::new();
            for node_count in [10, 20, 40, 80, 160] {
                let spacing = catenary.L / (node_count - 1) as f64;
                let distance = catenary.max_node_distance(node_count)?;
                println!("EA = {EA:e}, N = {node_count}: max node distance {distance:.6e} m");
                log_points.push((spacing.ln(), distance.ln()));
            }
            for pair in log_points.windows(2) {
                let order = (pair[1].1 - pair[0].1) / (pair[1].0 - pair[0].0);
                println!("EA = {EA:e}: pairwise order {order:.4}");
                assert!(
                    (order - 2.0).abs() < 0.1,
                    "EA = {EA}: pairwise order {order}"
                );
            }
            let fitted = least_squares_slope(&log_points);
            println!("EA = {EA:e}: least-squares order {fitted:.4}");
            assert!(
                (fitted - 2.0).abs() < 0.1,
                "EA = {EA}: fitted order {fitted}"
            );
        }
        Ok(())
    }

    #[test]
    fn solvers_converge_from_soft_to_stiff_springs() -> TestResult {
        let geometries = [
            ("thesis", 1.0, Vector3::new(9.0, 0.0, 0.0)),
            ("slack", 1.5, Vector3::new(9.0, 0.0, 0.0)),
            ("steep", 1.0, Vector3::new(2.0, -6.0, 0.0)),
            ("overstretched", 1.0, Vector3::new(12.0, 3.0, 0.0)),
        ];
        for (name, l0, anchor_b) in geometries {
            for exponent in 0..=9 {
                let k = 10f64.powi(exponent);
                let chain = ElasticChain::uniform(
                    10,
                    1.0,
                    l0,
                    k,
                    Vector3::zeros(),
                    anchor_b,
                    THESIS_GRAVITY,
                )?;
                let equilibrium = chain.solve_equilibrium()?;
                let catenary = ElasticCatenary::solve(
                    Vector3::zeros(),
                    anchor_b,
                    9.0 * l0,
                    THESIS_GRAVITY / l0,
                    k * l0,
                )?;
                let end_gap = (catenary.position(catenary.L) - anchor_b).norm();
                println!(
                    "{name} k = {k:e}: chain {} iterations (residual {:.1e}), \
                     catenary {} iterations (end gap {end_gap:.1e} m)",
                    equilibrium.newton_iterations,
                    equilibrium.relative_residual,
                    catenary.newton_iterations
                );
                assert!(equilibrium.relative_residual <= RELATIVE_TOLERANCE);
                assert!(catenary.relative_residual <= RELATIVE_TOLERANCE);
                assert!(
                    equilibrium.newton_iterations <= 60,
                    "{name} k = {k}: slow chain"
                );
                assert!(
                    catenary.newton_iterations <= 60,
                    "{name} k = {k}: slow catenary"
                );
                // Soft cables stretch to hundreds of metres; the gap scales with that length.
                assert!(end_gap <= 1e-12 * catenary.L * (1.0 + 1e3 / k));
            }
        }
        Ok(())
    }

    #[test]
    fn chain_needing_a_slack_spring_reports_no_convergence() -> TestResult {
        // One free node hanging 4.5 m below B ends up nearer than 4.5 m to A, so the spring
        // from A would have to push; the all-tension model has no equilibrium.
        let chain = ElasticChain::uniform(
            3,
            1.0,
            4.5,
            1e3,
            Vector3::zeros(),
            Vector3::new(4.0, 3.0, 0.0),
            THESIS_GRAVITY,
        )?;
        match chain.solve_equilibrium() {
            Err(error @ CatenaryError::NoConvergence { .. }) => {
                println!("{error}");
                Ok(())
            }
            other => Err(format!("expected NoConvergence, got {other:?}").into()),
        }
    }

    #[test]
    fn bad_input_is_rejected_with_the_field_named() -> TestResult {
        let origin = Vector3::zeros();
        let span = Vector3::new(9.0, 0.0, 0.0);
        let mut mismatched = ElasticChain::thesis_rope(1e3)?;
        mismatched.stiffnesses.pop();
        let mut negative_spring = ElasticChain::thesis_rope(1e3)?;
        negative_spring.rest_lengths[4] = -1.0;
        let failures: Vec<(&str, Result<(), CatenaryError>)> = vec![
            (
                "mass",
                ElasticChain::uniform(10, -1.0, 1.0, 1e3, origin, span, 9.81).map(drop),
            ),
            (
                "l0",
                ElasticChain::uniform(10, 1.0, f64::NAN, 1e3, origin, span, 9.81).map(drop),
            ),
            (
                "k",
                ElasticChain::uniform(10, 1.0, 1.0, 0.0, origin, span, 9.81).map(drop),
            ),
            (
                "gravity",
                ElasticChain::uniform(10, 1.0, 1.0, 1e3, origin, span, f64::INFINITY).map(drop),
            ),
            (
                "node_count",
                ElasticChain::uniform(2, 1.0, 1.0, 1e3, origin, span, 9.81).map(drop),
            ),
            ("stiffnesses", mismatched.solve_equilibrium().map(drop)),
            (
                "rest_lengths[4]",
                negative_spring.solve_equilibrium().map(drop),
            ),
            (
                "anchor_b.z",
                ElasticChain::uniform(10, 1.0, 1.0, 1e3, origin, Vector3::new(9.0, 0.0, 1.0), 9.81)
                    .map(drop),
            ),
            (
                "anchor_b.x",
                ElasticCatenary::solve(origin, Vector3::new(0.0, -3.0, 0.0), 9.0, 9.81, 1e3)
                    .map(drop),
            ),
            (
                "L",
                ElasticCatenary::solve(origin, span, -9.0, 9.81, 1e3).map(drop),
            ),
            (
                "w",
                ElasticCatenary::solve(origin, span, 9.0, f64::NAN, 1e3).map(drop),
            ),
            (
                "EA",
                ElasticCatenary::solve(origin, span, 9.0, 9.81, 0.0).map(drop),
            ),
            (
                "node_count",
                ElasticCatenary::thesis_rope(1e3)?
                    .max_node_distance(1)
                    .map(drop),
            ),
        ];
        for (field, result) in failures {
            let message = match result {
                Err(error) => error.to_string(),
                Ok(()) => return Err(format!("{field}: bad input was accepted").into()),
            };
            println!("{message}");
            assert!(message.contains(field), "{message:?} does not name {field}");
            assert!(message.contains("allowed"), "{message:?} gives no range");
        }
        Ok(())
    }
}

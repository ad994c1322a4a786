//! The continuous elastic catenary (Irvine), the limit of the chain as its springs shrink (the
//! module doc of [`super`], "Continuous elastic catenary").

#![allow(non_snake_case)] // H, V0, EA, L and W: the symbols of the thesis and of Irvine

use super::chain::ElasticChain;
use super::{
    require_positive, shallow_cable_guess, solve_closure, validate_anchors, CatenaryError,
    Evaluation, THESIS_GRAVITY,
};
use nalgebra::{Matrix2, Vector2, Vector3};

/// Irvine's elastic catenary, solved for its end tensions.
#[derive(Debug, Clone, PartialEq)]
pub struct ElasticCatenary {
    /// End at $`s = 0`$ (m), z = 0.
    pub anchor_a: Vector3<f64>,
    /// End at $`s = L`$ (m), z = 0.
    pub anchor_b: Vector3<f64>,
    /// Unstretched length $`L`$ (m).
    pub L: f64,
    /// Weight per unit unstretched length $`w`$ (N/m).
    pub w: f64,
    /// Axial stiffness $`EA`$ (N).
    pub EA: f64,
    /// Horizontal tension $`H`$ (N).
    pub H: f64,
    /// Vertical tension $`V_0`$ at $`s = 0`$, positive when the cable leaves `anchor_a` upwards
    /// (N).
    pub V0: f64,
    /// Newton steps taken, on $`H`$ and $`V_0`$ together.
    pub newton_iterations: usize,
    /// Final end-condition residual $`\lvert x(L) - B \rvert`$ over the stretched length.
    pub relative_residual: f64,
}

impl ElasticCatenary {
    /// Solves $`x(L) = x_B`$, $`y(L) = y_B`$ for $`(H, V_0)`$.
    pub fn solve(
        anchor_a: Vector3<f64>,
        anchor_b: Vector3<f64>,
        L: f64,
        w: f64,
        EA: f64,
    ) -> Result<Self, CatenaryError> {
        validate_anchors(&anchor_a, &anchor_b)?;
        require_positive("L", None, L)?;
        require_positive("w", None, w)?;
        require_positive("EA", None, EA)?;
        let chord = (anchor_b - anchor_a).xy();

        let evaluate = |H: f64, V0: f64| {
            let VL = V0 + w * L;
            let (T0, TL) = (H.hypot(V0), H.hypot(VL));
            let change = tension_change(H, V0, w * L);
            let coupling = -H / w * change.magnitude / (T0 * TL);
            Evaluation {
                residual: Vector2::new(
                    H * L / EA + H / w * change.asinh - chord.x,
                    (V0 * L + w * L * L / 2.0) / EA + change.magnitude / w - chord.y,
                ),
                jacobian: Matrix2::new(
                    L / EA + (change.asinh - change.sine) / w,
                    coupling,
                    coupling,
                    L / EA + change.sine / w,
                ),
                // Tension is convex in s, so the end tensions bound the stretched length.
                length_scale: L * (1.0 + T0.max(TL) / EA),
            }
        };

        let guess = shallow_cable_guess(chord, L, w * L, L / EA);
        let solution = solve_closure("continuous elastic catenary", guess, evaluate)?;
        Ok(Self {
            anchor_a,
            anchor_b,
            L,
            w,
            EA,
            H: solution.unknowns.x,
            V0: solution.unknowns.y,
            newton_iterations: solution.iterations,
            relative_residual: solution.relative_residual,
        })
    }

    /// Continuum limit of the thesis rope: $`L = 9`$ m, $`w = m g / l_0 = 9.81`$ N/m and
    /// $`EA = k l_0`$ with $`m = 1`$ kg, $`l_0 = 1`$ m and spring stiffness `k` (N/m).
    pub fn thesis_rope(k: f64) -> Result<Self, CatenaryError> {
        require_positive("k", None, k)?;
        Self::solve(
            Vector3::zeros(),
            Vector3::new(9.0, 0.0, 0.0),
            9.0,
            THESIS_GRAVITY,
            k,
        )
    }

    /// Cable point at unstretched arc length `s`; outside $`[0, L]`$ the same analytic
    /// expression continues the curve.
    pub fn position(&self, s: f64) -> Vector3<f64> {
        let (H, V0, w, EA) = (self.H, self.V0, self.w, self.EA);
        let change = tension_change(H, V0, w * s);
        let x = H * s / EA + H / w * change.asinh;
        let y = (V0 * s + w * s * s / 2.0) / EA + change.magnitude / w;
        self.anchor_a + Vector3::new(x, y, 0.0)
    }

    /// The `node_count`-node chain that discretises this cable: $`l_0 = L/(N-1)`$,
    /// $`k = EA/l_0`$ and free-node weight $`w\,l_0`$ (masses $`w l_0 / g`$ with
    /// [`THESIS_GRAVITY`]; $`g`$ cancels from the equilibrium).
    pub fn discrete_member(&self, node_count: usize) -> Result<ElasticChain, CatenaryError> {
        if node_count < 3 {
            return Err(CatenaryError::TooFewNodes { node_count });
        }
        let l0 = self.L / (node_count - 1) as f64;
        ElasticChain::uniform(
            node_count,
            self.w * l0 / THESIS_GRAVITY,
            l0,
            self.EA / l0,
            self.anchor_a,
            self.anchor_b,
            THESIS_GRAVITY,
        )
    }

    /// Largest distance (m) between node $`i`$ of the equilibrium of
    /// [`discrete_member`](Self::discrete_member) and the cable point $`s_i = i\,l_0`$.
    pub fn max_node_distance(&self, node_count: usize) -> Result<f64, CatenaryError> {
        let equilibrium = self.discrete_member(node_count)?.solve_equilibrium()?;
        let l0 = self.L / (node_count - 1) as f64;
        Ok(equilibrium
            .positions
            .iter()
            .enumerate()
            .map(|(i, node)| (node - self.position(i as f64 * l0)).norm())
            .fold(0.0, f64::max))
    }
}

/// How the tension direction and size change from $`(H, V_0)`$ to $`(H, V_0 + \Delta V)`$,
/// $`H > 0`$.
struct TensionChange {
    /// $`\operatorname{asinh}(V/H) - \operatorname{asinh}(V_0/H)`$.
    asinh: f64,
    /// $`V/T - V_0/T_0`$.
    sine: f64,
    /// $`T - T_0`$.
    magnitude: f64,
}

/// A taut cable barely turns, so $`V/H`$ and $`V_0/H`$ are large and close; the naive differences
/// would then lose most of their digits. With $`V`$ and $`V_0`$ of equal sign the cross term
/// $`V T_0 - V_0 T = H^2 \Delta V (V + V_0) / (V T_0 + V_0 T)`$ and
/// $`\operatorname{asinh} a - \operatorname{asinh} b
/// = \operatorname{asinh}\left(a\sqrt{1 + b^2} - b\sqrt{1 + a^2}\right)`$ avoid the cancellation;
/// with opposite signs the direct differences add and are already accurate.
fn tension_change(H: f64, V0: f64, delta_V: f64) -> TensionChange {
    let V = V0 + delta_V;
    let (T0, T) = (H.hypot(V0), H.hypot(V));
    let (asinh, cross) = if V * V0 > 0.0 {
        let ratio = delta_V * (V + V0) / (V * T0 + V0 * T);
        (ratio.asinh(), H * H * ratio)
    } else {
        ((V / H).asinh() - (V0 / H).asinh(), V * T0 - V0 * T)
    };
    TensionChange {
        asinh,
        sine: cross / (T * T0),
        magnitude: delta_V * (V + V0) / (T + T0),
    }
}

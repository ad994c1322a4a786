//! The sheet's exact static equilibrium (`docs/sheet-scene.md`): the minimiser of spring plus
//! gravity energy with the held nodes fixed, the sheet's analogue of the rope's discrete
//! catenary and the state every solver's rest state is compared with.
//!
//! The energy is $`E(x) = \sum_j \frac12 k_j(\lvert x_{a_j} - x_{b_j}\rvert - l_{0,j})^2 - \sum_i m_i\,g\cdot x_i`$
//! (Eq 2 and gravity's potential, [`MassSpringSystem::potential_energy`]) over the free nodes.
//! Newton's method minimises it: $`H\,\Delta x = -\nabla E = F(x)`$, $`x \leftarrow x + \alpha\,\Delta x`$,
//! with $`H = -\partial F/\partial x`$ the free nodes' Hessian assembled from Eq (4) and
//! $`\alpha`$ from a backtracking line search.
//!
//! - Start: the flat taut sheet has no transverse stiffness (every spring at its rest length:
//!   Eq (4)'s transverse factor $`1 - l_0/l`$ is 0, so $`H`$ is singular in $`y`$). The default
//!   start is a sagged guess instead, [`sagged_start`]: the grid with
//!   $`y = -s\,(1 - u^2 w^2)`$, $`u, w \in [-1, 1]`$ across the sheet, which holds every corner at
//!   $`y = 0`$ and only lengthens springs (their horizontal extent is the rest length), so that
//!   no spring starts compressed and every free node feels a sloped spring: from it the exact
//!   Hessian is positive definite at every iteration of the four report sheets. Any other start
//!   works too, the flat one included, through the shifted Hessian below; the result does not
//!   depend on the start (tested from five, to 1e-14 m).
//! - Hessian: the exact one where it is positive definite (its banded $`LDL^\top`$ has every
//!   pivot positive), else the definite-projected one ([`spring::force_jacobian_definite`]:
//!   compressed springs make the exact one indefinite along the way), shifted by a multiple of
//!   the identity where it is singular ([`shifted_factor`], the crate's one projected Newton's
//!   shift, [`crate::model::projected_newton`]), so that every direction descends
//!   and the last steps, at a minimum with positive definite $`H`$, are exact Newton steps and
//!   converge quadratically.
//! - Linear solves: this crate's scalar banded $`LDL^\top`$ ([`BandedLdlt`]) on the free nodes
//!   in grid order (half-bandwidth $`3(n + 1) + 2`$), never a kernel chosen at run time, so that
//!   the 17-digit result is the same on every machine.
//! - Stop: once the largest force on a free node is below [`RESIDUAL_TARGET`] and a further
//!   full Newton step no longer halves it, i.e. at round-off; the best iterate is kept.

use crate::error::{require_positive, Error, Result};
use crate::model::linear::{BandedLdlt, SymmetricMatrix};
use crate::model::projected_newton::{backtrack, shifted_factor, ShiftSchedule, ARMIJO};
use crate::model::scene::{SheetParams, SHEET_NODES_PER_SIDE, THESIS_STIFFNESSES};
use crate::model::spring;
use crate::model::system::{MassSpringSystem, Vec3};
use nalgebra::Matrix3;

/// The largest force on a free node, N, that counts as equilibrium (`docs/sheet-scene.md`).
pub const RESIDUAL_TARGET: f64 = 1e-7;
/// Newton iterations before giving up.
pub const MAX_ITERATIONS: usize = 200;
/// Sag of the default start at the sheet's middle, m.
pub const DEFAULT_SAG: f64 = 1.0;
/// The sheets of `report/data/sheet_equilibrium.csv`: n nodes per side.
pub const CSV_NODES_PER_SIDE: [usize; 2] = [SHEET_NODES_PER_SIDE, 20];

/// A static equilibrium and how it was reached.
#[derive(Debug, Clone, PartialEq)]
pub struct Equilibrium {
    /// Every node's position, held nodes included, m.
    pub x: Vec<Vec3>,
    /// The largest force component on a free node at `x`, N (from the Newton's own gradient;
    /// the tests recompute it with [`MassSpringSystem::forces`]).
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Of which with the definite-projected Hessian.
    pub projected_iterations: usize,
}

/// The sagged start: the sheet's grid with node (i, j) lowered by $`s\,(1 - u^2 w^2)`$,
/// $`u = 2i/(n-1) - 1`$, $`w = 2j/(n-1) - 1`$ (0 at the corners, $`s`$ at the middle).
pub fn sagged_start(params: &SheetParams, sag: f64) -> Result<Vec<Vec3>> {
    require_positive("sag", sag)?;
    let system = params.build()?;
    let last = (params.nodes_per_side - 1) as f64;
    Ok(shaped_start(&system, params, |i, j| {
        let (u, w) = (2.0 * i as f64 / last - 1.0, 2.0 * j as f64 / last - 1.0);
        -sag * (1.0 - u * u * w * w)
    }))
}

/// The grid of `params` with node (i, j) moved by `dy(i, j)` along y; held nodes stay.
pub fn shaped_start(
    system: &MassSpringSystem,
    params: &SheetParams,
    dy: impl Fn(usize, usize) -> f64,
) -> Vec<Vec3> {
    let n = params.nodes_per_side;
    let mut x: Vec<Vec3> = system.nodes().iter().map(|node| node.position).collect();
    for i in 0..n {
        for j in 0..n {
            let k = params.node(i, j);
            if !system.nodes()[k].fixed {
                x[k].y += dy(i, j);
            }
        }
    }
    x
}

/// The equilibrium of the sheet `params` from [`sagged_start`] with [`DEFAULT_SAG`].
pub fn sheet_equilibrium(params: &SheetParams) -> Result<Equilibrium> {
    let system = params.build()?;
    static_equilibrium(&system, &sagged_start(params, DEFAULT_SAG)?)
}

/// Which Hessian a Newton iteration uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Hessian {
    Exact,
    Projected,
}

/// The free nodes' unknowns: free node $`i`$ owns unknowns $`3f(i) + c`$.
struct FreeUnknowns {
    /// $`f(i)`$ for a free node, `None` for a held one.
    index: Vec<Option<usize>>,
    count: usize,
    /// Springs between two free nodes, as free indices: the Hessian's off-diagonal blocks.
    edges: Vec<(usize, usize)>,
}

impl FreeUnknowns {
    fn new(system: &MassSpringSystem) -> Self {
        let mut count = 0;
        let index = system
            .nodes()
            .iter()
            .map(|node| {
                (!node.fixed).then(|| {
                    count += 1;
                    count - 1
                })
            })
            .collect::<Vec<_>>();
        let edges = system
            .springs()
            .iter()
            .filter_map(|s| Some((index[s.a]?, index[s.b]?)))
            .collect();
        Self {
            index,
            count,
            edges,
        }
    }

    /// $`F(x)`$ on the free unknowns: Eq (3) per spring plus gravity.
    fn forces(&self, system: &MassSpringSystem, x: &[Vec3]) -> Vec<f64> {
        let mut f = vec![0.0; 3 * self.count];
        let mut add = |node: usize, force: Vec3| {
            if let Some(k) = self.index[node] {
                for c in 0..3 {
                    f[3 * k + c] += force[c];
                }
            }
        };
        for (i, node) in system.nodes().iter().enumerate() {
            add(i, node.mass * system.gravity());
        }
        for s in system.springs() {
            let fa = spring::force(&x[s.a], &x[s.b], s.rest_length, s.stiffness);
            add(s.a, fa);
            add(s.b, -fa);
        }
        f
    }

    /// $`H = -\partial F/\partial x`$ on the free unknowns from Eq (4), exact or projected.
    fn hessian(&self, system: &MassSpringSystem, x: &[Vec3], kind: Hessian) -> SymmetricMatrix {
        let mut h = SymmetricMatrix::from_node_graph(self.count, 3, &self.edges);
        for s in system.springs() {
            let jacobian = match kind {
                Hessian::Exact => spring::force_jacobian,
                Hessian::Projected => spring::force_jacobian_definite,
            };
            let block: Matrix3<f64> = -jacobian(&x[s.a], &x[s.b], s.rest_length, s.stiffness);
            // d²E/dx_a² = d²E/dx_b² = block, d²E/dx_a dx_b = -block.
            let (a, b) = (self.index[s.a], self.index[s.b]);
            for (p, q, sign) in [(a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)] {
                if let (Some(p), Some(q)) = (p, q) {
                    for r in 0..3 {
                        for c in 0..3 {
                            h.add(3 * p + r, 3 * q + c, sign * block[(r, c)]);
                        }
                    }
                }
            }
        }
        h
    }

    /// `x` moved by `alpha` times the free-unknown vector `dx`.
    fn moved(&self, x: &[Vec3], dx: &[f64], alpha: f64) -> Vec<Vec3> {
        x.iter()
            .zip(&self.index)
            .map(|(xi, k)| match k {
                Some(k) => xi + alpha * Vec3::new(dx[3 * k], dx[3 * k + 1], dx[3 * k + 2]),
                None => *xi,
            })
            .collect()
    }
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Halvings of the line search's step: down to 2⁻³⁹ ≈ 1.8e-12 of Newton's.
const HALVINGS: usize = 39;
/// The shifts of the projected Hessian: 1e-10 of its largest diagonal entry, growing tenfold,
/// until one above that entry has failed.
const SHIFTS: ShiftSchedule = ShiftSchedule {
    first: 1e-10,
    growth: 10.0,
    largest: 1.0,
};

/// Backtracking ([`backtrack`]): the largest $`\alpha = 2^{-m}`$ with
/// $`E(x + \alpha\,\Delta x) \le E(x) + c\,\alpha\,\nabla E^\top \Delta x`$, $`c = 10^{-4}`$; the
/// full step where the predicted decrease $`-\nabla E^\top\Delta x`$ is below the energy's
/// round-off (near the minimum, where only the force can still tell progress).
fn line_search(
    system: &MassSpringSystem,
    free: &FreeUnknowns,
    x: &[Vec3],
    f: &[f64],
    dx: &[f64],
) -> Result<f64> {
    let decrease: f64 = f.iter().zip(dx).map(|(f, d)| f * d).sum();
    let e0 = system.potential_energy(x);
    if decrease <= 1e3 * f64::EPSILON * e0.abs().max(1.0) {
        return Ok(1.0);
    }
    backtrack(HALVINGS, |alpha| {
        system.potential_energy(&free.moved(x, dx, alpha)) <= e0 - ARMIJO * alpha * decrease
    })
    .ok_or_else(|| Error::NotConverged {
        what: "static equilibrium line search".into(),
        detail: format!(
            "no decrease of the energy along the Newton direction (predicted {decrease:e} J)"
        ),
    })
}

/// The projected Hessian's factor, shifted where it is singular ([`shifted_factor`]): it is
/// only semidefinite, a node whose springs are all compressed keeping their axial stiffness
/// alone, and the flat start having none in y.
fn projected_factor(h: SymmetricMatrix, iteration: usize) -> Result<BandedLdlt> {
    shifted_factor(h, 0.0, &SHIFTS).map_err(|failure| Error::NotConverged {
        what: "static equilibrium".into(),
        detail: format!(
            "the projected Hessian stays indefinite with a shift of {:e} at Newton iteration \
             {iteration}: {}",
            failure.shift, failure.error
        ),
    })
}

/// The minimiser of spring plus gravity energy of `system` with its held nodes fixed, by
/// Newton with a line search from `start` (every node's position; held nodes are taken from
/// `system`). See the module doc for the start, the Hessian and the stopping rule.
pub fn static_equilibrium(system: &MassSpringSystem, start: &[Vec3]) -> Result<Equilibrium> {
    if start.len() != system.len() {
        return Err(Error::invalid(
            "start.len()",
            start.len(),
            &format!("one position per node ({})", system.len()),
        ));
    }
    let free = FreeUnknowns::new(system);
    let mut x: Vec<Vec3> = system
        .nodes()
        .iter()
        .zip(start)
        .map(|(node, s)| if node.fixed { node.position } else { *s })
        .collect();
    for (i, p) in x.iter().enumerate() {
        for c in 0..3 {
            crate::error::require_finite(format!("start[{i}][{c}]"), p[c])?;
        }
    }
    let mut best: Option<Equilibrium> = None;
    let mut projected_iterations = 0;
    for iteration in 0..MAX_ITERATIONS {
        let f = free.forces(system, &x);
        let residual = max_abs(&f);
        if !residual.is_finite() {
            return Err(Error::NotConverged {
                what: "static equilibrium".into(),
                detail: format!("the force became non-finite at Newton iteration {iteration}"),
            });
        }
        let stalled = best
            .as_ref()
            .is_some_and(|b| b.residual < RESIDUAL_TARGET && residual >= 0.5 * b.residual);
        if best.as_ref().is_none_or(|b| residual < b.residual) {
            best = Some(Equilibrium {
                x: x.clone(),
                residual,
                iterations: iteration,
                projected_iterations,
            });
        }
        if stalled || residual == 0.0 {
            return Ok(best.expect("set above"));
        }
        // H Δx = F: the exact Hessian where it is positive definite, else the projected one.
        let factor = match BandedLdlt::new(&free.hessian(system, &x, Hessian::Exact)) {
            Ok(factor) => factor,
            Err(_) => {
                projected_iterations += 1;
                projected_factor(free.hessian(system, &x, Hessian::Projected), iteration)?
            }
        };
        let mut dx = f.clone();
        factor.solve_in_place(&mut dx, 1);
        let alpha = line_search(system, &free, &x, &f, &dx)?;
        x = free.moved(&x, &dx, alpha);
    }
    match best {
        Some(b) if b.residual < RESIDUAL_TARGET => Ok(b),
        b => Err(Error::NotConverged {
            what: "static equilibrium".into(),
            detail: format!(
                "largest force {:e} N after {MAX_ITERATIONS} Newton iterations (target {RESIDUAL_TARGET:e} N)",
                b.map_or(f64::NAN, |b| b.residual)
            ),
        }),
    }
}

/// The free nodes' exact Hessian $`-\partial F/\partial x`$ at `x` (Eq 4 assembled), unknown
/// $`3f + c`$ for coordinate c of the f-th free node.
pub fn free_hessian(system: &MassSpringSystem, x: &[Vec3]) -> SymmetricMatrix {
    FreeUnknowns::new(system).hessian(system, x, Hessian::Exact)
}

/// The smallest eigenvalue of the free nodes' exact Hessian at `x`, N/m, by inverse iteration
/// with its banded $`LDL^\top`$ (the Rayleigh quotient after `iterations` solves). The
/// factorisation succeeding with every pivot positive is itself the proof that the matrix is
/// positive definite (Sylvester's law of inertia); an indefinite Hessian is an error.
pub fn smallest_hessian_eigenvalue(
    system: &MassSpringSystem,
    x: &[Vec3],
    iterations: usize,
) -> Result<f64> {
    let h = free_hessian(system, x);
    let factor = BandedLdlt::new(&h)?;
    let dim = h.dim();
    // A start with a component along every eigenvector, deterministic.
    let mut v: Vec<f64> = (0..dim).map(|i| 1.0 + (i as f64 * 0.618).sin()).collect();
    let mut hv = vec![0.0; dim];
    for _ in 0..iterations.max(1) {
        let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        v.iter_mut().for_each(|a| *a /= norm);
        factor.solve_in_place(&mut v, 1);
    }
    let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    v.iter_mut().for_each(|a| *a /= norm);
    h.mul_vec(&v, &mut hv);
    Ok(v.iter().zip(&hv).map(|(a, b)| a * b).sum())
}

/// The equilibria of `report/data/sheet_equilibrium.csv`: the specification's sheet at
/// n = 10 and 20, k = 1e3 and 1e6 N/m, as (k, n, equilibrium).
pub fn report_equilibria() -> Result<Vec<(f64, usize, Equilibrium)>> {
    let mut out = Vec::new();
    for k in THESIS_STIFFNESSES {
        for n in CSV_NODES_PER_SIDE {
            out.push((k, n, sheet_equilibrium(&SheetParams::spec(n, k))?));
        }
    }
    Ok(out)
}

//! The continuum's statics, as the chapter presents them (`docs/fem-scenes.md`): every number is
//! a Newton equilibrium of a scene of [`crate::model::continuum::scenes`], solved to a stated
//! residual, and each is recomputed by the tests at [`ChapterSize::Test`].
//!
//! - the five energies side by side: the soft beam (E = 1e6 Pa, r = 2), where they part ways,
//!   its tip sag and volume change; the membrane (n = 10) at both stiffnesses, its sag and area
//!   change;
//! - Cook's membrane: u_y at (48, 52) and at P2 for N = 2, 4, …, its observed order;
//! - the stiff beam (E = 1e9 Pa, the linear energy) against Euler-Bernoulli with Timoshenko's
//!   shear term, as mesh error (linear tets lock);
//! - the verification checks: each with its tolerance and the value reached.

use crate::error::Result;
use crate::model::continuum::energy::EnergyKind;
use crate::model::continuum::scenes::{
    beam, beam_node, beam_tip_deflection, cook, cook_node, membrane, patch, BEAM_DENSITY,
    BEAM_LENGTH, BEAM_POISSON, BEAM_SIDE, BEAM_YOUNGS, PATCH_MAP, PATCH_SHIFT,
};
use crate::model::continuum::statics::{static_equilibrium, Equilibrium};
use crate::model::continuum::system::ContinuumSystem;
use crate::model::scene::{SHEET_NODES_PER_SIDE, THESIS_GRAVITY, THESIS_STIFFNESSES};

/// The residual, relative to the largest nodal load, every equilibrium of the chapter is
/// solved to (ten times tighter than the statics' default).
pub const TOLERANCE: f64 = 1e-10;
/// The stiff beam's against beam theory: at r = 8 the round-off of its elastic forces, which
/// grow against the nodes' weights as the mesh is refined, stalls Newton at about 2.5e-10 of
/// the largest weight (measured), so the sequence is solved to the statics' default 1e-9.
pub const STIFF_BEAM_TOLERANCE: f64 = 1e-9;
/// The patch test's: relative to its largest initial residual (it has no loads), and the
/// distance of the interior nodes from the affine map it must reach, m.
pub const PATCH_TOLERANCE: f64 = 1e-14;
pub const PATCH_DISTANCE: f64 = 1e-14;
/// The largest departure of a membrane's equilibrium from the mesh's symmetry
/// (x, z) ↦ (9 − x, 9 − z), m.
pub const MEMBRANE_SYMMETRY: f64 = 1e-9;
/// The literature's converged u_y at (48, 52) of Cook's membrane (fem-scenes.md: "about 23.96").
pub const COOK_LITERATURE: f64 = 23.96;
/// Timoshenko's shear coefficient of a square section.
pub const SHEAR_COEFFICIENT: f64 = 5.0 / 6.0;

/// The chapter's size: the report's meshes, or the tests' smaller ones computed by the same
/// functions (so that `make test` does not compute the report's larger cases twice).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChapterSize {
    /// Beam r = 2, 4, 8 (the energies at r = 2); Cook N = 2 … 64.
    Report,
    /// Beam r = 1, 2 (the energies at r = 1); Cook N = 2 … 32.
    Test,
}

impl ChapterSize {
    /// The stiff beam's refinements r.
    pub fn beam_refinements(self) -> Vec<usize> {
        match self {
            ChapterSize::Report => vec![2, 4, 8],
            ChapterSize::Test => vec![1, 2],
        }
    }

    /// The refinement of the beam on which the energies are compared, soft and stiff
    /// (fem-scenes.md: the nonlinear energies up to r = 4; r = 2 is the default mesh).
    pub fn energy_refinement(self) -> usize {
        match self {
            ChapterSize::Report => 2,
            ChapterSize::Test => 1,
        }
    }

    /// Cook's meshes N, doubling.
    pub fn cook_meshes(self) -> Vec<usize> {
        match self {
            ChapterSize::Report => vec![2, 4, 8, 16, 32, 64],
            ChapterSize::Test => vec![2, 4, 8, 16, 32],
        }
    }
}

/// The soft beam's equilibrium under one energy.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamSag {
    pub energy: EnergyKind,
    /// The mean y-displacement of the tip's nodes, m.
    pub tip: f64,
    /// Σ V det F / Σ V − 1.
    pub volume_change: f64,
    pub equilibrium: Equilibrium,
    /// The mean deformed position (x, y) of each cross-section's nodes, from the clamp to the
    /// tip, m.
    pub axis: Vec<[f64; 2]>,
}

/// The membrane's equilibrium under one energy and stiffness.
#[derive(Debug, Clone, PartialEq)]
pub struct MembraneSag {
    pub energy: EnergyKind,
    /// The spring net's k the membrane matches (Y = 8k/3), N/m.
    pub stiffness: f64,
    /// The lowest node's y, m.
    pub lowest: f64,
    /// Σ A J / Σ A − 1, J = √det(FᵀF).
    pub area_change: f64,
    /// The largest departure from the symmetry (x, z) ↦ (9 − x, 9 − z), m.
    pub asymmetry: f64,
    pub equilibrium: Equilibrium,
    /// The deformed (x, y) of the row j = (n − 1)/2, the sheet chapter's centre line, m.
    pub centre_line: Vec<[f64; 2]>,
}

/// Cook's membrane at one mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct CookPoint {
    pub n: usize,
    /// u_y at (48, 52), node (N, N/2).
    pub mid: f64,
    /// u_y at P2 = (48, 60), node (N, N).
    pub corner: f64,
    pub relative_residual: f64,
}

/// The stiff beam at one refinement against beam theory.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamTheoryPoint {
    pub r: usize,
    /// The tip's sag (the negated mean y-displacement), m.
    pub sag: f64,
    /// Its ratio to [`beam_theory_sag`].
    pub ratio: f64,
    pub relative_residual: f64,
}

/// One verification check: the value reached passes if it is at most the tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    pub check: String,
    pub tolerance: f64,
    pub value: f64,
}

impl Check {
    pub fn passes(&self) -> bool {
        self.value <= self.tolerance
    }
}

/// Every number of the chapter's statics.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuumStatics {
    pub size: ChapterSize,
    /// The beam's refinement r of the energies' comparison ([`ChapterSize::energy_refinement`]).
    pub energy_refinement: usize,
    /// The soft beam under each energy, in [`EnergyKind::ALL`]'s order.
    pub soft_beam: Vec<BeamSag>,
    /// The membrane under each energy defined on membranes, at each of the thesis's
    /// stiffnesses.
    pub membranes: Vec<MembraneSag>,
    pub cook: Vec<CookPoint>,
    /// log₂ of the ratio of the last two changes of u_y(48, 52) as N doubles.
    pub cook_order: f64,
    /// Euler-Bernoulli's sag plus Timoshenko's shear term at E = 1e9 Pa, m.
    pub theory: f64,
    pub stiff_beam: Vec<BeamTheoryPoint>,
    pub checks: Vec<Check>,
}

impl ContinuumStatics {
    /// Solves every equilibrium of the chapter at `size`.
    pub fn compute(size: ChapterSize) -> Result<Self> {
        let r = size.energy_refinement();
        let soft_beam = EnergyKind::ALL
            .into_iter()
            .map(|energy| soft_beam(energy, r))
            .collect::<Result<Vec<_>>>()?;
        let mut membranes = Vec::new();
        for stiffness in THESIS_STIFFNESSES {
            for energy in EnergyKind::ALL
                .into_iter()
                .filter(|e| e.model().supports_membranes())
            {
                membranes.push(membrane_sag(energy, stiffness)?);
            }
        }
        let cook = size
            .cook_meshes()
            .into_iter()
            .map(cook_point)
            .collect::<Result<Vec<_>>>()?;
        let theory = beam_theory_sag(BEAM_YOUNGS[1]);
        let stiff_beam = size
            .beam_refinements()
            .into_iter()
            .map(|r| stiff_beam_point(r, theory))
            .collect::<Result<Vec<_>>>()?;
        let checks = checks(r, &soft_beam, &membranes, &cook)?;
        Ok(Self {
            size,
            energy_refinement: r,
            cook_order: observed_order(&cook.iter().map(|c| c.mid).collect::<Vec<_>>()),
            soft_beam,
            membranes,
            cook,
            theory,
            stiff_beam,
            checks,
        })
    }
}

/// The static equilibrium to [`TOLERANCE`].
fn solve(system: &ContinuumSystem) -> Result<Equilibrium> {
    static_equilibrium(system, TOLERANCE)
}

/// Σ V det F / Σ V − 1 (tets) or Σ A J / Σ A − 1 (membranes) at displacements `u`.
pub fn measure_change(system: &ContinuumSystem, u: &[f64]) -> f64 {
    let (mut rest, mut deformed) = (0.0, 0.0);
    for e in system.elements() {
        let f = e.deformation(u).f().clone();
        let j = if f.is_square() {
            f.determinant()
        } else {
            (f.transpose() * &f).determinant().sqrt()
        };
        rest += e.measure();
        deformed += e.measure() * j;
    }
    deformed / rest - 1.0
}

/// The soft beam (E = 1e6 Pa) at refinement r under `energy`.
pub fn soft_beam(energy: EnergyKind, r: usize) -> Result<BeamSag> {
    let system = beam(r, energy, BEAM_YOUNGS[0])?;
    let equilibrium = solve(&system)?;
    let u = &equilibrium.displacement;
    let x = system.rest_positions();
    let section = ((r + 1) * (r + 1)) as f64;
    let axis = (0..=10 * r)
        .map(|i| {
            let mut mean = [0.0; 2];
            for j in 0..=r {
                for k in 0..=r {
                    let n = beam_node(r, [i, j, k]);
                    mean[0] += (x[3 * n] + u[3 * n]) / section;
                    mean[1] += (x[3 * n + 1] + u[3 * n + 1]) / section;
                }
            }
            mean
        })
        .collect();
    Ok(BeamSag {
        energy,
        tip: beam_tip_deflection(r, u),
        volume_change: measure_change(&system, u),
        axis,
        equilibrium,
    })
}

/// The membrane (n = 10) matching the spring net of stiffness k under `energy`.
pub fn membrane_sag(energy: EnergyKind, stiffness: f64) -> Result<MembraneSag> {
    let n = SHEET_NODES_PER_SIDE;
    let system = membrane(n, energy, stiffness)?;
    let equilibrium = solve(&system)?;
    let u = &equilibrium.displacement;
    let x = system.rest_positions();
    let count = n * n;
    // Node i·n + j mirrors to (n − 1 − i)·n + (n − 1 − j) = n² − 1 − (i·n + j).
    let asymmetry = (0..count)
        .flat_map(|a| {
            let b = count - 1 - a;
            [
                (u[3 * a] + u[3 * b]).abs(),
                (u[3 * a + 1] - u[3 * b + 1]).abs(),
                (u[3 * a + 2] + u[3 * b + 2]).abs(),
            ]
        })
        .fold(0.0, f64::max);
    let lowest = (0..count)
        .map(|a| x[3 * a + 1] + u[3 * a + 1])
        .fold(f64::INFINITY, f64::min);
    let row = (n - 1) / 2;
    let centre_line = (0..n)
        .map(|i| {
            let a = i * n + row;
            [x[3 * a] + u[3 * a], x[3 * a + 1] + u[3 * a + 1]]
        })
        .collect();
    Ok(MembraneSag {
        energy,
        stiffness,
        lowest,
        area_change: measure_change(&system, u),
        asymmetry,
        centre_line,
        equilibrium,
    })
}

/// Cook's membrane at mesh N with the linear energy (fem-scenes.md: E = 1, ν = 1/3).
pub fn cook_point(n: usize) -> Result<CookPoint> {
    let system = cook(n, EnergyKind::Linear, 1.0)?;
    let eq = solve(&system)?;
    Ok(CookPoint {
        n,
        mid: eq.displacement[2 * cook_node(n, n, n / 2) + 1],
        corner: eq.displacement[2 * cook_node(n, n, n) + 1],
        relative_residual: eq.relative_residual,
    })
}

/// The observed order of a sequence converging as the mesh doubles: log₂ of the ratio of its
/// last two changes, (u_{N/2} − u_{N/4}) / (u_N − u_{N/2}) (NaN with fewer than three values).
pub fn observed_order(values: &[f64]) -> f64 {
    match values {
        [.., a, b, c] => ((b - a) / (c - b)).log2(),
        _ => f64::NAN,
    }
}

/// Euler-Bernoulli's sag of the cantilever under its own weight, qL⁴/(8EI), plus Timoshenko's
/// shear term qL²/(2κGA), with q = ρgA, I = a⁴/12, G = E/(2(1 + ν)), κ = 5/6 (fem-scenes.md).
pub fn beam_theory_sag(youngs: f64) -> f64 {
    let area = BEAM_SIDE * BEAM_SIDE;
    let q = BEAM_DENSITY * THESIS_GRAVITY * area;
    let inertia = BEAM_SIDE.powi(4) / 12.0;
    let shear = youngs / (2.0 * (1.0 + BEAM_POISSON));
    q * BEAM_LENGTH.powi(4) / (8.0 * youngs * inertia)
        + q * BEAM_LENGTH.powi(2) / (2.0 * SHEAR_COEFFICIENT * shear * area)
}

/// The stiff beam (E = 1e9 Pa, the linear energy) at refinement r against `theory`, solved to
/// [`STIFF_BEAM_TOLERANCE`].
pub fn stiff_beam_point(r: usize, theory: f64) -> Result<BeamTheoryPoint> {
    let system = beam(r, EnergyKind::Linear, BEAM_YOUNGS[1])?;
    let eq = static_equilibrium(&system, STIFF_BEAM_TOLERANCE)?;
    let sag = -beam_tip_deflection(r, &eq.displacement);
    Ok(BeamTheoryPoint {
        r,
        sag,
        ratio: sag / theory,
        relative_residual: eq.relative_residual,
    })
}

/// The largest distance of the patch's interior nodes from the affine map, m, under `energy`,
/// solved to [`PATCH_TOLERANCE`].
pub fn patch_distance(energy: EnergyKind) -> Result<f64> {
    let system = patch(energy)?;
    let eq = static_equilibrium(&system, PATCH_TOLERANCE)?;
    let x = system.rest_positions();
    let mut largest = 0.0_f64;
    for n in (0..system.node_count()).filter(|&n| !system.is_fixed(n)) {
        for (r, row) in PATCH_MAP.iter().enumerate() {
            let mapped: f64 = row
                .iter()
                .zip(&x[3 * n..3 * n + 3])
                .map(|(a, x)| a * x)
                .sum::<f64>()
                + PATCH_SHIFT[r];
            largest = largest.max((x[3 * n + r] + eq.displacement[3 * n + r] - mapped).abs());
        }
    }
    Ok(largest)
}

/// The verification checks: the patch test for every energy; the residual Newton reached on
/// the stiff beam (E = 1e9 Pa, the energies' r) with every nonlinear energy, on the soft beam and on the
/// membranes; the membranes' symmetry; Cook's u_y(48, 52) rising from below 23.96.
fn checks(
    r: usize,
    soft_beam: &[BeamSag],
    membranes: &[MembraneSag],
    cook: &[CookPoint],
) -> Result<Vec<Check>> {
    let mut checks = Vec::new();
    for energy in EnergyKind::ALL {
        checks.push(Check {
            check: format!(
                "patch test, {}: interior nodes off the affine map (m)",
                energy.name()
            ),
            tolerance: PATCH_DISTANCE,
            value: patch_distance(energy)?,
        });
    }
    for energy in EnergyKind::ALL
        .into_iter()
        .filter(|&e| e != EnergyKind::Linear)
    {
        let system = beam(r, energy, BEAM_YOUNGS[1])?;
        checks.push(Check {
            check: format!(
                "stiff beam (E = 1e9 Pa, r = {r}), {}: Newton's residual",
                energy.name()
            ),
            tolerance: TOLERANCE,
            value: solve(&system)?.relative_residual,
        });
    }
    for b in soft_beam {
        checks.push(Check {
            check: format!(
                "soft beam (E = 1e6 Pa, r = {r}), {}: Newton's residual",
                b.energy.name()
            ),
            tolerance: TOLERANCE,
            value: b.equilibrium.relative_residual,
        });
    }
    for m in membranes {
        checks.push(Check {
            check: format!(
                "membrane (k = {:e} N/m), {}: departure from its symmetry (m)",
                m.stiffness,
                m.energy.name()
            ),
            tolerance: MEMBRANE_SYMMETRY,
            value: m.asymmetry,
        });
    }
    let mids: Vec<f64> = cook.iter().map(|c| c.mid).collect();
    checks.push(Check {
        check: format!(
            "Cook, u_y(48, 52) for N = {} … {}: largest fall as N doubles, or rise past {COOK_LITERATURE}",
            cook[0].n,
            cook[cook.len() - 1].n
        ),
        tolerance: 0.0,
        value: mids
            .windows(2)
            .map(|w| w[0] - w[1])
            .chain(mids.iter().map(|u| u - COOK_LITERATURE))
            .fold(f64::NEG_INFINITY, f64::max)
            .max(0.0),
    });
    Ok(checks)
}

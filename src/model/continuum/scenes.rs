//! The meshes of `docs/fem-scenes.md`: "beam" (a tet cantilever), "membrane" (the sheet as
//! linear triangles), "cook" (Cook's membrane in plane stress) and "patch" (the affine patch
//! test), with the node numbering, element split, masses, clamps and loads the specification
//! states.

use super::energy::EnergyKind;
use super::lame::{Lame, Loading};
use super::system::{ContinuumSystem, ElementKind, Masses, Material, Mesh};
use crate::error::{Error, Result};
use crate::model::scene::{SheetParams, THESIS_GRAVITY};

/// The beam's length along x, m.
pub const BEAM_LENGTH: f64 = 1.0;
/// The side of its square cross-section, m.
pub const BEAM_SIDE: f64 = 0.1;
/// Its density, kg/m³.
pub const BEAM_DENSITY: f64 = 1000.0;
/// Its Poisson ratio.
pub const BEAM_POISSON: f64 = 0.3;
/// Its two Young's moduli, Pa: soft (large sag, where the energies part ways) and stiff (the
/// linear regime).
pub const BEAM_YOUNGS: [f64; 2] = [1e6, 1e9];
/// The largest refinement r the builders accept: fem-scenes.md's largest mesh, r = 16
/// (161 × 17² = 46 529 nodes, 245 760 tets). Beyond it the statics' sparse factor grows past
/// what the project's machines hold (its fill grows as the unknowns to the power 4/3 on a
/// 3D mesh), and no scene of the specification asks for it.
pub const MAX_REFINEMENT: usize = 16;

/// The membrane's Poisson ratio (fem-scenes.md: with Y = 8k/3 it matches the spring net's
/// C₁₁₂₂ and C₁₂₁₂).
pub const MEMBRANE_POISSON: f64 = 1.0 / 3.0;

/// Cook's membrane: its corners P0..P3, its Poisson ratio, and the total vertical force on
/// its right edge, N.
pub const COOK_CORNERS: [[f64; 2]; 4] = [[0.0, 0.0], [48.0, 44.0], [48.0, 60.0], [0.0, 44.0]];
pub const COOK_POISSON: f64 = 1.0 / 3.0;
pub const COOK_FORCE: f64 = 1.0;
/// Cook's Young's modulus, Pa, with thickness 1.
pub const COOK_YOUNGS: f64 = 1.0;
/// The largest mesh N of Cook's membrane the builder accepts: fem-scenes.md's N = 2 … 64.
pub const COOK_MAX_ELEMENTS_PER_SIDE: usize = 64;

/// The patch test's affine map x = A X + b and its material (any would do: every energy's
/// equilibrium is the affine map).
pub const PATCH_MAP: [[f64; 3]; 3] = [[1.1, 0.1, 0.0], [0.0, 0.95, 0.05], [0.02, 0.0, 1.05]];
pub const PATCH_SHIFT: [f64; 3] = [0.1, -0.05, 0.02];
pub const PATCH_CELLS: usize = 3;
pub const PATCH_YOUNGS: f64 = 1.0;
pub const PATCH_POISSON: f64 = 0.3;

/// The densities of the scenes without gravity, which only the (lumped) masses see and the
/// statics never do, kg/m³ (kg/m² for Cook's membrane).
const UNIT_DENSITY: f64 = 1.0;

/// The axes' orders of the 6 tets of a cube.
const PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// The box of `cells` cubes split into 6 tets each, mirrored from cube to cube (fem-scenes.md,
/// "beam"): the cube's local corner c(a, b, c) is the node at (i + a′, j + b′, k + c′), a′ = a
/// for even i and 1 − a for odd i (likewise b′, c′); its tets are, for each permutation
/// (p1, p2, p3) of the axes, c000, c000 + e_p1, c000 + e_p1 + e_p2, c111, each ordered to
/// positive volume by swapping its last two nodes where needed. `node` numbers a grid point.
fn mirrored_tetrahedra(
    cells: [usize; 3],
    node: impl Fn([usize; 3]) -> usize,
    positions: &[f64],
) -> Vec<Vec<usize>> {
    let mut tets = Vec::with_capacity(6 * cells.iter().product::<usize>());
    let position = |n: usize| {
        nalgebra::Vector3::new(positions[3 * n], positions[3 * n + 1], positions[3 * n + 2])
    };
    for i in 0..cells[0] {
        for j in 0..cells[1] {
            for k in 0..cells[2] {
                let cell = [i, j, k];
                let corner = |local: [usize; 3]| {
                    node(std::array::from_fn(|axis| {
                        let mirrored = if cell[axis] % 2 == 0 {
                            local[axis]
                        } else {
                            1 - local[axis]
                        };
                        cell[axis] + mirrored
                    }))
                };
                for [p1, p2, _] in PERMUTATIONS {
                    let mut second = [0; 3];
                    second[p1] = 1;
                    let mut third = second;
                    third[p2] = 1;
                    let mut tet = vec![
                        corner([0; 3]),
                        corner(second),
                        corner(third),
                        corner([1; 3]),
                    ];
                    let [x0, x1, x2, x3] = [0, 1, 2, 3].map(|a| position(tet[a]));
                    if (x1 - x0).cross(&(x2 - x0)).dot(&(x3 - x0)) < 0.0 {
                        tet.swap(2, 3);
                    }
                    tets.push(tet);
                }
            }
        }
    }
    tets
}

/// The number of node (i, j, k) of the beam at refinement r: i·(r+1)² + j·(r+1) + k.
pub fn beam_node(r: usize, [i, j, k]: [usize; 3]) -> usize {
    i * (r + 1) * (r + 1) + j * (r + 1) + k
}

/// The beam "beam r" of fem-scenes.md: nodes x_i = i/(10r), y_j = −0.05 + j·0.1/r,
/// z_k = −0.05 + k·0.1/r, the mirrored 6-tet split, lumped masses ρV/4, the face x = 0
/// clamped, gravity along −y; (E, ν = 0.3) converted for a solid. Refuses r outside
/// 1..=[`MAX_REFINEMENT`] (`beam.refinement`) and a bad E (`youngs_modulus`).
pub fn beam(r: usize, energy: EnergyKind, youngs: f64) -> Result<ContinuumSystem> {
    if !(1..=MAX_REFINEMENT).contains(&r) {
        return Err(Error::invalid(
            "beam.refinement",
            r,
            &format!(
                "an integer from 1 to {MAX_REFINEMENT} (cells across; fem-scenes.md's meshes are \
                 r = 2, 4, 8, 16)"
            ),
        ));
    }
    let lame = Lame::from_youngs_poisson(youngs, BEAM_POISSON, Loading::Solid)?;
    let along = 10 * r;
    let count = (along + 1) * (r + 1) * (r + 1);
    let mut positions = vec![0.0; 3 * count];
    let mut fixed = vec![false; count];
    for i in 0..=along {
        for j in 0..=r {
            for k in 0..=r {
                let n = beam_node(r, [i, j, k]);
                positions[3 * n] = BEAM_LENGTH * i as f64 / along as f64;
                positions[3 * n + 1] = BEAM_SIDE * (j as f64 / r as f64 - 0.5);
                positions[3 * n + 2] = BEAM_SIDE * (k as f64 / r as f64 - 0.5);
                fixed[n] = i == 0;
            }
        }
    }
    let elements = mirrored_tetrahedra([along, r, r], |p| beam_node(r, p), &positions);
    let mesh = Mesh {
        kind: ElementKind::Tetrahedron,
        elements,
        masses: Masses::Lumped(BEAM_DENSITY),
        displacement: vec![0.0; 3 * count],
        loads: vec![0.0; 3 * count],
        gravity: vec![0.0, -THESIS_GRAVITY, 0.0],
        positions,
        fixed,
    };
    ContinuumSystem::new(mesh, Material { energy, lame })
}

/// The beam's tip deflection: the mean y-displacement of the nodes at X = 1 m, m.
pub fn beam_tip_deflection(r: usize, displacement: &[f64]) -> f64 {
    let tip: Vec<usize> = (0..=r)
        .flat_map(|j| (0..=r).map(move |k| beam_node(r, [10 * r, j, k])))
        .collect();
    tip.iter().map(|&n| displacement[3 * n + 1]).sum::<f64>() / tip.len() as f64
}

/// The membrane of fem-scenes.md: the sheet of `sheet-scene.md` at n nodes a side (its
/// positions, its uniform masses 100/n² kg, its four held corners, gravity along −y), each
/// cell (i, j) split along (i, j)–(i+1, j+1) for even i + j and along (i+1, j)–(i, j+1) for
/// odd, with plane-stress (Y = 8k/3 N/m, ν = 1/3).
pub fn membrane(n: usize, energy: EnergyKind, stiffness: f64) -> Result<ContinuumSystem> {
    let sheet = SheetParams::spec(n, stiffness).build()?;
    let lame = Lame::from_youngs_poisson(
        8.0 * stiffness / 3.0,
        MEMBRANE_POISSON,
        Loading::PlaneStress,
    )?;
    let node = |i: usize, j: usize| i * n + j;
    let mut elements = Vec::with_capacity(2 * (n - 1) * (n - 1));
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            let [a, b, c, d] = [
                node(i, j),
                node(i + 1, j),
                node(i + 1, j + 1),
                node(i, j + 1),
            ];
            if (i + j) % 2 == 0 {
                elements.extend([vec![a, b, c], vec![a, c, d]]);
            } else {
                elements.extend([vec![a, b, d], vec![b, c, d]]);
            }
        }
    }
    let nodes = sheet.nodes();
    let mesh = Mesh {
        kind: ElementKind::Membrane,
        positions: nodes
            .iter()
            .flat_map(|p| p.position.iter().copied())
            .collect(),
        elements,
        masses: Masses::PerNode(nodes.iter().map(|p| p.mass).collect()),
        fixed: nodes.iter().map(|p| p.fixed).collect(),
        displacement: vec![0.0; 3 * nodes.len()],
        loads: vec![0.0; 3 * nodes.len()],
        gravity: sheet.gravity().iter().copied().collect(),
    };
    ContinuumSystem::new(mesh, Material { energy, lame })
}

/// The number of Cook's node (i, j) at mesh N: i·(N+1) + j.
pub fn cook_node(n: usize, i: usize, j: usize) -> usize {
    i * (n + 1) + j
}

/// Cook's membrane at mesh N (even, from 2 to [`COOK_MAX_ELEMENTS_PER_SIDE`], fem-scenes.md's
/// range: its measuring point (48, 52) is node (N, N/2)): nodes X(s, t) bilinear in the corners at s = i/N, t = j/N, each quad split along
/// (i, j)–(i+1, j+1), the edge s = 0 clamped, the edge s = 1 loaded by a uniform vertical
/// traction of total [`COOK_FORCE`] (each segment of length ℓ carries F·ℓ/16, half to each
/// end), plane stress (E, ν = 1/3), thickness 1, no gravity.
pub fn cook(n: usize, energy: EnergyKind, youngs: f64) -> Result<ContinuumSystem> {
    if !(2..=COOK_MAX_ELEMENTS_PER_SIDE).contains(&n) || n % 2 == 1 {
        return Err(Error::invalid(
            "cook.elements_per_side",
            n,
            &format!(
                "an even integer from 2 to {COOK_MAX_ELEMENTS_PER_SIDE} (fem-scenes.md's N = 2 … \
                 64; the measuring point (48, 52) is node (N, N/2))"
            ),
        ));
    }
    let lame = Lame::from_youngs_poisson(youngs, COOK_POISSON, Loading::PlaneStress)?;
    let [p0, p1, p2, p3] = COOK_CORNERS;
    let count = (n + 1) * (n + 1);
    let mut positions = vec![0.0; 2 * count];
    for i in 0..=n {
        for j in 0..=n {
            let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
            for c in 0..2 {
                positions[2 * cook_node(n, i, j) + c] = (1.0 - s) * (1.0 - t) * p0[c]
                    + s * (1.0 - t) * p1[c]
                    + s * t * p2[c]
                    + (1.0 - s) * t * p3[c];
            }
        }
    }
    let mut elements = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        for j in 0..n {
            let [a, b, c, d] = [
                cook_node(n, i, j),
                cook_node(n, i + 1, j),
                cook_node(n, i + 1, j + 1),
                cook_node(n, i, j + 1),
            ];
            elements.extend([vec![a, b, c], vec![a, c, d]]);
        }
    }
    let edge_length = p2[1] - p1[1];
    let mut loads = vec![0.0; 2 * count];
    for j in 0..n {
        let (a, b) = (cook_node(n, n, j), cook_node(n, n, j + 1));
        let length = (positions[2 * b + 1] - positions[2 * a + 1])
            .hypot(positions[2 * b] - positions[2 * a]);
        for end in [a, b] {
            loads[2 * end + 1] += 0.5 * COOK_FORCE * length / edge_length;
        }
    }
    let mesh = Mesh {
        kind: ElementKind::PlaneTriangle,
        elements,
        masses: Masses::Lumped(UNIT_DENSITY),
        fixed: (0..count).map(|p| p <= n).collect(),
        displacement: vec![0.0; 2 * count],
        loads,
        gravity: vec![0.0, 0.0],
        positions,
    };
    ContinuumSystem::new(mesh, Material { energy, lame })
}

/// The patch test: the unit cube in 3 × 3 × 3 cubes split as the beam's (64 nodes, 8 of them
/// interior and free), every boundary node moved by x = A X + b ([`PATCH_MAP`],
/// [`PATCH_SHIFT`]), no gravity; (E, ν) = (1, 0.3) converted for a solid.
pub fn patch(energy: EnergyKind) -> Result<ContinuumSystem> {
    let lame = Lame::from_youngs_poisson(PATCH_YOUNGS, PATCH_POISSON, Loading::Solid)?;
    let side = PATCH_CELLS + 1;
    let node = |[i, j, k]: [usize; 3]| (i * side + j) * side + k;
    let count = side * side * side;
    let mut positions = vec![0.0; 3 * count];
    let mut displacement = vec![0.0; 3 * count];
    let mut fixed = vec![false; count];
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                let n = node([i, j, k]);
                let x = [i, j, k].map(|a| a as f64 / PATCH_CELLS as f64);
                positions[3 * n..3 * n + 3].copy_from_slice(&x);
                fixed[n] = [i, j, k].iter().any(|&a| a == 0 || a == PATCH_CELLS);
                if fixed[n] {
                    for (r, row) in PATCH_MAP.iter().enumerate() {
                        let mapped: f64 = row.iter().zip(&x).map(|(a, x)| a * x).sum();
                        displacement[3 * n + r] = mapped + PATCH_SHIFT[r] - x[r];
                    }
                }
            }
        }
    }
    let elements = mirrored_tetrahedra([PATCH_CELLS; 3], node, &positions);
    let mesh = Mesh {
        kind: ElementKind::Tetrahedron,
        elements,
        masses: Masses::Lumped(UNIT_DENSITY),
        fixed,
        displacement,
        loads: vec![0.0; 3 * count],
        gravity: vec![0.0; 3],
        positions,
    };
    ContinuumSystem::new(mesh, Material { energy, lame })
}

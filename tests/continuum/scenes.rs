//! The scenes' meshes (`src/model/continuum/scenes.rs`): counts, volumes, conformity, the
//! beam's symmetry, masses, clamps and loads as fem-scenes.md states them.

use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::continuum::scenes::{
    beam, beam_node, cook, cook_node, membrane, patch, BEAM_DENSITY, BEAM_LENGTH, BEAM_SIDE,
    COOK_FORCE,
};
use mass_spring_solvers::model::continuum::system::ContinuumSystem;
use mass_spring_solvers::Error;
use std::collections::BTreeMap;

/// Every face of the tets, sorted, with the number of tets that have it.
fn face_counts(system: &ContinuumSystem) -> BTreeMap<[usize; 3], usize> {
    let mut faces = BTreeMap::new();
    for e in system.elements() {
        let n = e.nodes();
        for skip in 0..4 {
            let mut face: Vec<usize> = (0..4).filter(|&a| a != skip).map(|a| n[a]).collect();
            face.sort_unstable();
            *faces.entry([face[0], face[1], face[2]]).or_insert(0) += 1;
        }
    }
    faces
}

/// Whether a face lies on the boundary of the box [lo, hi] (all three nodes on one side).
fn on_box_boundary(
    system: &ContinuumSystem,
    face: &[usize; 3],
    lo: [f64; 3],
    hi: [f64; 3],
) -> bool {
    let x = system.rest_positions();
    (0..3).any(|axis| {
        [lo[axis], hi[axis]]
            .iter()
            .any(|&side| face.iter().all(|&n| (x[3 * n + axis] - side).abs() < 1e-12))
    })
}

/// Beam r = 2: 189 nodes and 480 tets, r = 4: 1025 and 3840; every tet of positive volume,
/// summing to the box's; the split conforming (every interior face shared by exactly two tets,
/// every boundary face by one) and, at even r, symmetric under z ↦ −z (the mirror image of
/// every tet is a tet); masses ρV/4 summing to ρ times the volume; the face x = 0 clamped.
/// Wrong implementations it catches (tried): the split without mirroring (one diagonal in
/// every cube: conforming but not symmetric), and the mirroring taken from i alone on every axis.
#[test]
fn the_beam_mesh_is_conforming_symmetric_and_weighed() {
    for (r, nodes, tets) in [(2, 189, 480), (4, 1025, 3840)] {
        let system = beam(r, EnergyKind::Linear, 1e9).unwrap();
        assert_eq!(
            (system.node_count(), system.elements().len()),
            (nodes, tets)
        );
        let volume: f64 = system.elements().iter().map(|e| e.measure()).sum();
        assert!(system.elements().iter().all(|e| e.measure() > 0.0));
        let box_volume = BEAM_LENGTH * BEAM_SIDE * BEAM_SIDE;
        assert!((volume - box_volume).abs() < 1e-15, "{volume}");
        let mass: f64 = system.masses().iter().sum();
        assert!((mass - BEAM_DENSITY * box_volume).abs() < 1e-9);
        let half = BEAM_SIDE / 2.0;
        for (face, count) in face_counts(&system) {
            let boundary = on_box_boundary(
                &system,
                &face,
                [0.0, -half, -half],
                [BEAM_LENGTH, half, half],
            );
            assert_eq!(count, if boundary { 1 } else { 2 }, "face {face:?}");
        }
        let mirror = |n: usize| {
            let (i, rest) = (n / ((r + 1) * (r + 1)), n % ((r + 1) * (r + 1)));
            beam_node(r, [i, rest / (r + 1), r - rest % (r + 1)])
        };
        let sorted = |nodes: &[usize]| {
            let mut v = nodes.to_vec();
            v.sort_unstable();
            v
        };
        let tets: std::collections::BTreeSet<Vec<usize>> = system
            .elements()
            .iter()
            .map(|e| sorted(e.nodes()))
            .collect();
        for e in system.elements() {
            let image: Vec<usize> = e.nodes().iter().map(|&n| mirror(n)).collect();
            assert!(
                tets.contains(&sorted(&image)),
                "the mirror of {:?} is no tet",
                e.nodes()
            );
        }
        for n in 0..nodes {
            assert_eq!(system.is_fixed(n), system.rest_positions()[3 * n] == 0.0);
        }
    }
}

/// Cook's mesh N = 4: 25 nodes, 32 positive triangles covering the quadrilateral's 1440
/// (half the cross product of its diagonals, |(48, 60) × (−48, 0)|/2); the loads vertical,
/// summing to F = 1, a quarter on each inner node of the right edge and an eighth on its ends;
/// the edge s = 0 clamped; an odd N refused. Wrong implementation it catches (tried): the
/// whole segment's force given to each end (total 2F).
#[test]
fn cooks_mesh_and_loads() {
    let n = 4;
    let system = cook(n, EnergyKind::Linear, 1.0).unwrap();
    assert_eq!((system.node_count(), system.elements().len()), (25, 32));
    assert!(system.elements().iter().all(|e| e.measure() > 0.0));
    let area: f64 = system.elements().iter().map(|e| e.measure()).sum();
    assert!((area - 1440.0).abs() < 1e-9, "{area}");
    let loads = system.forces(&vec![0.0; 2 * system.node_count()]);
    let total_y: f64 = loads.iter().skip(1).step_by(2).sum();
    let total_x: f64 = loads.iter().step_by(2).map(|f| f.abs()).sum();
    assert!((total_y - COOK_FORCE).abs() < 1e-15 && total_x == 0.0);
    let right: Vec<f64> = (0..=n).map(|j| loads[2 * cook_node(n, n, j) + 1]).collect();
    assert!(
        (right[0] - 0.125).abs() < 1e-15 && (right[1] - 0.25).abs() < 1e-15,
        "{right:?}"
    );
    assert!((0..=n).all(|j| system.is_fixed(cook_node(n, 0, j))));
    // fem-scenes.md's range N = 2 … 64, even; 64 itself is accepted.
    for bad in [0, 3, 66] {
        assert!(
            matches!(cook(bad, EnergyKind::Linear, 1.0), Err(Error::InvalidParameter { field, .. }) if field == "cook.elements_per_side"),
            "N = {bad}"
        );
    }
    assert!(cook(64, EnergyKind::Linear, 1.0).is_ok());
}

/// The membrane at n = 10: 100 nodes, 162 triangles covering 81 m², the sheet's masses
/// (1 kg each) and four held corners; the patch: 64 nodes, 8 free, 162 tets filling the unit
/// cube, conforming. A linear membrane and a bad refinement are refused, naming the field.
/// Wrong implementation it catches (tried): the system without its check of the energy on
/// membranes (a linear membrane accepted).
#[test]
fn the_membrane_and_the_patch() {
    let m = membrane(10, EnergyKind::StableNeoHookean, 1e3).unwrap();
    assert_eq!((m.node_count(), m.elements().len()), (100, 162));
    let area: f64 = m.elements().iter().map(|e| e.measure()).sum();
    assert!((area - 81.0).abs() < 1e-12);
    assert!(m.masses().iter().all(|&mass| (mass - 1.0).abs() < 1e-15));
    assert_eq!((0..100).filter(|&n| m.is_fixed(n)).count(), 4);
    let p = patch(EnergyKind::Arap).unwrap();
    assert_eq!((p.node_count(), p.elements().len()), (64, 162));
    assert_eq!((0..64).filter(|&n| !p.is_fixed(n)).count(), 8);
    let volume: f64 = p.elements().iter().map(|e| e.measure()).sum();
    assert!((volume - 1.0).abs() < 1e-14);
    for (face, count) in face_counts(&p) {
        let boundary = on_box_boundary(&p, &face, [0.0; 3], [1.0; 3]);
        assert_eq!(count, if boundary { 1 } else { 2 });
    }
    assert!(
        matches!(membrane(10, EnergyKind::Linear, 1e3), Err(Error::InvalidParameter { field, .. }) if field == "energy")
    );
    // fem-scenes.md's meshes r = 2 … 16.
    for bad in [0, 17] {
        assert!(
            matches!(beam(bad, EnergyKind::Linear, 1e9), Err(Error::InvalidParameter { field, .. }) if field == "beam.refinement"),
            "r = {bad}"
        );
    }
    assert!(
        matches!(beam(2, EnergyKind::Linear, -1.0), Err(Error::InvalidParameter { field, .. }) if field == "youngs_modulus")
    );
}

//! The element kernels (`src/model/continuum/element.rs`): nodal forces and element Hessians
//! against finite differences of the element energy, and the refusal of bad rest elements.

use super::Random;
use mass_spring_solvers::model::continuum::element::Element;
use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::continuum::hyperelastic::Hyperelastic;
use mass_spring_solvers::model::continuum::lame::Lame;
use mass_spring_solvers::Error;
use nalgebra::DMatrix;

const LAME: Lame = Lame {
    mu: 1.3,
    lambda: 2.1,
};

/// A tet, a plane triangle and a membrane triangle tilted in 3D, with their rest positions
/// (flat, d a node), at nodes 0..c+1 but for a shuffle that tests the node indexing.
fn elements() -> Vec<(Element, Vec<f64>)> {
    let tet = vec![0.1, 0.0, 0.0, 1.0, 0.2, 0.0, 0.0, 1.1, 0.1, 0.2, 0.1, 0.9];
    let plane = vec![0.0, 0.0, 1.0, 0.1, 0.2, 0.9];
    let membrane = vec![0.0, 0.0, 0.0, 1.0, 0.3, 0.2, 0.1, 0.8, -0.4];
    vec![
        (Element::solid(0, &[2, 0, 1, 3], &tet).unwrap(), tet),
        (Element::solid(1, &[1, 2, 0], &plane).unwrap(), plane),
        (
            Element::membrane(2, &[0, 2, 1], &membrane).unwrap(),
            membrane,
        ),
    ]
}

/// V Ψ of an element at displacements `u`.
fn element_energy(e: &Element, energy: &dyn Hyperelastic, u: &[f64]) -> f64 {
    e.measure() * energy.density(&e.deformation(u), &LAME)
}

/// The elastic forces of an element at `u`.
fn element_forces(e: &Element, energy: &dyn Hyperelastic, u: &[f64]) -> Vec<f64> {
    let mut forces = vec![0.0; u.len()];
    e.add_forces(&energy.stress(&e.deformation(u), &LAME), &mut forces);
    forces
}

/// The nodal forces −V P D_m⁻ᵀ (node 0 minus the others' sum) are −∂(VΨ)/∂x, and the element
/// Hessian with the exact ∂P/∂F is −∂f/∂x, by central differences at random displacements;
/// the forces sum to zero. For every energy on the three element kinds, nodes listed out of
/// order. Wrong implementation it catches (tried): node 0's force given the others' sum
/// instead of minus it.
#[test]
fn forces_and_hessians_are_derivatives_of_the_element_energy() {
    let mut random = Random::new(11);
    for (element, rest) in elements() {
        for kind in EnergyKind::ALL {
            if element.is_membrane() && !kind.model().supports_membranes() {
                continue;
            }
            let energy = kind.model();
            let u: Vec<f64> = rest.iter().map(|_| 0.3 * random.uniform()).collect();
            let h = 1e-6;
            let forces = element_forces(&element, energy, &u);
            let hessian_map =
                element.hessian(&energy.stress_derivative(&element.deformation(&u), &LAME));
            let n = u.len();
            let d = element.space_dimension();
            for k in 0..n {
                let (mut plus, mut minus) = (u.clone(), u.clone());
                plus[k] += h;
                minus[k] -= h;
                let fd = (element_energy(&element, energy, &plus)
                    - element_energy(&element, energy, &minus))
                    / (2.0 * h);
                assert!(
                    (forces[k] + fd).abs() < 1e-6,
                    "{} force[{k}] = {} against {}",
                    kind.name(),
                    forces[k],
                    -fd
                );
                let df: Vec<f64> = element_forces(&element, energy, &plus)
                    .iter()
                    .zip(element_forces(&element, energy, &minus))
                    .map(|(p, m)| -(p - m) / (2.0 * h))
                    .collect();
                // The element Hessian's rows and columns are in the element's node order.
                let b = element
                    .nodes()
                    .iter()
                    .position(|&node| node == k / d)
                    .unwrap();
                for (a, &node) in element.nodes().iter().enumerate() {
                    for i in 0..d {
                        let exact = hessian_map[(a * d + i, b * d + k % d)];
                        let fd = df[node * d + i];
                        assert!(
                            (exact - fd).abs() < 1e-5,
                            "{} H[{a}{i},{k}] = {exact} against {fd}",
                            kind.name()
                        );
                    }
                }
            }
            for i in 0..d {
                let total: f64 = (0..n / d).map(|node| forces[node * d + i]).sum();
                assert!(total.abs() < 1e-12, "{}: net force {total}", kind.name());
            }
        }
    }
}

/// An inverted tet (two nodes swapped), a flat tet, a clockwise plane triangle and a
/// collinear membrane triangle are refused, the error naming the element. Wrong
/// implementation it catches (tried): a check of |det D_m| (accepting inverted elements).
#[test]
fn degenerate_and_inverted_rest_elements_are_refused() {
    let tet = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    assert!(Element::solid(4, &[0, 1, 2, 3], &tet).is_ok());
    let flat = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0];
    let triangle = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
    let collinear = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0];
    let cases = [
        Element::solid(7, &[0, 2, 1, 3], &tet),
        Element::solid(8, &[0, 1, 2, 3], &flat),
        Element::solid(9, &[0, 2, 1], &triangle),
        Element::membrane(10, &[0, 1, 2], &collinear),
    ];
    for (case, index) in cases.into_iter().zip(7..) {
        match case {
            Err(Error::InvalidParameter { field, .. }) => {
                assert_eq!(field, format!("elements[{index}]"))
            }
            other => panic!("element {index}: {other:?}"),
        }
    }
    // A rotation of ∂F/∂x: the rest element's F is F₀ at zero displacement.
    let e = Element::solid(0, &[0, 1, 2, 3], &tet).unwrap();
    assert_eq!(
        e.deformation(&[0.0; 12]).f(),
        &DMatrix::<f64>::identity(3, 3)
    );
}

//! The beam in motion (`docs/fem-scenes.md`, "beam"; issue 50, item 5): released from rest
//! in its rest shape under each optimization integrator ([`released`]), its kinetic-energy
//! peaks and its total energy; a free beam spinning without clamp or gravity
//! ([`spinning`]), its angular momentum; and the lowest bending frequency of the lumped
//! linear model ([`lowest_bending_frequency`]) against beam theory
//! ([`beam_theory_frequency`]).

use crate::error::{Error, Result};
use crate::integrators::continuum::{ContinuumIntegrator, ContinuumState, StageLog};
use crate::integrators::optimization_integrator::OptimizationIntegrator;
use crate::model::continuum::energy::EnergyKind;
use crate::model::continuum::scenes::{beam, BEAM_DENSITY, BEAM_LENGTH, BEAM_SIDE};
use crate::model::continuum::statics::{static_equilibrium, DEFAULT_TOLERANCE};
use crate::model::continuum::system::{ContinuumSystem, ElementKind, Masses, Mesh};
use crate::model::linear::Factorization;
use crate::model::metrics::{Peak, PeakDetector};
use crate::model::scene::THESIS_GRAVITY;
use crate::studies::continuum::statics::beam_theory_sag;

/// The first root of the cantilever's frequency equation 1 + cos β cosh β = 0.
pub const CANTILEVER_ROOT: f64 = 1.875104;
/// Inverse iterations of [`lowest_bending_frequency`]: from the static deflection, which is
/// nearly the mode, the frequency settles to round-off within a few (tested: 6 and 12 agree
/// to 1e-12).
const INVERSE_ITERATIONS: usize = 8;

/// The beam's section: area A, m², and second moment I = a⁴/12, m⁴.
fn section() -> (f64, f64) {
    (BEAM_SIDE * BEAM_SIDE, BEAM_SIDE.powi(4) / 12.0)
}

/// fem-scenes.md, "beam": The cantilever's first bending frequency, rad/s: Euler-Bernoulli's
/// ω = β² √(EI/(ρAL⁴)), β = 1.875104, with Timoshenko's shear correction taken as its static
/// flexibility (interpretation, not a printed formula: Rayleigh's quotient with the static
/// deflection as the mode gives ω² ∝ 1/δ, so ω is scaled by √(δ_EB/δ), δ of
/// [`beam_theory_sag`]; a correction of about −0.5 % here; rotary inertia is left out).
pub fn beam_theory_frequency(youngs: f64) -> f64 {
    let (area, inertia) = section();
    let euler = CANTILEVER_ROOT.powi(2)
        * (youngs * inertia / (BEAM_DENSITY * area * BEAM_LENGTH.powi(4))).sqrt();
    let q = BEAM_DENSITY * THESIS_GRAVITY * area;
    let bending = q * BEAM_LENGTH.powi(4) / (8.0 * youngs * inertia);
    euler * (bending / beam_theory_sag(youngs)).sqrt()
}

/// The masses of the free unknowns, in free-node order, kg.
fn free_masses(system: &ContinuumSystem) -> Vec<f64> {
    let d = system.dimension();
    (0..system.node_count())
        .filter(|&i| !system.is_fixed(i))
        .flat_map(|i| std::iter::repeat_n(system.masses()[i], d))
        .collect()
}

/// The lowest frequency ω₁ (rad/s) of the lumped model linearised at rest, K φ = ω² M φ over
/// the free unknowns (K the exact Hessian at the start, M the lumped masses), by inverse
/// iteration from the static deflection under the system's loads (for the beam: gravity's,
/// symmetric in z, so the iteration stays with the bending in y); ω² the Rayleigh quotient.
pub fn lowest_bending_frequency(system: &ContinuumSystem) -> Result<f64> {
    let start = system.start();
    let stiffness = system.hessian(start, false);
    let factor = Factorization::new(&stiffness)?;
    let masses = free_masses(system);
    let mut mode = system.free_part(&system.forces(start));
    if mode.iter().all(|f| *f == 0.0) {
        return Err(Error::invalid(
            "system",
            "no load",
            "a load (gravity) whose static deflection starts the inverse iteration",
        ));
    }
    factor.solve_in_place(&mut mode, 1);
    let mut product = vec![0.0; mode.len()];
    for _ in 0..INVERSE_ITERATIONS {
        let mut next: Vec<f64> = mode.iter().zip(&masses).map(|(x, m)| m * x).collect();
        factor.solve_in_place(&mut next, 1);
        let norm = next.iter().map(|x| x * x).sum::<f64>().sqrt();
        mode = next.into_iter().map(|x| x / norm).collect();
    }
    stiffness.mul_vec(&mode, &mut product);
    let k: f64 = mode.iter().zip(&product).map(|(x, y)| x * y).sum();
    let m: f64 = mode.iter().zip(&masses).map(|(x, m)| m * x * x).sum();
    Ok((k / m).sqrt())
}

/// A run's samples, one per step from t = 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// The time step, s.
    pub dt: f64,
    /// Kinetic energy, J.
    pub kinetic: Vec<f64>,
    /// Kinetic plus potential energy (elastic minus the loads' work), J.
    pub total: Vec<f64>,
    /// Angular momentum about the origin, Σ m (X + u) × v, N·m·s (3D systems; zero in the
    /// plane).
    pub angular_momentum: Vec<[f64; 3]>,
    /// What the stages took.
    pub log: StageLog,
}

impl Trajectory {
    /// The kinetic-energy peaks: a sample above the previous one and at least the next one.
    pub fn peaks(&self) -> Vec<Peak> {
        let mut detector = PeakDetector::new(self.dt);
        self.kinetic
            .iter()
            .filter_map(|&ke| detector.push(ke))
            .collect()
    }
}

/// Σ m (X + u) × v about the origin, for a 3D system.
pub fn angular_momentum(system: &ContinuumSystem, state: &ContinuumState) -> [f64; 3] {
    let mut total = [0.0; 3];
    if system.dimension() != 3 {
        return total;
    }
    let x = system.rest_positions();
    for (i, m) in system.masses().iter().enumerate() {
        let p = [0, 1, 2].map(|c| x[3 * i + c] + state.u[3 * i + c]);
        let v = &state.v[3 * i..3 * i + 3];
        total[0] += m * (p[1] * v[2] - p[2] * v[1]);
        total[1] += m * (p[2] * v[0] - p[0] * v[2]);
        total[2] += m * (p[0] * v[1] - p[1] * v[0]);
    }
    total
}

/// `steps` steps of `integrator` (dt s) on `system` from `start`, every stage solved to
/// the default tolerance ([`crate::integrators::continuum::DEFAULT_TOLERANCE`]).
pub fn run(
    system: &ContinuumSystem,
    integrator: OptimizationIntegrator,
    dt: f64,
    steps: usize,
    start: ContinuumState,
) -> Result<Trajectory> {
    let mut stepper = ContinuumIntegrator::new(
        system,
        integrator,
        dt,
        crate::integrators::continuum::DEFAULT_TOLERANCE,
    )?;
    let mut state = start;
    let mut trajectory = Trajectory {
        dt,
        kinetic: Vec::with_capacity(steps + 1),
        total: Vec::with_capacity(steps + 1),
        angular_momentum: Vec::with_capacity(steps + 1),
        log: StageLog::default(),
    };
    for step in 0..=steps {
        if step > 0 {
            stepper.step(&mut state)?;
        }
        let kinetic = state.kinetic_energy(system);
        trajectory.kinetic.push(kinetic);
        trajectory.total.push(kinetic + system.energy(&state.u));
        trajectory
            .angular_momentum
            .push(angular_momentum(system, &state));
    }
    trajectory.log = stepper.log();
    Ok(trajectory)
}

/// The beam "beam r" with `energy` and E = `youngs`, released from rest in its rest shape,
/// `steps` steps of `integrator`.
pub fn released(
    r: usize,
    energy: EnergyKind,
    youngs: f64,
    integrator: OptimizationIntegrator,
    dt: f64,
    steps: usize,
) -> Result<Trajectory> {
    let system = beam(r, energy, youngs)?;
    let start = ContinuumState::released(&system);
    run(&system, integrator, dt, steps, start)
}

/// The energy the release turns into motion, E(rest) − E(equilibrium), J: for a linear
/// model the kinetic energy passing the equilibrium, the height of a conservative run's peaks.
pub fn released_energy(system: &ContinuumSystem) -> Result<f64> {
    let equilibrium = static_equilibrium(system, DEFAULT_TOLERANCE)?;
    Ok(system.energy(system.start()) - system.energy(&equilibrium.displacement))
}

/// The beam "beam r" freed: no clamp and no gravity (both exert torques), the same nodes,
/// elements and lumped masses.
pub fn free_beam(r: usize, energy: EnergyKind, youngs: f64) -> Result<ContinuumSystem> {
    let clamped = beam(r, energy, youngs)?;
    let n = clamped.node_count();
    ContinuumSystem::new(
        Mesh {
            kind: ElementKind::Tetrahedron,
            positions: clamped.rest_positions().to_vec(),
            elements: clamped
                .elements()
                .iter()
                .map(|e| e.nodes().to_vec())
                .collect(),
            masses: Masses::PerNode(clamped.masses().to_vec()),
            fixed: vec![false; n],
            displacement: vec![0.0; 3 * n],
            loads: vec![0.0; 3 * n],
            gravity: vec![0.0; 3],
        },
        clamped.material(),
    )
}

/// At rest in the rest shape, spinning rigidly at `spin` (rad/s, a vector) about the centre
/// of mass: v = ω × (X − X_c).
pub fn spinning_start(system: &ContinuumSystem, spin: [f64; 3]) -> ContinuumState {
    let mut state = ContinuumState::released(system);
    let x = system.rest_positions();
    let total: f64 = system.masses().iter().sum();
    let centre = [0, 1, 2].map(|c| {
        system
            .masses()
            .iter()
            .enumerate()
            .map(|(i, m)| m * x[3 * i + c])
            .sum::<f64>()
            / total
    });
    for i in 0..system.node_count() {
        let r = [0, 1, 2].map(|c| x[3 * i + c] - centre[c]);
        state.v[3 * i] = spin[1] * r[2] - spin[2] * r[1];
        state.v[3 * i + 1] = spin[2] * r[0] - spin[0] * r[2];
        state.v[3 * i + 2] = spin[0] * r[1] - spin[1] * r[0];
    }
    state
}

/// The free beam ([`free_beam`]) spinning at `spin` from its rest shape, `steps` steps of
/// `integrator`.
pub fn spinning(
    r: usize,
    energy: EnergyKind,
    youngs: f64,
    spin: [f64; 3],
    integrator: OptimizationIntegrator,
    dt: f64,
    steps: usize,
) -> Result<Trajectory> {
    let system = free_beam(r, energy, youngs)?;
    let start = spinning_start(&system, spin);
    run(&system, integrator, dt, steps, start)
}

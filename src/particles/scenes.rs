//! Scenes: the tutorial's cloth dropped from 10 m and its pendulum that bounces on the floor
//! (as [`ParticleSystem`]s), and a cloth hanging from two pinned corners (a plain
//! [`MassSpringSystem`] that the thesis's solvers run).
//!
//! The tutorial gives no numbers besides the 10 m drop; the defaults below are chosen so that
//! the motion is visible and symplectic Euler and RK4 run well at `dt = 1e-3` s: the default
//! cloth has $`\omega_{max} \approx 257`$ rad/s and the pendulum 96 rad/s at rest (limits
//! $`2/\omega_{max}`$ and $`2\sqrt2/\omega_{max}`$, see [`super::integrators`]). Explicit Euler
//! has no stable step for an undamped mode; with the springs' damping $`k_d`$ its axial modes
//! are stable only for $`dt < k_d/k_s`$ (5e-4 s for the default cloth).

use super::{Drag, Ground, ParticleSystem, Particles};
use crate::error::{require_finite, require_non_negative, require_positive, Error, Result};
use crate::model::system::{MassSpringSystem, Node, Spring, Vec3};

/// A rectangular cloth of `nx` × `ny` particles as a triangle mesh: a spring on every edge of
/// the grid (structural springs) and one diagonal per quad, from particle $`(i, j)`$ to
/// $`(i+1, j+1)`$; every rest length is the initial distance.
///
/// The single diagonal direction is the tutorial's "malla poligonal de triángulos"; it makes the
/// cloth slightly anisotropic (it shears more easily along the other diagonal).
#[derive(Debug, Clone, PartialEq)]
pub struct ClothParams {
    /// Particles along the first side, >= 2.
    pub nx: usize,
    /// Particles along the second side, >= 2.
    pub ny: usize,
    /// Distance between neighbouring particles, m (> 0).
    pub spacing: f64,
    /// Mass of every particle, kg (> 0).
    pub particle_mass: f64,
    /// Stiffness of every spring, N/m (> 0).
    pub stiffness: f64,
    /// Axial damping of every spring, N·s/m (>= 0; used by the particle system only).
    pub damping: f64,
    /// Gravity along -y, m/s² (>= 0).
    pub gravity: f64,
}

impl Default for ClothParams {
    /// A 1 m × 1 m cloth of 10 × 10 particles, 1 kg/m², k = 100 N/m.
    fn default() -> Self {
        Self {
            nx: 10,
            ny: 10,
            spacing: 1.0 / 9.0,
            particle_mass: 0.01,
            stiffness: 100.0,
            damping: 0.05,
            gravity: 9.81,
        }
    }
}

impl ClothParams {
    /// Rejects any parameter outside its range, naming the field.
    pub fn validate(&self) -> Result<()> {
        for (field, n) in [("cloth.nx", self.nx), ("cloth.ny", self.ny)] {
            if n < 2 {
                return Err(Error::invalid(field, n, "an integer >= 2"));
            }
        }
        require_positive("cloth.spacing", self.spacing)?;
        require_positive("cloth.particle_mass", self.particle_mass)?;
        require_positive("cloth.stiffness", self.stiffness)?;
        require_non_negative("cloth.damping", self.damping)?;
        require_non_negative("cloth.gravity", self.gravity)?;
        Ok(())
    }

    /// Index of particle $`(i, j)`$, $`i < n_x`$, $`j < n_y`$.
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }

    /// The springs: structural along $`i`$, structural along $`j`$, then the diagonals.
    fn springs(&self) -> Vec<Spring> {
        let (nx, ny) = (self.nx, self.ny);
        let spring = |a: usize, b: usize, rest_length: f64| Spring {
            a,
            b,
            rest_length,
            stiffness: self.stiffness,
            damping: self.damping,
        };
        let along_i = (0..ny).flat_map(|j| (0..nx - 1).map(move |i| (i, j, i + 1, j)));
        let along_j = (0..ny - 1).flat_map(|j| (0..nx).map(move |i| (i, j, i, j + 1)));
        let diagonal = (0..ny - 1).flat_map(|j| (0..nx - 1).map(move |i| (i, j, i + 1, j + 1)));
        along_i
            .chain(along_j)
            .map(|(i, j, p, q)| spring(self.index(i, j), self.index(p, q), self.spacing))
            .chain(diagonal.map(|(i, j, p, q)| {
                spring(
                    self.index(i, j),
                    self.index(p, q),
                    self.spacing * 2f64.sqrt(),
                )
            }))
            .collect()
    }

    /// The cloth with particle $`(i, j)`$ at `origin + i·spacing·u + j·spacing·w`, at rest.
    fn build(
        &self,
        origin: Vec3,
        u: Vec3,
        w: Vec3,
        fixed: impl Fn(usize, usize) -> bool,
    ) -> Result<MassSpringSystem> {
        self.validate()?;
        let nodes = (0..self.ny)
            .flat_map(|j| (0..self.nx).map(move |i| (i, j)))
            .map(|(i, j)| Node {
                mass: self.particle_mass,
                position: origin + self.spacing * (i as f64 * u + j as f64 * w),
                velocity: Vec3::zeros(),
                fixed: fixed(i, j),
            })
            .collect();
        MassSpringSystem::new(nodes, self.springs(), Vec3::new(0.0, -self.gravity, 0.0))
    }

    /// The cloth lying flat in the horizontal plane $`y`$ = `height` (along $`x`$ and $`z`$), every
    /// particle free.
    pub fn horizontal(&self, height: f64) -> Result<MassSpringSystem> {
        require_finite("cloth.height", height)?;
        self.build(Vec3::new(0.0, height, 0.0), Vec3::x(), Vec3::z(), |_, _| {
            false
        })
    }

    /// The cloth in the vertical plane $`z = 0`$, top row at $`y = 0`$ from $`x = 0`$ to
    /// $`x = (n_x - 1)\,s`$ with $`s`$ = `spacing`, rows below it, pinned at its two top corners
    /// and released at rest with unstretched springs (like the thesis rope, it then falls and
    /// swings).
    pub fn hanging(&self) -> Result<MassSpringSystem> {
        self.validate()?;
        let last = self.nx - 1;
        self.build(Vec3::zeros(), Vec3::x(), -Vec3::y(), |i, j| {
            j == 0 && (i == 0 || i == last)
        })
    }
}

/// The tutorial's example: a cloth dropped flat from `height` onto the floor $`y = 0`$ under
/// gravity, with a light viscous drag ("es recomendable aplicar una cierta fricción").
#[derive(Debug, Clone, PartialEq)]
pub struct ClothDropParams {
    pub cloth: ClothParams,
    /// Initial height of the cloth, m (> 0; the tutorial drops it from 10 m).
    pub height: f64,
    /// Drag coefficient $`k_f`$ on every particle, N·s/m (>= 0).
    pub drag: f64,
    /// Restitution of the floor, in [0, 1].
    pub restitution: f64,
}

impl ClothDropParams {
    /// The tutorial's drop: from 10 m, default cloth, $`k_f`$ = 1e-4 N·s/m, $`e`$ = 0.3.
    pub fn tutorial() -> Self {
        Self {
            cloth: ClothParams::default(),
            height: 10.0,
            drag: 1e-4,
            restitution: 0.3,
        }
    }

    /// The particle system: the cloth's gravity and damped springs, the drag and the floor.
    pub fn build(&self) -> Result<ParticleSystem> {
        require_positive("cloth_drop.height", self.height)?;
        require_non_negative("cloth_drop.drag", self.drag)?;
        let ground = Ground::new(0.0, self.restitution)?;
        let drag = Drag {
            k_f: self.drag,
            particles: Particles::All,
        };
        ParticleSystem::from_system(self.cloth.horizontal(self.height)?)
            .with_force(Box::new(drag))
            .map(|p| p.with_ground(ground))
    }
}

/// The tutorial's pendulum: a chain of particles and damped springs hanging from an anchored
/// pivot, released horizontal from rest. The chain is longer than the pivot is high, so it
/// strikes the floor $`y = 0`$ and bounces, losing energy.
#[derive(Debug, Clone, PartialEq)]
pub struct PendulumParams {
    /// Free particles in the chain, >= 1.
    pub particles: usize,
    /// Rest length of each spring, m (> 0).
    pub segment_length: f64,
    /// Mass of every free particle, kg (> 0).
    pub particle_mass: f64,
    /// Spring stiffness, N/m (> 0).
    pub stiffness: f64,
    /// Spring damping, N·s/m (>= 0).
    pub damping: f64,
    /// Height of the pivot above the floor, m (> 0).
    pub pivot_height: f64,
    /// Drag coefficient $`k_f`$ on every particle, N·s/m (>= 0).
    pub drag: f64,
    /// Restitution of the floor, in [0, 1].
    pub restitution: f64,
    /// Gravity along -y, m/s² (>= 0).
    pub gravity: f64,
}

impl PendulumParams {
    /// Five 0.2 kg particles on 0.5 m springs (2.5 m of chain) from a pivot 2 m high.
    pub fn tutorial() -> Self {
        Self {
            particles: 5,
            segment_length: 0.5,
            particle_mass: 0.2,
            stiffness: 500.0,
            damping: 0.5,
            pivot_height: 2.0,
            drag: 0.02,
            restitution: 0.5,
            gravity: 9.81,
        }
    }

    /// The particle system: pivot (anchored) then the chain along $`+x`$, at rest.
    pub fn build(&self) -> Result<ParticleSystem> {
        if self.particles < 1 {
            return Err(Error::invalid(
                "pendulum.particles",
                self.particles,
                "an integer >= 1",
            ));
        }
        require_positive("pendulum.segment_length", self.segment_length)?;
        require_positive("pendulum.particle_mass", self.particle_mass)?;
        require_positive("pendulum.stiffness", self.stiffness)?;
        require_non_negative("pendulum.damping", self.damping)?;
        require_positive("pendulum.pivot_height", self.pivot_height)?;
        require_non_negative("pendulum.drag", self.drag)?;
        require_non_negative("pendulum.gravity", self.gravity)?;
        let nodes = (0..=self.particles)
            .map(|i| Node {
                mass: self.particle_mass,
                position: Vec3::new(i as f64 * self.segment_length, self.pivot_height, 0.0),
                velocity: Vec3::zeros(),
                fixed: i == 0,
            })
            .collect();
        let springs = (0..self.particles)
            .map(|i| Spring {
                a: i,
                b: i + 1,
                rest_length: self.segment_length,
                stiffness: self.stiffness,
                damping: self.damping,
            })
            .collect();
        let system = MassSpringSystem::new(nodes, springs, Vec3::new(0.0, -self.gravity, 0.0))?;
        let drag = Drag {
            k_f: self.drag,
            particles: Particles::All,
        };
        let ground = Ground::new(0.0, self.restitution)?;
        ParticleSystem::from_system(system)
            .with_force(Box::new(drag))
            .map(|p| p.with_ground(ground))
    }
}

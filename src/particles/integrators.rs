//! The tutorial's numerical methods ("Método de Euler", "Método de Runge-Kutta, de orden 4")
//! over the particle system's first-order state $`y = (x, v)`$, $`y' = (v, f/m)`$, plus the
//! symplectic (semi-implicit) Euler of Baraff and Witkin's notes.
//!
//! | method | update | order | stable for an undamped mode $`\omega`$ |
//! |---|---|---|---|
//! | explicit Euler | $`y_{n+1} = y_n + h\,y'_n`$ | 1 | never: each step multiplies its amplitude by $`\sqrt{1 + \omega^2h^2}`$ |
//! | symplectic Euler | $`v_{n+1} = v_n + h\,f(x_n, v_n)/m`$, $`x_{n+1} = x_n + h\,v_{n+1}`$ | 1 | $`\omega h < 2`$ |
//! | RK4 | $`y_{n+1} = y_n + \frac h6(k_1 + 2k_2 + 2k_3 + k_4)`$ | 4 | $`\omega h < 2\sqrt2`$ |
//!
//! Erratum (tutorial): "Euler es un Runge-Kutta de orden 2" is wrong. Explicit Euler is the
//! one-stage Runge-Kutta method and is first order: it keeps the Taylor series up to the $`h`$
//! term, its local error is $`O(h^2)`$ and its global error at a fixed time $`O(h)`$ (the order-2
//! Runge-Kutta methods are midpoint and Heun). The tests measure slopes 1, 1 and 4.
//!
//! The ground, when present, is resolved after each complete step (after the four stages of
//! RK4), so contacts are first order in $`h`$ whatever the method.

use super::ParticleSystem;
use crate::error::{require_positive, Error, Result};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};

/// The three integrators of the tutorial.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Integrator {
    ExplicitEuler,
    SymplecticEuler,
    Rk4,
}

impl Integrator {
    /// Every integrator, in the tutorial's order.
    pub const ALL: [Integrator; 3] = [
        Integrator::ExplicitEuler,
        Integrator::SymplecticEuler,
        Integrator::Rk4,
    ];

    /// The name used on the command line.
    pub fn key(self) -> &'static str {
        match self {
            Integrator::ExplicitEuler => "explicit-euler",
            Integrator::SymplecticEuler => "symplectic-euler",
            Integrator::Rk4 => "rk4",
        }
    }

    /// Order of the global error at a fixed time.
    pub fn order(self) -> u32 {
        match self {
            Integrator::ExplicitEuler | Integrator::SymplecticEuler => 1,
            Integrator::Rk4 => 4,
        }
    }
}

impl std::str::FromStr for Integrator {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        Integrator::ALL
            .into_iter()
            .find(|i| i.key() == s)
            .ok_or_else(|| {
                Error::invalid(
                    "integrator",
                    s,
                    "one of explicit-euler, symplectic-euler, rk4",
                )
            })
    }
}

impl std::fmt::Display for Integrator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Integrator::ExplicitEuler => "explicit Euler",
            Integrator::SymplecticEuler => "symplectic Euler",
            Integrator::Rk4 => "RK4",
        })
    }
}

/// A particle system advanced by one of the tutorial's integrators with a fixed step $`h`$.
#[derive(Debug)]
pub struct ParticleStepper {
    particles: ParticleSystem,
    integrator: Integrator,
    h: f64,
    /// The force accumulator.
    f: Vec<Vec3>,
    /// The stages' derivatives $`k_1..k_4`$ (explicit and symplectic Euler use $`k_1`$ only).
    k: [State; 4],
    /// The state at which RK4 evaluates its stages 2-4.
    stage: State,
}

impl ParticleStepper {
    /// A stepper for `particles` with `integrator` and time step `dt` (s, > 0).
    pub fn new(particles: ParticleSystem, integrator: Integrator, dt: f64) -> Result<Self> {
        require_positive("dt", dt)?;
        let n = particles.system().len();
        let zeros = State::zeros(n);
        Ok(Self {
            particles,
            integrator,
            h: dt,
            f: vec![Vec3::zeros(); n],
            k: std::array::from_fn(|_| zeros.clone()),
            stage: zeros,
        })
    }

    /// The particle system being advanced.
    pub fn particles(&self) -> &ParticleSystem {
        &self.particles
    }

    /// The integrator.
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Explicit Euler: $`x_{n+1} = x_n + h\,v_n`$, $`v_{n+1} = v_n + h\,f(x_n, v_n)/m`$.
    fn explicit_euler(&mut self, y: &mut State) {
        let [k1, ..] = &mut self.k;
        self.particles.derivative(y, &mut self.f, k1);
        axpy(y, self.h, k1);
    }

    /// Symplectic Euler: $`v_{n+1} = v_n + h\,f(x_n, v_n)/m`$, then $`x_{n+1} = x_n + h\,v_{n+1}`$
    /// (the new velocity moves the particle; anchored particles have zero derivative and stay).
    fn symplectic_euler(&mut self, y: &mut State) {
        let [k1, ..] = &mut self.k;
        self.particles.derivative(y, &mut self.f, k1);
        for (i, node) in self.particles.system().nodes().iter().enumerate() {
            if !node.fixed {
                y.v[i] += self.h * k1.v[i];
                y.x[i] += self.h * y.v[i];
            }
        }
    }

    /// Classic RK4: $`k_1 = F(y)`$, $`k_2 = F(y + \frac h2 k_1)`$, $`k_3 = F(y + \frac h2 k_2)`$,
    /// $`k_4 = F(y + h\,k_3)`$, $`y_{n+1} = y_n + \frac h6(k_1 + 2k_2 + 2k_3 + k_4)`$ (the forces
    /// do not depend on $`t`$).
    fn rk4(&mut self, y: &mut State) {
        let h = self.h;
        self.particles.derivative(y, &mut self.f, &mut self.k[0]);
        for (s, weight) in [0.5 * h, 0.5 * h, h].into_iter().enumerate() {
            let (done, next) = self.k.split_at_mut(s + 1);
            self.stage.clone_from(y);
            axpy(&mut self.stage, weight, &done[s]);
            self.particles
                .derivative(&self.stage, &mut self.f, &mut next[0]);
        }
        for (k, weight) in self.k.iter().zip([1.0, 2.0, 2.0, 1.0]) {
            axpy(y, weight * h / 6.0, k);
        }
    }
}

/// $`y \leftarrow y + a\,d`$ for a state and a derivative.
pub(super) fn axpy(y: &mut State, a: f64, d: &State) {
    for (x, dx) in y.x.iter_mut().zip(&d.x) {
        *x += a * dx;
    }
    for (v, dv) in y.v.iter_mut().zip(&d.v) {
        *v += a * dv;
    }
}

impl TimeStepper for ParticleStepper {
    fn name(&self) -> String {
        format!("{} (particle system)", self.integrator)
    }

    fn dt(&self) -> f64 {
        self.h
    }

    fn system(&self) -> &MassSpringSystem {
        self.particles.system()
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        match self.integrator {
            Integrator::ExplicitEuler => self.explicit_euler(state),
            Integrator::SymplecticEuler => self.symplectic_euler(state),
            Integrator::Rk4 => self.rk4(state),
        }
        self.particles.resolve_contacts(state);
        Ok(())
    }
}

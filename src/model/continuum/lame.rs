//! The one conversion from Young's modulus and Poisson's ratio to the Lamé parameters
//! (`docs/fem-scenes.md`, "Conventions"), in 3D and in plane stress.

use crate::error::{require_positive, shown, Error, Result};

/// How the material is loaded: a solid (tets), or a sheet in plane stress (membranes in 3D,
/// Cook's membrane in the plane), whose through-thickness stress is zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Loading {
    Solid,
    PlaneStress,
}

/// The Lamé parameters μ (shear modulus) and λ of an isotropic material, Pa (N/m for a
/// membrane, whose (Y = E·t, ν) enter per unit rest area).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lame {
    pub mu: f64,
    pub lambda: f64,
}

impl Lame {
    /// [Sifakis 2012, Lamé parameters] (unverified; no reference code checked: the standard relations as docs/fem-scenes.md states them)
    /// μ = E / (2(1 + ν)), λ = Eν / ((1 + ν)(1 − 2ν)) for a solid; in plane stress
    /// λ* = 2λμ / (λ + 2μ) = Eν / (1 − ν²), written in that closed form so that it stays finite
    /// as ν → 0.5 (where the solid's λ does not).
    ///
    /// Refuses E ≤ 0 (or not finite), ν ≥ 0.5 (incompressible: λ is infinite in 3D, and the
    /// scenes' elements lock) and ν ≤ −1 (μ negative or infinite), naming the field.
    pub fn from_youngs_poisson(youngs: f64, poisson: f64, loading: Loading) -> Result<Self> {
        require_positive("youngs_modulus", youngs)?;
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(Error::invalid(
                "poisson_ratio",
                shown(poisson),
                "a number in (-1, 0.5), both ends excluded",
            ));
        }
        let mu = youngs / (2.0 * (1.0 + poisson));
        let lambda = match loading {
            Loading::Solid => youngs * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
            Loading::PlaneStress => youngs * poisson / (1.0 - poisson * poisson),
        };
        Ok(Self { mu, lambda })
    }
}

//! The five energies of `docs/fem-scenes.md`, one module each, behind
//! [`Hyperelastic`](super::hyperelastic::Hyperelastic), and their names.

use super::hyperelastic::Hyperelastic;
use crate::error::{Error, Result};

mod arap;
mod corotated;
mod linear;
mod stable_neo_hookean;
mod stvk;

pub use arap::Arap;
pub use corotated::Corotated;
pub use linear::Linear;
pub use stable_neo_hookean::StableNeoHookean;
pub use stvk::StVenantKirchhoff;

/// An energy by name: what a scene's element and the command line choose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EnergyKind {
    Linear,
    Arap,
    Corotated,
    StVenantKirchhoff,
    StableNeoHookean,
}

impl EnergyKind {
    /// Every energy, in the order of fem-scenes.md's table.
    pub const ALL: [EnergyKind; 5] = [
        EnergyKind::Linear,
        EnergyKind::Arap,
        EnergyKind::Corotated,
        EnergyKind::StVenantKirchhoff,
        EnergyKind::StableNeoHookean,
    ];

    /// The energy's implementation.
    pub fn model(self) -> &'static dyn Hyperelastic {
        match self {
            EnergyKind::Linear => &Linear,
            EnergyKind::Arap => &Arap,
            EnergyKind::Corotated => &Corotated,
            EnergyKind::StVenantKirchhoff => &StVenantKirchhoff,
            EnergyKind::StableNeoHookean => &StableNeoHookean,
        }
    }

    /// Its name (`stable-neo-hookean`).
    pub fn name(self) -> &'static str {
        self.model().name()
    }

    /// The energy called `name` (a name of [`Self::ALL`]), else an error listing them.
    pub fn parse(field: &str, name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|e| e.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|e| e.name()).collect();
                Error::invalid(field, name, &format!("one of {}", names.join(", ")))
            })
    }
}

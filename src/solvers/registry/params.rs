//! A solver's options beyond its time step and iteration count ([`SolverParams`]), each checked
//! against its range.

use super::SolverId;
use crate::error::{require_within, shown, Error, Result};
use crate::integrators::damping::RayleighDamping;
use crate::integrators::dissipation::{
    Dissipation, PowerLawDrag, RayleighForm, DRAG_UNIT, MAX_DRAG,
};
use crate::integrators::first_iterate::FirstIterate;
use crate::integrators::optimization_integrator::OptimizationIntegrator;
use crate::solvers::anderson::AndersonParams;
use crate::solvers::chebyshev::{ChebyshevParams, RhoRule};
use crate::solvers::local_global::{AdmmMerit, Base};
use crate::solvers::quasi_newton::LbfgsParams;
use crate::solvers::vbd::{LocalHessian, VbdParams};
use crate::solvers::xpbd_substeps::{Sweep, XpbdSubstepsParams, MAX_CONSTRAINT_DAMPING};

/// The options of the solvers that have any; each solver reads its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverParams {
    /// PBD: the dimensionless factor in [0, 1] scaling each constraint's correction.
    pub stiffness_factor: f64,
    /// rk45: the error tolerance of each adaptive step.
    pub tolerance: f64,
    /// Chebyshev: the base iteration's spectral radius; None: estimated on the scene.
    pub spectral_radius: Option<f64>,
    /// Chebyshev: the under-relaxation.
    pub gamma: f64,
    /// Chebyshev: the warm-up iterations.
    pub warmup: usize,
    /// Anderson: the window.
    pub window: usize,
    /// The damped solvers: Rayleigh damping.
    pub damping: RayleighDamping,
    /// L-BFGS: the window (pairs kept).
    pub history: usize,
    /// Every solver iterating on the incremental potential: where each step starts; None:
    /// the solver's own start (its paper's or the thesis's).
    pub first_iterate: Option<FirstIterate>,
    /// Chebyshev: how the spectral radius is found when not given.
    pub rho_rule: RhoRule,
    /// Anderson on ADMM: the safeguard's merit.
    pub safeguard: AdmmMerit,
    /// VBD: the local Hessian rule.
    pub hessian: LocalHessian,
    /// XPBD substeps: Macklin 2019's constraint damping, N·s/m.
    pub constraint_damping: f64,
    /// XPBD substeps: the constraint pass.
    pub sweep: Sweep,
    /// rk45: the most adaptive steps (accepted or rejected) a run may attempt, a work budget;
    /// None: no limit.
    pub adaptive_attempts: Option<u64>,
    /// Every minimizing solver: the optimization integrator.
    pub integrator: OptimizationIntegrator,
    /// The dissipative solvers: the form of their Rayleigh damping.
    pub rayleigh_form: RayleighForm,
    /// The dissipative solvers: power-law drag.
    pub drag: PowerLawDrag,
}

impl SolverParams {
    /// The option `name` (an [`OptionInfo::name`](super::OptionInfo::name)) as text; None for an unset optional value
    /// or a name no solver has.
    pub fn get(&self, name: &str) -> Option<String> {
        Some(match name {
            "stiffness_factor" => self.stiffness_factor.to_string(),
            "tolerance" => self.tolerance.to_string(),
            "spectral_radius" => self.spectral_radius?.to_string(),
            "gamma" => self.gamma.to_string(),
            "warmup" => self.warmup.to_string(),
            "window" => self.window.to_string(),
            "alpha" => self.damping.alpha.to_string(),
            "beta" => self.damping.beta.to_string(),
            "history" => self.history.to_string(),
            "first_iterate" => self.first_iterate?.key().to_string(),
            "rho_rule" => self.rho_rule.key().to_string(),
            "safeguard" => self.safeguard.key().to_string(),
            "hessian" => self.hessian.key().to_string(),
            "constraint_damping" => self.constraint_damping.to_string(),
            "sweep" => self.sweep.key().to_string(),
            "integrator" => self.integrator.key().to_string(),
            "rayleigh_form" => self.rayleigh_form.key().to_string(),
            "drag" => self.drag.coefficient.to_string(),
            "drag_exponent" => self.drag.exponent.to_string(),
            _ => return None,
        })
    }

    /// Sets the option `name` (an [`OptionInfo::name`](super::OptionInfo::name)) from its text, checked against its
    /// range by the solver that reads it.
    pub fn set(&mut self, name: &str, value: &str) -> Result<()> {
        let number = || -> Result<f64> {
            value
                .parse()
                .map_err(|_| Error::invalid(name, value, "a number"))
        };
        match name {
            "stiffness_factor" => {
                self.stiffness_factor = crate::solvers::pbd::require_factor(name, number()?)?;
            }
            "tolerance" => {
                self.tolerance = require_within(name, number()?, 1e-12, 0.1, TOLERANCE_UNIT)?
            }
            "spectral_radius" => self.spectral_radius = Some(number()?),
            "gamma" => self.gamma = number()?,
            "warmup" => self.warmup = require_count_within(name, number()?, 0, u32::MAX as usize)?,
            "window" => self.window = require_integer(name, number()?, 1)?,
            "alpha" => self.damping.alpha = require_within(name, number()?, 0.0, 1e6, "1/s")?,
            "beta" => self.damping.beta = require_within(name, number()?, 0.0, 1e3, "s")?,
            "history" => self.history = require_count_within(name, number()?, 1, MAX_HISTORY)?,
            "first_iterate" => self.first_iterate = Some(value.parse()?),
            "rho_rule" => self.rho_rule = value.parse()?,
            "safeguard" => self.safeguard = value.parse()?,
            "hessian" => self.hessian = value.parse()?,
            "constraint_damping" => {
                self.constraint_damping =
                    require_within(name, number()?, 0.0, MAX_CONSTRAINT_DAMPING, "N·s/m")?
            }
            "sweep" => self.sweep = value.parse()?,
            "integrator" => self.integrator = value.parse()?,
            "rayleigh_form" => self.rayleigh_form = value.parse()?,
            "drag" => {
                self.drag.coefficient = require_within(name, number()?, 0.0, MAX_DRAG, DRAG_UNIT)?
            }
            "drag_exponent" => self.drag.exponent = number()?,
            _ => {
                let names: Vec<&str> = SolverId::ALL
                    .iter()
                    .flat_map(|s| s.info().options.iter().map(|o| o.name))
                    .collect();
                return Err(Error::invalid(
                    "option",
                    name,
                    &format!("one of {}", names.join(", ")),
                ));
            }
        }
        self.chebyshev(Base::Liu).validate()?;
        self.anderson(Base::Liu).validate()?;
        self.lbfgs().validate()?;
        self.xpbd_substeps().validate()?;
        self.dissipation().validate()
    }

    /// The dissipation of the dissipative solvers.
    pub fn dissipation(&self) -> Dissipation {
        Dissipation {
            rayleigh: self.damping,
            form: self.rayleigh_form,
            drag: self.drag,
        }
    }

    /// The first iterate set, or `own`.
    pub fn first_iterate_or(&self, own: FirstIterate) -> FirstIterate {
        self.first_iterate.unwrap_or(own)
    }

    /// The parameters of VBD.
    pub fn vbd(&self) -> VbdParams {
        let own = VbdParams::default();
        VbdParams {
            first_iterate: self.first_iterate_or(own.first_iterate),
            hessian: self.hessian,
        }
    }

    /// The parameters of XPBD with substeps (one iteration per substep).
    pub fn xpbd_substeps(&self) -> XpbdSubstepsParams {
        XpbdSubstepsParams {
            constraint_damping: self.constraint_damping,
            sweep: self.sweep,
            ..XpbdSubstepsParams::default()
        }
    }

    /// The parameters of L-BFGS (its line search at the defaults).
    pub fn lbfgs(&self) -> LbfgsParams {
        LbfgsParams {
            window: self.history,
            ..LbfgsParams::default()
        }
    }

    /// The parameters of Chebyshev acceleration of `base`.
    pub fn chebyshev(&self, base: Base) -> ChebyshevParams {
        let own = ChebyshevParams::default();
        ChebyshevParams {
            base,
            spectral_radius: self.spectral_radius,
            rho_rule: self.rho_rule,
            gamma: self.gamma,
            warmup: self.warmup,
            first_iterate: self.first_iterate_or(own.first_iterate),
        }
    }

    /// The parameters of Anderson acceleration of `base`.
    pub fn anderson(&self, base: Base) -> AndersonParams {
        let own = AndersonParams::default();
        AndersonParams {
            base,
            window: self.window,
            safeguard: self.safeguard,
            first_iterate: self.first_iterate_or(own.first_iterate),
        }
    }
}

/// The largest L-BFGS window the command line takes (Liu 2017 keeps 5 pairs).
pub const MAX_HISTORY: usize = 100;

/// What rk45's tolerance is relative to.
const TOLERANCE_UNIT: &str = "m and m/s, relative to 1 + |component|";

/// `value` as a count: a whole number at least `min`.
fn require_integer(field: &str, value: f64, min: usize) -> Result<usize> {
    if value.is_finite() && value.fract() == 0.0 && value >= min as f64 && value <= u32::MAX as f64
    {
        Ok(value as usize)
    } else {
        Err(Error::invalid(
            field,
            shown(value),
            &format!("an integer >= {min}"),
        ))
    }
}

/// `value` as a count from `min` to `max`.
fn require_count_within(field: &str, value: f64, min: usize, max: usize) -> Result<usize> {
    if value.is_finite() && value.fract() == 0.0 && (min as f64..=max as f64).contains(&value) {
        Ok(value as usize)
    } else {
        Err(Error::invalid(
            field,
            shown(value),
            &format!("an integer from {min} to {max}"),
        ))
    }
}

impl Default for SolverParams {
    fn default() -> Self {
        let chebyshev = ChebyshevParams::default();
        Self {
            stiffness_factor: 1.0,
            tolerance: 1e-6,
            spectral_radius: chebyshev.spectral_radius,
            gamma: chebyshev.gamma,
            warmup: chebyshev.warmup,
            window: AndersonParams::default().window,
            damping: RayleighDamping::NONE,
            history: LbfgsParams::default().window,
            first_iterate: None,
            rho_rule: chebyshev.rho_rule,
            safeguard: AndersonParams::default().safeguard,
            hessian: VbdParams::default().hessian,
            constraint_damping: XpbdSubstepsParams::default().constraint_damping,
            sweep: XpbdSubstepsParams::default().sweep,
            adaptive_attempts: None,
            integrator: OptimizationIntegrator::default(),
            rayleigh_form: RayleighForm::default(),
            drag: PowerLawDrag::NONE,
        }
    }
}

//! The analytic catenary against the Newton rest state (§3.1, Figure 2): the exact static
//! equilibrium of the discrete elastic chain beside the final state of our Backward Euler
//! reference.

use crate::format::{sig, sig4, MarkdownTable};
use crate::tables::stiffness_label;
use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::model::catenary::ElasticChain;
use mass_spring_solvers::model::scene::THESIS_STIFFNESSES;
use mass_spring_solvers::model::system::Vec3;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::ResultSet;

/// The exact discrete-chain equilibrium of the thesis rope per stiffness.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Catenary {
    rest: Vec<(f64, Vec<Vec3>)>,
}

impl Catenary {
    /// The equilibrium at both thesis stiffnesses.
    pub fn compute() -> Result<Self> {
        let mut rest = Vec::new();
        for k in THESIS_STIFFNESSES {
            rest.push((k, exact_discrete_rest_state(k)?));
        }
        Ok(Self { rest })
    }

    /// The node positions at stiffness `k`, if available.
    pub fn analytic(&self, k: f64) -> Option<&[Vec3]> {
        self.rest
            .iter()
            .find(|(s, _)| *s == k)
            .map(|(_, n)| n.as_slice())
    }

    /// Every (stiffness, nodes).
    pub fn all(&self) -> impl Iterator<Item = (f64, &[Vec3])> {
        self.rest.iter().map(|(k, n)| (*k, n.as_slice()))
    }
}

/// The exact static equilibrium of the thesis rope at stiffness `k`: the discrete elastic
/// chain of [`mass_spring_solvers::model::catenary`], solved to machine precision.
fn exact_discrete_rest_state(k: f64) -> Result<Vec<Vec3>> {
    ElasticChain::thesis_rope(k)
        .and_then(|chain| chain.solve_equilibrium())
        .map(|equilibrium| equilibrium.positions)
        .map_err(|e| Error::Input(format!("exact catenary at k = {k} N/m: {e}")))
}

/// The comparison of Section "Analytic catenary": per stiffness and node, the analytic and
/// the Newton rest positions and their distance; and a summary line per stiffness.
pub fn comparison(results: &ResultSet, catenary: &Catenary) -> String {
    let mut out = String::new();
    let mut summary = MarkdownTable::new(&[
        ">k (N/m)",
        ">lowest node, analytic (m)",
        ">sum of distances (m)",
        ">max distance (m)",
        ">last peak energy of the run (J)",
        ">expected residual amplitude (m)",
        ">amplitude / max distance",
    ]);
    let mut details = String::new();
    for k in THESIS_STIFFNESSES {
        let Some(reference) = results
            .rows
            .iter()
            .find(|m| m.published.solver == SolverId::BackwardEuler && m.published.stiffness == k)
        else {
            continue;
        };
        let Some(exact) = catenary.analytic(k) else {
            continue;
        };
        let distances: Vec<f64> = exact
            .iter()
            .zip(&reference.final_positions)
            .map(|(a, b)| (a - b).norm())
            .collect();
        let lowest = exact.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        // A residual oscillation of kinetic energy E over the free mass M at angular frequency
        // ω = π/(T/2) has amplitude √(2E/M)/ω.
        let free_mass = (exact.len().saturating_sub(2)) as f64
            * mass_spring_solvers::model::scene::THESIS_NODE_MASS;
        let amplitude = reference
            .last_peak_energy
            .zip(reference.half_period_exact)
            .map(|(e, half)| (2.0 * e / free_mass).sqrt() * half / std::f64::consts::PI);
        summary.row(vec![
            stiffness_label(k),
            sig4(lowest),
            sig4(distances.iter().sum()),
            sig4(distances.iter().copied().fold(0.0, f64::max)),
            reference.last_peak_energy.map_or("–".into(), sig4),
            amplitude.map_or("–".into(), sig4),
            amplitude.map_or("–".into(), |a| {
                sig(a / distances.iter().copied().fold(0.0, f64::max), 2)
            }),
        ]);
        let mut t = MarkdownTable::new(&[
            ">node",
            ">x analytic (m)",
            ">y analytic (m)",
            ">x Newton (m)",
            ">y Newton (m)",
            ">distance (m)",
        ]);
        for (i, ((a, b), d)) in exact
            .iter()
            .zip(&reference.final_positions)
            .zip(&distances)
            .enumerate()
        {
            t.row(vec![
                i.to_string(),
                sig(a.x, 7),
                sig(a.y, 7),
                sig(b.x, 7),
                sig(b.y, 7),
                sig4(*d),
            ]);
        }
        details += &format!("\n**k = {}**\n\n{}", stiffness_label(k), t.render());
    }
    if summary.is_empty() {
        out += "_The Backward Euler reference was not run._\n";
    } else {
        out += &summary.render();
        out += &details;
    }
    out
}

//! The thesis's question, as it asks it ([`super`], item 6 of its specification): its
//! conclusions (§4.4 and §5) decided from the benchmark's rows at matched cost.
//!
//! A **cell** is a case and an accuracy level: for dynamics a relative physical error (the
//! RMS per node over the exact motion's amplitude, [`DYNAMICS_LEVELS`]), for statics an RMS
//! distance to the exact equilibrium of a run the thesis's rule stopped
//! ([`STATICS_LEVELS_M`]). In a cell each of the thesis's three solvers costs the flops of its
//! cheapest configuration that reaches the level; the **winners** are the solvers within
//! [`TIE`] of the cheapest (costs closer than that are ties). A cell no solver reaches decides
//! nothing. The thesis's solvers run under its own scheme (Backward Euler for Liu 2013 and
//! ADMM) at fixed iteration counts, as the thesis ran them.

use super::rows::Row;
use crate::solvers::registry::SolverId;

/// The thesis's three solvers.
pub const THESIS_THREE: [SolverId; 3] =
    [SolverId::Xpbd, SolverId::FastMassSpring, SolverId::AdmmPd];

/// The dynamics levels: relative physical errors of 10 %, 1 % and 0.1 %.
pub const DYNAMICS_LEVELS: [f64; 3] = [0.1, 0.01, 0.001];

/// The statics levels: RMS distances to the exact equilibrium, m.
pub const STATICS_LEVELS_M: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// Costs within this fraction of the cheapest are ties.
pub const TIE: f64 = 0.1;

/// Dynamics or statics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Regime {
    Dynamics,
    Statics,
}

impl Regime {
    pub fn levels(self) -> &'static [f64] {
        match self {
            Regime::Dynamics => &DYNAMICS_LEVELS,
            Regime::Statics => &STATICS_LEVELS_M,
        }
    }

    /// A row's accuracy in this regime, if it reaches it: the relative physical error, or the
    /// rest error of a run at rest.
    pub fn accuracy(self, row: &Row) -> Option<f64> {
        if !row.finished() {
            return None;
        }
        match self {
            Regime::Dynamics => (row.kind == "dynamics")
                .then_some(row.physical_rel)
                .flatten(),
            Regime::Statics => (row.kind == "statics" && row.at_rest == Some(true))
                .then_some(row.rest_error_rms_m)
                .flatten(),
        }
    }
}

/// The flops of `solver`'s cheapest configuration in `rows` (one case's) that reaches `level`.
pub fn cheapest(rows: &[&Row], regime: Regime, solver: SolverId, level: f64) -> Option<f64> {
    rows.iter()
        .filter(|r| r.solver == solver.id() && r.thesis_scheme() && r.count_mode())
        .filter(|r| regime.accuracy(r).is_some_and(|a| a <= level))
        .filter_map(|r| r.flops)
        .min_by(f64::total_cmp)
}

/// The winners of a cell among `solvers` (within [`TIE`] of the cheapest), with every
/// solver's cost; empty winners when none reaches the level.
pub fn winners(
    rows: &[&Row],
    regime: Regime,
    level: f64,
    solvers: &[SolverId],
) -> (Vec<SolverId>, Vec<(SolverId, Option<f64>)>) {
    let costs: Vec<(SolverId, Option<f64>)> = solvers
        .iter()
        .map(|&s| (s, cheapest(rows, regime, s, level)))
        .collect();
    let best = costs.iter().filter_map(|(_, c)| *c).min_by(f64::total_cmp);
    let winners = match best {
        None => Vec::new(),
        Some(best) => costs
            .iter()
            .filter(|(_, c)| c.is_some_and(|c| c <= (1.0 + TIE) * best))
            .map(|(s, _)| *s)
            .collect(),
    };
    (winners, costs)
}

/// What the data says of a conclusion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Verdict {
    Holds,
    Fails,
    Undecided,
}

impl Verdict {
    pub fn id(self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::Fails => "fails",
            Verdict::Undecided => "undecided",
        }
    }
}

/// One of the thesis's conclusions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Conclusion {
    /// §4.4.1, §5: for statics the Projective-Dynamics methods (Liu 2013, ADMM) are best.
    StaticsProjectiveDynamics,
    /// §5: ... with ADMM preferred for its versatility.
    StaticsAdmmVersatile,
    /// §4.4.2, §5: no method stands out in dynamics.
    DynamicsNoneStandsOut,
    /// §5: Liu 2013 is worse than ADMM and XPBD in dynamics.
    DynamicsLiuWorse,
    /// §5: XPBD for dynamics.
    DynamicsXpbd,
    /// §5: ADMM for both statics and dynamics.
    AdmmForBoth,
}

impl Conclusion {
    /// The conclusion in a few words.
    pub fn label(self) -> &'static str {
        match self {
            Conclusion::StaticsProjectiveDynamics => {
                "statics: the Projective-Dynamics methods (Fast m-s, ADMM) are best"
            }
            Conclusion::StaticsAdmmVersatile => "statics: ADMM preferred, for its versatility",
            Conclusion::DynamicsNoneStandsOut => "dynamics: no method stands out",
            Conclusion::DynamicsLiuWorse => "dynamics: Fast m-s is worse than ADMM and XPBD",
            Conclusion::DynamicsXpbd => "dynamics: XPBD is the method to use",
            Conclusion::AdmmForBoth => "ADMM for both statics and dynamics",
        }
    }

    /// What its verdict rests on.
    pub fn criterion(self) -> &'static str {
        match self {
            Conclusion::StaticsProjectiveDynamics => {
                "holds if every statics cell's winners are Fast m-s or ADMM; fails if XPBD alone wins one"
            }
            Conclusion::StaticsAdmmVersatile => {
                "versatility (other materials, constraints) is not what the benchmark measures"
            }
            Conclusion::DynamicsNoneStandsOut => {
                "fails if one solver alone is cheapest in every dynamics cell"
            }
            Conclusion::DynamicsLiuWorse => "holds if Fast m-s is among the winners of no dynamics cell",
            Conclusion::DynamicsXpbd => "holds if XPBD is among the winners of every dynamics cell",
            Conclusion::AdmmForBoth => {
                "holds if ADMM is among the winners of every statics and dynamics cell"
            }
        }
    }
}

impl Conclusion {
    pub const ALL: [Conclusion; 6] = [
        Conclusion::StaticsProjectiveDynamics,
        Conclusion::StaticsAdmmVersatile,
        Conclusion::DynamicsNoneStandsOut,
        Conclusion::DynamicsLiuWorse,
        Conclusion::DynamicsXpbd,
        Conclusion::AdmmForBoth,
    ];

    /// The regimes whose cells decide it (none for versatility, which the benchmark does not
    /// measure).
    pub fn regimes(self) -> &'static [Regime] {
        match self {
            Conclusion::StaticsProjectiveDynamics => &[Regime::Statics],
            Conclusion::StaticsAdmmVersatile => &[],
            Conclusion::DynamicsNoneStandsOut
            | Conclusion::DynamicsLiuWorse
            | Conclusion::DynamicsXpbd => &[Regime::Dynamics],
            Conclusion::AdmmForBoth => &[Regime::Statics, Regime::Dynamics],
        }
    }

    /// The verdict from the winners of every decided cell (cells with at least one winner).
    pub fn decide(self, cells: &[Vec<SolverId>]) -> Verdict {
        let decided: Vec<&Vec<SolverId>> = cells.iter().filter(|w| !w.is_empty()).collect();
        if decided.is_empty() || self == Conclusion::StaticsAdmmVersatile {
            return Verdict::Undecided;
        }
        let pd = |w: &Vec<SolverId>| {
            w.iter()
                .all(|s| matches!(s, SolverId::FastMassSpring | SolverId::AdmmPd))
        };
        let holds_in_all = |test: &dyn Fn(&Vec<SolverId>) -> bool| decided.iter().all(|w| test(w));
        match self {
            Conclusion::StaticsProjectiveDynamics => {
                if holds_in_all(&|w| pd(w)) {
                    Verdict::Holds
                } else if decided.iter().any(|w| w.as_slice() == [SolverId::Xpbd]) {
                    Verdict::Fails
                } else {
                    Verdict::Undecided
                }
            }
            Conclusion::DynamicsNoneStandsOut => {
                // One solver alone cheapest in every decided cell stands out.
                let alone: Vec<Option<SolverId>> = decided
                    .iter()
                    .map(|w| (w.len() == 1).then(|| w[0]))
                    .collect();
                let stands_out = alone[0].is_some() && alone.iter().all(|a| *a == alone[0]);
                if decided.len() < 2 {
                    Verdict::Undecided
                } else if stands_out {
                    Verdict::Fails
                } else {
                    Verdict::Holds
                }
            }
            Conclusion::DynamicsLiuWorse => {
                if holds_in_all(&|w| !w.contains(&SolverId::FastMassSpring)) {
                    Verdict::Holds
                } else {
                    Verdict::Fails
                }
            }
            Conclusion::DynamicsXpbd => {
                if holds_in_all(&|w| w.contains(&SolverId::Xpbd)) {
                    Verdict::Holds
                } else {
                    Verdict::Fails
                }
            }
            Conclusion::AdmmForBoth => {
                if holds_in_all(&|w| w.contains(&SolverId::AdmmPd)) {
                    Verdict::Holds
                } else {
                    Verdict::Fails
                }
            }
            Conclusion::StaticsAdmmVersatile => Verdict::Undecided,
        }
    }
}

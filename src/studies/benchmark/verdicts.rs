//! The thesis's question at matched cost ([`super`], item 6 of its specification): its
//! conclusions (§4.4 and §5) decided from the benchmark's rows, each by a rule written from
//! the sentence it decides.
//!
//! A **cell** is a case and an accuracy level: for dynamics a relative physical error (the
//! RMS per node over the exact motion's amplitude, [`DYNAMICS_LEVELS`]), for statics an RMS
//! distance to the exact equilibrium of a run the thesis's rule stopped
//! ([`STATICS_LEVELS_M`]). In a cell each of the thesis's three solvers costs the flops of its
//! cheapest configuration that reaches the level, at fixed iteration counts, from the one start
//! of the benchmark; a cell no solver reaches decides nothing. Solver `a` **beats** `b` in a
//! cell when `a` reaches it and `b` either does not or costs more than $`(1 + t)`$ times `a`'s
//! cost, $`t`$ the tie; the **winners** of a cell are the solvers no other beats.
//!
//! Each rule is decided under every [`Setting`]: the ties of [`TIES`], set by issue 47 (with
//! the earlier benchmark's results known), the integrators a minimizing solver may use ([`Schemes`]: the thesis's
//! Backward Euler, or the best of the four; XPBD keeps its own scheme in both), and what a
//! cost counts ([`Measure`]: counted flops, or wall time where a measurement exists). A conclusion
//! **holds** or **fails** only where every setting agrees; otherwise it *depends on* the
//! setting that moves it ([`Overall`]).

use super::rows::Row;
use crate::solvers::registry::SolverId;

/// The thesis's three solvers.
pub const THESIS_THREE: [SolverId; 3] =
    [SolverId::Xpbd, SolverId::FastMassSpring, SolverId::AdmmPd];

/// The dynamics levels: relative physical errors of 10 %, 1 % and 0.1 %.
pub const DYNAMICS_LEVELS: [f64; 3] = [0.1, 0.01, 0.001];

/// The statics levels: RMS distances to the exact equilibrium, m.
pub const STATICS_LEVELS_M: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// The ties of the sensitivity: costs within this fraction of each other are ties.
pub const TIES: [f64; 3] = [0.1, 0.25, 0.5];

/// The tie of the tables that show one (the smallest of [`TIES`]).
pub const TIE: f64 = TIES[0];

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

/// The integrators a minimizing solver's configurations may use in a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Schemes {
    /// The thesis's Backward Euler only.
    BackwardEuler,
    /// The best of the four (Backward Euler, implicit midpoint, BDF2, TR-BDF2).
    AllFour,
}

impl Schemes {
    pub const ALL: [Schemes; 2] = [Schemes::BackwardEuler, Schemes::AllFour];

    /// For prose and table headers.
    pub fn label(self) -> &'static str {
        match self {
            Schemes::BackwardEuler => "Backward Euler only",
            Schemes::AllFour => "best of the four integrators",
        }
    }

    /// Whether a row's integrator is admitted (a solver with its own scheme always is).
    pub fn admits(self, row: &Row) -> bool {
        match self {
            Schemes::BackwardEuler => row.thesis_scheme(),
            Schemes::AllFour => true,
        }
    }
}

/// What a cell's costs count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Measure {
    /// The benchmark's counted floating-point operations.
    Flops,
    /// Wall time, as a measurement of `make timing` gives it: the least of its batch means
    /// (the science layer never times: the caller supplies each row's).
    WallTime,
    /// The same measurement's largest batch mean: with [`Measure::WallTime`], the verdicts'
    /// sensitivity to the timing's own spread.
    WallTimeSlowest,
}

impl Measure {
    pub const ALL: [Measure; 3] = [Measure::Flops, Measure::WallTime, Measure::WallTimeSlowest];

    /// A short column label.
    pub fn short(self) -> &'static str {
        match self {
            Measure::Flops => "flops",
            Measure::WallTime => "wall",
            Measure::WallTimeSlowest => "wall, slowest",
        }
    }

    /// What it counts, for prose.
    pub fn label(self) -> &'static str {
        match self {
            Measure::Flops => "counted flops",
            Measure::WallTime => "wall time (the least batch mean)",
            Measure::WallTimeSlowest => "wall time (the largest batch mean)",
        }
    }
}

/// A row's cost under one [`Measure`] (None: not measured).
pub type CostOf<'c> = &'c dyn Fn(&Row) -> Option<f64>;

/// A row's counted flops.
pub fn flops(row: &Row) -> Option<f64> {
    row.flops
}

/// `solver`'s cheapest configuration in `rows` (one case's) that reaches `level` under
/// `schemes`, at fixed iteration counts, by counted flops.
pub fn cheapest<'a>(
    rows: &[&'a Row],
    regime: Regime,
    solver: SolverId,
    level: f64,
    schemes: Schemes,
) -> Option<&'a Row> {
    cheapest_by(rows, regime, solver, level, schemes, &flops)
}

/// [`cheapest`] by the cost `cost` (a row it gives none is not a candidate).
pub fn cheapest_by<'a>(
    rows: &[&'a Row],
    regime: Regime,
    solver: SolverId,
    level: f64,
    schemes: Schemes,
    cost: CostOf,
) -> Option<&'a Row> {
    rows.iter()
        .copied()
        .filter(|r| r.solver == solver.id() && schemes.admits(r) && r.count_mode())
        .filter(|r| regime.accuracy(r).is_some_and(|a| a <= level))
        .filter_map(|r| cost(r).map(|c| (r, c)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(r, _)| r)
}

/// One cell: its regime and each solver's cheapest cost (None: not reached).
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    pub regime: Regime,
    pub costs: Vec<(SolverId, Option<f64>)>,
}

impl Cell {
    /// The cell of `rows` (one case's) at `level` among `solvers` under `schemes`, each
    /// solver's cost the least `cost` of its configurations that reach the level.
    pub fn of(
        rows: &[&Row],
        regime: Regime,
        level: f64,
        solvers: &[SolverId],
        schemes: Schemes,
        cost: CostOf,
    ) -> Self {
        Self {
            regime,
            costs: solvers
                .iter()
                .map(|&s| {
                    (
                        s,
                        cheapest_by(rows, regime, s, level, schemes, cost).and_then(cost),
                    )
                })
                .collect(),
        }
    }

    /// `solver`'s cost; None where it does not reach the level or is not in the cell.
    pub fn cost(&self, solver: SolverId) -> Option<f64> {
        self.costs
            .iter()
            .find(|(s, _)| *s == solver)
            .and_then(|(_, c)| *c)
    }

    /// Whether any solver reaches the level.
    pub fn decided(&self) -> bool {
        self.costs.iter().any(|(_, c)| c.is_some())
    }

    /// Whether `a` beats `b` at the tie `tie`: `a` reaches the level and `b` does not, or
    /// costs more than $`(1 + t)`$ times as much.
    pub fn beats(&self, a: SolverId, b: SolverId, tie: f64) -> bool {
        match (self.cost(a), self.cost(b)) {
            (Some(_), None) => true,
            (Some(ca), Some(cb)) => (1.0 + tie) * ca < cb,
            (None, _) => false,
        }
    }

    /// The solvers that reach the level and that no other beats at the tie `tie`.
    pub fn winners(&self, tie: f64) -> Vec<SolverId> {
        self.costs
            .iter()
            .filter(|(s, c)| {
                c.is_some() && !self.costs.iter().any(|(o, _)| self.beats(*o, *s, tie))
            })
            .map(|(s, _)| *s)
            .collect()
    }
}

/// What the data says of a conclusion under one setting.
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

    /// Holds if `holds`, else fails.
    pub(super) fn from_holds(holds: bool) -> Self {
        if holds {
            Verdict::Holds
        } else {
            Verdict::Fails
        }
    }
}

/// The thesis's time steps, s.
pub const THESIS_DTS: [f64; 3] = [0.1, 0.01, 0.001];

/// The real-time steps the thesis quotes, s: 1/24 s ("0.042") and 1/60 s ("0.017").
pub const REAL_TIME_DTS: [f64; 2] = [1.0 / 24.0, 1.0 / 60.0];

/// The thesis's time steps or the real-time ones (reading (a), [`super::thesis_protocol`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StepGroup {
    Thesis,
    RealTime,
}

impl StepGroup {
    pub const ALL: [StepGroup; 2] = [StepGroup::Thesis, StepGroup::RealTime];

    /// Its time steps, s.
    pub fn dts(self) -> &'static [f64] {
        match self {
            StepGroup::Thesis => &THESIS_DTS,
            StepGroup::RealTime => &REAL_TIME_DTS,
        }
    }

    /// A short column label.
    pub fn short(self) -> &'static str {
        match self {
            StepGroup::Thesis => "thesis dt",
            StepGroup::RealTime => "real-time dt",
        }
    }
}

/// What a setting admits besides its tie: the integrators of reading (b), the time steps of
/// reading (a) ([`super::thesis_protocol`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scope {
    Schemes(Schemes),
    /// The thesis's time steps (0.1, 0.01, 0.001 s), or the real-time ones it quotes.
    TimeSteps(StepGroup),
}

impl Scope {
    /// What a verdict that moves with the scope depends on.
    pub fn axis(self) -> &'static str {
        match self {
            Scope::Schemes(_) => "the integrators",
            Scope::TimeSteps(_) => "the time steps",
        }
    }

    /// A short column label.
    pub fn short(self) -> &'static str {
        match self {
            Scope::Schemes(Schemes::BackwardEuler) => "BE",
            Scope::Schemes(Schemes::AllFour) => "any",
            Scope::TimeSteps(g) => g.short(),
        }
    }
}

/// One setting of the sensitivity: a tie (or similarity tolerance), a scope and, for a
/// reading at matched cost, what the cost counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    pub tie: f64,
    pub scope: Scope,
    /// None for reading (a), which compares measured quantities, not costs.
    pub measure: Option<Measure>,
}

impl Setting {
    /// Every setting of `measures` × `scopes` × [`TIES`], in that order.
    pub fn grid(scopes: &[Scope], measures: &[Option<Measure>]) -> Vec<Setting> {
        measures
            .iter()
            .flat_map(|&measure| {
                scopes.iter().flat_map(move |&scope| {
                    TIES.map(|tie| Setting {
                        tie,
                        scope,
                        measure,
                    })
                })
            })
            .collect()
    }
}

/// A conclusion's verdict over every setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Overall {
    /// Every setting gives this verdict.
    Agreed(Verdict),
    /// The settings disagree: whether the verdict moves with the tie (the rest fixed), the
    /// axis of the scope if it moves with it (the rest fixed), and whether it moves with what
    /// the cost counts (the rest fixed).
    DependsOn {
        tie: bool,
        scope: Option<&'static str>,
        measure: bool,
    },
}

impl Overall {
    /// The verdicts of every setting, summed up.
    pub fn of(verdicts: &[(Setting, Verdict)]) -> Self {
        let Some(first) = verdicts.first().map(|(_, v)| *v) else {
            return Overall::Agreed(Verdict::Undecided);
        };
        if verdicts.iter().all(|(_, v)| *v == first) {
            return Overall::Agreed(first);
        }
        let moves = |same: &dyn Fn(&Setting, &Setting) -> bool| {
            verdicts
                .iter()
                .any(|(a, va)| verdicts.iter().any(|(b, vb)| same(a, b) && va != vb))
        };
        Overall::DependsOn {
            tie: moves(&|a, b| a.scope == b.scope && a.measure == b.measure),
            scope: moves(&|a, b| a.tie == b.tie && a.measure == b.measure)
                .then(|| verdicts[0].0.scope.axis()),
            measure: moves(&|a, b| a.tie == b.tie && a.scope == b.scope),
        }
    }

    /// `holds`, `fails`, `undecided`, or `depends on the tie and the integrators`.
    pub fn id(self) -> String {
        match self {
            Overall::Agreed(v) => v.id().into(),
            Overall::DependsOn {
                tie,
                scope,
                measure,
            } => {
                let on: Vec<&str> = [
                    tie.then_some("the tie"),
                    scope,
                    measure.then_some("flops against wall time"),
                ]
                .into_iter()
                .flatten()
                .collect();
                let last = on.len() - 1;
                let list = match last {
                    0 => on[0].to_string(),
                    _ => format!("{} and {}", on[..last].join(", "), on[last]),
                };
                format!("depends on {list}")
            }
        }
    }
}

/// A conclusion decided under every setting of one reading.
#[derive(Debug, Clone, PartialEq)]
pub struct Decided {
    pub conclusion: Conclusion,
    pub sensitivity: Vec<(Setting, Verdict)>,
    pub overall: Overall,
}

/// One of the thesis's conclusions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Conclusion {
    /// §4.4.1, §5: for statics the Projective-Dynamics methods (Liu 2013, ADMM) are best.
    StaticsProjectiveDynamics,
    /// §4.4.1: within that family there is no great difference.
    StaticsFamilyAlike,
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
    pub const ALL: [Conclusion; 7] = [
        Conclusion::StaticsProjectiveDynamics,
        Conclusion::StaticsFamilyAlike,
        Conclusion::StaticsAdmmVersatile,
        Conclusion::DynamicsNoneStandsOut,
        Conclusion::DynamicsLiuWorse,
        Conclusion::DynamicsXpbd,
        Conclusion::AdmmForBoth,
    ];

    /// The conclusion in a few words.
    pub fn label(self) -> &'static str {
        match self {
            Conclusion::StaticsProjectiveDynamics => {
                "statics: the Projective-Dynamics methods (Fast m-s, ADMM) are best"
            }
            Conclusion::StaticsFamilyAlike => {
                "statics: within that family (Fast m-s, ADMM) no great difference"
            }
            Conclusion::StaticsAdmmVersatile => "statics: ADMM preferred, for its versatility",
            Conclusion::DynamicsNoneStandsOut => "dynamics: no method stands out",
            Conclusion::DynamicsLiuWorse => "dynamics: Fast m-s is worse than ADMM and XPBD",
            Conclusion::DynamicsXpbd => "dynamics: XPBD is the method to use",
            Conclusion::AdmmForBoth => "ADMM for both statics and dynamics",
        }
    }

    /// The rule its verdict follows, as the report states it.
    pub fn criterion(self) -> &'static str {
        match self {
            Conclusion::StaticsProjectiveDynamics => {
                "holds if in every decided statics cell Fast m-s or ADMM beats XPBD; fails if XPBD ties or beats both in one"
            }
            Conclusion::StaticsFamilyAlike => {
                "holds if in every statics cell that Fast m-s or ADMM reaches neither beats the other; fails if one does"
            }
            Conclusion::StaticsAdmmVersatile => {
                "not decided here: versatility (other energies and constraints) is decided in the continuum chapter, where ADMM runs energies that PD cannot"
            }
            Conclusion::DynamicsNoneStandsOut => {
                "fails if one solver beats each of the other two in every decided dynamics cell; holds otherwise"
            }
            Conclusion::DynamicsLiuWorse => {
                "holds if ADMM beats Fast m-s in every cell either reaches and XPBD beats Fast m-s in every cell either reaches; fails if Fast m-s ties or beats either in one"
            }
            Conclusion::DynamicsXpbd => {
                "holds if no solver beats XPBD in any decided dynamics cell; fails if one does"
            }
            Conclusion::AdmmForBoth => {
                "holds if no solver beats ADMM in any decided statics or dynamics cell; fails if one does"
            }
        }
    }

    /// The regimes whose cells decide it (none for versatility, which the benchmark does not
    /// measure).
    pub fn regimes(self) -> &'static [Regime] {
        match self {
            Conclusion::StaticsProjectiveDynamics | Conclusion::StaticsFamilyAlike => {
                &[Regime::Statics]
            }
            Conclusion::StaticsAdmmVersatile => &[],
            Conclusion::DynamicsNoneStandsOut
            | Conclusion::DynamicsLiuWorse
            | Conclusion::DynamicsXpbd => &[Regime::Dynamics],
            Conclusion::AdmmForBoth => &[Regime::Statics, Regime::Dynamics],
        }
    }

    /// The verdict from `cells` (of any regime: each conclusion reads its own) at the tie
    /// `tie`.
    pub fn decide(self, cells: &[Cell], tie: f64) -> Verdict {
        use SolverId::{AdmmPd as Admm, FastMassSpring as Liu, Xpbd};
        let mine: Vec<&Cell> = cells
            .iter()
            .filter(|c| self.regimes().contains(&c.regime))
            .collect();
        // The cells where at least one of `solvers` reaches the level.
        let reached_by = |solvers: &[SolverId]| -> Vec<&Cell> {
            mine.iter()
                .copied()
                .filter(|c| solvers.iter().any(|&s| c.cost(s).is_some()))
                .collect()
        };
        let decided = reached_by(&THESIS_THREE);
        if decided.is_empty() {
            return Verdict::Undecided;
        }
        let in_every = |cells: &[&Cell], test: &dyn Fn(&Cell) -> bool| -> Verdict {
            if cells.is_empty() {
                Verdict::Undecided
            } else {
                Verdict::from_holds(cells.iter().all(|c| test(c)))
            }
        };
        match self {
            Conclusion::StaticsProjectiveDynamics => in_every(&decided, &|c| {
                c.beats(Liu, Xpbd, tie) || c.beats(Admm, Xpbd, tie)
            }),
            Conclusion::StaticsFamilyAlike => in_every(&reached_by(&[Liu, Admm]), &|c| {
                !c.beats(Liu, Admm, tie) && !c.beats(Admm, Liu, tie)
            }),
            Conclusion::StaticsAdmmVersatile => Verdict::Undecided,
            Conclusion::DynamicsNoneStandsOut => {
                let stands_out = THESIS_THREE.into_iter().any(|s| {
                    decided.iter().all(|c| {
                        THESIS_THREE
                            .into_iter()
                            .filter(|&o| o != s)
                            .all(|o| c.beats(s, o, tie))
                    })
                });
                Verdict::from_holds(!stands_out)
            }
            Conclusion::DynamicsLiuWorse => {
                let against = |other: SolverId| {
                    in_every(&reached_by(&[Liu, other]), &|c| c.beats(other, Liu, tie))
                };
                match (against(Admm), against(Xpbd)) {
                    (Verdict::Fails, _) | (_, Verdict::Fails) => Verdict::Fails,
                    (Verdict::Holds, Verdict::Holds) => Verdict::Holds,
                    _ => Verdict::Undecided,
                }
            }
            Conclusion::DynamicsXpbd => in_every(&decided, &|c| {
                !THESIS_THREE.into_iter().any(|o| c.beats(o, Xpbd, tie))
            }),
            Conclusion::AdmmForBoth => in_every(&decided, &|c| {
                !THESIS_THREE.into_iter().any(|o| c.beats(o, Admm, tie))
            }),
        }
    }

    /// The verdict under every setting of reading (b), each of `measures` and each scheme,
    /// from the cells `cells_of` gives for them.
    pub fn at_matched_cost(
        self,
        measures: &[Measure],
        cells_of: &dyn Fn(Schemes, Measure) -> Vec<Cell>,
    ) -> Decided {
        let sets: Vec<((Schemes, Measure), Vec<Cell>)> = measures
            .iter()
            .flat_map(|&m| Schemes::ALL.map(|s| ((s, m), cells_of(s, m))))
            .collect();
        let scopes = Schemes::ALL.map(Scope::Schemes);
        let measures: Vec<Option<Measure>> = measures.iter().copied().map(Some).collect();
        let sensitivity: Vec<(Setting, Verdict)> = Setting::grid(&scopes, &measures)
            .into_iter()
            .map(|setting| {
                let cells = &sets
                    .iter()
                    .find(|((s, m), _)| {
                        Scope::Schemes(*s) == setting.scope && Some(*m) == setting.measure
                    })
                    .expect("a cell set per scheme and measure")
                    .1;
                (setting, self.decide(cells, setting.tie))
            })
            .collect();
        Decided {
            conclusion: self,
            overall: Overall::of(&sensitivity),
            sensitivity,
        }
    }
}

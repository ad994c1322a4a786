//! The places where the thesis as printed is inconsistent, and the form the code uses.
//!
//! Each entry was checked against the cited papers (see `docs/thesis-errata.md`); the code
//! implements the consistent form and its documentation says so. Solver modules that find
//! more append them here.

use crate::format::MarkdownTable;

/// One erratum of the thesis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Erratum {
    /// Where: `Eq 4`, `Algorithm 1, line 6`, `§3.3`.
    pub location: &'static str,
    /// As printed.
    pub printed: &'static str,
    /// The consistent form the code uses.
    pub used: &'static str,
    /// Why.
    pub why: &'static str,
}

/// Every erratum, in the order of the thesis.
pub const ERRATA: &[Erratum] = &[
    Erratum {
        location: "Eq 4",
        printed: "$H = -\\partial^2 E/\\partial x^2$, called \"Hessiana\"",
        used: "$dF/dx$, the negative of the energy Hessian",
        why: "a naming convention rather than a mistake, but a sign trap: Eq 12 uses $dF/dx$",
    },
    Erratum {
        location: "Eq 11",
        printed: "$v(t+dt) = v(t) + M^{-1}F\\,dt + \\frac{dF}{dx}(x(t+dt) - x(t))\\,dt$",
        used: "the last term also multiplied by $M^{-1}$",
        why: "follows from Eq 8 with Eq 10 substituted",
    },
    Erratum {
        location: "Eq 12, iterated",
        printed: "$(M - dt^2\\frac{dF}{dx})\\,v(t+dt) = M v(t) + dt\\,F(x(t))$ re-evaluated at each iterate",
        used: "Newton on $r(v) = M(v - v_n) - dt\\,F(x_n + dt\\,v)$: $(M - dt^2K_k)\\,v_{k+1} = M v_n + dt\\,F(x_k) + dt\\,K_k(x_n - x_k)$",
        why: "re-evaluated at each iterate without the last term, the printed form is a fixed-point iteration that does not solve the implicit equations 8-9: after five iterations its residual stays orders of magnitude above Newton's (the test `newton_iterations_solve_the_backward_euler_equations`)",
    },
    Erratum {
        location: "Eq 20",
        printed: "$\\min_x \\frac{1}{2dt^2}(x^n - y)^\\top M (x^n - y) + E(x)$",
        used: "$\\arg\\min_x \\frac{1}{2dt^2}(x - y)^\\top M (x - y) + E(x)$",
        why: "$x^n$ does not depend on $x$",
    },
    Erratum {
        location: "Eqs 27 and 29",
        printed: "$b = M x + f_{ext}\\,dt^2$, then $(M + dt^2 L)\\,x = J d\\,dt^2 - b$",
        used: "$(M + dt^2 L)\\,x = M y + dt^2 f_{ext} + dt^2 J d$ with $y = x_n + dt\\,v_n$",
        why: "as printed the inertia term has the wrong sign and no velocity (Liu 2013 uses $y$; the thesis's $b$ and Eq 23 disagree in sign)",
    },
    Erratum {
        location: "Eq 34",
        printed: "$(x^n - x^{n+1})^\\top M (x^n - x^{n+1})$",
        used: "$(x - \\tilde x)^\\top M (x - \\tilde x)$",
        why: "the same slip as Eq 20; Eq 35 has it right",
    },
    Erratum {
        location: "Eq 36",
        printed: "$g(x) = U_*(z)$",
        used: "$g(z) = U_*(z)$",
        why: "$g$ is a function of $z$ in Eq 30",
    },
    Erratum {
        location: "Eq 40, last line",
        printed: "$D^\\top W W$",
        used: "$D^\\top W^\\top W$",
        why: "harmless for a diagonal $W$, but inconsistent with the line above",
    },
    Erratum {
        location: "§3.3",
        printed: "\"el cálculo de Δx (Ecuación 17)\"",
        used: "Eq 19",
        why: "$\\Delta x$ is Eq 19; Eq 17 is the linear system for $\\Delta\\lambda$",
    },
    Erratum {
        location: "Algorithm 1, line 6",
        printed: "$x_{i+1} = x_i + \\Delta x$, with $i$ also the node index",
        used: "the projection updates the predicted positions $p$; lines 10-11 then set $v = (p - x)/dt$, $x = p$",
        why: "as printed $p$ never changes",
    },
    Erratum {
        location: "Algorithm 3",
        printed: "no prediction $y$, no velocity update",
        used: "$y = x_n + dt\\,v_n$ enters $b$; $v_{n+1} = (x_{n+1} - x_n)/dt$ after the loop",
        why: "needed for dynamics; Algorithm 4 has both (lines 2.1, 2.11)",
    },
    Erratum {
        location: "Tutorial (seed 004)",
        printed: "\"Euler es un Runge-Kutta de orden 2\"",
        used: "explicit Euler is first order (a one-stage Runge-Kutta method)",
        why: "its error per unit time is $O(h)$",
    },
];

/// The errata as a Markdown table.
pub fn table() -> MarkdownTable {
    let mut t = MarkdownTable::new(&["where", "printed", "form used", "why"]);
    for e in ERRATA {
        t.row(vec![
            e.location.into(),
            e.printed.into(),
            e.used.into(),
            e.why.into(),
        ]);
    }
    t
}

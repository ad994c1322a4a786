//! Equation traceability, literate style: every numbered equation of the thesis (1-56), what
//! it is, and the functions that implement it, found by scanning the crate's source for the
//! documentation tags of the developer guide; and the solvers' step functions quoted
//! straight from `src/` through marked regions, so that the report's text and the code
//! cannot drift apart.
//!
//! A tag is the first line of a documentation comment (`///` or `//!`) and reads exactly
//! `Eq. (18): ...`, `Eqs. (48), (49): ...` or `Eqs. (45)-(47): ...`. A quoted region is the
//! text between a line `// region: NAME` and a line `// endregion: NAME`; several regions
//! with the same name in one file are quoted in order.

use crate::format::MarkdownTable;
use mass_spring_solvers::error::{Error, Result};
use std::collections::BTreeMap;
use std::path::Path;

mod papers;
mod quote;
pub use papers::{
    paper_summary, paper_table, parse_paper_tag, scan_paper_text, scan_papers, verification,
    PaperTag, Verified, READ_TEXTS, UNREAD_TEXTS,
};
pub use quote::{extract_region, solver_file, solver_step, Quote, STEP_REGION};

/// The thesis's numbered equations: number and what each one is.
pub const EQUATIONS: [(u8, &str); 56] = [
    (1, "spring deformation $C = \\lvert x_1 - x_2 \\rvert - l_0$"),
    (2, "Hooke energy $E = \\frac12 k C^\\top C$"),
    (3, "force $F = -\\partial E/\\partial x$"),
    (4, "force Jacobian $-\\partial^2 E/\\partial x^2$ (the thesis's \"Hessian\")"),
    (5, "Newton's second law $\\sum F_i = m a$"),
    (6, "implicit Euler position update $x(t+dt) = x(t) + v(t+dt)\\,dt$"),
    (7, "implicit Euler velocity update $v(t+dt) = v(t) + a(t+dt)\\,dt$"),
    (8, "velocity update with forces $v(t+dt) = v(t) + M^{-1}F(x(t+dt))\\,dt$"),
    (9, "position update $x(t+dt) = x(t) + v(t+dt)\\,dt$"),
    (10, "linearised force $F(x(t+dt)) \\approx F(x(t)) + \\frac{dF}{dx}\\Delta x$"),
    (11, "linearised velocity update (Eq 10 in Eq 8)"),
    (12, "Backward Euler linear system $(M - dt^2 \\frac{dF}{dx}) v(t+dt) = M v(t) + dt F(x(t))$"),
    (13, "PBD scaling $s_j = -C_j / (\\nabla C_j M^{-1} \\nabla C_j^\\top)$"),
    (14, "PBD correction $\\Delta x = s_j M^{-1} \\nabla C_j$"),
    (15, "compliant multiplier $\\lambda = -\\alpha^{-1} C(x)$"),
    (16, "compliant equations of motion $Ma - \\nabla C^\\top\\lambda = 0$, $C + \\alpha\\lambda = 0$"),
    (17, "XPBD linear system for $\\Delta\\lambda$"),
    (18, "XPBD multiplier increment $\\Delta\\lambda$ of one constraint"),
    (19, "XPBD position update $\\Delta x = M^{-1} \\nabla C^\\top \\Delta\\lambda$"),
    (20, "implicit Euler as a minimisation (incremental potential)"),
    (21, "Liu's auxiliary spring direction $d$ (variational form of the spring energy)"),
    (22, "Eq 21 with $\\lvert d \\rvert = l_0$"),
    (23, "Liu's joint minimisation over $x$ and $d$"),
    (24, "mass matrix $M$"),
    (25, "stiffness-weighted Laplacian $L$"),
    (26, "stiffness-weighted incidence matrix $J$"),
    (27, "right-hand side $b$ (inertia and external forces)"),
    (28, "local step: spring direction $d_i = l_0 (x_1 - x_2)/\\lvert x_1 - x_2 \\rvert$"),
    (29, "global step $(M + dt^2 L) x = \\dots$"),
    (30, "ADMM problem $\\min f(x) + g(z)$ s.t. $Ax + Bz = c$"),
    (31, "ADMM $x$-update"),
    (32, "ADMM $z$-update"),
    (33, "ADMM dual update"),
    (34, "implicit Euler in ADMM form"),
    (35, "$f(x) = \\frac{1}{2dt^2}\\lVert x - \\tilde x \\rVert_M^2$"),
    (36, "$g(z) = U_*(z)$"),
    (37, "$A = WD$"),
    (38, "$B = -W$"),
    (39, "$c = 0$"),
    (40, "ADMM-PD global step $(M + dt^2 D^\\top W^\\top W D) x = M\\tilde x + dt^2 D^\\top W^\\top W (z - \\bar u)$"),
    (41, "ADMM-PD local step $z_i = \\arg\\min U_i(z_i) + \\frac12\\lVert W_i(D_i x - z_i + \\bar u_i) \\rVert^2$"),
    (42, "ADMM-PD scaled dual update $\\bar u_i \\mathrel{+}= D_i x - z_i$"),
    (43, "linear system with fixed unknowns (block form)"),
    (44, "matrix with identity rows and columns for the fixed unknowns"),
    (45, "auxiliary vector $u = (0, \\bar x)$"),
    (46, "product $A u$"),
    (47, "$b \\leftarrow b - A u$"),
    (48, "distance constraint $C = \\lvert x_1 - x_2 \\rvert - l_0 = 0$"),
    (49, "constraint gradient $\\nabla C = (n, -n)$, $n = (x_1 - x_2)/\\lvert x_1 - x_2 \\rvert$"),
    (50, "$\\nabla C M^{-1} \\nabla C^\\top = 1/m_1 + 1/m_2$"),
    (51, "XPBD per-node corrections $\\Delta x_1$, $\\Delta x_2$"),
    (52, "the rope's Laplacian $L$ (block tridiagonal)"),
    (53, "the rope's incidence matrix $J$"),
    (54, "ADMM reduction matrix $D = J^\\top$, unweighted"),
    (55, "projection $p_i = l_0 (D_i x + \\bar u_i)/\\lvert D_i x + \\bar u_i \\rvert$"),
    (56, "$z_i = \\frac12(p_i + D_i x + \\bar u_i)$ for $\\omega_i^2 = k$"),
];

/// Whether an equation must be implemented by code (issue 4): 1-4, 6-10, 12-14, 18-20,
/// 24-29 and 40-56.
pub fn must_have_code(equation: u8) -> bool {
    matches!(equation, 1..=4 | 6..=10 | 12..=14 | 18..=20 | 24..=29 | 40..=56)
}

/// The kind of an equation that is not implemented by code of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NotCode {
    /// It defines a symbol or a problem that other equations then solve.
    Definition,
    /// It is a step of a derivation whose result is implemented.
    Derivation,
}

impl NotCode {
    fn label(self) -> &'static str {
        match self {
            NotCode::Definition => "definition",
            NotCode::Derivation => "derivation",
        }
    }
}

/// The equations that may be a derivation or a definition instead of code, with the reason.
pub const NOT_CODE: [(u8, NotCode, &str); 18] = [
    (5, NotCode::Definition, "the premise of the dynamics; the model's masses and forces and Eqs 8-9 realise it"),
    (11, NotCode::Derivation, "intermediate step from Eqs 8 and 10 to Eq 12 (printed without $M^{-1}$ in its last term: erratum); the code solves Eq 12"),
    (15, NotCode::Definition, "defines $\\lambda$; XPBD accumulates $\\lambda$ through Eq 18 and never evaluates Eq 15"),
    (16, NotCode::Derivation, "the continuous compliant equations of motion that Eqs 17-19 discretise"),
    (17, NotCode::Derivation, "the coupled system for $\\Delta\\lambda$; solved one constraint at a time (Gauss-Seidel), where it is Eq 18"),
    (21, NotCode::Derivation, "Liu's identity that motivates the local step; its minimiser over $d$ is Eq 28"),
    (22, NotCode::Derivation, "restates Eq 21 with $\\lvert d \\rvert = l_0$"),
    (23, NotCode::Derivation, "the joint minimisation that the local-global alternation (Eqs 28, 29) solves block by block"),
    (30, NotCode::Definition, "the generic ADMM problem; Eqs 34-39 specialise it into Eqs 40-42"),
    (31, NotCode::Derivation, "the generic ADMM $x$-update; its specialisation Eq 40 is implemented"),
    (32, NotCode::Derivation, "the generic ADMM $z$-update; its specialisation Eq 41 is implemented"),
    (33, NotCode::Derivation, "the generic ADMM dual update; its specialisation Eq 42 is implemented"),
    (34, NotCode::Definition, "Eq 20 written in ADMM form (erratum: the inertial term is $(x - \\tilde x)$)"),
    (35, NotCode::Definition, "the choice of $f$ that turns Eq 31 into Eq 40"),
    (36, NotCode::Definition, "the choice of $g$ that turns Eq 32 into Eq 41 (erratum: $g(z)$)"),
    (37, NotCode::Definition, "the choice of $A$ in Eqs 31-33"),
    (38, NotCode::Definition, "the choice of $B$ in Eqs 31-33"),
    (39, NotCode::Definition, "the choice of $c$ in Eqs 31-33"),
];

/// The listed reason of an equation that may go without code, if it is listed.
pub fn not_code(equation: u8) -> Option<(NotCode, &'static str)> {
    NOT_CODE
        .iter()
        .find(|(n, _, _)| *n == equation)
        .map(|&(_, kind, reason)| (kind, reason))
}

/// One tagged item of the source.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Tag {
    /// The equations the tag names.
    pub equations: Vec<u8>,
    /// The item under the tag: `spring::energy`, `BackwardEuler::newton_iteration`, or the
    /// module for a `//!` tag.
    pub item: String,
    /// File relative to the crate root, `src/model/spring.rs`.
    pub file: String,
    /// 1-based line of the tag.
    pub line: usize,
}

/// The equation numbers of a tag line (the first line of a doc comment, without `///`), or
/// `None` if the line is not a tag: `Eq. (18): ...`, `Eqs. (48), (49): ...`,
/// `Eqs. (45)-(47): ...` (mixtures such as `Eqs. (6), (8)-(9): ...` also parse).
pub fn parse_tag(line: &str) -> Option<Vec<u8>> {
    let rest = line
        .strip_prefix("Eqs. ")
        .or_else(|| line.strip_prefix("Eq. "))?;
    let (list, _) = rest.split_once(':')?;
    let mut equations = Vec::new();
    for part in list.split(',') {
        let number = |s: &str| -> Option<u8> {
            let n: u8 = s
                .trim()
                .strip_prefix('(')?
                .strip_suffix(')')?
                .parse()
                .ok()?;
            (1..=56).contains(&n).then_some(n)
        };
        match part.split_once('-') {
            Some((a, b)) => {
                let (a, b) = (number(a)?, number(b)?);
                if a > b {
                    return None;
                }
                equations.extend(a..=b);
            }
            None => equations.push(number(part)?),
        }
    }
    (!equations.is_empty()).then_some(equations)
}

/// The item a declaration line declares: the name after `fn`, `struct`, `enum`, `const`,
/// `static`, `trait`, `type` or `mod`, or the whole `impl ...` header.
fn declared_item(line: &str) -> Option<String> {
    let code = line.split("//").next().unwrap_or(line).trim();
    let words: Vec<&str> = code.split_whitespace().collect();
    if let Some(first) = words
        .iter()
        .position(|w| *w == "impl" || w.starts_with("impl<"))
    {
        let header = words[first..].join(" ");
        return Some(header.trim_end_matches('{').trim().to_string());
    }
    let keyword = words.iter().position(|w| {
        matches!(
            *w,
            "fn" | "struct" | "enum" | "const" | "static" | "trait" | "type" | "mod"
        )
    })?;
    let name = words.get(keyword + 1)?;
    let end = name
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(name.len());
    (end > 0).then(|| name[..end].to_string())
}

/// The type an `impl` header implements for: `impl<T> Foo<T> for Bar {` gives `Bar`.
fn impl_target(header: &str) -> String {
    let header = header.trim_end_matches('{').trim();
    let target = header.rsplit(" for ").next().unwrap_or(header);
    let target = target.trim_start_matches("impl").trim();
    let target = if target.starts_with('<') {
        // Skip the generic parameters of `impl<...>`.
        let mut depth = 0;
        let mut cut = target.len();
        for (i, c) in target.char_indices() {
            match c {
                '<' => depth += 1,
                '>' => {
                    depth -= 1;
                    if depth == 0 {
                        cut = i + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        target[cut..].trim()
    } else {
        target
    };
    let end = target
        .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
        .unwrap_or(target.len());
    target[..end].rsplit("::").next().unwrap_or("").to_string()
}

/// The module path of a source file: `src/model/spring.rs` → `model::spring`.
fn module_of(file: &str) -> String {
    let path = file.trim_start_matches("src/").trim_end_matches(".rs");
    let path = path.trim_end_matches("/mod").trim_end_matches("lib");
    path.trim_end_matches('/').replace('/', "::")
}

/// The tags of one source file's text; `file` is its path relative to the crate root.
pub fn scan_text(file: &str, text: &str) -> Vec<Tag> {
    scan_items(file, text, parse_tag)
        .into_iter()
        .map(|(equations, item, line)| Tag {
            equations,
            item,
            file: file.to_string(),
            line,
        })
        .collect()
}

/// The doc blocks of `text` whose first line `parse` accepts: what it read, the item the
/// block documents and the block's 1-based line.
fn scan_items<T>(
    file: &str,
    text: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Vec<(T, String, usize)> {
    let module = module_of(file);
    let lines: Vec<&str> = text.lines().collect();
    let mut tags = Vec::new();
    let mut impl_type: Option<String> = None;
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        if !line.starts_with(char::is_whitespace) {
            if line.starts_with("impl") {
                impl_type = Some(impl_target(line));
            } else if line.starts_with('}') {
                impl_type = None;
            }
        }
        let trimmed = line.trim_start();
        let doc = trimmed
            .strip_prefix("///")
            .filter(|_| !trimmed.starts_with("////"))
            .map(|d| (d, false))
            .or_else(|| trimmed.strip_prefix("//!").map(|d| (d, true)));
        let Some((first, inner)) = doc else {
            i += 1;
            continue;
        };
        // The start of a doc block: the previous line is not a doc line of the same kind.
        let marker = if inner { "//!" } else { "///" };
        let continues = i > 0 && lines[i - 1].trim_start().starts_with(marker);
        let tag_line = i + 1;
        let mut j = i + 1;
        while j < lines.len() && lines[j].trim_start().starts_with(marker) {
            j += 1;
        }
        if !continues {
            if let Some(parsed) = parse(first.trim()) {
                let item = if inner {
                    Some(module.clone())
                } else {
                    lines[j..]
                        .iter()
                        .find(|l| {
                            let t = l.trim_start();
                            !(t.is_empty() || t.starts_with("#[") || t.starts_with("//"))
                        })
                        .and_then(|l| declared_item(l))
                        .map(|name| {
                            let nested = lines[j..]
                                .iter()
                                .find(|l| !l.trim_start().starts_with("#["))
                                .is_some_and(|l| l.starts_with(char::is_whitespace));
                            match (&impl_type, nested) {
                                (Some(t), true) if !t.is_empty() => format!("{t}::{name}"),
                                _ if module.is_empty() => name,
                                _ => format!("{module}::{name}"),
                            }
                        })
                };
                tags.push((
                    parsed,
                    item.unwrap_or_else(|| format!("{module} (item not recognised)")),
                    tag_line,
                ));
            }
        }
        i = j;
    }
    tags
}

/// Every `.rs` file under `dir`, sorted, as paths relative to `root` with `/` separators.
fn rust_files(root: &Path, dir: &Path, out: &mut Vec<String>) -> Result<()> {
    let read = |e: std::io::Error| Error::Input(format!("reading {}: {e}", dir.display()));
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .map_err(read)?
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(read)?;
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let path = entry.path();
        if path.is_dir() {
            rust_files(root, &path, out)?;
        } else if path.extension().is_some_and(|e| e == "rs") {
            let relative = path.strip_prefix(root).unwrap_or(&path);
            let parts: Vec<String> = relative
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            out.push(parts.join("/"));
        }
    }
    Ok(())
}

/// Reads a file of the crate, naming it in the error.
pub fn read_source(root: &Path, file: &str) -> Result<String> {
    std::fs::read_to_string(root.join(file))
        .map_err(|e| Error::Input(format!("reading {file}: {e}")))
}

/// Every tag in `root/src/**/*.rs`, in file and line order.
pub fn scan(root: &Path) -> Result<Vec<Tag>> {
    scan_files(root, scan_text)
}

fn scan_files<T>(root: &Path, scan: impl Fn(&str, &str) -> Vec<T>) -> Result<Vec<T>> {
    let mut files = Vec::new();
    rust_files(root, &root.join("src"), &mut files)?;
    let mut tags = Vec::new();
    for file in files {
        tags.extend(scan(&file, &read_source(root, &file)?));
    }
    Ok(tags)
}

/// How an equation is accounted for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Coverage<'a> {
    /// Implemented by these tagged items.
    Code(Vec<&'a Tag>),
    /// Listed as a derivation or definition.
    Listed(NotCode, &'static str),
    /// Neither.
    Missing,
}

/// How each equation 1..=56 is accounted for.
pub fn coverage(tags: &[Tag]) -> BTreeMap<u8, Coverage<'_>> {
    EQUATIONS
        .iter()
        .map(|&(n, _)| {
            let code: Vec<&Tag> = tags.iter().filter(|t| t.equations.contains(&n)).collect();
            let c = if !code.is_empty() {
                Coverage::Code(code)
            } else if let Some((kind, reason)) = not_code(n) {
                Coverage::Listed(kind, reason)
            } else {
                Coverage::Missing
            };
            (n, c)
        })
        .collect()
}

/// The equations that break the rule: neither tagged nor listed, or required to have code
/// and having none. Empty when the traceability is complete.
pub fn missing(tags: &[Tag]) -> Vec<u8> {
    coverage(tags)
        .into_iter()
        .filter(|(n, c)| match c {
            Coverage::Code(_) => false,
            Coverage::Listed(..) => must_have_code(*n),
            Coverage::Missing => true,
        })
        .map(|(n, _)| n)
        .collect()
}

/// The traceability table for the report: equation, what it is, implementing items with
/// file:line links (or the listed reason), status.
pub fn table(tags: &[Tag]) -> MarkdownTable {
    let mut t = MarkdownTable::new(&[">Eq.", "what it is", "implemented by", "status"]);
    let what: BTreeMap<u8, &str> = EQUATIONS.into_iter().collect();
    for (n, c) in coverage(tags) {
        let (by, status) = match c {
            Coverage::Code(code) => (
                code.iter()
                    .map(|t| {
                        format!(
                            "`{}` ([{}:{}](../{}#L{}))",
                            t.item, t.file, t.line, t.file, t.line
                        )
                    })
                    .collect::<Vec<_>>()
                    .join("<br>"),
                "code".to_string(),
            ),
            Coverage::Listed(kind, reason) => (reason.to_string(), kind.label().to_string()),
            Coverage::Missing => ("–".to_string(), "**missing**".to_string()),
        };
        t.row(vec![n.to_string(), what[&n].to_string(), by, status]);
    }
    t
}

/// The traceability table without line numbers (for the snapshot, so that unrelated edits
/// that move lines do not change it): `Eq | status | items (file)`.
pub fn summary(tags: &[Tag]) -> String {
    let mut out = String::new();
    for (n, c) in coverage(tags) {
        let text = match c {
            Coverage::Code(code) => {
                let items: Vec<String> = code
                    .iter()
                    .map(|t| format!("{} ({})", t.item, t.file))
                    .collect();
                format!("code: {}", items.join(", "))
            }
            Coverage::Listed(kind, _) => kind.label().to_string(),
            Coverage::Missing => "MISSING".to_string(),
        };
        out += &format!("Eq. ({n:2}) {text}\n");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tags_parse() {
        assert_eq!(parse_tag("Eq. (18): the update"), Some(vec![18]));
        assert_eq!(parse_tag("Eqs. (48), (49): gradient"), Some(vec![48, 49]));
        assert_eq!(parse_tag("Eqs. (45)-(47): fixed"), Some(vec![45, 46, 47]));
        assert_eq!(parse_tag("Eqs. (6), (8)-(9): x"), Some(vec![6, 8, 9]));
        assert_eq!(parse_tag("Eq. (57): out of range"), None);
        assert_eq!(parse_tag("Eq. (4) projected: no colon list"), None);
        assert_eq!(parse_tag("The force of Eq. (3): not first"), None);
        assert_eq!(parse_tag("Eqs. (47)-(45): reversed"), None);
    }

    #[test]
    fn scanning_finds_items_and_lines() {
        let text = "//! Module.\n\n/// Eq. (1): $C$.\n/// more\n#[inline]\npub fn constraint(a: f64) -> f64 {\n    a\n}\n\nimpl Foo for Bar {\n    /// Eqs. (10), (12): iteration.\n    fn newton(&self) {}\n}\n/// Not a tag.\n/// Eq. (2): second line does not count.\nfn other() {}\n";
        let tags = scan_text("src/model/spring.rs", text);
        assert_eq!(tags.len(), 2);
        assert_eq!(tags[0].item, "model::spring::constraint");
        assert_eq!(tags[0].line, 3);
        assert_eq!(tags[1].item, "Bar::newton");
        assert_eq!(tags[1].equations, vec![10, 12]);
    }

    #[test]
    fn the_lists_are_consistent() {
        for (i, (n, _)) in EQUATIONS.iter().enumerate() {
            assert_eq!(*n as usize, i + 1);
        }
        for (n, _, _) in NOT_CODE {
            assert!(
                !must_have_code(n),
                "Eq. ({n}) must have code and cannot be listed"
            );
        }
        assert!(not_code(5).is_some());
        let no_tags: Vec<Tag> = Vec::new();
        let all_missing = missing(&no_tags);
        assert!(all_missing.contains(&1) && !all_missing.contains(&5));
    }

    #[test]
    fn regions() {
        let text = "fn a() {}\n    // region: step\n    fn step() {\n        x();\n    }\n    // endregion: step\n// region: step\nfn b() {}\n// endregion: step\n";
        let q = extract_region("src/x.rs", text, "step").unwrap();
        assert_eq!(q.line, 3);
        assert_eq!(q.code, "fn step() {\n    x();\n}\n// ...\nfn b() {}");
        let err = extract_region("src/x.rs", "fn a() {}\n", "step")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("src/x.rs") && err.contains("// region: step"),
            "{err}"
        );
        let err = extract_region("src/x.rs", "// region: step\n", "step")
            .unwrap_err()
            .to_string();
        assert!(err.contains("never closed"), "{err}");
    }
}

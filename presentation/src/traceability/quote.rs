//! The code the report quotes: a named region (`// region: step`) of a solver's source file,
//! dedented.

use super::read_source;
use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::solvers::registry::SolverId;
use std::path::Path;

/// Where each solver's step function lives and the region that quotes it.
pub const STEP_REGION: &str = "step";

/// The source file of each solver of the thesis's tables.
pub fn solver_file(kind: SolverId) -> &'static str {
    kind.info().file
}

/// A region of source text quoted in the report.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Quote {
    pub file: String,
    /// 1-based first line of the first region's body.
    pub line: usize,
    /// The regions' text, dedented; several regions are separated by a `// ...` line.
    pub code: String,
}

/// The text between `// region: NAME` and `// endregion: NAME` in `text` (the file `file`).
/// Errors name the file and the marker when a marker is missing or unbalanced.
pub fn extract_region(file: &str, text: &str, name: &str) -> Result<Quote> {
    let start = format!("// region: {name}");
    let end = format!("// endregion: {name}");
    let mut bodies: Vec<Vec<&str>> = Vec::new();
    let mut first_line = None;
    let mut open: Option<(usize, Vec<&str>)> = None;
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t == start {
            if let Some((at, _)) = open {
                return Err(Error::Input(format!(
                    "{file}:{}: `{start}` opened again before `{end}` closed the region opened at line {}",
                    i + 1,
                    at + 1
                )));
            }
            open = Some((i, Vec::new()));
            first_line.get_or_insert(i + 2);
        } else if t == end {
            match open.take() {
                Some((_, body)) => bodies.push(body),
                None => {
                    return Err(Error::Input(format!(
                        "{file}:{}: `{end}` without a preceding `{start}`",
                        i + 1
                    )))
                }
            }
        } else if let Some((_, body)) = open.as_mut() {
            body.push(line);
        }
    }
    if let Some((at, _)) = open {
        return Err(Error::Input(format!(
            "{file}:{}: `{start}` is never closed by `{end}`",
            at + 1
        )));
    }
    if bodies.is_empty() {
        return Err(Error::Input(format!(
            "{file} has no `{start}` marker: put `{start}` and `{end}` comment lines around the code the report quotes"
        )));
    }
    let parts: Vec<String> = bodies.iter().map(|b| dedent(b)).collect();
    Ok(Quote {
        file: file.to_string(),
        line: first_line.unwrap_or(1),
        code: parts.join("\n// ...\n"),
    })
}

/// Lines with their common leading whitespace removed, trailing blank lines dropped.
fn dedent(lines: &[&str]) -> String {
    let indent = lines
        .iter()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.len() - l.trim_start().len())
        .min()
        .unwrap_or(0);
    let mut out: Vec<&str> = lines
        .iter()
        .map(|l| l.get(indent..).unwrap_or("").trim_end())
        .collect();
    while out.last().is_some_and(|l| l.is_empty()) {
        out.pop();
    }
    while out.first().is_some_and(|l| l.is_empty()) {
        out.remove(0);
    }
    out.join("\n")
}

/// The step region of a solver, read from the crate at `root`.
pub fn solver_step(root: &Path, kind: SolverId) -> Result<Quote> {
    let file = solver_file(kind);
    extract_region(file, &read_source(root, file)?, STEP_REGION)
}

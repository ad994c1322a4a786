//! The report's figure numbering and citations, recomputed from the Markdown:
//! - every image is followed by a caption `*Figure N. ...*` with N a plain number;
//! - the thesis's figures (`figures/figNN-...`) carry the thesis's number NN, 1 to 15, and
//!   every other figure the next number from the document's first (16 in REPORT.md, after the
//!   thesis's; 1 in TIMING.md, which has none of them) in order of appearance, so that the
//!   numbers rise through the document;
//! - no "Figure" reference carries a letter (`Figure B1`);
//! - every figure is cited, as a link to its anchor, outside its own caption and outside the
//!   list of data files (where the text discusses it).

/// The figures of a document: (line index, image target, caption number if any).
fn figures(md: &str) -> Vec<(usize, String, Option<u32>)> {
    let lines: Vec<&str> = md.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(image) = line.split("![").nth(1) else {
            continue;
        };
        let target = image
            .split("](")
            .nth(1)
            .and_then(|t| t.split(')').next())
            .unwrap_or("")
            .to_string();
        let caption = lines[i + 1..].iter().find(|l| !l.trim().is_empty());
        let number = caption
            .and_then(|c| c.strip_prefix("*Figure "))
            .and_then(|c| c.split(['.', ' ']).next())
            .and_then(|n| n.parse().ok());
        out.push((i, target, number));
    }
    out
}

/// The thesis figure a file stem mirrors: `figures/fig05-...` is Figure 5.
fn thesis_number(target: &str) -> Option<u32> {
    target
        .strip_prefix("figures/fig")
        .and_then(|s| s.get(..2))
        .and_then(|n| n.parse().ok())
}

/// Everything wrong with a document's figure numbering; empty when it passes.
pub fn numbering_problems(md: &str, first: u32) -> Vec<String> {
    let mut out = Vec::new();
    let mut next = first;
    let mut last = 0;
    for (line, target, number) in figures(md) {
        let Some(number) = number else {
            out.push(format!(
                "line {}: {target} has no numbered caption",
                line + 1
            ));
            continue;
        };
        let expected = thesis_number(&target).unwrap_or_else(|| {
            next += 1;
            next - 1
        });
        if number != expected {
            out.push(format!(
                "line {}: {target} is Figure {number}, not {expected}",
                line + 1
            ));
        }
        if number <= last {
            out.push(format!(
                "line {}: Figure {number} after Figure {last}",
                line + 1
            ));
        }
        last = last.max(number);
    }
    for word in md.split("Figure").skip(1) {
        let word = word.strip_prefix('s').unwrap_or(word);
        let key: String = word
            .strip_prefix(' ')
            .unwrap_or("")
            .chars()
            .take_while(char::is_ascii_alphanumeric)
            .collect();
        if key.starts_with(|c: char| c.is_ascii_uppercase())
            && key[1..].starts_with(|c: char| c.is_ascii_digit())
        {
            out.push(format!("a figure reference with a letter: Figure {key}"));
        }
    }
    out
}

/// The figures not cited by a link to their anchor outside their caption and the data list.
pub fn uncited(md: &str) -> Vec<u32> {
    let lines: Vec<&str> = md.lines().collect();
    figures(md)
        .into_iter()
        .filter_map(|(_, _, number)| number)
        .filter(|n| {
            let link = format!("](#f{n})");
            let caption = format!("*Figure {n}. ");
            !lines.iter().any(|l| {
                l.contains(&link) && !l.starts_with(&caption) && !l.starts_with("- [`data/")
            })
        })
        .collect()
}

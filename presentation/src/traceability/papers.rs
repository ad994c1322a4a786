//! The tags of the papers after the thesis (`[Wang 2015, Eq. 14]`): how each was verified
//! against the paper's text or its authors' code, and their table.

use super::{scan_files, scan_items};
use crate::format::MarkdownTable;
use mass_spring_solvers::error::Result;
use std::path::Path;

/// How a paper tag was checked (`docs/papers.md` says which texts could be read).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verified {
    /// Against the paper's text.
    Text,
    /// Against the authors' reference code, which the tag's doc line names.
    ReferenceCode,
    /// Neither: the tag's doc line says so, and names the code checked or that none exists.
    Unverified,
}

impl Verified {
    /// The column's word.
    pub fn label(self) -> &'static str {
        match self {
            Verified::Text => "text",
            Verified::ReferenceCode => "reference code",
            Verified::Unverified => "unverified",
        }
    }
}

/// The works whose text was read (papers.md): their tags are checked against it.
pub const READ_TEXTS: [&str; 3] = ["Chen 2024", "Macklin 2019", "Wang 2015"];

/// The works whose tags may be unverified: those whose body could not be read (papers.md,
/// the continuum's among them: Bouaziz 2014 in paraphrase, Sifakis 2012's table of contents,
/// Smith 2018's opening), and the textbook the sheet's Newton solver cites.
pub const UNREAD_TEXTS: [&str; 8] = [
    "Bouaziz 2014",
    "Brown 2018",
    "Liu 2017",
    "Nocedal 2006",
    "Peng 2018",
    "Sifakis 2012",
    "Smith 2018",
    "Zhang 2019",
];

/// How the tag of `paper` whose doc line is `line` was checked: a read text's tags against
/// it; another's against the reference code its line names ("checked against ..."), unless
/// the line says "unverified". `None` for a line of an unread work that says neither, or of
/// a work on neither list: a tag the table cannot vouch for.
pub fn verification(paper: &str, line: &str) -> Option<Verified> {
    let line = line.to_lowercase();
    if READ_TEXTS.contains(&paper) {
        return (!line.contains("unverified")).then_some(Verified::Text);
    }
    if !UNREAD_TEXTS.contains(&paper) {
        return None;
    }
    let names_code = line.contains("checked against")
        || line.contains("no reference code")
        || line.contains("no body text or reference code");
    match (line.contains("unverified"), names_code) {
        (true, true) => Some(Verified::Unverified),
        (false, true) if line.contains("checked against") => Some(Verified::ReferenceCode),
        _ => None,
    }
}

/// A tag of a paper after the thesis, `[Wang 2015, Eq. 14, Alg. 1]`, at the start of the first
/// line of a doc comment (never `Eq. (N)`, which names the thesis's equations).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PaperTag {
    /// `Wang 2015`.
    pub paper: String,
    /// What of the paper: `Eq. 14`, `Alg. 1`, `Rayleigh damping`.
    pub reference: String,
    /// How it was checked; `None` when the doc line does not say ([`verification`]).
    pub verified: Option<Verified>,
    pub item: String,
    pub file: String,
    pub line: usize,
}

/// The paper and the reference of a paper-tag line: `[Author Year, what]` at its start, the
/// author a capitalised word, the year four digits.
pub fn parse_paper_tag(line: &str) -> Option<(String, String)> {
    let (inside, _) = line.strip_prefix('[')?.split_once(']')?;
    let (paper, reference) = inside.split_once(", ")?;
    let (author, year) = paper.rsplit_once(' ')?;
    let well_formed = author.starts_with(|c: char| c.is_ascii_uppercase())
        && year.len() == 4
        && year.chars().all(|c| c.is_ascii_digit())
        && !reference.trim().is_empty();
    well_formed.then(|| (paper.to_string(), reference.trim().to_string()))
}

/// The second traceability table: every paper tag, by paper.
pub fn paper_table(tags: &[PaperTag]) -> MarkdownTable {
    let mut sorted: Vec<&PaperTag> = tags.iter().collect();
    sorted.sort_by(|a, b| (&a.paper, &a.file, a.line).cmp(&(&b.paper, &b.file, b.line)));
    let mut t = MarkdownTable::new(&["paper", "what", "verified against", "code", "where"]);
    for tag in sorted {
        t.row(vec![
            tag.paper.clone(),
            tag.reference.clone(),
            tag.verified
                .map_or("**not stated**", Verified::label)
                .to_string(),
            format!("`{}`", tag.item),
            format!(
                "[`{}:{}`](../{}#L{})",
                tag.file, tag.line, tag.file, tag.line
            ),
        ]);
    }
    t
}

/// The paper tags of one source file's text.
pub fn scan_paper_text(file: &str, text: &str) -> Vec<PaperTag> {
    let parse = |line: &str| {
        parse_paper_tag(line).map(|(paper, reference)| {
            let verified = verification(&paper, line);
            (paper, reference, verified)
        })
    };
    scan_items(file, text, parse)
        .into_iter()
        .map(|((paper, reference, verified), item, line)| PaperTag {
            paper,
            reference,
            verified,
            item,
            file: file.to_string(),
            line,
        })
        .collect()
}

/// The paper-tag table without line numbers, for its snapshot: one line per tag,
/// `paper | what | verified against | item (file)`.
pub fn paper_summary(tags: &[PaperTag]) -> String {
    let mut sorted: Vec<&PaperTag> = tags.iter().collect();
    sorted.sort_by(|a, b| (&a.paper, &a.file, a.line).cmp(&(&b.paper, &b.file, b.line)));
    sorted
        .iter()
        .map(|t| {
            format!(
                "{} | {} | {} | {} ({})\n",
                t.paper,
                t.reference,
                t.verified.map_or("NOT STATED", Verified::label),
                t.item,
                t.file
            )
        })
        .collect()
}

/// Every paper tag in `root/src/**/*.rs`, in file and line order.
pub fn scan_papers(root: &Path) -> Result<Vec<PaperTag>> {
    scan_files(root, scan_paper_text)
}

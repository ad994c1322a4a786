//! The report's navigation: an anchor on every section, table and figure, a linked table of
//! contents, and every plain reference in the text ("section 6.4", "Table 2", "Figure B1")
//! turned into a link to its anchor. Run once over the finished Markdown, so that no chapter
//! writes a link by hand and none goes stale.
//!
//! Figures are numbered here too, in one sequence ([`number_figures`]): each chapter captions its
//! figures with a key of its own (`*Figure T1.*`, `*Figure B1.*`), and the thesis's figures with
//! the thesis's numbers.
//!
//! Anchors are inline HTML (`<a id="s6.4"></a>`) at the start of the heading, the table's bold
//! title or the figure's image: explicit ids work in every renderer (GitHub's, markdown-it's),
//! where generated heading ids differ between them.

/// The anchor id of a section (`6`, `6.4`, `A.2`), a table (`2`) or a figure (`16`, `B1`).
pub fn section_id(number: &str) -> String {
    format!("s{number}")
}

pub fn table_id(number: &str) -> String {
    format!("t{number}")
}

pub fn figure_id(number: &str) -> String {
    format!("f{number}")
}

/// The thesis's figures keep the thesis's numbers, 1 to this (our figures mirror them).
pub const THESIS_FIGURES: u32 = 15;

/// The keys of a document's figure captions (`*Figure KEY. ...*` after an image), in order.
fn caption_keys(md: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut image = false;
    let mut fenced = false;
    for line in md.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
        }
        if fenced {
            continue;
        }
        if image {
            if let Some(key) = line.strip_prefix("*Figure ").and_then(number_at) {
                out.push(key);
            }
        }
        if line.starts_with("![") {
            image = true;
        } else if !line.trim().is_empty() {
            image = false;
        }
    }
    out
}

/// `md` with its figures in one sequence: a caption key that is a thesis figure's number (1 to
/// [`THESIS_FIGURES`]) stays; every other key becomes the next number from
/// `THESIS_FIGURES + 1` in order of first appearance, in its caption and in every
/// "Figure KEY" of the text (code spans aside).
pub fn number_figures(md: &str) -> String {
    let mut next = THESIS_FIGURES;
    let mut numbers: Vec<(String, String)> = Vec::new();
    for key in caption_keys(md) {
        let thesis = key
            .parse::<u32>()
            .is_ok_and(|n| (1..=THESIS_FIGURES).contains(&n));
        if thesis || numbers.iter().any(|(k, _)| k == key) {
            continue;
        }
        next += 1;
        numbers.push((key.to_string(), next.to_string()));
    }
    let mut out = String::with_capacity(md.len());
    let mut fenced = false;
    for line in md.split_inclusive('\n') {
        if line.starts_with("```") {
            fenced = !fenced;
        }
        if fenced {
            out += line;
            continue;
        }
        let mut in_code = false;
        let mut rest = line;
        while let Some(c) = rest.chars().next() {
            if c == '`' {
                in_code = !in_code;
            }
            let word = ["Figures ", "Figure "]
                .into_iter()
                .find(|w| !in_code && rest.starts_with(w));
            if let Some(word) = word {
                let after = &rest[word.len()..];
                if let Some((key, number)) =
                    number_at(after).and_then(|key| numbers.iter().find(|(k, _)| k == key))
                {
                    out += word;
                    out += number;
                    rest = &after[key.len()..];
                    continue;
                }
                out += word;
                rest = after;
                continue;
            }
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

/// What a line anchors, if anything: (id, heading level for the contents, its text).
fn anchor_of(line: &str, previous_image: Option<&str>) -> Option<(String, usize, String)> {
    if let Some(rest) = line.strip_prefix("## ") {
        let number = rest.split_whitespace().next()?.trim_end_matches('.');
        let number = number.strip_prefix("Appendix").map_or(number, str::trim);
        let number = if rest.starts_with("Appendix ") {
            rest.split_whitespace().nth(1)?.trim_end_matches('.')
        } else {
            number
        };
        return looks_numbered(number).then(|| (section_id(number), 2, rest.to_string()));
    }
    if let Some(rest) = line.strip_prefix("### ") {
        let number = rest.split_whitespace().next()?;
        return looks_numbered(number).then(|| (section_id(number), 3, rest.to_string()));
    }
    if let Some(rest) = line.strip_prefix("**Table ") {
        let number = rest.split(['.', ' ']).next()?;
        return (!number.is_empty()).then(|| (table_id(number), 0, String::new()));
    }
    if line.starts_with("*Figure ") && previous_image.is_some() {
        let number = line["*Figure ".len()..].split(['.', ' ']).next()?;
        return (!number.is_empty()).then(|| (figure_id(number), 0, String::new()));
    }
    None
}

/// `6`, `6.4`, `A`, `A.2`: a section number.
fn looks_numbered(s: &str) -> bool {
    let mut parts = s.split('.');
    let first = parts.next().unwrap_or("");
    let first_ok = !first.is_empty()
        && (first.chars().all(|c| c.is_ascii_digit())
            || (first.len() == 1 && first.chars().all(|c| c.is_ascii_uppercase())));
    first_ok && parts.all(|p| !p.is_empty() && p.chars().all(|c| c.is_ascii_digit()))
}

/// The anchors of a document: (id, level, text), in order.
pub fn anchors(md: &str) -> Vec<(String, usize, String)> {
    let mut out = Vec::new();
    let mut image: Option<&str> = None;
    let mut fenced = false;
    for line in md.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
        }
        if fenced {
            continue;
        }
        if let Some(a) = anchor_of(line, image) {
            out.push(a);
        }
        if line.starts_with("![") {
            image = Some(line);
        } else if !line.trim().is_empty() {
            image = None;
        }
    }
    out
}

/// The anchor of the contents, which every section links back to.
pub const CONTENTS_ID: &str = "contents";

/// The linked table of contents of `md`: every section and subsection.
pub fn contents(md: &str) -> String {
    let mut out = format!("<a id=\"{CONTENTS_ID}\"></a>\n\n**Contents**\n\n");
    for (id, level, text) in anchors(md) {
        if level == 0 {
            continue;
        }
        let indent = if level == 3 { "  " } else { "" };
        out += &format!("{indent}- [{}](#{id})\n", text.replace(['[', ']'], ""));
    }
    out
}

/// Splits a line into (is_plain_text, segment): code spans, links and images are not plain.
fn segments(line: &str) -> Vec<(bool, &str)> {
    let bytes = line.as_bytes();
    let mut out = Vec::new();
    let (mut start, mut i) = (0, 0);
    while i < bytes.len() {
        let end = match bytes[i] {
            b'`' => line[i + 1..].find('`').map(|j| i + 1 + j + 1),
            b'!' | b'[' => {
                let open = if bytes[i] == b'!' { i + 1 } else { i };
                (bytes.get(open) == Some(&b'['))
                    .then(|| line[open..].find("](").map(|j| open + j))
                    .flatten()
                    .and_then(|j| line[j..].find(')').map(|k| j + k + 1))
            }
            b'<' => line[i..].find('>').map(|j| i + j + 1),
            _ => None,
        };
        match end {
            Some(end) => {
                if start < i {
                    out.push((true, &line[start..i]));
                }
                out.push((false, &line[i..end]));
                start = end;
                i = end;
            }
            None => i += line[i..].chars().next().map_or(1, char::len_utf8),
        }
    }
    if start < line.len() {
        out.push((true, &line[start..]));
    }
    out
}

/// A reference's id from its number.
type IdOf = fn(&str) -> String;

/// The words that introduce a reference, and the id each kind's numbers map to.
const KINDS: [(&str, IdOf); 8] = [
    ("sections ", section_id),
    ("section ", section_id),
    ("Section ", section_id),
    ("appendix ", section_id),
    ("Appendix ", section_id),
    ("Tables ", table_id),
    ("Table ", table_id),
    ("Figure ", figure_id),
];

/// The number after a reference word: `6.4`, `2`, `B1` (a trailing period is not part).
fn number_at(text: &str) -> Option<&str> {
    let end = text
        .char_indices()
        .find(|&(i, c)| {
            !(c.is_ascii_alphanumeric()
                || (c == '.' && text[i + 1..].starts_with(|d: char| d.is_ascii_digit())))
        })
        .map_or(text.len(), |(i, _)| i);
    let n = &text[..end];
    // An appendix is one capital letter alone: `appendix B`.
    if n.len() == 1 && n.starts_with(|c: char| c.is_ascii_uppercase()) {
        return Some(n);
    }
    let first_digit = n.find(|c: char| c.is_ascii_digit())?;
    // A number, or one capital letter and a number: B1, S1, T6, A.2.
    let letter = &n[..first_digit];
    let letter_ok = letter.is_empty()
        || (letter.len() <= 2
            && letter.starts_with(|c: char| c.is_ascii_uppercase())
            && letter[1..].chars().all(|c| c == '.'));
    let digits_ok = n[first_digit..]
        .chars()
        .all(|c| c.is_ascii_digit() || c == '.');
    (letter_ok && digits_ok).then_some(n)
}

/// A plain text segment with every reference to a known anchor linked.
fn link_text(text: &str, known: &[String], own: Option<&str>) -> String {
    let mut out = String::new();
    let mut rest = text;
    'scan: while !rest.is_empty() {
        for (word, id_of) in KINDS {
            if let Some(after) = rest.strip_prefix(word) {
                if let Some(number) = number_at(after) {
                    let id = id_of(number);
                    if known.contains(&id) && own != Some(id.as_str()) {
                        let phrase = &rest[..word.len() + number.len()];
                        out += &format!("[{phrase}](#{id})");
                        rest = &rest[phrase.len()..];
                        continue 'scan;
                    }
                }
            }
        }
        let c = rest.chars().next().expect("not empty");
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    out
}

/// `md` with an anchor on every section, table and figure and every plain reference to one
/// of them linked.
pub fn linkify(md: &str) -> String {
    let found = anchors(md);
    let known: Vec<String> = found.iter().map(|(id, _, _)| id.clone()).collect();
    let mut out = String::with_capacity(md.len() * 11 / 10);
    let lines: Vec<&str> = md.lines().collect();
    let mut image: Option<usize> = None;
    let mut fenced = false;
    let mut figure_anchor_at: Vec<(usize, String)> = Vec::new();
    // Figures: the anchor goes on the image line before the caption.
    for (i, line) in lines.iter().enumerate() {
        if line.starts_with("```") {
            fenced = !fenced;
        }
        if fenced {
            continue;
        }
        if line.starts_with("*Figure ") {
            if let (Some(at), Some((id, _, _))) = (image, anchor_of(line, Some(""))) {
                figure_anchor_at.push((at, id));
            }
        }
        if line.starts_with("![") {
            image = Some(i);
        } else if !line.trim().is_empty() {
            image = None;
        }
    }
    fenced = false;
    for (i, line) in lines.iter().enumerate() {
        if line.starts_with("```") {
            fenced = !fenced;
        }
        if fenced || line.starts_with("|---") || line.starts_with("| ---") {
            out += line;
            out.push('\n');
            continue;
        }
        let own = anchor_of(line, Some("")).map(|(id, _, _)| id);
        let mut text = String::new();
        for (plain, segment) in segments(line) {
            if plain && !line.starts_with('#') {
                text += &link_text(segment, &known, own.as_deref());
            } else {
                text += segment;
            }
        }
        let prefix = |id: &str| format!("<a id=\"{id}\"></a>");
        if let Some((_, id)) = figure_anchor_at.iter().find(|(at, _)| *at == i) {
            out += &prefix(id);
            out += &text;
        } else if let Some(id) = own.filter(|_| !line.starts_with("*Figure ")) {
            if let Some((level, heading)) = ["## ", "### "]
                .iter()
                .find_map(|level| Some((level, text.strip_prefix(level)?)))
            {
                // A way back from every section and subsection of a long report.
                out += &format!(
                    "{level}{}{heading}\n\n[Back to contents](#{CONTENTS_ID})",
                    prefix(&id)
                );
            } else {
                out += &prefix(&id);
                out += &text;
            }
        } else {
            out += &text;
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_become_links_and_anchors_appear() {
        let md = "## 6. Forensics\n\nSee section 6.4 and Table 2, Figure B1, `section 6.4`.\n\n\
                  ### 6.4 Liu\n\n**Table 2. XPBD**\n\n![x](figures/x.svg)\n\n*Figure B1. Curves.*\n\n\
                  Section 9 is missing; the thesis's §4.4 is not ours.\n";
        let out = linkify(md);
        assert!(out.contains("## <a id=\"s6\"></a>6. Forensics"), "{out}");
        assert!(out.contains("### <a id=\"s6.4\"></a>6.4 Liu"));
        assert!(out.contains("<a id=\"t2\"></a>**Table 2. XPBD**"));
        assert!(out.contains("<a id=\"fB1\"></a>![x](figures/x.svg)"));
        assert!(out.contains(
            "See [section 6.4](#s6.4) and [Table 2](#t2), [Figure B1](#fB1), `section 6.4`."
        ));
        // Negative cases: a reference without an anchor, and the thesis's own sections.
        assert!(out.contains("Section 9 is missing; the thesis's §4.4 is not ours."));
        let toc = contents(md);
        assert!(
            toc.contains("- [6. Forensics](#s6)\n  - [6.4 Liu](#s6.4)"),
            "{toc}"
        );
    }

    /// Every section and subsection links back to the contents, and an appendix is referred to
    /// by its letter alone. Negative case: a letter that names no appendix stays plain (tried
    /// once before the letter rule: `appendix B` stayed plain and this test failed); a heading
    /// of the fourth level, not in the contents, gets no link (3 links, not 4).
    #[test]
    fn sections_link_back_and_appendices_by_letter() {
        let md =
            "## 1. One\n\nSee appendix B and appendix C.\n\n### 1.1 Sub\n\n#### Not listed\n\n\
                  ## Appendix B. Names\n\nText.\n";
        let out = linkify(&format!("{}{md}", contents(md)));
        assert!(
            out.contains("See [appendix B](#sB) and appendix C."),
            "{out}"
        );
        assert_eq!(out.matches("[Back to contents](#contents)").count(), 3);
        assert!(out.contains("### <a id=\"s1.1\"></a>1.1 Sub\n\n[Back to contents](#contents)"));
        assert!(out.contains("<a id=\"contents\"></a>"));
    }

    #[test]
    fn figures_are_numbered_in_one_sequence() {
        let md = "![a](a.svg)\n\n*Figure 1. Thesis.*\n\nSee Figure T1, Figures B1 and `Figure T1`.\n\n\
                  ![b](b.svg)\n\n*Figure T1. Ours.*\n\n![c](c.svg)\n\n*Figure 2. Thesis.*\n\n\
                  ![d](d.svg)\n\n*Figure B1. Ours too.*\n\nFigure 16 and Figure T2 are not captions.\n";
        let out = number_figures(md);
        assert!(out.contains("*Figure 16. Ours.*"), "{out}");
        assert!(out.contains("*Figure 17. Ours too.*"));
        assert!(out.contains("*Figure 1. Thesis.*") && out.contains("*Figure 2. Thesis.*"));
        assert!(out.contains("See Figure 16, Figures 17 and `Figure T1`."));
        // Negative cases: a number or key without a caption is not renumbered.
        assert!(out.contains("Figure 16 and Figure T2 are not captions."));
    }
}

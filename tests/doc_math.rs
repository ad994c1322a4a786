//! The equations reach the reader intact: every math segment of every doc comment under `src/`
//! and of `report/REPORT.md` survives the Markdown parser in front of KaTeX.
//!
//! Doc comments are parsed as rustdoc parses them (pulldown-cmark 0.11, rustdoc's options,
//! smart punctuation included) and read as `katex-header.html` reads the HTML: inline math is a
//! code span flanked by `$` in the same text (`` $`...`$ ``), display math a ```` ```math ````
//! block (`docs/building.md`, "Contributor notes: equations"). Any other `$`, or a TeX command in plain
//! text, is math that Markdown rewrites before KaTeX sees it (`\,` loses its backslash, `U_*`
//! opens an emphasis). REPORT.md is read as GitHub reads it, with pulldown-cmark's math
//! extension (`$...$`, `$$...$$`). Set `REPORT_MD` to check another REPORT.md (one generated
//! into /tmp, say).

use std::fmt::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};

use pulldown_cmark::{CodeBlockKind, Event, Options, Parser, Tag, TagEnd};

/// rustdoc's `main_body_opts` (src/librustdoc/html/markdown.rs).
fn rustdoc_options() -> Options {
    Options::ENABLE_TABLES
        | Options::ENABLE_FOOTNOTES
        | Options::ENABLE_STRIKETHROUGH
        | Options::ENABLE_TASKLISTS
        | Options::ENABLE_SMART_PUNCTUATION
}

/// GitHub-flavoured Markdown with math, as REPORT.md is read.
fn report_options() -> Options {
    Options::ENABLE_TABLES
        | Options::ENABLE_FOOTNOTES
        | Options::ENABLE_STRIKETHROUGH
        | Options::ENABLE_TASKLISTS
        | Options::ENABLE_MATH
}

/// A Markdown text and where each of its lines comes from.
struct Document {
    file: String,
    markdown: String,
    /// 1-based source line of each Markdown line.
    source_lines: Vec<usize>,
}

impl Document {
    fn location(&self, offset: usize) -> String {
        let line = self.markdown[..offset].matches('\n').count();
        format!("{}:{}", self.file, self.source_lines[line])
    }
}

/// The doc comments of one source file: each run of consecutive `///` (or `//!`) lines, with
/// the markers and the common indentation removed, as rustdoc hands them to Markdown.
fn doc_comments(file: &str, text: &str) -> Vec<Document> {
    let mut documents = Vec::new();
    let mut current: Option<(&str, Vec<(usize, &str)>)> = None;
    for (index, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        let doc = if trimmed.starts_with("////") {
            None
        } else {
            ["///", "//!"]
                .into_iter()
                .find_map(|marker| Some((marker, trimmed.strip_prefix(marker)?)))
        };
        match (doc, &mut current) {
            (Some((marker, body)), Some((kind, lines))) if marker == *kind => {
                lines.push((index + 1, body));
            }
            (doc, current) => {
                if let Some((_, lines)) = current.take() {
                    documents.push(unindent(file, &lines));
                }
                *current = doc.map(|(marker, body)| (marker, vec![(index + 1, body)]));
            }
        }
    }
    if let Some((_, lines)) = current {
        documents.push(unindent(file, &lines));
    }
    documents
}

fn unindent(file: &str, lines: &[(usize, &str)]) -> Document {
    let indent = lines
        .iter()
        .filter(|(_, body)| !body.trim().is_empty())
        .map(|(_, body)| body.len() - body.trim_start().len())
        .min()
        .unwrap_or(0);
    let markdown = lines
        .iter()
        .map(|(_, body)| body.get(indent..).unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    Document {
        file: file.to_string(),
        markdown,
        source_lines: lines.iter().map(|(line, _)| *line).collect(),
    }
}

/// What is wrong with a formula itself: empty, a control character, unbalanced braces,
/// `\left`/`\right` or environments, or a `$` inside it.
fn tex_problems(tex: &str) -> Vec<String> {
    let mut problems = Vec::new();
    if tex.trim().is_empty() {
        problems.push("empty math".to_string());
    }
    if let Some((_, c)) = control_character(tex) {
        problems.push(format!("control character U+{:04X}", c as u32));
    }
    let mut depth = 0i32;
    let mut environments = Vec::new();
    let mut lefts = 0;
    let mut rights = 0;
    let mut chars = tex.char_indices();
    while let Some((at, c)) = chars.next() {
        match c {
            '\\' => {
                let rest = &tex[at + 1..];
                let command: String = rest.chars().take_while(char::is_ascii_alphabetic).collect();
                match command.as_str() {
                    "" => {
                        chars.next();
                    }
                    "left" => lefts += 1,
                    "right" => rights += 1,
                    "begin" | "end" => {
                        let name = rest[command.len()..]
                            .strip_prefix('{')
                            .and_then(|r| r.split_once('}'))
                            .map_or("", |(name, _)| name);
                        if command == "begin" {
                            environments.push(name);
                        } else if environments.pop() != Some(name) {
                            problems.push(format!("\\end{{{name}}} without its \\begin"));
                        }
                    }
                    _ => {}
                }
                for _ in 0..command.len() {
                    chars.next();
                }
            }
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth < 0 {
                    problems.push("a `}` closes no `{`".to_string());
                    depth = 0;
                }
            }
            '$' => problems.push("a `$` inside math".to_string()),
            _ => {}
        }
    }
    if depth > 0 {
        problems.push(format!("{depth} unclosed `{{`"));
    }
    if lefts != rights {
        problems.push(format!("{lefts} \\left against {rights} \\right"));
    }
    for name in environments {
        problems.push(format!("\\begin{{{name}}} without its \\end"));
    }
    problems
}

/// A TeX command (`\frac`, `\,`, `\;`, `\!`) in text that is not math: Markdown keeps the
/// letters and eats the punctuation, so the formula it belonged to is garbled.
fn tex_in_text(source: &str) -> Option<(usize, &str)> {
    source.match_indices('\\').find_map(|(at, _)| {
        let rest = &source[at + 1..];
        let letters = rest.len()
            - rest
                .trim_start_matches(|c: char| c.is_ascii_alphabetic())
                .len();
        let length = match rest.chars().next()? {
            c if c.is_ascii_alphabetic() => letters,
            ',' | ';' | ':' | '!' => 1,
            _ => return None,
        };
        Some((at, &source[at..at + 1 + length]))
    })
}

/// A character other than a line break or a tab that no renderer shows: a `\f` that went
/// through a string escape became a form feed once.
fn control_character(text: &str) -> Option<(usize, char)> {
    text.char_indices()
        .find(|(_, c)| c.is_control() && !matches!(c, '\n' | '\t'))
}

/// The inline content of the HTML as the browser holds it: adjacent text merges into one text
/// node (kept here as the parser's pieces, each with its source range), any element boundary
/// separates nodes.
enum Node {
    Text(Vec<(String, Range<usize>)>),
    Code(String, Range<usize>),
    Boundary(&'static str),
}

impl Node {
    fn text_ends_with_dollar(&self) -> bool {
        matches!(self, Node::Text(pieces) if pieces.last().is_some_and(|(t, _)| t.ends_with('$')))
    }

    fn text_starts_with_dollar(&self) -> bool {
        matches!(self, Node::Text(pieces) if pieces.first().is_some_and(|(t, _)| t.starts_with('$')))
    }
}

/// The text between a code span's backticks as CommonMark defines its content: line endings
/// become spaces and one space on each side is dropped when both are there.
fn code_span_source(source: &str) -> String {
    let inner = source.trim_matches('`');
    let mut joined = String::new();
    let mut lines = inner.split('\n');
    joined.push_str(lines.next().unwrap_or(""));
    for line in lines {
        joined.push(' ');
        joined.push_str(line.trim_start());
    }
    if joined.len() >= 2
        && joined.starts_with(' ')
        && joined.ends_with(' ')
        && !joined.trim().is_empty()
    {
        joined = joined[1..joined.len() - 1].to_string();
    }
    joined
}

fn check_doc_comment(document: &Document, problems: &mut Vec<String>) {
    let markdown = &document.markdown;
    if let Some((at, c)) = control_character(markdown) {
        problems.push(format!(
            "{}: control character U+{:04X} in a doc comment",
            document.location(at),
            c as u32
        ));
    }
    let mut nodes = Vec::new();
    let mut math_block: Option<(String, usize)> = None;
    let mut other_block = false;
    for (event, range) in Parser::new_ext(markdown, rustdoc_options()).into_offset_iter() {
        match event {
            Event::Start(Tag::CodeBlock(kind)) => match kind {
                CodeBlockKind::Fenced(lang) if lang.as_ref() == "math" => {
                    math_block = Some((String::new(), range.start));
                }
                _ => other_block = true,
            },
            Event::End(TagEnd::CodeBlock) => {
                if let Some((tex, at)) = math_block.take() {
                    for problem in tex_problems(&tex) {
                        problems.push(format!(
                            "{}: ```math block: {problem}",
                            document.location(at)
                        ));
                    }
                }
                other_block = false;
            }
            Event::Text(text) if math_block.is_some() => {
                math_block.as_mut().expect("inside").0.push_str(&text);
            }
            _ if other_block => {}
            Event::Text(_) | Event::SoftBreak => {
                let text = match event {
                    Event::Text(text) => text.into_string(),
                    _ => "\n".to_string(),
                };
                match nodes.last_mut() {
                    Some(Node::Text(pieces)) => pieces.push((text, range)),
                    _ => nodes.push(Node::Text(vec![(text, range)])),
                }
            }
            Event::Code(code) => nodes.push(Node::Code(code.into_string(), range)),
            Event::Start(Tag::Emphasis) => nodes.push(Node::Boundary("<em>")),
            Event::End(TagEnd::Emphasis) => nodes.push(Node::Boundary("</em>")),
            Event::Start(Tag::Strong) => nodes.push(Node::Boundary("<strong>")),
            Event::End(TagEnd::Strong) => nodes.push(Node::Boundary("</strong>")),
            _ => nodes.push(Node::Boundary(" ")),
        }
    }
    // The header's rule: a code element whose neighbours are text ending and starting with `$`.
    let mut flank_used = vec![(false, false); nodes.len()];
    for (i, node) in nodes.iter().enumerate() {
        let Node::Code(tex, range) = node else {
            continue;
        };
        let before = i > 0 && nodes[i - 1].text_ends_with_dollar();
        let after = nodes.get(i + 1).is_some_and(Node::text_starts_with_dollar);
        if !(before && after) {
            continue;
        }
        flank_used[i - 1].1 = true;
        flank_used[i + 1].0 = true;
        let written = code_span_source(&markdown[range.clone()]);
        if *tex != written {
            problems.push(format!(
                "{}: math written as `{written}` reaches KaTeX as `{tex}`",
                document.location(range.start)
            ));
        }
        for problem in tex_problems(tex) {
            problems.push(format!(
                "{}: $`{tex}`$: {problem}",
                document.location(range.start)
            ));
        }
    }
    for (i, node) in nodes.iter().enumerate() {
        let Node::Text(pieces) = node else {
            continue;
        };
        let (first_used, last_used) = flank_used[i];
        for (p, (text, range)) in pieces.iter().enumerate() {
            let is_flank = |at: usize| {
                (first_used && p == 0 && at == 0)
                    || (last_used && p + 1 == pieces.len() && at + 1 == text.len())
            };
            if let Some(at) = text
                .match_indices('$')
                .map(|(at, _)| at)
                .find(|&at| !is_flank(at))
            {
                problems.push(format!(
                    "{}: `$` outside the math convention (inline math is $`...`$); rendered as «{}»",
                    document.location(range.start),
                    rendered_from(&text[at..], &pieces[p + 1..], &nodes[i + 1..])
                ));
            }
        }
        // An escape is a piece of its own whose range may skip the backslash: read the source
        // of the whole node.
        let start = pieces.first().map_or(0, |(_, range)| range.start);
        let end = pieces.last().map_or(0, |(_, range)| range.end);
        if let Some((at, command)) = tex_in_text(&markdown[start..end]) {
            problems.push(format!(
                "{}: TeX `{command}` outside math, Markdown rewrites it",
                document.location(start + at)
            ));
        }
    }
}

/// The HTML from a stray `$` on, for the message: shows what emphasis and escapes did.
fn rendered_from(text: &str, pieces: &[(String, Range<usize>)], nodes: &[Node]) -> String {
    let mut out = text.to_string();
    pieces.iter().for_each(|(piece, _)| out.push_str(piece));
    for node in nodes {
        if out.chars().count() > 160 {
            break;
        }
        match node {
            Node::Text(pieces) => pieces.iter().for_each(|(piece, _)| out.push_str(piece)),
            Node::Code(code, _) => {
                let _ = write!(out, "<code>{code}</code>");
            }
            Node::Boundary(tag) => out.push_str(tag),
        }
    }
    out.replace('\n', " ").chars().take(160).collect()
}

fn check_report(document: &Document, problems: &mut Vec<String>) {
    let markdown = &document.markdown;
    if let Some((at, c)) = control_character(markdown) {
        problems.push(format!(
            "{}: control character U+{:04X}",
            document.location(at),
            c as u32
        ));
    }
    let mut in_code = false;
    for (event, range) in Parser::new_ext(markdown, report_options()).into_offset_iter() {
        match event {
            Event::Start(Tag::CodeBlock(_)) => in_code = true,
            Event::End(TagEnd::CodeBlock) => in_code = false,
            Event::InlineMath(tex) | Event::DisplayMath(tex) => {
                let written = markdown[range.clone()].trim_matches('$');
                if *tex != *written {
                    problems.push(format!(
                        "{}: math written as `{written}` is read as `{tex}`",
                        document.location(range.start)
                    ));
                }
                for problem in tex_problems(&tex) {
                    problems.push(format!(
                        "{}: ${tex}$: {problem}",
                        document.location(range.start)
                    ));
                }
            }
            Event::Text(text) if !in_code => {
                if text.contains('$') {
                    problems.push(format!(
                        "{}: a `$` that opens no math: «{text}»",
                        document.location(range.start)
                    ));
                }
                // An escaped character's range starts after its backslash.
                let from = range.start - usize::from(markdown[..range.start].ends_with('\\'));
                if let Some((_, command)) = tex_in_text(&markdown[from..range.end]) {
                    problems.push(format!(
                        "{}: TeX `{command}` outside math",
                        document.location(range.start)
                    ));
                }
            }
            _ => {}
        }
    }
}

fn rust_files(dir: &Path, files: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("src/ reads")
        .map(|entry| entry.expect("directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(&path, files);
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
}

fn doc_comment_problems(file: &str, text: &str) -> Vec<String> {
    let mut problems = Vec::new();
    for document in doc_comments(file, text) {
        check_doc_comment(&document, &mut problems);
    }
    problems
}

fn report_problems(file: &str, text: &str) -> Vec<String> {
    let document = Document {
        file: file.to_string(),
        markdown: text.to_string(),
        source_lines: (1..=text.lines().count() + 1).collect(),
    };
    let mut problems = Vec::new();
    check_report(&document, &mut problems);
    problems
}

#[test]
fn doc_comment_math_reaches_katex_intact() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    let mut problems = Vec::new();
    let mut segments = 0;
    for path in &files {
        let text = std::fs::read_to_string(path).expect("source reads");
        let name = path
            .strip_prefix(root)
            .expect("under the root")
            .display()
            .to_string();
        problems.extend(doc_comment_problems(&name, &text));
        segments += text.matches("$`").count() + text.matches("```math").count();
    }
    assert!(
        segments > 300,
        "only {segments} math segments found in src/: the scan is broken"
    );
    assert!(
        problems.is_empty(),
        "{} problems:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn report_math_reaches_the_reader_intact() {
    let path = std::env::var_os("REPORT_MD").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("report/REPORT.md"),
        PathBuf::from,
    );
    let text = std::fs::read_to_string(&path).expect("REPORT.md reads");
    let problems = report_problems(&path.display().to_string(), &text);
    assert!(
        text.matches('$').count() > 100,
        "REPORT.md has almost no math: wrong file?"
    );
    assert!(
        problems.is_empty(),
        "{} problems:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

/// The checker itself: each kind of damage the issue names is caught, and good math passes.
#[test]
fn the_checker_catches_what_markdown_does_to_math() {
    let good = "/// Newton on $`r(v) = M(v - v_n) - dt\\,F(x_n + dt\\,v)`$ with $`U_*(z)`$ and\n\
                /// $`\\lVert x - \\tilde x \\rVert_M^2`$:\n\
                /// ```math\n\
                /// (M - dt^2 K)\\,v = M v_n \\\\ K = \\tfrac{dF}{dx}\n\
                /// ```\n\
                fn f() {}\n";
    assert_eq!(doc_comment_problems("good.rs", good), Vec::<String>::new());

    let broken = [
        ("/// the step $r(v) = dt\\,F$.\n", "`$` outside"),
        ("/// $U_*(z)$ and $|x - y|_M^2$\n", "`$` outside"),
        ("/// dt\\,F without dollars\n", "TeX `\\,`"),
        ("/// $`\\sum \u{c}rac12 k`$\n", "U+000C"),
        ("/// $`\\frac{1}{2`$\n", "unclosed"),
        ("/// $`\\left( x`$\n", "\\left"),
        ("/// $`x`\n", "`$` outside"),
        (
            "/// ```math\n/// \\begin{aligned} x \\end{array}\n/// ```\n",
            "\\end{array}",
        ),
    ];
    for (source, expected) in broken {
        let problems = doc_comment_problems("broken.rs", source);
        assert!(
            problems.iter().any(|p| p.contains(expected)),
            "{source:?} should give a problem containing {expected:?}, gave {problems:?}"
        );
    }
    let emphasis = doc_comment_problems(
        "admm.rs",
        "//! $f(x) = \\frac{1}{2dt^2}|x - \\tilde x|_M^2$,\n//! $g(z) = U_*(z)$ (the springs' energy)\n",
    );
    assert!(emphasis[0].contains("<em>"), "{emphasis:?}");

    assert_eq!(
        report_problems("ok.md", "$a\\,b$ and\n\n$$\\frac12$$\n"),
        Vec::<String>::new()
    );
    for (source, expected) in [
        ("| a | b |\n|---|---|\n| $x|y$ | c |\n", "opens no math"),
        ("text \\frac12\n", "TeX `\\frac"),
        ("dt\\,F without dollars\n", "TeX `\\,`"),
        ("$\\left( x$\n", "\\left"),
        ("a \u{c}orm feed\n", "U+000C"),
    ] {
        let problems = report_problems("bad.md", source);
        assert!(
            problems.iter().any(|p| p.contains(expected)),
            "{source:?} should give a problem containing {expected:?}, gave {problems:?}"
        );
    }
}

//! The README names only what exists: every relative link and every path in a code span is a
//! file or directory of the repository, every `--test NAME` a test target of `tests/`, every
//! `make TARGET` a target of the Makefile; and its count of reproduced rows is the report's.
//! The negative case: a README naming a stale test file, test target, make target and link
//! fails on each.

use std::path::Path;

/// The test targets of `tests/`: `tests/NAME.rs` or `tests/NAME/main.rs`.
fn test_target_exists(root: &Path, name: &str) -> bool {
    root.join("tests").join(format!("{name}.rs")).is_file()
        || root.join("tests").join(name).join("main.rs").is_file()
}

/// The Makefile's targets: `name:` at the start of a line.
fn make_targets(root: &Path) -> Vec<String> {
    std::fs::read_to_string(root.join("Makefile"))
        .unwrap()
        .lines()
        .filter_map(|l| l.split_once(':').map(|(t, _)| t))
        .filter(|t| !t.is_empty() && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '-'))
        .map(String::from)
        .collect()
}

/// The words that follow `marker` in `text` (`--test thesis` → `thesis`).
fn words_after<'a>(text: &'a str, marker: &str) -> Vec<&'a str> {
    text.match_indices(marker)
        .filter_map(|(i, _)| {
            text[i + marker.len()..]
                .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-'))
                .next()
        })
        .filter(|w| !w.is_empty())
        .collect()
}

/// The relative link targets of Markdown links and images, anchors dropped.
fn link_targets(text: &str) -> Vec<&str> {
    text.match_indices("](")
        .filter_map(|(i, _)| {
            let rest = &text[i + 2..];
            let target = &rest[..rest.find(')')?];
            let target = target.split('#').next()?;
            (!target.is_empty() && !target.contains("://")).then_some(target)
        })
        .collect()
}

/// Paths in code spans: a span that starts with a directory of the repository.
fn code_paths(text: &str) -> Vec<&str> {
    const ROOTS: [&str; 8] = [
        "src/",
        "tests/",
        "docs/",
        "report/",
        "data/",
        "benches/",
        "snapshots/",
        "scenes/",
    ];
    text.split('`')
        .skip(1)
        .step_by(2)
        .filter(|span| ROOTS.iter().any(|r| span.starts_with(r)))
        .filter(|span| !span.contains(['*', ' ']))
        .collect()
}

/// Everything the README names that does not exist.
fn problems(readme: &str, root: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for target in link_targets(readme).into_iter().chain(code_paths(readme)) {
        if !root.join(target).exists() {
            out.push(format!("{target} does not exist"));
        }
    }
    for name in words_after(readme, "--test ") {
        if !test_target_exists(root, name) {
            out.push(format!("--test {name}: no such test target"));
        }
    }
    let targets = make_targets(root);
    for name in words_after(readme, "make ") {
        if !targets.iter().any(|t| t == name) {
            out.push(format!("make {name}: no such Makefile target"));
        }
    }
    out
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn everything_the_readme_names_exists() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let found = problems(&readme, root());
    assert!(found.is_empty(), "{found:#?}");
    assert!(readme.lines().count() <= 150, "the README is a front page");
    // It names the two commands, and the make targets it names were found.
    assert!(readme.contains("make report") && readme.contains("make test"));
}

#[test]
fn a_stale_name_fails() {
    let stale = "Run `cargo test --test report` after `make everything`; see \
                 `tests/report.rs` and [the notes](docs/notes.md). \
                 Fine: `cargo test --test thesis`, `make test`, [report](report/REPORT.md).";
    let found = problems(stale, root());
    assert_eq!(
        found,
        [
            "docs/notes.md does not exist",
            "tests/report.rs does not exist",
            "--test report: no such test target",
            "make everything: no such Makefile target",
        ],
        "{found:#?}"
    );
}

/// Everything REPORT.md links to or names in a code span that does not exist: links relative to
/// `report/`, code-span paths relative to `report/` for the report's own files (`data/`,
/// `figures/`, `long/`, `timing/`) and to the repository otherwise, a `:line` suffix dropped;
/// glob patterns are left out.
fn report_problems(report: &str, root: &Path) -> Vec<String> {
    const REPORT_DIRS: [&str; 4] = ["data/", "figures/", "long/", "timing/"];
    const REPOSITORY_DIRS: [&str; 6] = [
        "src/",
        "tests/",
        "docs/",
        "presentation/",
        "benches/",
        "snapshots/",
    ];
    let mut out = Vec::new();
    for target in link_targets(report) {
        if !root.join("report").join(target).exists() {
            out.push(format!("link {target} does not exist"));
        }
    }
    for span in report.split('`').skip(1).step_by(2) {
        if span.contains(['*', ' ', '[']) {
            continue;
        }
        let path = span.split(':').next().unwrap_or(span);
        let base = if REPORT_DIRS.iter().any(|d| path.starts_with(d)) {
            root.join("report")
        } else if REPOSITORY_DIRS.iter().any(|d| path.starts_with(d)) {
            root.to_path_buf()
        } else {
            continue;
        };
        if !base.join(path).exists() {
            out.push(format!("{path} does not exist"));
        }
    }
    out
}

/// Every link and every file REPORT.md cites resolves in the project. Negative case: a cited
/// file that was moved (`src/solvers/registry.rs`, a directory since) and a link to a missing
/// figure are reported.
#[test]
fn every_link_and_cited_file_of_the_report_resolves() {
    let report = std::fs::read_to_string(root().join("report/REPORT.md")).unwrap();
    let found = report_problems(&report, root());
    assert!(found.is_empty(), "{found:#?}");
    let stale = "See `src/solvers/registry.rs:12`, ![x](figures/none.svg), `docs/papers.md`, \
                 `data/results.csv` and `data/benchmark_*.csv`.";
    assert_eq!(
        report_problems(stale, root()),
        [
            "link figures/none.svg does not exist",
            "src/solvers/registry.rs does not exist"
        ]
    );
}

/// The numbers a template reads in `text` (whitespace flattened): the text between its `{}`
/// holes is matched literally, each hole reads one number (digits and points); None where the
/// template matches nowhere.
fn read(text: &str, template: &str) -> Option<Vec<String>> {
    let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let parts: Vec<&str> = template.split("{}").collect();
    // The first place where the whole template matches.
    flat.match_indices(parts[0]).find_map(|(at, _)| {
        let mut rest = &flat[at + parts[0].len()..];
        let mut found = Vec::new();
        for literal in &parts[1..] {
            let end = rest
                .find(|c: char| !(c.is_ascii_digit() || c == '.'))
                .unwrap_or(rest.len());
            if end == 0 {
                return None;
            }
            found.push(rest[..end].to_string());
            rest = rest[end..].strip_prefix(literal)?;
        }
        Some(found)
    })
}

/// Each claim of the README's headline results, as the README words it and as the report's
/// findings (or its figure caption) word the same claim: the numbers must be the same, claim
/// by claim, not merely present somewhere in the findings.
const CLAIMS: [(&str, &str); 6] = [
    (
        "reproduce {} of the {} published rows not used to fit",
        "reproduce {} of the {} published rows not used to fit",
    ),
    (
        "need {}× (Chebyshev ADMM)",
        "Chebyshev ADMM {}× fewer than ADMM",
    ),
    (
        "to {}× (Anderson Fast m-s)",
        "Anderson Fast m-s {}× fewer than Fast m-s",
    ),
    (
        "Anderson ADMM's ratio, {}× from one start, moves over {}-{}×",
        "Anderson ADMM {}× ({}-{}×) fewer",
    ),
    ("Kendall τ-b = {},", "Kendall τ-b = {} ("),
    (
        "(Figure {} of the report)",
        "<a id=\"f{}\"></a>![Figure 25](figures/benchmark_rope_k1e3.svg)",
    ),
];

/// The claims of `readme` whose numbers differ from the report's (or that either text lacks).
fn claims_differing(readme: &str, report: &str) -> Vec<String> {
    let headline = readme
        .split("## Headline results")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("a Headline results section");
    CLAIMS
        .iter()
        .filter_map(|(ours, theirs)| {
            let (a, b) = (read(headline, ours), read(report, theirs));
            (a.is_none() || a != b).then(|| format!("{ours}: README {a:?}, report {b:?}"))
        })
        .collect()
}

/// Each number of the README's headline results is the report's, claim by claim. Negative
/// cases: a README saying 11.7× for Chebyshev ADMM, or swapping the two ends of Anderson ADMM's
/// range, is caught (the old check, a bag of the findings' numbers, passed the swap).
#[test]
fn the_readmes_numbers_are_the_reports() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let report = std::fs::read_to_string(root().join("report/REPORT.md")).unwrap();
    let differing = claims_differing(&readme, &report);
    assert!(differing.is_empty(), "{differing:#?}");
    let range = read(&readme, CLAIMS[3].0).unwrap();
    let swapped = readme.replace(
        &format!("{}-{}×", range[1], range[2]),
        &format!("{}-{}×", range[2], range[1]),
    );
    let wrong = swapped.replace("11.3×", "11.7×");
    assert_eq!(claims_differing(&wrong, &report).len(), 2);
}

/// The README's count of reproduced rows and the rows it counts from, "N of the M published
/// rows not used to fit the scene", are the report's (whose findings compute them).
#[test]
fn the_readmes_count_of_reproduced_rows_is_the_reports() {
    let phrase = |text: &str| {
        let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
        let at = flat
            .find(" published rows not used to fit the scene")
            .unwrap();
        let words: Vec<&str> = flat[..at].rsplit(' ').take(4).collect();
        words.join(" ")
    };
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let report = std::fs::read_to_string(root().join("report/REPORT.md")).unwrap();
    assert_eq!(phrase(&readme), phrase(&report));
}

/// `make test` runs `tests/thesis` beside the other test binaries, which it names by a
/// wildcard over the files `tests/*.rs` and `presentation/tests/*.rs`: a test target in a
/// directory of its own (`NAME/main.rs`) other than `thesis` would be left out of both. So
/// `thesis` must be the only one, and the Makefile must still run it and the wildcard.
#[test]
fn make_test_runs_every_test_target() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut in_directories = Vec::new();
    for tests in [root.join("tests"), root.join("presentation/tests")] {
        for entry in std::fs::read_dir(&tests).unwrap() {
            let path = entry.unwrap().path();
            if path.join("main.rs").is_file() {
                in_directories.push(path.strip_prefix(root).unwrap().display().to_string());
            }
        }
    }
    assert_eq!(
        in_directories,
        ["tests/thesis"],
        "make test runs only tests/thesis of these"
    );
    let makefile = std::fs::read_to_string(root.join("Makefile")).unwrap();
    for line in [
        "$(CARGO) test --test thesis",
        "$(wildcard tests/*.rs presentation/tests/*.rs)",
        "$(CARGO) test --lib --bins $(OTHER_TESTS)",
    ] {
        assert!(
            makefile.contains(line),
            "the Makefile's test target runs {line}"
        );
    }
}

/// The files of `tests/` are test targets listed in the two manifests (the root's `autotests =
/// false`; the tests that read the report are the presentation crate's): each must be a target
/// of exactly one package, or cargo would not build it, or would build it twice.
#[test]
fn each_test_file_is_a_target_of_one_package() {
    // A root target's file follows from its name; a presentation target's is written out.
    let mut listed: Vec<String> = test_targets("Cargo.toml")
        .iter()
        .map(|t| format!("tests/{}.rs", t["name"].as_str().unwrap()))
        .collect();
    for t in test_targets("presentation/Cargo.toml") {
        let path = t["path"].as_str().unwrap();
        listed.push(path.strip_prefix("../").unwrap().to_string());
    }
    listed.sort();
    let mut files = Vec::new();
    for entry in std::fs::read_dir(root().join("tests")).unwrap() {
        let path = entry.unwrap().path();
        let relative = path.strip_prefix(root()).unwrap();
        if path.extension().is_some_and(|e| e == "rs") {
            files.push(relative.display().to_string());
        } else if path.join("main.rs").is_file() {
            files.push(relative.join("main.rs").display().to_string());
        }
    }
    files.sort();
    assert_eq!(
        listed, files,
        "each file of tests/ is a test target of one package"
    );
}

/// The `[[test]]` tables of the manifest at `path` (relative to the repository).
fn test_targets(path: &str) -> Vec<toml::Table> {
    let text = std::fs::read_to_string(root().join(path)).unwrap();
    let manifest: toml::Table = toml::from_str(&text).unwrap();
    manifest
        .get("test")
        .and_then(|t| t.as_array())
        .map_or(Vec::new(), |targets| {
            targets
                .iter()
                .map(|t| t.as_table().unwrap().clone())
                .collect()
        })
}

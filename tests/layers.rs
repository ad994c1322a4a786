//! The crate's layers (`src/lib.rs`'s module doc) kept: no module imports from a layer below it
//! in that list, and no two modules import each other, directly or through others.
//!
//! The imports are read from the source text: every path `crate::a::b::…` (in a `use`, a
//! `use crate::{…}` group or inline), every `super::…`, and a folder module's uses of its own
//! files (`child::…`, except its `pub use child::…` re-exports, which are the folder's face and
//! not a use). Comments and test modules (from `#[cfg(test)]` on) are not read. Each path goes
//! to the longest module it names.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The layers, lowest first (`src/lib.rs`): a module may import from its own layer and the
/// ones before it. `error` is shared by all.
const LAYERS: [&str; 7] = [
    "error",
    "platform",
    "model",
    "integrators",
    "particles",
    "solvers",
    "studies",
];

/// A module's path (`model::spring`) and the text of its file.
type Modules = BTreeMap<String, String>;

fn read_modules(src: &Path) -> Modules {
    fn walk(dir: &Path, prefix: &[String], out: &mut Modules) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for path in entries {
            let name = path.file_stem().unwrap().to_str().unwrap().to_string();
            if path.is_dir() {
                if prefix.is_empty() && name == "bin" {
                    continue;
                }
                let mut p = prefix.to_vec();
                p.push(name);
                walk(&path, &p, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let mut p = prefix.to_vec();
                if !matches!(name.as_str(), "mod" | "lib" | "main") {
                    p.push(name);
                }
                out.insert(p.join("::"), std::fs::read_to_string(&path).unwrap());
            }
        }
    }
    let mut out = Modules::new();
    walk(src, &[], &mut out);
    out
}

/// The code of a file without its comments and test module.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap();
    text.lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// Identifiers and `::` of a path that starts at byte `at`, with `{…}` groups expanded: every
/// full path the group names.
fn paths_from(text: &str, at: usize) -> Vec<Vec<String>> {
    let bytes = text.as_bytes();
    let mut i = at;
    let mut prefix = Vec::new();
    loop {
        let start = i;
        while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
            i += 1;
        }
        if i > start {
            prefix.push(text[start..i].to_string());
        }
        if text[i..].starts_with("::") {
            i += 2;
            if text[i..].starts_with('{') {
                // The group's items, split at its top-level commas.
                let mut depth = 0;
                let mut item_start = i + 1;
                let mut out = Vec::new();
                for (k, c) in text[i..].char_indices() {
                    let k = i + k;
                    match c {
                        '{' => depth += 1,
                        '}' | ',' if depth == 1 => {
                            let item = text[item_start..k].trim();
                            if !item.is_empty() {
                                for rest in paths_from(item, 0) {
                                    out.push([prefix.clone(), rest].concat());
                                }
                            }
                            item_start = k + 1;
                            if c == '}' {
                                return out;
                            }
                        }
                        '}' => depth -= 1,
                        _ => {}
                    }
                }
                return out;
            }
        } else {
            return vec![prefix];
        }
    }
}

/// The modules `module` imports.
fn imports(modules: &Modules, module: &str) -> BTreeSet<String> {
    let text = code(&modules[module]);
    let own: Vec<&str> = if module.is_empty() {
        vec![]
    } else {
        module.split("::").collect()
    };
    // A path that names no module names an item of the crate root.
    let resolve = |path: &[String]| -> Option<String> {
        (1..=path.len())
            .rev()
            .map(|k| path[..k].join("::"))
            .find(|m| modules.contains_key(m))
            .or_else(|| (!path.is_empty()).then(String::new))
    };
    let children: Vec<String> = modules
        .keys()
        .filter_map(|m| {
            let rest = if module.is_empty() {
                m.as_str()
            } else {
                m.strip_prefix(module)?.strip_prefix("::")?
            };
            (!rest.is_empty() && !rest.contains("::")).then(|| rest.to_string())
        })
        .collect();
    let mut out = BTreeSet::new();
    let starts = |word: &str| -> Vec<usize> {
        text.match_indices(word)
            .filter(|(i, _)| {
                *i == 0 || {
                    let b = text.as_bytes()[i - 1];
                    !(b.is_ascii_alphanumeric() || b == b'_' || b == b':')
                }
            })
            .map(|(i, _)| i)
            .collect()
    };
    for at in starts("crate::") {
        for path in paths_from(&text, at + "crate::".len()) {
            out.extend(resolve(&path));
        }
    }
    for at in starts("super::") {
        let parent = &own[..own.len().saturating_sub(1)];
        for path in paths_from(&text, at + "super::".len()) {
            let full: Vec<String> = parent.iter().map(|s| s.to_string()).chain(path).collect();
            out.extend(resolve(&full));
        }
    }
    for child in &children {
        for at in starts(&format!("{child}::")) {
            let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
            if text[line_start..at].trim_start().starts_with("pub use") {
                continue;
            }
            for path in paths_from(&text, at) {
                let full: Vec<String> = own.iter().map(|s| s.to_string()).chain(path).collect();
                out.extend(resolve(&full));
            }
        }
    }
    out.remove(module);
    out
}

/// The layer of a module: the position of its first segment in [`LAYERS`]; the crate root's
/// items (its re-exports: `crate::Vec3`) are shared like `error`'s.
fn layer(module: &str) -> usize {
    if module.is_empty() {
        return 0;
    }
    let first = module.split("::").next().unwrap();
    LAYERS
        .iter()
        .position(|l| *l == first)
        .unwrap_or(LAYERS.len())
}

/// Every import that goes to a higher layer, as `from -> to`.
fn upward(modules: &Modules) -> Vec<String> {
    let mut out = Vec::new();
    for m in modules.keys().filter(|m| !m.is_empty()) {
        for to in imports(modules, m) {
            if layer(&to) > layer(m) {
                out.push(format!("{m} -> {to}"));
            }
        }
    }
    out
}

/// The import circles: the strongly connected components of more than one module (Tarjan).
/// The crate root (`lib.rs`, `main.rs`) is one of the modules, named `""`.
fn circles(modules: &Modules) -> Vec<Vec<String>> {
    let names: Vec<&String> = modules.keys().collect();
    let index_of: BTreeMap<&str, usize> = names
        .iter()
        .enumerate()
        .map(|(i, m)| (m.as_str(), i))
        .collect();
    let edges: Vec<Vec<usize>> = names
        .iter()
        .map(|m| {
            imports(modules, m)
                .iter()
                .filter_map(|t| index_of.get(t.as_str()).copied())
                .collect()
        })
        .collect();
    struct Tarjan<'a> {
        edges: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        stack: Vec<usize>,
        on_stack: Vec<bool>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    impl Tarjan<'_> {
        fn visit(&mut self, v: usize) {
            self.index[v] = Some(self.next);
            self.low[v] = self.next;
            self.next += 1;
            self.stack.push(v);
            self.on_stack[v] = true;
            for &w in &self.edges[v] {
                match self.index[w] {
                    None => {
                        self.visit(w);
                        self.low[v] = self.low[v].min(self.low[w]);
                    }
                    Some(i) if self.on_stack[w] => self.low[v] = self.low[v].min(i),
                    Some(_) => {}
                }
            }
            if Some(self.low[v]) == self.index[v] {
                let mut component = Vec::new();
                loop {
                    let w = self.stack.pop().unwrap();
                    self.on_stack[w] = false;
                    component.push(w);
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    self.out.push(component);
                }
            }
        }
    }
    let n = names.len();
    let mut t = Tarjan {
        edges: &edges,
        index: vec![None; n],
        low: vec![0; n],
        stack: Vec::new(),
        on_stack: vec![false; n],
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            t.visit(v);
        }
    }
    t.out
        .into_iter()
        .map(|c| {
            let mut c: Vec<String> = c.into_iter().map(|i| names[i].clone()).collect();
            c.sort();
            c
        })
        .collect()
}

fn modules_of(dir: &str) -> Modules {
    read_modules(&Path::new(env!("CARGO_MANIFEST_DIR")).join(dir))
}

fn science() -> Modules {
    modules_of("src")
}

#[test]
fn every_layer_imports_only_from_the_layers_before_it() {
    let modules = science();
    assert!(modules.len() > 60, "read {} modules", modules.len());
    for m in modules.keys().filter(|m| !m.is_empty()) {
        assert!(layer(m) < LAYERS.len(), "{m} is in no layer of src/lib.rs");
    }
    assert_eq!(upward(&modules), Vec::<String>::new());
}

#[test]
fn no_module_imports_itself_through_others() {
    assert_eq!(circles(&science()), Vec::<Vec<String>>::new());
}

#[test]
fn the_presentation_crate_and_the_binaries_have_no_circle() {
    for dir in [
        "presentation/src",
        "src/bin/mss",
        "presentation/src/bin/timing",
    ] {
        let modules = modules_of(dir);
        assert!(modules.len() > 3, "{dir}: read {} modules", modules.len());
        assert_eq!(circles(&modules), Vec::<Vec<String>>::new(), "{dir}");
    }
}

#[test]
fn the_checks_find_an_upward_import_and_a_circle() {
    let modules: Modules = [
        ("", "pub mod model;\npub mod solvers;\n"),
        (
            "model",
            "pub mod spring;\npub mod system;\npub use system::State;\n",
        ),
        // A circle through a group, an upward import inline.
        (
            "model::spring",
            "use crate::model::{system::Vec3};\nfn f() { crate::solvers::xpbd::step() }\n",
        ),
        (
            "model::system",
            "use super::spring; // crate::solvers in a comment is no import\n",
        ),
        ("solvers", "pub mod xpbd;\n"),
        (
            "solvers::xpbd",
            "use crate::model::system::State;\n#[cfg(test)]\nuse crate::solvers;\n",
        ),
    ]
    .into_iter()
    .map(|(m, t)| (m.to_string(), t.to_string()))
    .collect();
    assert_eq!(
        upward(&modules),
        vec!["model::spring -> solvers::xpbd".to_string()]
    );
    assert_eq!(
        circles(&modules),
        vec![vec![
            "model::spring".to_string(),
            "model::system".to_string(),
            "solvers::xpbd".to_string(),
        ]]
    );
    // The folder's `pub use` re-export is not a use: `model` is in no circle with its files.
    assert!(imports(&modules, "model").is_empty());
    // A module that uses an item of the crate root, which uses the module: a circle.
    let mut with_root = modules.clone();
    with_root.insert(
        String::new(),
        "pub mod solvers;\npub struct Data;\nfn f() { solvers::xpbd::step() }\n".into(),
    );
    with_root.insert("solvers::xpbd".into(), "use crate::Data;\n".into());
    assert!(circles(&with_root).contains(&vec![String::new(), "solvers::xpbd".to_string()]));
}

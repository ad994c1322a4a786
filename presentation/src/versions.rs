//! The crate's version and the direct dependencies of the workspace's two crates (the science
//! crate's `Cargo.toml`, the presentation's `presentation/Cargo.toml`) with their resolved
//! versions, read with `Cargo.lock` at report time.

use crate::format::MarkdownTable;
use mass_spring_solvers::error::{Error, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// A direct dependency and what it resolved to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Dependency {
    pub name: String,
    /// The workspace crate whose manifest names it.
    pub used_by: String,
    /// `normal` or `dev`.
    pub kind: &'static str,
    /// The version requirement in `Cargo.toml`.
    pub requirement: String,
    /// Features asked for, comma-separated (`default-features = false` shown as `no default`).
    pub features: String,
    /// The version in `Cargo.lock` (several if the lock holds several).
    pub resolved: String,
}

/// The crate and its direct dependencies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Versions {
    pub name: String,
    pub version: String,
    pub rust_version: String,
    pub dependencies: Vec<Dependency>,
}

#[derive(Deserialize)]
struct Lock {
    #[serde(default)]
    package: Vec<LockedPackage>,
}

#[derive(Deserialize)]
struct LockedPackage {
    name: String,
    version: String,
}

fn parse_error(file: &str, e: impl std::fmt::Display) -> Error {
    Error::Input(format!("parsing {file}: {e}"))
}

fn numbers(version: &str) -> Vec<u64> {
    version
        .split(['+', '-'])
        .next()
        .unwrap_or("")
        .split('.')
        .map_while(|p| p.trim_start_matches(['^', '=', '~']).parse().ok())
        .collect()
}

/// Whether `version` satisfies the caret requirement `requirement` (`"0.24"`, `"1"`, `"4.6"`).
fn caret_matches(requirement: &str, version: &str) -> bool {
    let (r, v) = (numbers(requirement), numbers(version));
    if r.is_empty() || v.len() < r.len() {
        return false;
    }
    // Components up to the first non-zero one must be equal; the rest may only grow.
    let fixed = r.iter().position(|&x| x != 0).unwrap_or(r.len() - 1);
    r[..=fixed] == v[..=fixed] && v[..r.len()] >= r[..]
}

impl Versions {
    /// Parses the manifest and the lock file's text.
    pub fn parse(manifest: &str, lock: &str) -> Result<Self> {
        let manifest: toml::Table =
            toml::from_str(manifest).map_err(|e| parse_error("Cargo.toml", e))?;
        let lock: Lock = toml::from_str(lock).map_err(|e| parse_error("Cargo.lock", e))?;
        let mut locked: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
        for p in &lock.package {
            locked.entry(&p.name).or_default().push(&p.version);
        }
        let package = manifest
            .get("package")
            .and_then(|p| p.as_table())
            .ok_or_else(|| parse_error("Cargo.toml", "no [package] table"))?;
        let field = |key: &str| {
            package
                .get(key)
                .and_then(|v| v.as_str())
                .unwrap_or("")
                .to_string()
        };
        let mut dependencies = Vec::new();
        for (section, kind) in [("dependencies", "normal"), ("dev-dependencies", "dev")] {
            let Some(table) = manifest.get(section).and_then(|t| t.as_table()) else {
                continue;
            };
            for (name, spec) in table {
                // The workspace's own crates (path dependencies) are not dependencies of it.
                if spec.as_table().is_some_and(|t| t.contains_key("path")) {
                    continue;
                }
                let (requirement, features) = match spec {
                    toml::Value::String(s) => (s.clone(), String::new()),
                    toml::Value::Table(t) => {
                        let requirement = t
                            .get("version")
                            .and_then(|v| v.as_str())
                            .unwrap_or("")
                            .to_string();
                        let mut features: Vec<String> = t
                            .get("features")
                            .and_then(|f| f.as_array())
                            .map(|f| {
                                f.iter()
                                    .filter_map(|v| v.as_str().map(String::from))
                                    .collect()
                            })
                            .unwrap_or_default();
                        if t.get("default-features").and_then(|v| v.as_bool()) == Some(false) {
                            features.insert(0, "no default".to_string());
                        }
                        (requirement, features.join(", "))
                    }
                    _ => (String::new(), String::new()),
                };
                let package_name = match spec {
                    toml::Value::Table(t) => {
                        t.get("package").and_then(|v| v.as_str()).unwrap_or(name)
                    }
                    _ => name,
                };
                let resolved = locked
                    .get(package_name)
                    .map(|versions| {
                        // Another major version of the same crate may be in the lock as some
                        // other crate's dependency: show the one the requirement selects.
                        let matching: Vec<&str> = versions
                            .iter()
                            .copied()
                            .filter(|v| caret_matches(&requirement, v))
                            .collect();
                        if matching.is_empty() {
                            versions.join(", ")
                        } else {
                            matching.join(", ")
                        }
                    })
                    .unwrap_or_else(|| "not in Cargo.lock".to_string());
                dependencies.push(Dependency {
                    name: name.clone(),
                    used_by: field("name"),
                    kind,
                    requirement,
                    features,
                    resolved,
                });
            }
        }
        Ok(Self {
            name: field("name"),
            version: field("version"),
            rust_version: field("rust-version"),
            dependencies,
        })
    }

    /// Reads `Cargo.toml`, `presentation/Cargo.toml` and `Cargo.lock` of the workspace at
    /// `root`: the science crate's name and version, both crates' dependencies.
    pub fn read(root: &Path) -> Result<Self> {
        let read = |file: &str| {
            std::fs::read_to_string(root.join(file))
                .map_err(|e| Error::Input(format!("reading {file}: {e}")))
        };
        let lock = read("Cargo.lock")?;
        let mut versions = Self::parse(&read("Cargo.toml")?, &lock)?;
        let presentation = Self::parse(&read("presentation/Cargo.toml")?, &lock)?;
        versions.dependencies.extend(presentation.dependencies);
        Ok(versions)
    }

    /// The dependencies as a Markdown table.
    pub fn table(&self) -> MarkdownTable {
        let mut t = MarkdownTable::new(&[
            "crate",
            "used by",
            "kind",
            "requirement",
            "features",
            "resolved (Cargo.lock)",
        ]);
        for d in &self.dependencies {
            t.row(vec![
                format!("`{}`", d.name),
                format!("`{}`", d.used_by),
                d.kind.to_string(),
                d.requirement.clone(),
                d.features.clone(),
                d.resolved.clone(),
            ]);
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_manifest_and_lock() {
        let manifest = "[package]\nname = \"a\"\nversion = \"0.1.0\"\nrust-version = \"1.85\"\n[dependencies]\nx = \"1\"\ny = { version = \"0.3\", default-features = false, features = [\"f\"] }\nw = { path = \"w\" }\n[dev-dependencies]\nz = \"2\"\n";
        let lock = "version = 4\n[[package]]\nname = \"x\"\nversion = \"1.2.3\"\n[[package]]\nname = \"x\"\nversion = \"2.0.1\"\n[[package]]\nname = \"y\"\nversion = \"0.3.7\"\n";
        let v = Versions::parse(manifest, lock).unwrap();
        assert_eq!(v.version, "0.1.0");
        assert_eq!(v.dependencies[0].resolved, "1.2.3");
        assert_eq!(v.dependencies[1].features, "no default, f");
        assert_eq!(v.dependencies[2].resolved, "not in Cargo.lock");
        assert_eq!(v.dependencies[2].kind, "dev");
        // The path dependency `w` (a crate of the workspace) is left out; each is `a`'s.
        assert_eq!(v.dependencies.len(), 3);
        assert!(v.dependencies.iter().all(|d| d.used_by == "a"));
        assert!(caret_matches("0.24", "0.24.4") && !caret_matches("0.24", "0.25.0"));
        assert!(
            caret_matches("4.6", "4.6.7")
                && !caret_matches("4.6", "4.5.9")
                && !caret_matches("2", "1.0.69")
        );
        assert!(caret_matches("1", "1.2.1+spec-1.1.0"));
    }
}

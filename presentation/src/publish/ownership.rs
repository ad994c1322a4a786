//! Whose the output directory is: the report's own manifest ([`MANIFEST`], in the exact format
//! [`manifest_text`] writes, every entry a regular file inside), a report from before
//! manifests, or an empty directory; and what in it the report may not replace (a mount point,
//! a directory this user cannot rename, a foreign entry where the new report writes). Every
//! check here runs before anything is written.

use super::files::{io_error, sorted_entries, MANIFEST, MANIFEST_HEADER, REPORT_TITLE};
use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::platform::paths::{describe_file_type, is_mount_point, mount_points};
use std::collections::BTreeSet;
use std::ffi::OsStr;
use std::fs;
use std::path::{Component, Path, PathBuf};

/// The top-level entries the report writes: a foreign entry under one of these names is
/// refused before the experiments run.
const REPORT_ENTRIES: [&str; 4] = ["REPORT.md", "run-info.md", "data", "figures"];

/// Temporary directories of the writer before this module, inside the output directory.
const LEGACY_STAGING_PREFIX: &str = ".tmp-";

/// Which entries of the existing output directory the previous run wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Ownership {
    /// The files listed in the manifest.
    Listed(BTreeSet<PathBuf>),
    /// A report written before manifests existed.
    Legacy,
}

impl Ownership {
    pub(super) fn owns_file(&self, rel: &Path) -> bool {
        match self {
            Ownership::Listed(files) => files.contains(rel),
            Ownership::Legacy => {
                let parts: Vec<&OsStr> = rel.iter().collect();
                let ext = rel.extension().and_then(OsStr::to_str);
                match parts.as_slice() {
                    [one] => *one == "REPORT.md" || *one == "run-info.md",
                    [dir, _] => {
                        (*dir == "data" && ext == Some("csv"))
                            || (*dir == "figures" && ext == Some("svg"))
                    }
                    _ => false,
                }
            }
        }
    }

    pub(super) fn owns_something_under(&self, dir: &Path) -> bool {
        match self {
            Ownership::Listed(files) => files.iter().any(|f| f.starts_with(dir) && f != dir),
            Ownership::Legacy => dir == Path::new("data") || dir == Path::new("figures"),
        }
    }
}

/// Checks that a manifest or report path is relative and stays inside the report.
pub(super) fn relative_inside(path: &Path, what: &str) -> Result<()> {
    let ok = path.components().count() > 0
        && path.components().all(|c| matches!(c, Component::Normal(_)));
    if ok {
        Ok(())
    } else {
        Err(Error::Input(format!(
            "{what} {} must be a relative path inside the report",
            path.display()
        )))
    }
}

/// What a directory's `MANIFEST` says.
#[derive(Debug)]
pub(super) enum Manifest {
    Missing,
    /// The one [`manifest_text`] writes, with the files it lists.
    Ours(BTreeSet<PathBuf>),
    /// Another program's file of that name, and why it is not the report's.
    Foreign(String),
}

/// Reads `dir`'s manifest: the report's only in the exact format [`manifest_text`] writes (its
/// header, then relative paths inside the directory, sorted, one a line, itself among them).
pub(super) fn read_manifest(dir: &Path) -> Result<Manifest> {
    let path = dir.join(MANIFEST);
    match fs::symlink_metadata(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Manifest::Missing),
        Err(e) => return Err(io_error("reading", &path, e)),
        Ok(m) if !m.is_file() => {
            return Ok(Manifest::Foreign(format!(
                "its {MANIFEST} is not a regular file"
            )))
        }
        Ok(_) => {}
    }
    let bytes = fs::read(&path).map_err(|e| io_error("reading", &path, e))?;
    let Some(body) = String::from_utf8(bytes)
        .ok()
        .and_then(|text| text.strip_prefix(MANIFEST_HEADER).map(str::to_string))
    else {
        return Ok(Manifest::Foreign(format!(
            "its {MANIFEST} does not start with the header report writes"
        )));
    };
    let header_lines = MANIFEST_HEADER.lines().count();
    let mut files = BTreeSet::new();
    let mut previous: Option<PathBuf> = None;
    for (n, line) in body.lines().enumerate() {
        let file = PathBuf::from(line);
        let in_order = previous.as_ref().is_none_or(|p| *p < file);
        if line.is_empty() || relative_inside(&file, "").is_err() || !in_order {
            return Ok(Manifest::Foreign(format!(
                "line {} of its {MANIFEST} ({line:?}) is not an entry of the sorted list of \
                 relative paths report writes",
                n + 1 + header_lines
            )));
        }
        previous = Some(file.clone());
        files.insert(file);
    }
    if !body.is_empty() && !body.ends_with('\n') || !files.contains(Path::new(MANIFEST)) {
        return Ok(Manifest::Foreign(format!(
            "its {MANIFEST} is not in the format report writes (it ends without a newline or \
             does not list itself)"
        )));
    }
    Ok(Manifest::Ours(files))
}

/// Why a listed entry is not the report's: a listed path must be a regular file (or missing)
/// reached through real directories inside `dir`, never through a symbolic link.
fn listed_entry_problem(dir: &Path, rel: &Path) -> Option<String> {
    let mut path = dir.to_path_buf();
    let parts: Vec<_> = rel.components().collect();
    for (i, part) in parts.iter().enumerate() {
        path.push(part);
        let last = i + 1 == parts.len();
        match fs::symlink_metadata(&path) {
            Err(_) => return None,
            Ok(m) if last && m.is_file() => return None,
            Ok(m) if !last && m.is_dir() => {}
            Ok(m) => {
                return Some(format!(
                    "its {MANIFEST} lists {}, which is not a regular file inside it ({} is {})",
                    rel.display(),
                    path.display(),
                    describe_file_type(&m.file_type())
                ))
            }
        }
    }
    None
}

/// The manifest of `files`: one relative path a line, sorted, after a header.
pub(super) fn manifest_text(files: &BTreeSet<PathBuf>) -> String {
    let mut text = MANIFEST_HEADER.to_string();
    for f in files {
        text += &f.to_string_lossy().replace('\\', "/");
        text.push('\n');
    }
    text
}

/// The refusal of a directory that is not the report's.
fn not_ours(dir: &Path, why: &str) -> Error {
    Error::Input(format!(
        "the output directory {} is not a report this program wrote: {why}; nothing was \
         changed. Give --out an empty or new directory, or the report directory itself",
        dir.display()
    ))
}

/// Whose the existing directory `dir` is; refuses one the report may not replace.
fn ownership(dir: &Path) -> Result<Ownership> {
    match read_manifest(dir)? {
        Manifest::Ours(files) => {
            if let Some(why) = files.iter().find_map(|f| listed_entry_problem(dir, f)) {
                return Err(not_ours(dir, &why));
            }
            return Ok(Ownership::Listed(files));
        }
        Manifest::Foreign(why) => return Err(not_ours(dir, &why)),
        Manifest::Missing => {}
    }
    if sorted_entries(dir)?.is_empty() {
        return Ok(Ownership::Listed(BTreeSet::new()));
    }
    let report = fs::read_to_string(dir.join("REPORT.md")).unwrap_or_default();
    if report.starts_with(REPORT_TITLE) {
        return Ok(Ownership::Legacy);
    }
    Err(Error::Input(format!(
        "the output directory {} is not empty and has no {MANIFEST}, so it is not a report \
         this program wrote; nothing was changed. Give --out an empty or new directory, or the \
         report directory itself",
        dir.display()
    )))
}

/// Whose the entries at `dir` are, if it exists; refuses what the report may not replace.
pub(super) fn existing_ownership(dir: &Path) -> Result<Ownership> {
    match fs::symlink_metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            Ok(Ownership::Listed(BTreeSet::new()))
        }
        Err(e) => Err(io_error("reading", dir, e)),
        Ok(m) if !m.is_dir() => Err(Error::Input(format!(
            "the output path {} exists and is not a directory; nothing was changed",
            dir.display()
        ))),
        Ok(meta) => {
            refuse_mounts(dir)?;
            check_replaceable(dir, &meta)?;
            let ownership = ownership(dir)?;
            let reserved: BTreeSet<PathBuf> = REPORT_ENTRIES
                .iter()
                .map(|e| Path::new(e).join("?"))
                .collect();
            foreign_entries(dir, &ownership, &reserved)?;
            refuse_what_cannot_be_published(dir, &ownership)?;
            Ok(ownership)
        }
    }
}

/// Refuses an output directory that is a mount point or holds one: the swap renames it and the
/// clean-up removes the previous report, and neither may reach into another file system.
fn refuse_mounts(dir: &Path) -> Result<()> {
    let mounts = mount_points();
    if is_mount_point(dir, mounts.as_deref()) {
        return Err(Error::Input(format!(
            "the output directory {} is a mount point: report replaces its output by renaming \
             it, which a mount point refuses; nothing was changed. Give --out a directory inside it",
            dir.display()
        )));
    }
    if let Some(inside) = mounts
        .iter()
        .flatten()
        .find(|m| m.starts_with(dir) && m.as_path() != dir)
    {
        return Err(Error::Input(format!(
            "{} is a mount point inside the output directory: the new report would hold a copy \
             of that file system and the previous one could not be removed; nothing was \
             changed. Unmount it or move it out of {}",
            inside.display(),
            dir.display()
        )));
    }
    Ok(())
}

/// Refuses, before the run, an existing output directory this user could not rename at the end:
/// one not writable (renaming a directory rewrites its `..`), or another user's in a sticky
/// directory such as `/tmp`.
#[cfg(unix)]
fn check_replaceable(dir: &Path, meta: &fs::Metadata) -> Result<()> {
    use rustix::fs::{accessat, Access, AtFlags, CWD};
    use std::os::unix::fs::MetadataExt;
    let parent = dir.parent().unwrap_or(Path::new("/"));
    let parent_meta = fs::metadata(parent).map_err(|e| io_error("reading", parent, e))?;
    let euid = rustix::process::geteuid().as_raw();
    let sticky = parent_meta.mode() & 0o1000 != 0;
    if euid != 0 && sticky && meta.uid() != euid && parent_meta.uid() != euid {
        return Err(Error::Input(format!(
            "the output directory {} belongs to another user in the sticky directory {}, so \
             this user cannot replace it; nothing was changed",
            dir.display(),
            parent.display()
        )));
    }
    if accessat(CWD, dir, Access::WRITE_OK, AtFlags::EACCESS).is_err() {
        return Err(Error::Input(format!(
            "the output directory {} is not writable by this user, so it cannot be replaced; \
             nothing was changed",
            dir.display()
        )));
    }
    Ok(())
}

#[cfg(not(unix))]
fn check_replaceable(_dir: &Path, _meta: &fs::Metadata) -> Result<()> {
    Ok(())
}

/// The entries of `old`, the previous report once the new one is in place at `new`, that
/// neither the previous run wrote nor are in `new`: entries added to the target while the new
/// report was staged, after its foreign entries were listed (a file inside a foreign
/// directory counts alone). Each is carried over into `new` before `old` is removed.
pub(super) fn strays(old: &Path, new: &Path, ownership: &Ownership) -> Result<Vec<PathBuf>> {
    fn walk(
        old: &Path,
        new: &Path,
        rel_dir: &Path,
        ownership: &Ownership,
        out: &mut Vec<PathBuf>,
    ) -> Result<()> {
        for name in sorted_entries(&old.join(rel_dir))? {
            let rel = rel_dir.join(&name);
            // At the top, what the foreign entries leave out too: the manifest and a
            // legacy run's staging directory.
            if rel_dir.as_os_str().is_empty()
                && (name == MANIFEST || name.to_string_lossy().starts_with(LEGACY_STAGING_PREFIX))
            {
                continue;
            }
            let path = old.join(&rel);
            let meta = fs::symlink_metadata(&path).map_err(|e| io_error("reading", &path, e))?;
            let in_new = fs::symlink_metadata(new.join(&rel)).is_ok();
            if meta.is_dir() && (in_new || ownership.owns_something_under(&rel)) {
                walk(old, new, &rel, ownership, out)?;
            } else if !in_new && !ownership.owns_file(&rel) {
                out.push(rel);
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(old, new, Path::new(""), ownership, &mut out)?;
    Ok(out)
}

/// The entries of the existing report that the previous run did not write, topmost first
/// (a foreign directory is one entry). A foreign entry at a path `new_files` needs is an error.
pub(super) fn foreign_entries(
    dir: &Path,
    ownership: &Ownership,
    new_files: &BTreeSet<PathBuf>,
) -> Result<Vec<PathBuf>> {
    fn walk(
        dir: &Path,
        rel_dir: &Path,
        ownership: &Ownership,
        new_files: &BTreeSet<PathBuf>,
        out: &mut Vec<PathBuf>,
    ) -> Result<()> {
        for name in sorted_entries(&dir.join(rel_dir))? {
            let rel = rel_dir.join(&name);
            let at_top = rel_dir.as_os_str().is_empty();
            if at_top
                && (name == MANIFEST || name.to_string_lossy().starts_with(LEGACY_STAGING_PREFIX))
            {
                continue;
            }
            let path = dir.join(&rel);
            let is_dir = fs::symlink_metadata(&path)
                .map_err(|e| io_error("reading", &path, e))?
                .is_dir();
            let new_under = new_files.iter().any(|f| f.starts_with(&rel) && *f != rel);
            if is_dir && (ownership.owns_something_under(&rel) || new_under) {
                walk(dir, &rel, ownership, new_files, out)?;
            } else if is_dir || !ownership.owns_file(&rel) {
                if new_under || new_files.contains(&rel) {
                    return Err(Error::Input(format!(
                        "{} was not written by the report (it is not in {}) but the new \
                         report needs that path; nothing was changed. Move it away and run again",
                        path.display(),
                        dir.join(MANIFEST).display()
                    )));
                }
                out.push(rel);
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, Path::new(""), ownership, new_files, &mut out)?;
    Ok(out)
}

/// Refuses, before the run, every entry of `dir` a publication could not handle: a named
/// pipe, socket or device anywhere in it, whoever owns it (only regular files, directories and
/// symbolic links are carried over, and opening the others could wait forever); and, for a user
/// other than root, a foreign file this user can neither link nor read, a directory it cannot
/// list, or a directory whose entries it cannot remove (the previous report is removed after
/// the swap, and what could not be would be left in a staging directory). Links are not
/// followed, and only the directories walked are entered (mounts are refused before).
#[cfg(unix)]
pub(super) fn refuse_what_cannot_be_published(dir: &Path, ownership: &Ownership) -> Result<()> {
    use rustix::fs::{accessat, Access, AtFlags, CWD};
    use std::os::unix::fs::MetadataExt;
    let euid = rustix::process::geteuid().as_raw();
    let may = |path: &Path, access: Access| {
        euid == 0 || accessat(CWD, path, access, AtFlags::EACCESS).is_ok()
    };
    let refuse = |path: &Path, why: String| {
        Err(Error::Input(format!(
            "{} {why}; nothing was changed. Move it out of {} (or make it this user's) and run \
             again",
            path.display(),
            dir.display()
        )))
    };
    let mut pending = vec![(
        PathBuf::new(),
        fs::symlink_metadata(dir).map_err(|e| io_error("reading", dir, e))?,
    )];
    while let Some((rel_dir, dir_meta)) = pending.pop() {
        let here = dir.join(&rel_dir);
        let own_dir = euid == 0 || dir_meta.uid() == euid;
        // The owner's own directory is opened up before its removal (`files::open_up`).
        if !own_dir && !may(&here, Access::READ_OK | Access::WRITE_OK | Access::EXEC_OK) {
            return refuse(
                &here,
                "is another user's directory that this user cannot list and empty, so the \
                 previous report could not be carried over or removed"
                    .into(),
            );
        }
        let sticky = dir_meta.mode() & 0o1000 != 0;
        for name in sorted_entries(&here)? {
            let rel = rel_dir.join(&name);
            let path = dir.join(&rel);
            let meta = fs::symlink_metadata(&path).map_err(|e| io_error("reading", &path, e))?;
            let kind = meta.file_type();
            if !(kind.is_file() || kind.is_dir() || kind.is_symlink()) {
                return refuse(
                    &path,
                    format!(
                        "is {}: report carries over only regular files, directories and \
                         symbolic links",
                        describe_file_type(&kind)
                    ),
                );
            }
            let own = euid == 0 || meta.uid() == euid;
            if sticky && !own_dir && !own {
                return refuse(
                    &path,
                    "is another user's entry in a sticky directory, which this user cannot \
                     remove"
                        .into(),
                );
            }
            // A file of this user's is linked; another's is linked only with read and write
            // access (protected hard links), and else copied, which needs read access.
            if kind.is_file() && !own && !ownership.owns_file(&rel) && !may(&path, Access::READ_OK)
            {
                return refuse(
                    &path,
                    "is another user's file that this user can neither link nor read, so it \
                     could not be carried over"
                        .into(),
                );
            }
            if kind.is_dir() {
                pending.push((rel, meta));
            }
        }
    }
    Ok(())
}

#[cfg(not(unix))]
pub(super) fn refuse_what_cannot_be_published(_dir: &Path, _ownership: &Ownership) -> Result<()> {
    Ok(())
}

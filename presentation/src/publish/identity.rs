//! What the output directory was when the run started, checked again at publication: the
//! experiments run for minutes between [`super::ReportTarget::open`] and
//! [`super::ReportTarget::publish`], and a directory or file put in place of the one checked
//! meanwhile (`mv report report.moved; mkdir report`) must not be replaced or deleted as if it
//! were the report's.
//!
//! The output directory is known by its device and inode, which a rename keeps and a new
//! directory does not share with one still linked (the one moved away); it is looked up again
//! from a handle on its parent taken at the start, not by its path, and that path is checked to
//! lead to the same parent, so that a parent renamed meanwhile is noticed too. A file of the
//! previous report is known by its device, inode and status-change time, which also tell a
//! file rewritten in place and a new file given a freed inode number. A foreign entry is not
//! compared: it is carried over whole, whatever it is by then.

use super::files::io_error;
use super::ownership::Ownership;
use mass_spring_solvers::error::{Error, Result};
use std::collections::BTreeMap;
use std::ffi::OsString;
use std::fs;
use std::os::fd::OwnedFd;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// An entry's device and inode.
type Identity = (u64, u64);

/// The [`Identity`] of the entry `meta` describes.
fn identity_of(meta: &fs::Metadata) -> Identity {
    (meta.dev(), meta.ino())
}

/// A file's device, inode and status-change time (s, ns): the inode number of a file removed
/// during the run may be given to the next one created, and a file rewritten in place keeps
/// its inode, but either changes the time.
type FileVersion = (u64, u64, i64, i64);

/// The [`FileVersion`] of the file `meta` describes.
fn version_of(meta: &fs::Metadata) -> FileVersion {
    (meta.dev(), meta.ino(), meta.ctime(), meta.ctime_nsec())
}

/// The output directory and the files in it that a publication replaces or removes (those
/// the previous report wrote), as they were at the start.
#[derive(Debug)]
pub(super) struct Recorded {
    /// The directory holding the output directory, opened at the start.
    parent: OwnedFd,
    parent_path: PathBuf,
    parent_identity: Identity,
    name: OsString,
    /// The output directory's identity; `None` when it did not exist.
    dir: Option<Identity>,
    /// Every file the previous report wrote that exists, by its path relative to the output.
    owned: BTreeMap<PathBuf, FileVersion>,
}

impl Recorded {
    /// Records `dir` and the files `ownership` gives the report in it. Runs under the lock.
    pub(super) fn take(dir: &Path, ownership: &Ownership) -> Result<Self> {
        use rustix::fs::{fstat, openat, Mode, OFlags, CWD};
        let parent_path = dir.parent().unwrap_or(Path::new("/")).to_path_buf();
        // O_PATH: a handle that names the directory without reading it, so that a parent this
        // user may only search is still held.
        let parent = openat(
            CWD,
            &parent_path,
            OFlags::PATH | OFlags::DIRECTORY | OFlags::CLOEXEC,
            Mode::empty(),
        )
        .map_err(|e| io_error("opening", &parent_path, e.into()))?;
        let stat = fstat(&parent).map_err(|e| io_error("reading", &parent_path, e.into()))?;
        let name = dir.file_name().unwrap_or_default().to_owned();
        let mut recorded = Self {
            parent,
            parent_identity: (stat.st_dev, stat.st_ino),
            parent_path,
            name,
            dir: None,
            owned: BTreeMap::new(),
        };
        recorded.dir = recorded.dir_now(dir)?;
        if recorded.dir.is_some() {
            recorded.owned = owned_files(dir, ownership)?;
        }
        Ok(recorded)
    }

    /// The output directory's identity now, looked up from the parent handle; `None` if it is
    /// missing.
    fn dir_now(&self, dir: &Path) -> Result<Option<Identity>> {
        use rustix::fs::{statat, AtFlags};
        match statat(&self.parent, &self.name, AtFlags::SYMLINK_NOFOLLOW) {
            Ok(stat) => Ok(Some((stat.st_dev, stat.st_ino))),
            Err(rustix::io::Errno::NOENT) => Ok(None),
            Err(e) => Err(io_error("reading", dir, e.into())),
        }
    }

    /// Whether `path` (the output directory renamed or exchanged away) is the output directory
    /// recorded: a directory put in its place after the last [`Recorded::verify`] is not.
    pub(super) fn is_the_output_directory(&self, path: &Path) -> bool {
        let now = fs::symlink_metadata(path).map(|m| identity_of(&m)).ok();
        now.is_some() && now == self.dir
    }

    /// Refuses a publication into a target that is not the one recorded: the parent path
    /// leading elsewhere, the output directory replaced (or made, or removed) during the run,
    /// or a file of the previous report replaced, added or removed. Writes nothing.
    pub(super) fn verify(&self, dir: &Path, ownership: &Ownership) -> Result<()> {
        let changed = |what: String| {
            Error::Input(format!(
                "{what} during the run, so the target is not the one checked at the start; \
                 nothing was written, renamed or deleted in {} or beside it. Run again to \
                 publish into the directory as it is now",
                dir.display()
            ))
        };
        let parent_now = fs::metadata(&self.parent_path)
            .map(|m| identity_of(&m))
            .ok();
        if parent_now != Some(self.parent_identity) {
            return Err(changed(format!(
                "{} was moved or replaced",
                self.parent_path.display()
            )));
        }
        let now = self.dir_now(dir)?;
        if now != self.dir {
            let what = match (self.dir, now) {
                (None, _) => "was created",
                (_, None) => "was moved away",
                _ => "was replaced by another directory",
            };
            return Err(changed(format!(
                "the output directory {} {what}",
                dir.display()
            )));
        }
        if now.is_none() {
            return Ok(());
        }
        let owned = owned_files(dir, ownership)?;
        let differing = owned
            .iter()
            .find(|(rel, id)| self.owned.get(*rel) != Some(id))
            .or_else(|| self.owned.iter().find(|(rel, _)| !owned.contains_key(*rel)));
        match differing {
            Some((rel, _)) => Err(changed(format!(
                "{}, a file of the previous report, was changed, replaced, added or removed",
                dir.join(rel).display()
            ))),
            None => Ok(()),
        }
    }
}

/// The entries of `dir` at the paths `ownership` gives the report, with their identities: the
/// files a publication replaces or removes (a foreign entry is carried over, not lost).
fn owned_files(dir: &Path, ownership: &Ownership) -> Result<BTreeMap<PathBuf, FileVersion>> {
    let mut out = BTreeMap::new();
    let mut pending = vec![PathBuf::new()];
    while let Some(rel_dir) = pending.pop() {
        let here = dir.join(&rel_dir);
        for entry in fs::read_dir(&here).map_err(|e| io_error("reading", &here, e))? {
            let entry = entry.map_err(|e| io_error("reading", &here, e))?;
            let rel = rel_dir.join(entry.file_name());
            let meta = fs::symlink_metadata(entry.path())
                .map_err(|e| io_error("reading", &entry.path(), e))?;
            if meta.is_dir() {
                if ownership.owns_something_under(&rel) {
                    pending.push(rel);
                }
            } else if ownership.owns_file(&rel) {
                out.insert(rel, version_of(&meta));
            }
        }
    }
    Ok(out)
}

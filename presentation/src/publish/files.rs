//! The file-system operations of a publication: the names the report owns, listing, removal
//! that never follows a symbolic link and never crosses a mount point, carrying files over, and
//! the atomic exchange of two directories.

use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::platform::paths::{describe_file_type, device_of, mount_points};
use std::ffi::{OsStr, OsString};
use std::fs::{self};
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

/// The file, inside the output directory, listing the files the report wrote.
pub const MANIFEST: &str = "MANIFEST";

/// The start of the first line of every `REPORT.md` this project writes.
pub const REPORT_TITLE: &str = "# Solvers de Elasticidad y Restricciones en Simulación";

pub(super) const MANIFEST_HEADER: &str = "\
# The files written by `report` (mass-spring-solvers). The next run replaces exactly these;
# anything else in this directory is carried over untouched.
";

pub(super) fn io_error(what: &str, path: &Path, e: std::io::Error) -> Error {
    Error::Input(format!("{what} {}: {e}", path.display()))
}

/// Digits of the nanoseconds in a journal name: the time since 1970 has 19 until 2286.
pub(super) const NANOS_DIGITS: usize = 19;

/// `<pid>-<nanoseconds>`, the nanoseconds in exactly [`NANOS_DIGITS`] digits.
pub(super) fn unique_suffix() -> String {
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    format!(
        "{}-{nanos:0width$}",
        std::process::id(),
        width = NANOS_DIGITS
    )
}

/// Whether `name` is `prefix` followed by a [`unique_suffix`]: the exact shape the journal
/// writes, so that a user's `.report.old-2024-backup` is never taken for it.
pub(super) fn is_journal_name(name: &OsStr, prefix: &OsStr) -> bool {
    let Some(rest) = name
        .as_encoded_bytes()
        .strip_prefix(prefix.as_encoded_bytes())
    else {
        return false;
    };
    let digits = |s: &[u8]| !s.is_empty() && s.iter().all(u8::is_ascii_digit);
    match rest.iter().position(|&b| b == b'-') {
        Some(dash) => {
            let (pid, nanos) = (&rest[..dash], &rest[dash + 1..]);
            digits(pid) && pid.len() <= 10 && digits(nanos) && nanos.len() == NANOS_DIGITS
        }
        None => false,
    }
}

/// `.<name>.<kind>` beside `dir`.
pub(super) fn sibling(dir: &Path, kind: &str) -> PathBuf {
    let mut name = OsString::from(".");
    name.push(dir.file_name().unwrap_or_default());
    name.push(".");
    name.push(kind);
    dir.with_file_name(name)
}

/// The entries of `dir`, sorted by name.
pub(super) fn sorted_entries(dir: &Path) -> Result<Vec<OsString>> {
    let mut names = fs::read_dir(dir)
        .map_err(|e| io_error("reading", dir, e))?
        .map(|e| e.map(|e| e.file_name()))
        .collect::<std::io::Result<Vec<_>>>()
        .map_err(|e| io_error("reading", dir, e))?;
    names.sort();
    Ok(names)
}

/// Removes a tree this module made (a staging directory, or a previous report after the swap),
/// first making its directories writable: the previous report may hold a directory a user made
/// read-only, and its files are still linked from the new report, so only the directories are
/// touched. A symbolic link is removed, never followed; a directory on another device or listed
/// as a mount point is not entered: it is an error, and it and what holds it are left.
pub(super) fn remove_tree(path: &Path) -> Result<()> {
    let meta = match fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        other => other.map_err(|e| io_error("reading", path, e))?,
    };
    if !meta.is_dir() {
        return fs::remove_file(path).map_err(|e| io_error("removing", path, e));
    }
    let device = device_of(path).map_err(|e| io_error("reading", path, e))?;
    remove_directory(path, &meta, device, mount_points().as_deref())
}

pub(super) fn remove_directory(
    path: &Path,
    meta: &fs::Metadata,
    device: u64,
    mounts: Option<&[PathBuf]>,
) -> Result<()> {
    open_up(path, meta.permissions()).map_err(|e| io_error("unlocking", path, e))?;
    for name in sorted_entries(path)? {
        let child = path.join(&name);
        let child_meta =
            fs::symlink_metadata(&child).map_err(|e| io_error("reading", &child, e))?;
        if child_meta.is_dir() {
            let crossing = device_of(&child).map_or(true, |d| d != device)
                || mounts.is_some_and(|m| m.contains(&child));
            if crossing {
                return Err(Error::Input(format!(
                    "{} is a mount point (another file system): it is not entered, and it and \
                     the directories holding it are left in place",
                    child.display()
                )));
            }
            remove_directory(&child, &child_meta, device, mounts)?;
        } else {
            fs::remove_file(&child).map_err(|e| io_error("removing", &child, e))?;
        }
    }
    fs::remove_dir(path).map_err(|e| io_error("removing", path, e))
}

/// Gives the owner read, write and search permission on a directory.
#[cfg(unix)]
pub(super) fn open_up(dir: &Path, perms: fs::Permissions) -> std::io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    let mode = perms.mode();
    if mode & 0o700 == 0o700 {
        return Ok(());
    }
    fs::set_permissions(dir, fs::Permissions::from_mode(mode | 0o700))
}

#[cfg(not(unix))]
pub(super) fn open_up(dir: &Path, mut perms: fs::Permissions) -> std::io::Result<()> {
    if !perms.readonly() {
        return Ok(());
    }
    #[allow(clippy::permissions_set_readonly_false)] // no other users to consider here
    perms.set_readonly(false);
    fs::set_permissions(dir, perms)
}

/// Recreates `src` at `dst`: directories anew, files as hard links (copies where links are
/// refused), symbolic links as links to the same target.
pub(super) fn carry_over(src: &Path, dst: &Path) -> Result<()> {
    let meta = fs::symlink_metadata(src).map_err(|e| io_error("reading", src, e))?;
    if meta.is_dir() {
        fs::create_dir(dst).map_err(|e| io_error("creating", dst, e))?;
        for name in sorted_entries(src)? {
            carry_over(&src.join(&name), &dst.join(&name))?;
        }
        fs::set_permissions(dst, meta.permissions()).map_err(|e| io_error("copying", dst, e))
    } else if meta.file_type().is_symlink() {
        let target = fs::read_link(src).map_err(|e| io_error("reading", src, e))?;
        symlink(&target, dst).map_err(|e| io_error("linking", dst, e))
    } else {
        fs::hard_link(src, dst)
            .or_else(|_| copy_regular_file(src, dst))
            .map_err(|e| io_error("carrying over", src, e))
    }
}

/// Copies `src` to a new file `dst` with its permissions, reading it only once `fstat` on the
/// open descriptor says it is a regular file: it is opened without following a link and
/// without waiting (`O_NONBLOCK`), so that a named pipe put in its place is refused at once
/// instead of waiting for a writer that never comes.
#[cfg(unix)]
fn copy_regular_file(src: &Path, dst: &Path) -> std::io::Result<()> {
    use rustix::fs::{openat, Mode, OFlags, CWD};
    let flags = OFlags::RDONLY | OFlags::NOFOLLOW | OFlags::NONBLOCK | OFlags::CLOEXEC;
    let mut from = fs::File::from(openat(CWD, src, flags, Mode::empty())?);
    let meta = from.metadata()?;
    if !meta.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "it is {}, and only regular files are copied",
                describe_file_type(&meta.file_type())
            ),
        ));
    }
    let mut to = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(dst)?;
    std::io::copy(&mut from, &mut to)?;
    to.set_permissions(meta.permissions())
}

#[cfg(not(unix))]
fn copy_regular_file(src: &Path, dst: &Path) -> std::io::Result<()> {
    fs::copy(src, dst).map(|_| ())
}

#[cfg(unix)]
pub(super) fn symlink(target: &Path, link: &Path) -> std::io::Result<()> {
    std::os::unix::fs::symlink(target, link)
}

#[cfg(windows)]
pub(super) fn symlink(target: &Path, link: &Path) -> std::io::Result<()> {
    std::os::windows::fs::symlink_file(target, link)
}

/// `renameat2(a, b, RENAME_EXCHANGE)`; `Ok(false)` where the file system or kernel refuses it.
#[cfg(any(target_os = "linux", target_os = "android"))]
pub(super) fn exchange(a: &Path, b: &Path) -> std::io::Result<bool> {
    use rustix::fs::{renameat_with, RenameFlags, CWD};
    match renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE) {
        Ok(()) => Ok(true),
        Err(e) if e == rustix::io::Errno::INVAL || e == rustix::io::Errno::NOSYS => Ok(false),
        Err(e) => Err(e.into()),
    }
}

#[cfg(not(any(target_os = "linux", target_os = "android")))]
pub(super) fn exchange(_a: &Path, _b: &Path) -> std::io::Result<bool> {
    Ok(false)
}

//! The output files of `mss` (`--ke-csv`, `--positions-csv`) and `timing`, checked and opened
//! before the run so that a bad path fails at once, and written without ever harming what is
//! there. What a path is, is decided by `stat` after resolving it, never by its prefix:
//!
//! - a path that names one of this process's descriptors (`/dev/stdout`, `/dev/stderr`,
//!   `/dev/fd/N`, `/proc/self/fd/N`, or a link to one) is written through that descriptor, in
//!   place: `--ke-csv /dev/stdout >> log.csv` appends;
//! - a new path, or an existing writable regular file (symbolic links followed, or refused where
//!   the caller says so), wherever it lives (`/dev/shm` included), is written into an anonymous
//!   file beside it (Linux `O_TMPFILE`, where `/proc/self/fd` can name it) that becomes the file
//!   only when the run succeeds: a failed or interrupted run leaves the destination as it was
//!   and nothing beside it (elsewhere, a `.mss-<pid>-<k>.partial` file, removed when the run
//!   fails). [`OutputFile::finish_all`] writes every file of a run before it replaces any;
//! - a character device is written in place; a named pipe too, once a reader has opened it
//!   within [`FIFO_PATIENCE`] (else it is refused);
//! - refused, naming the option, before anything runs: a directory or a path ending in `/`, a
//!   name over [`NAME_MAX`] bytes, a read-only file, a path whose directory does not exist or may
//!   not be written, a symbolic link whose target does not exist (or a loop), a file another
//!   user owns in a sticky directory (which only its owner may replace), a mounted-over file, a
//!   socket or a block device, the scene file, and one file given to two options (a character
//!   device such as `/dev/null` aside).

use crate::error::{Error, Result};
use crate::platform::paths::{
    describe_file_type, is_char_device, is_fifo, is_mount_point, mount_points, named_descriptor,
    open_fifo_for_writing, FIFO_PATIENCE, NAME_MAX,
};
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Whether an output path may be a symbolic link.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Links {
    /// The file it points to is the one replaced (`mss`'s series: the user names the file).
    Follow,
    /// Refused (the files of `timing`'s own output directory, where a link is not its own).
    Refuse,
}

/// The identity of a file: device and inode where the file exists, else its resolved path.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Identity {
    Inode(u64, u64),
    Path(PathBuf),
}

#[cfg(unix)]
fn inode(meta: &fs::Metadata) -> Identity {
    use std::os::unix::fs::MetadataExt;
    Identity::Inode(meta.dev(), meta.ino())
}

#[cfg(not(unix))]
fn inode(_meta: &fs::Metadata) -> Identity {
    Identity::Path(PathBuf::new())
}

fn identity(path: &Path) -> Option<Identity> {
    match fs::metadata(path) {
        Ok(meta) if cfg!(unix) => Some(inode(&meta)),
        Ok(_) => fs::canonicalize(path).ok().map(Identity::Path),
        Err(_) => {
            let parent = fs::canonicalize(parent_of(path)).ok()?;
            Some(Identity::Path(parent.join(path.file_name()?)))
        }
    }
}

fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Where the bytes go while the run lasts.
#[derive(Debug)]
enum Sink {
    /// A descriptor, a device or a pipe, written as the rows come.
    InPlace,
    /// An anonymous file in `dest`'s directory, linked to `dest` at the end.
    #[cfg(any(target_os = "linux", target_os = "android"))]
    Anonymous { dest: PathBuf },
    /// A named file beside `dest`, renamed over it at the end.
    Named { dest: PathBuf, partial: PathBuf },
}

/// An output file of a run, opened and checked.
#[derive(Debug)]
pub struct OutputFile {
    option: &'static str,
    path: PathBuf,
    writer: BufWriter<File>,
    sink: Sink,
}

fn refuse(option: &str, path: &Path, allowed: &str) -> Error {
    Error::invalid(option, path.display(), allowed)
}

/// A name beside the destination for this process's `k`-th temporary file, as short whatever
/// the destination's name (a 254-byte name leaves no room to extend it).
fn temporary_name(dest: &Path, kind: &str) -> PathBuf {
    static COUNT: AtomicU64 = AtomicU64::new(0);
    let k = COUNT.fetch_add(1, Ordering::Relaxed);
    dest.with_file_name(format!(".mss-{}-{k}.{kind}", std::process::id()))
}

impl OutputFile {
    /// Checks and opens every output `(option, path)`, following symbolic links; `input` is the
    /// scene file, which must not be overwritten.
    pub fn open_all(
        outputs: &[(&'static str, &Path)],
        input: Option<&Path>,
    ) -> Result<Vec<OutputFile>> {
        let input = input.and_then(identity);
        let mut seen: Vec<(&str, Identity)> = Vec::new();
        let mut opened = Vec::new();
        for &(option, path) in outputs {
            // A sink such as /dev/null takes any number of writers.
            let sink = fs::metadata(path).is_ok_and(|m| is_char_device(&m));
            if let Some(id) = identity(path).filter(|_| !sink) {
                if input.as_ref() == Some(&id) {
                    return Err(refuse(option, path, "not the scene file"));
                }
                if let Some((other, _)) = seen.iter().find(|(_, s)| *s == id) {
                    return Err(refuse(
                        option,
                        path,
                        &format!("a file not given to {other} as well"),
                    ));
                }
                seen.push((option, id));
            }
            opened.push(Self::open(option, path, Links::Follow)?);
        }
        Ok(opened)
    }

    /// Checks and opens one output file (see the module documentation), naming `option` in
    /// every refusal.
    pub fn open(option: &'static str, path: &Path, links: Links) -> Result<Self> {
        let refused = |allowed: &str| refuse(option, path, allowed);
        if path.as_os_str().as_encoded_bytes().ends_with(b"/") {
            return Err(refused("a file name, not a path ending in / (a directory)"));
        }
        if path
            .file_name()
            .is_some_and(|n| n.as_encoded_bytes().len() > NAME_MAX)
        {
            return Err(refused(&format!("a file name of at most {NAME_MAX} bytes")));
        }
        let new = |file: File, sink: Sink| Self {
            option,
            path: path.to_path_buf(),
            writer: BufWriter::new(file),
            sink,
        };
        if let Some(file) = descriptor(path)
            .map_err(|e| refused(&format!("a descriptor this process may write ({e})")))?
        {
            return Ok(new(file, Sink::InPlace));
        }
        let link = fs::symlink_metadata(path)
            .ok()
            .filter(|m| m.file_type().is_symlink());
        if link.is_some() && links == Links::Refuse {
            return Err(refused(
                "a regular file or a new name, not a symbolic link (the file it points to is \
                 not this program's to replace)",
            ));
        }
        match fs::metadata(path) {
            Ok(m) if m.is_dir() => Err(refused("a file, not a directory")),
            Ok(m) if m.is_file() => {
                let (file, sink) = replace_existing(path, &m).map_err(|e| refused(&e))?;
                Ok(new(file, sink))
            }
            Ok(m) if is_char_device(&m) => {
                let file = fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|e| refused(&format!("a writable device ({e})")))?;
                Ok(new(file, Sink::InPlace))
            }
            Ok(m) if is_fifo(&m) => {
                let file = open_fifo_for_writing(path, FIFO_PATIENCE).map_err(|e| {
                    refused(&format!(
                        "a named pipe with a reader: none opened it within {} s ({e})",
                        FIFO_PATIENCE.as_secs_f64()
                    ))
                })?;
                Ok(new(file, Sink::InPlace))
            }
            Ok(m) => Err(refused(&format!(
                "a regular file, a character device or a named pipe (this is {})",
                describe_file_type(&m.file_type())
            ))),
            Err(_) if link.is_some() => Err(refused(
                "a symbolic link to an existing file or directory entry (its target does not \
                 exist, is in a missing directory, or the links loop)",
            )),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                let (file, sink) = create_new(path).map_err(|e| refused(&e))?;
                Ok(new(file, sink))
            }
            Err(e) => Err(refused(&format!("a path this user may write ({e})"))),
        }
    }

    /// Where the rows go.
    pub fn writer(&mut self) -> &mut dyn Write {
        &mut self.writer
    }

    fn fail(&self, e: std::io::Error) -> Error {
        Error::Input(format!("{} {}: {e}", self.option, self.path.display()))
    }

    /// Flushes and, for a replaced file, puts the new file in place.
    pub fn finish(self) -> Result<()> {
        Self::finish_all(vec![self])
    }

    /// Flushes every file, then puts each replaced file in place: a file that cannot be
    /// written to its end (a full disk) replaces none of them.
    pub fn finish_all(mut files: Vec<OutputFile>) -> Result<()> {
        for f in &mut files {
            if let Err(e) = f.writer.flush() {
                return Err(f.fail(e));
            }
        }
        for f in files {
            let (option, path) = (f.option, f.path.clone());
            let fail =
                |e: std::io::Error| Error::Input(format!("{option} {}: {e}", path.display()));
            let file = f.writer.into_inner().map_err(|e| fail(e.into_error()))?;
            // A named partial file that fails to move is removed when `sink` drops.
            match &f.sink {
                Sink::InPlace => {}
                #[cfg(any(target_os = "linux", target_os = "android"))]
                Sink::Anonymous { dest } => link_into_place(&file, dest).map_err(fail)?,
                Sink::Named { dest, partial } => {
                    drop(file);
                    fs::rename(partial, dest).map_err(fail)?;
                }
            }
        }
        Ok(())
    }
}

impl Drop for Sink {
    /// A run that did not finish removes its named partial file (an anonymous one vanishes
    /// with its descriptor).
    fn drop(&mut self) {
        if let Sink::Named { partial, .. } = self {
            let _ = fs::remove_file(partial);
        }
    }
}

/// The checks of an existing regular file before the run, and its replacement opened; the
/// error says what the file must be.
fn replace_existing(path: &Path, meta: &fs::Metadata) -> std::result::Result<(File, Sink), String> {
    if meta.permissions().readonly() {
        return Err("a writable file (this one is read-only)".into());
    }
    // Links are followed: the file they point to is the one replaced.
    let dest = fs::canonicalize(path).map_err(|e| format!("a path that resolves ({e})"))?;
    if is_mount_point(&dest, mount_points().as_deref()) {
        return Err(
            "a file that is not a mount point (this one is mounted over, so a rename cannot \
             replace it)"
                .into(),
        );
    }
    let dir = parent_of(&dest);
    check_replaceable(dir, meta)?;
    replacing(dest.clone(), Some(meta.permissions()))
        .map_err(|e| format!("a file in a directory this user may write ({e})"))
}

/// The checks of a new file before the run, and its replacement opened.
fn create_new(path: &Path) -> std::result::Result<(File, Sink), String> {
    let dir = parent_of(path);
    let in_directory = |detail: String| {
        format!(
            "a path in an existing directory ({} is not one{detail})",
            dir.display()
        )
    };
    match fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(in_directory(String::new())),
        Err(e) => return Err(in_directory(format!(": {e}"))),
    }
    let real = fs::canonicalize(dir).map_err(|e| in_directory(format!(": {e}")))?;
    if !writable(&real) {
        return Err(format!(
            "a file in a directory this user may write ({} is not)",
            dir.display()
        ));
    }
    let name = path
        .file_name()
        .ok_or_else(|| in_directory(String::new()))?;
    replacing(real.join(name), None)
        .map_err(|e| format!("a file in a directory this user may write ({e})"))
}

/// Whether this user (its effective ids) may create and remove entries in `dir`.
#[cfg(unix)]
fn writable(dir: &Path) -> bool {
    use rustix::fs::{accessat, Access, AtFlags, CWD};
    accessat(
        CWD,
        dir,
        Access::WRITE_OK | Access::EXEC_OK,
        AtFlags::EACCESS,
    )
    .is_ok()
}

#[cfg(not(unix))]
fn writable(dir: &Path) -> bool {
    fs::metadata(dir).is_ok_and(|m| !m.permissions().readonly())
}

/// Refuses, before the run, an existing file a rename in `dir` could not replace: the
/// directory not writable, or sticky (like `/tmp`) with the file and the directory another
/// user's.
#[cfg(unix)]
fn check_replaceable(dir: &Path, meta: &fs::Metadata) -> std::result::Result<(), String> {
    use std::os::unix::fs::MetadataExt;
    let dir_meta =
        fs::metadata(dir).map_err(|e| format!("a file in a readable directory ({e})"))?;
    let euid = rustix::process::geteuid().as_raw();
    let sticky = dir_meta.mode() & 0o1000 != 0;
    if euid != 0 && sticky && meta.uid() != euid && dir_meta.uid() != euid {
        return Err(format!(
            "a file this user may replace (it belongs to another user in the sticky directory \
             {}, where only its owner may replace it)",
            dir.display()
        ));
    }
    if !writable(dir) {
        return Err(format!(
            "a file in a directory this user may write ({} is not)",
            dir.display()
        ));
    }
    Ok(())
}

#[cfg(not(unix))]
fn check_replaceable(_dir: &Path, _meta: &fs::Metadata) -> std::result::Result<(), String> {
    Ok(())
}

/// The file that replaces `dest` at the end, with `dest`'s permissions if it has some.
fn replacing(dest: PathBuf, permissions: Option<fs::Permissions>) -> std::io::Result<(File, Sink)> {
    let (file, sink) = open_replacement(dest)?;
    if let Some(p) = permissions {
        file.set_permissions(p)?;
    }
    Ok((file, sink))
}

#[cfg(any(target_os = "linux", target_os = "android"))]
fn open_replacement(dest: PathBuf) -> std::io::Result<(File, Sink)> {
    use rustix::fs::{openat, Mode, OFlags, CWD};
    use std::os::fd::AsRawFd;
    let anonymous = openat(
        CWD,
        parent_of(&dest),
        OFlags::TMPFILE | OFlags::WRONLY | OFlags::CLOEXEC,
        Mode::from_raw_mode(0o644),
    );
    match anonymous {
        // Linked into place through /proc/self/fd: without /proc (a chroot, a minimal
        // container) a named file is used instead.
        Ok(fd) if Path::new(&format!("/proc/self/fd/{}", fd.as_raw_fd())).exists() => {
            Ok((File::from(fd), Sink::Anonymous { dest }))
        }
        Ok(_) => named(dest),
        // File systems without O_TMPFILE.
        Err(e) if e == rustix::io::Errno::OPNOTSUPP || e == rustix::io::Errno::ISDIR => named(dest),
        Err(e) => Err(e.into()),
    }
}

#[cfg(not(any(target_os = "linux", target_os = "android")))]
fn open_replacement(dest: PathBuf) -> std::io::Result<(File, Sink)> {
    named(dest)
}

fn named(dest: PathBuf) -> std::io::Result<(File, Sink)> {
    let partial = temporary_name(&dest, "partial");
    let file = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&partial)?;
    Ok((file, Sink::Named { dest, partial }))
}

/// Gives the anonymous `file` the name `dest`: directly when `dest` does not exist, else under
/// a temporary name renamed over it (the only moment a name beside `dest` exists).
#[cfg(any(target_os = "linux", target_os = "android"))]
fn link_into_place(file: &File, dest: &Path) -> std::io::Result<()> {
    use rustix::fs::{linkat, AtFlags, CWD};
    use std::os::fd::AsRawFd;
    let proc_path = format!("/proc/self/fd/{}", file.as_raw_fd());
    match linkat(CWD, &proc_path, CWD, dest, AtFlags::SYMLINK_FOLLOW) {
        Ok(()) => return Ok(()),
        Err(e) if e != rustix::io::Errno::EXIST => return Err(e.into()),
        Err(_) => {}
    }
    let temporary = temporary_name(dest, "new");
    linkat(CWD, &proc_path, CWD, &temporary, AtFlags::SYMLINK_FOLLOW)?;
    fs::rename(&temporary, dest).inspect_err(|_| {
        let _ = fs::remove_file(&temporary);
    })
}

/// The descriptor `path` names, duplicated (so that it shares the offset and the flags the
/// shell gave it: `>> log.csv` appends), if it names one of this process's: `/dev/stdout`,
/// `/dev/fd/N`, `/proc/self/fd/N`, or a link to one. A descriptor beyond the standard three is
/// reopened for appending (duplicating an arbitrary descriptor number needs `unsafe`).
fn descriptor(path: &Path) -> std::io::Result<Option<File>> {
    use std::os::fd::AsFd;
    let Some(fd) = named_descriptor(path) else {
        return Ok(None);
    };
    let owned = match fd {
        0 => std::io::stdin().as_fd().try_clone_to_owned()?,
        1 => std::io::stdout().as_fd().try_clone_to_owned()?,
        2 => std::io::stderr().as_fd().try_clone_to_owned()?,
        _ => return fs::OpenOptions::new().append(true).open(path).map(Some),
    };
    Ok(Some(File::from(owned)))
}

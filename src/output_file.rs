//! The output files of `mss` (`--ke-csv`, `--positions-csv`), checked and opened before the
//! run so that a bad path fails at once, and written without ever harming what is there:
//!
//! - a new path, or an existing writable regular file (symbolic links followed), is written
//!   into an anonymous file beside it (Linux `O_TMPFILE`) that becomes the file only when the
//!   run succeeds: a failed or interrupted run leaves the destination as it was and nothing
//!   beside it (elsewhere, a `.<name>.partial-<pid>` file, removed when the run fails);
//! - a path under `/dev`, or any existing file that is not a regular file (a device, a named
//!   pipe), is written in place and never replaced;
//! - a directory, a read-only file, a path whose directory does not exist or may not be
//!   written, the scene file, and one file given to two options are refused, naming the option.

use crate::error::{Error, Result};
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

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
    /// A device or pipe, written as the rows come.
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

impl OutputFile {
    /// Checks and opens every output `(option, path)`; `input` is the scene file, which must
    /// not be overwritten.
    pub fn open_all(
        outputs: &[(&'static str, &Path)],
        input: Option<&Path>,
    ) -> Result<Vec<OutputFile>> {
        let input = input.and_then(identity);
        let mut seen: Vec<(&str, Identity)> = Vec::new();
        let mut opened = Vec::new();
        for &(option, path) in outputs {
            let id = identity(path);
            if let Some(id) = &id {
                if input.as_ref() == Some(id) {
                    return Err(refuse(option, path, "not the scene file"));
                }
                if let Some((other, _)) = seen.iter().find(|(_, s)| s == id) {
                    return Err(refuse(
                        option,
                        path,
                        &format!("a file not given to {other} as well"),
                    ));
                }
                seen.push((option, id.clone()));
            }
            opened.push(Self::open(option, path)?);
        }
        Ok(opened)
    }

    fn open(option: &'static str, path: &Path) -> Result<Self> {
        let meta = fs::metadata(path);
        let in_place = path.starts_with("/dev") || meta.as_ref().is_ok_and(|m| !m.is_file());
        let (file, sink) = match &meta {
            Ok(m) if m.is_dir() => return Err(refuse(option, path, "a file, not a directory")),
            _ if in_place => {
                let file = fs::OpenOptions::new().write(true).open(path).map_err(|e| {
                    refuse(option, path, &format!("a writable device or pipe ({e})"))
                })?;
                (file, Sink::InPlace)
            }
            Ok(m) if m.permissions().readonly() => {
                return Err(refuse(
                    option,
                    path,
                    "a writable file (this one is read-only)",
                ))
            }
            _ => {
                // Links are followed: the file they point to is the one replaced.
                let dest = match fs::canonicalize(path) {
                    Ok(real) => real,
                    Err(_) => path.to_path_buf(),
                };
                let dir = parent_of(&dest);
                if !dir.is_dir() {
                    return Err(refuse(
                        option,
                        path,
                        &format!(
                            "a path in an existing directory ({} is not one)",
                            dir.display()
                        ),
                    ));
                }
                let (file, sink) = Self::replacing(dest)
                    .and_then(|(file, sink)| {
                        // A replaced file keeps its permissions.
                        if let Ok(m) = &meta {
                            file.set_permissions(m.permissions())?;
                        }
                        Ok((file, sink))
                    })
                    .map_err(|e| {
                        refuse(
                            option,
                            path,
                            &format!("a file in a directory this user may write ({e})"),
                        )
                    })?;
                (file, sink)
            }
        };
        Ok(Self {
            option,
            path: path.to_path_buf(),
            writer: BufWriter::new(file),
            sink,
        })
    }

    #[cfg(any(target_os = "linux", target_os = "android"))]
    fn replacing(dest: PathBuf) -> std::io::Result<(File, Sink)> {
        use rustix::fs::{openat, Mode, OFlags, CWD};
        let anonymous = openat(
            CWD,
            parent_of(&dest),
            OFlags::TMPFILE | OFlags::WRONLY | OFlags::CLOEXEC,
            Mode::from_raw_mode(0o644),
        );
        match anonymous {
            Ok(fd) => Ok((File::from(fd), Sink::Anonymous { dest })),
            // File systems without O_TMPFILE.
            Err(e) if e == rustix::io::Errno::OPNOTSUPP || e == rustix::io::Errno::ISDIR => {
                Self::named(dest)
            }
            Err(e) => Err(e.into()),
        }
    }

    #[cfg(not(any(target_os = "linux", target_os = "android")))]
    fn replacing(dest: PathBuf) -> std::io::Result<(File, Sink)> {
        Self::named(dest)
    }

    fn named(dest: PathBuf) -> std::io::Result<(File, Sink)> {
        let mut name = std::ffi::OsString::from(".");
        name.push(dest.file_name().unwrap_or_default());
        name.push(format!(".partial-{}", std::process::id()));
        let partial = dest.with_file_name(name);
        let file = fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&partial)?;
        Ok((file, Sink::Named { dest, partial }))
    }

    /// Where the rows go.
    pub fn writer(&mut self) -> &mut dyn Write {
        &mut self.writer
    }

    /// Flushes and, for a replaced file, puts the new file in place.
    pub fn finish(self) -> Result<()> {
        let Self {
            option,
            path,
            writer,
            sink,
        } = self;
        let fail = |e: std::io::Error| Error::Input(format!("{option} {}: {e}", path.display()));
        let file = writer.into_inner().map_err(|e| fail(e.into_error()))?;
        // A named partial file that fails to move is removed when `sink` drops.
        match &sink {
            Sink::InPlace => Ok(()),
            #[cfg(any(target_os = "linux", target_os = "android"))]
            Sink::Anonymous { dest } => link_into_place(&file, dest).map_err(fail),
            Sink::Named { dest, partial } => {
                drop(file);
                fs::rename(partial, dest).map_err(fail)
            }
        }
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
    let mut name = std::ffi::OsString::from(".");
    name.push(dest.file_name().unwrap_or_default());
    name.push(format!(".new-{}", std::process::id()));
    let temporary = dest.with_file_name(name);
    linkat(CWD, &proc_path, CWD, &temporary, AtFlags::SYMLINK_FOLLOW)?;
    fs::rename(&temporary, dest).inspect_err(|_| {
        let _ = fs::remove_file(&temporary);
    })
}

/// The mount points of this process's mount namespace, from `/proc/self/mountinfo` (field 5,
/// its octal escapes decoded); `None` where it cannot be read (not Linux, `/proc` not mounted).
pub fn mount_points() -> Option<Vec<PathBuf>> {
    let text = fs::read_to_string("/proc/self/mountinfo").ok()?;
    Some(
        text.lines()
            .filter_map(|line| line.split(' ').nth(4))
            .map(unescape_mount_path)
            .collect(),
    )
}

/// `\040` (space), `\011` (tab), `\012` (newline) and `\134` (backslash) as the kernel writes
/// them in `mountinfo`.
fn unescape_mount_path(field: &str) -> PathBuf {
    let bytes = field.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let octal = bytes
            .get(i + 1..i + 4)
            .filter(|d| bytes[i] == b'\\' && d.iter().all(|c| (b'0'..=b'7').contains(c)));
        match octal {
            Some(d) => {
                out.push((d[0] - b'0') * 64 + (d[1] - b'0') * 8 + (d[2] - b'0'));
                i += 4;
            }
            None => {
                out.push(bytes[i]);
                i += 1;
            }
        }
    }
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStringExt;
        PathBuf::from(std::ffi::OsString::from_vec(out))
    }
    #[cfg(not(unix))]
    PathBuf::from(String::from_utf8_lossy(&out).into_owned())
}

/// The device of the file system holding `path` itself (a link not followed).
#[cfg(unix)]
pub fn device_of(path: &Path) -> std::io::Result<u64> {
    use std::os::unix::fs::MetadataExt;
    fs::symlink_metadata(path).map(|m| m.dev())
}

#[cfg(not(unix))]
pub fn device_of(path: &Path) -> std::io::Result<u64> {
    fs::symlink_metadata(path).map(|_| 0)
}

/// Whether `path` (absolute, links resolved) is a mount point: listed in `mountinfo` (which
/// also finds a bind mount of the same file system), or on another device than its directory.
pub fn is_mount_point(path: &Path, mounts: Option<&[PathBuf]>) -> bool {
    if mounts.is_some_and(|m| m.iter().any(|p| p == path)) {
        return true;
    }
    let parent = path.parent().unwrap_or(path);
    matches!((device_of(path), device_of(parent)), (Ok(a), Ok(b)) if a != b)
}

/// What a file that is not a regular file is, for messages: "a directory", "a named pipe", ...
pub fn describe_file_type(kind: &fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a named pipe";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a directory"
    } else if kind.is_symlink() {
        "a symbolic link"
    } else if kind.is_file() {
        "a regular file"
    } else {
        "not a regular file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mountinfo_escapes_are_decoded() {
        assert_eq!(
            unescape_mount_path(r"/mnt/a\040b\134c"),
            PathBuf::from(r"/mnt/a b\c")
        );
        assert_eq!(unescape_mount_path(r"/x\04"), PathBuf::from(r"/x\04"));
    }
}

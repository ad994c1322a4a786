//! What a path names, decided by `stat` after resolving it, for the checks of output and
//! input paths before a run ([`crate::platform::output_file`], the report's publishing (`mass_spring_report::publish`),
//! [`crate::particles::scene_file`]): one of this process's descriptors, a named pipe (waited for a short
//! stated time, never forever), a mount point (`/proc/self/mountinfo`, which also lists bind
//! mounts of one file system), a file's kind in words.

use std::fs::{self, File};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How long a named pipe is waited for: a reader of an output, a writer of a scene file.
pub const FIFO_PATIENCE: Duration = Duration::from_secs(1);

/// The longest file name the usual file systems take (`NAME_MAX`), in bytes.
pub const NAME_MAX: usize = 255;

/// Whether `meta` is a character device's (`/dev/null`, a terminal).
#[cfg(unix)]
pub fn is_char_device(meta: &fs::Metadata) -> bool {
    std::os::unix::fs::FileTypeExt::is_char_device(&meta.file_type())
}

#[cfg(not(unix))]
pub fn is_char_device(_meta: &fs::Metadata) -> bool {
    false
}

/// Whether `meta` is a named pipe's.
#[cfg(unix)]
pub fn is_fifo(meta: &fs::Metadata) -> bool {
    std::os::unix::fs::FileTypeExt::is_fifo(&meta.file_type())
}

#[cfg(not(unix))]
pub fn is_fifo(_meta: &fs::Metadata) -> bool {
    false
}

/// The number of the descriptor `path` names: the links of the path are followed one by one
/// until one is an entry of this process's `fd` directory on procfs.
#[cfg(any(target_os = "linux", target_os = "android"))]
pub fn named_descriptor(path: &Path) -> Option<i32> {
    let mut current = std::path::absolute(path).ok()?;
    // The kernel's own limit on links in a path.
    for _ in 0..40 {
        let name = current.file_name()?.to_owned();
        let parent = fs::canonicalize(current.parent()?).ok()?;
        if is_own_descriptor_directory(&parent) {
            return name.to_str()?.parse().ok();
        }
        let here = parent.join(&name);
        if !fs::symlink_metadata(&here).ok()?.file_type().is_symlink() {
            return None;
        }
        current = parent.join(fs::read_link(&here).ok()?);
    }
    None
}

#[cfg(not(any(target_os = "linux", target_os = "android")))]
pub fn named_descriptor(_path: &Path) -> Option<i32> {
    None
}

/// `/proc/<this pid>/fd` or `/proc/<this pid>/task/<tid>/fd`, on procfs.
#[cfg(any(target_os = "linux", target_os = "android"))]
fn is_own_descriptor_directory(dir: &Path) -> bool {
    const PROC_SUPER_MAGIC: u64 = 0x9fa0;
    let pid = std::process::id().to_string();
    let parts: Vec<&std::ffi::OsStr> = dir.iter().collect();
    let own = match parts.as_slice() {
        [_, proc, p, fd] => *proc == "proc" && *p == pid.as_str() && *fd == "fd",
        [_, proc, p, task, _, fd] => {
            *proc == "proc" && *p == pid.as_str() && *task == "task" && *fd == "fd"
        }
        _ => false,
    };
    #[allow(clippy::unnecessary_cast)] // the type of f_type differs between platforms
    let on_procfs = rustix::fs::statfs(dir).is_ok_and(|s| s.f_type as u64 == PROC_SUPER_MAGIC);
    own && on_procfs
}

/// Opens a named pipe for writing once a reader has it open, waiting at most `patience`.
#[cfg(unix)]
pub fn open_fifo_for_writing(path: &Path, patience: Duration) -> std::io::Result<File> {
    use rustix::fs::{fcntl_getfl, fcntl_setfl, openat, Mode, OFlags, CWD};
    let deadline = Instant::now() + patience;
    loop {
        // Without a reader a non-blocking open fails with ENXIO instead of waiting.
        match openat(
            CWD,
            path,
            OFlags::WRONLY | OFlags::NONBLOCK | OFlags::CLOEXEC,
            Mode::empty(),
        ) {
            Ok(fd) => {
                fcntl_setfl(&fd, fcntl_getfl(&fd)? - OFlags::NONBLOCK)?;
                return Ok(File::from(fd));
            }
            Err(rustix::io::Errno::NXIO) if Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(10));
            }
            Err(e) => return Err(e.into()),
        }
    }
}

#[cfg(not(unix))]
pub fn open_fifo_for_writing(path: &Path, _patience: Duration) -> std::io::Result<File> {
    fs::OpenOptions::new().write(true).open(path)
}

/// The bytes a writer sends through the named pipe `path`, up to `limit` (more is cut off for
/// the caller to refuse); `None` if no writer opened it within `patience`.
#[cfg(unix)]
pub fn read_named_pipe(
    path: &Path,
    patience: Duration,
    limit: u64,
) -> std::io::Result<Option<Vec<u8>>> {
    use rustix::fs::{fcntl_getfl, fcntl_setfl, openat, Mode, OFlags, CWD};
    // A non-blocking open for reading succeeds at once; reads then return end of file until
    // a writer comes, and "would block" once one is there but has not written yet.
    let fd = openat(
        CWD,
        path,
        OFlags::RDONLY | OFlags::NONBLOCK | OFlags::CLOEXEC,
        Mode::empty(),
    )?;
    let mut file = File::from(fd);
    let deadline = Instant::now() + patience;
    let (mut bytes, mut buffer) = (Vec::new(), vec![0u8; 1 << 16]);
    let mut blocking = false;
    loop {
        match file.read(&mut buffer) {
            Ok(0) if bytes.is_empty() && !blocking => {
                if Instant::now() >= deadline {
                    return Ok(None);
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            Ok(0) => break,
            Ok(n) => {
                bytes.extend_from_slice(&buffer[..n]);
                if bytes.len() as u64 > limit {
                    break;
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                fcntl_setfl(&file, fcntl_getfl(&file)? - OFlags::NONBLOCK)?;
                blocking = true;
            }
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(Some(bytes))
}

#[cfg(not(unix))]
pub fn read_named_pipe(
    path: &Path,
    _patience: Duration,
    limit: u64,
) -> std::io::Result<Option<Vec<u8>>> {
    let mut bytes = Vec::new();
    File::open(path)?.take(limit + 1).read_to_end(&mut bytes)?;
    Ok(Some(bytes))
}

/// Whether `path` is a named pipe (links followed).
pub fn is_named_pipe(path: &Path) -> bool {
    fs::metadata(path).is_ok_and(|m| is_fifo(&m))
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

/// The largest scene file read (16 MiB, some 140 000 nodes of a spring scene): a larger one,
/// or an endless one (`/dev/zero`), is refused before it is parsed. Parsing takes about 45 bytes of memory a
/// byte of file (1.0 GB for a 22 MB file of 200 000 nodes), so this bounds it near 750 MB.
pub const MAX_SCENE_FILE_BYTES: u64 = 16 << 20;

/// The text of a scene file (the spring scenes' or the continuum's), at most
/// [`MAX_SCENE_FILE_BYTES`] (a larger or endless one, `/dev/zero`, is refused before it is
/// parsed), UTF-8; a named pipe
/// nobody writes to is refused after [`FIFO_PATIENCE`]. Every error starts with the file's
/// path.
pub fn read_scene_text(path: &Path) -> crate::error::Result<String> {
    use crate::error::Error;
    let limit = MAX_SCENE_FILE_BYTES;
    let fail = |e: String| Error::Input(format!("scene file {}: {e}", path.display()));
    let mut bytes = Vec::new();
    if is_named_pipe(path) {
        // A pipe nobody writes to is refused after a short wait instead of blocking silently.
        bytes = read_named_pipe(path, FIFO_PATIENCE, limit)
            .map_err(|e| fail(e.to_string()))?
            .ok_or_else(|| {
                fail(format!(
                    "a named pipe with a writer: none opened it within {} s",
                    FIFO_PATIENCE.as_secs_f64()
                ))
            })?;
    } else {
        File::open(path)
            .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
            .map_err(|e| fail(e.to_string()))?;
    }
    if bytes.len() as u64 > limit {
        return Err(fail(format!(
            "longer than {} MiB, the limit of a scene file",
            limit >> 20
        )));
    }
    String::from_utf8(bytes).map_err(|e| fail(format!("not UTF-8 text: {e}")))
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

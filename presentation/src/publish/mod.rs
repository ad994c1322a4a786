//! Publishing the report: the output directory is replaced as a whole, and only what the
//! report wrote is replaced.
//!
//! [`ReportTarget::open`] runs before the experiments: it takes a lock beside the output
//! directory (`.report.lock` for `report/`, opened `O_NOFOLLOW | O_NONBLOCK` and refused unless
//! it is a regular file), cleans or recovers what a crashed run left (`.report.tmp-<pid>-<ns>`,
//! `.report.old-<pid>-<ns>`: only names of exactly that shape, and only directories), reads the
//! directory's [`MANIFEST`] and refuses a directory it may not replace, and creates the staging
//! directory beside it (which also proves that the parent is writable). The directory is the
//! report's only when its `MANIFEST` is the one this module writes: its header, its sorted
//! relative paths, itself listed, and every listed entry a regular file inside it. A mount point
//! as the output or inside it is refused there too: the swap renames directories and the
//! clean-up removes them, and neither may cross into another file system. [`ReportTarget::publish`] writes the new report and its
//! manifest into the staging directory, carries every entry the previous report did not write
//! into it (hard links, or copies), and swaps the two directories:
//!
//! - on Linux with `renameat2(RENAME_EXCHANGE)`, so that at every instant the output path holds
//!   the complete previous report or the complete new one;
//! - elsewhere (or where the file system refuses the exchange) by two renames, output →
//!   `.report.old-*` then staging → output; a crash between them leaves no output directory
//!   but the previous report under `.report.old-*`, which the next [`ReportTarget::open`] puts
//!   back (the names themselves are the journal).
//!
//! A directory that exists, is not empty and has no manifest is refused, unless it is a report
//! written before manifests existed (its `REPORT.md` starts with [`REPORT_TITLE`]): then
//! `REPORT.md`, `run-info.md`, `data/*.csv` and `figures/*.svg` count as the report's. A
//! directory whose `MANIFEST` is not the report's is refused likewise. Every refusal comes
//! before anything is written, so its "nothing was changed" is true.
//!
//! Clean-up (`files::remove_tree`) never follows a symbolic link and never crosses into another file
//! system: what holds a mount point is left in place, with a message.

mod files;
#[cfg(unix)]
mod identity;
mod ownership;

pub use files::{MANIFEST, REPORT_TITLE};

use crate::output::OutputFile;
use files::{
    carry_over, exchange, io_error, is_journal_name, remove_tree, sibling, sorted_entries,
    unique_suffix, NANOS_DIGITS,
};
#[cfg(unix)]
use identity::Recorded;
use mass_spring_solvers::error::{Error, Result};
use mass_spring_solvers::platform::paths::{describe_file_type, NAME_MAX};
use ownership::{
    existing_ownership, foreign_entries, manifest_text, read_manifest,
    refuse_what_cannot_be_published, relative_inside, strays, Manifest, Ownership,
};
use std::collections::BTreeSet;
use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The most digits of a process id in a journal name (`is_journal_name` accepts no more).
const PID_DIGITS: usize = 10;

/// The longest output directory name whose journal siblings fit in [`NAME_MAX`]:
/// `.<name>.tmp-<pid>-<ns>` adds a dot, `.tmp-`, the pid, a dash and the nanoseconds.
const MAX_OUTPUT_NAME: usize = NAME_MAX - (1 + ".tmp-".len() + PID_DIGITS + 1 + NANOS_DIGITS);

/// How long [`ReportTarget::open`] waits for a busy lock.
const LOCK_PATIENCE: Duration = Duration::from_millis(500);

/// How a test stops [`ReportTarget::publish_with`] at its `n`-th checkpoint (counted from 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// The process dies there: nothing is cleaned up (the lock is released, as by the kernel).
    Crash(usize),
    /// An I/O error there: the writer takes its ordinary error path.
    IoError(usize),
}

/// How the directories are swapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Swap {
    /// `renameat2(RENAME_EXCHANGE)`, falling back to [`Swap::Journal`] where it is refused.
    Exchange,
    /// Two renames, recoverable from the directory names (see the module documentation).
    Journal,
}

impl Swap {
    /// The platform's best.
    pub fn platform() -> Self {
        if cfg!(any(target_os = "linux", target_os = "android")) {
            Swap::Exchange
        } else {
            Swap::Journal
        }
    }
}

/// The output directory, locked and checked, with its staging directory beside it.
#[derive(Debug)]
pub struct ReportTarget {
    dir: PathBuf,
    staging: PathBuf,
    old: PathBuf,
    ownership: Ownership,
    /// The output directory and the report's files in it as found at the start, checked
    /// again before anything is published.
    #[cfg(unix)]
    recorded: Recorded,
    notes: Vec<String>,
    /// Set by an injected crash: a killed process cleans nothing up.
    crashed: bool,
    _lock: Lock,
}

impl Drop for ReportTarget {
    /// A run that ends without publishing (a failed experiment) removes its staging directory;
    /// the lock is released after it.
    fn drop(&mut self) {
        if !self.crashed {
            // Best effort: what is left is removed by the next run.
            let _ = remove_tree(&self.staging);
        }
    }
}

/// Only one writer per output directory: an advisory lock on a file beside it, released by the
/// kernel when the process ends, however it ends.
#[derive(Debug)]
struct Lock {
    _file: File,
}

impl Lock {
    /// Takes the lock `path` of the directory `dir`, waiting [`LOCK_PATIENCE`] at most.
    fn acquire(path: &Path, dir: &Path) -> Result<Self> {
        let file = open_lock_file(path)?;
        // A lock is held a moment longer than its run by a child forked meanwhile (until it
        // execs), so a busy lock is retried briefly before it is reported.
        let deadline = Instant::now() + LOCK_PATIENCE;
        loop {
            match try_lock(&file) {
                Ok(()) => break,
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                    if Instant::now() >= deadline {
                        return Err(Error::Input(format!(
                            "another report run is writing {} (or `timing` is writing into it: \
                             it holds the lock {}); wait for it to finish or stop it, then run \
                             again",
                            dir.display(),
                            path.display()
                        )));
                    }
                    std::thread::sleep(Duration::from_millis(10));
                }
                Err(e) => return Err(io_error("locking", path, e)),
            }
        }
        Ok(Self { _file: file })
    }
}

/// Opens the lock file for reading (enough for `flock`, so that a lock file another user left
/// does not stop a run), creating it if it is missing; never through a symbolic link
/// (`O_NOFOLLOW`), never waiting for a writer of a FIFO (`O_NONBLOCK`), and only a regular file.
#[cfg(unix)]
fn open_lock_file(path: &Path) -> Result<File> {
    use rustix::fs::{openat, Mode, OFlags, CWD};
    use rustix::io::Errno;
    let not_regular = |what: &str| {
        Error::Input(format!(
            "the lock file {} is not a regular file ({what}); nothing was changed. Remove it \
             if no report run is using it, and run again",
            path.display()
        ))
    };
    let flags = OFlags::RDONLY | OFlags::NOFOLLOW | OFlags::NONBLOCK | OFlags::CLOEXEC;
    // A few attempts: another run may create the file between the two opens.
    let mut opened = Err(Errno::NOENT);
    for _ in 0..3 {
        opened = openat(CWD, path, flags, Mode::empty()).or_else(|e| match e {
            Errno::NOENT => openat(
                CWD,
                path,
                flags | OFlags::CREATE | OFlags::EXCL,
                Mode::from_raw_mode(0o644),
            ),
            e => Err(e),
        });
        if !matches!(opened, Err(Errno::EXIST)) {
            break;
        }
    }
    let file = match opened {
        Ok(fd) => File::from(fd),
        // O_NOFOLLOW on a symbolic link (or O_EXCL on a dangling one, then again).
        Err(Errno::LOOP) | Err(Errno::EXIST) => return Err(not_regular("a symbolic link")),
        Err(e) => return Err(io_error("opening the lock file", path, e.into())),
    };
    let kind = file
        .metadata()
        .map_err(|e| io_error("reading the lock file", path, e))?
        .file_type();
    if !kind.is_file() {
        return Err(not_regular(describe_file_type(&kind)));
    }
    Ok(file)
}

#[cfg(not(unix))]
fn open_lock_file(path: &Path) -> Result<File> {
    fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(path)
        .map_err(|e| io_error("creating the lock file", path, e))
}

#[cfg(unix)]
fn try_lock(file: &File) -> std::io::Result<()> {
    rustix::fs::flock(file, rustix::fs::FlockOperation::NonBlockingLockExclusive)
        .map_err(std::io::Error::from)
}

#[cfg(not(unix))]
fn try_lock(_file: &File) -> std::io::Result<()> {
    // No advisory locks without rustix: one writer at a time is then the user's business.
    Ok(())
}

/// Why [`ReportTarget::publish_with`] stopped early.
enum Stop {
    Failed(Error),
    Crashed(Error),
}

impl From<Error> for Stop {
    fn from(e: Error) -> Self {
        Stop::Failed(e)
    }
}

/// Counts the checkpoints of one publication and fires the injected fault.
struct Checkpoints {
    passed: usize,
    fault: Option<Fault>,
    /// Whether the new report is in place: a later failure must not remove it.
    swapped: bool,
}

impl Checkpoints {
    fn pass(&mut self, what: &str) -> std::result::Result<(), Stop> {
        let n = self.passed;
        self.passed += 1;
        let message =
            |kind: &str| Error::Input(format!("injected {kind} at checkpoint {n}: {what}"));
        match self.fault {
            Some(Fault::Crash(at)) if at == n => Err(Stop::Crashed(message("crash"))),
            Some(Fault::IoError(at)) if at == n => Err(Stop::Failed(message("I/O error"))),
            _ => Ok(()),
        }
    }
}

impl ReportTarget {
    /// Locks `dir`, recovers or cleans what a crashed run left, refuses a directory the report
    /// may not replace (not a directory; not empty and no manifest; a foreign entry where the
    /// report writes) and creates the staging directory. Run it before the long work.
    pub fn open(dir: &Path) -> Result<Self> {
        let dir = resolved(dir)?;
        let Some(name) = dir.file_name() else {
            return Err(Error::Input(format!(
                "the output directory {} has no name of its own; give a directory below it",
                dir.display()
            )));
        };
        // Before the lock file is made beside it: its staging directory must fit the name.
        let length = name.as_encoded_bytes().len();
        if length > MAX_OUTPUT_NAME {
            return Err(Error::Input(format!(
                "the output directory's name {} is {length} bytes; report takes names of at \
                 most {MAX_OUTPUT_NAME} bytes, so that its staging directory beside it \
                 (.<name>.tmp-<pid>-<nanoseconds>) fits the file system's {NAME_MAX}; nothing \
                 was changed. Give --out a shorter name",
                dir.display()
            )));
        }
        let parent = dir.parent().unwrap_or(Path::new("/"));
        if !parent.is_dir() {
            return Err(Error::Input(format!(
                "the directory {} that would hold the output directory does not exist (or is \
                 not a directory); nothing was changed. Create it first, or give another --out",
                parent.display()
            )));
        }
        // Checked once before anything is written (so that a refused directory gets not even a
        // lock file beside it), and again under the lock, after the recovery.
        existing_ownership(&dir)?;
        let lock = Lock::acquire(&sibling(&dir, "lock"), &dir)?;
        let notes = recover(&dir)?;
        let ownership = existing_ownership(&dir).map_err(|e| match e {
            // Say what the recovery did change.
            Error::Input(m) if !notes.is_empty() => Error::Input(m.replace(
                "nothing was changed",
                &format!("nothing else was changed ({})", notes.join("; ")),
            )),
            e => e,
        })?;
        #[cfg(unix)]
        let recorded = Recorded::take(&dir, &ownership)?;
        let suffix = unique_suffix();
        let staging = sibling(&dir, &format!("tmp-{suffix}"));
        fs::create_dir(&staging).map_err(|e| {
            io_error(
                "the output directory's parent is not writable: creating",
                &staging,
                e,
            )
        })?;
        Ok(Self {
            old: sibling(&dir, &format!("old-{suffix}")),
            dir,
            staging,
            ownership,
            #[cfg(unix)]
            recorded,
            notes,
            crashed: false,
            _lock: lock,
        })
    }

    /// The output directory (absolute, symbolic links resolved).
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// What [`ReportTarget::open`] recovered or cleaned, for the user.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// Writes `files` and the manifest, carries the foreign entries over and swaps the new
    /// report in (see the module documentation).
    pub fn publish(self, files: &[OutputFile]) -> Result<()> {
        self.publish_with(files, Swap::platform(), None)
    }

    /// [`ReportTarget::publish`] with a chosen swap and, for tests, a fault injected at a
    /// checkpoint. A crash returns an error and leaves everything as a killed process would.
    pub fn publish_with(
        mut self,
        files: &[OutputFile],
        swap: Swap,
        fault: Option<Fault>,
    ) -> Result<()> {
        let mut checkpoints = Checkpoints {
            passed: 0,
            fault,
            swapped: false,
        };
        match self.steps(files, swap, &mut checkpoints) {
            Ok(()) => Ok(()),
            Err(Stop::Crashed(e)) => {
                self.crashed = true;
                Err(e)
            }
            Err(Stop::Failed(e)) if checkpoints.swapped => Err(Error::Input(format!(
                "the new report is in place, but {e}; the next run removes what is left"
            ))),
            Err(Stop::Failed(e)) => {
                let cleanup = remove_tree(&self.staging);
                Err(match cleanup {
                    Ok(()) => Error::Input(format!("{e}; the previous report is unchanged")),
                    Err(c) => Error::Input(format!(
                        "{e}; the previous report is unchanged ({c}: the next run removes it)"
                    )),
                })
            }
        }
    }

    fn steps(
        &self,
        files: &[OutputFile],
        swap: Swap,
        checkpoints: &mut Checkpoints,
    ) -> std::result::Result<(), Stop> {
        let mut written = BTreeSet::new();
        for file in files {
            relative_inside(&file.path, "report file")?;
            if file.path == Path::new(MANIFEST) || !written.insert(file.path.clone()) {
                return Err(Error::Input(format!(
                    "report file {} is given twice or is the manifest",
                    file.path.display()
                ))
                .into());
            }
        }
        // Before anything is written: the target is still the one checked at the start, and
        // holds nothing added since that this user could not carry over or remove.
        self.verify_target()?;
        let foreign = if self.dir.exists() {
            refuse_what_cannot_be_published(&self.dir, &self.ownership)?;
            foreign_entries(&self.dir, &self.ownership, &written)?
        } else {
            Vec::new()
        };
        for file in files {
            let path = self.staging.join(&file.path);
            if let Some(parent) = path.parent() {
                fs::create_dir_all(parent).map_err(|e| io_error("creating", parent, e))?;
            }
            fs::write(&path, &file.contents).map_err(|e| io_error("writing", &path, e))?;
            checkpoints.pass(&format!("wrote {}", file.path.display()))?;
        }
        written.insert(PathBuf::from(MANIFEST));
        let manifest = self.staging.join(MANIFEST);
        fs::write(&manifest, manifest_text(&written))
            .map_err(|e| io_error("writing", &manifest, e))?;
        checkpoints.pass("wrote the manifest")?;
        for rel in &foreign {
            let dst = self.staging.join(rel);
            if let Some(parent) = dst.parent() {
                fs::create_dir_all(parent).map_err(|e| io_error("creating", parent, e))?;
            }
            carry_over(&self.dir.join(rel), &dst)?;
            checkpoints.pass(&format!("carried over {}", rel.display()))?;
        }
        // Again just before the swap, which is the first change to the target: writing the
        // staging directory took a while.
        self.verify_target()?;
        if !self.dir.exists() {
            fs::rename(&self.staging, &self.dir)
                .map_err(|e| io_error("moving into place", &self.dir, e))?;
            checkpoints.swapped = true;
            checkpoints.pass("moved the new report into place")?;
            return Ok(());
        }
        let exchanged = swap == Swap::Exchange
            && exchange(&self.staging, &self.dir)
                .map_err(|e| io_error("exchanging the report with", &self.staging, e))?;
        if exchanged && !self.moved_away_is_recorded(&self.staging) {
            // Replaced between the last check and the exchange: the user's directory is now at
            // the staging path; the exchange undone, it is back and the new report is staged.
            return match exchange(&self.staging, &self.dir) {
                Ok(true) => Err(self.replaced_at_the_swap().into()),
                undo => Err(self.stranded(&self.staging, undo.err())),
            };
        }
        let old = if exchanged {
            checkpoints.swapped = true;
            checkpoints.pass("exchanged the two directories")?;
            &self.staging
        } else {
            self.journal_swap(checkpoints)?;
            &self.old
        };
        // What was added to the target after its foreign entries were listed, while the new
        // report was staged, is in the previous directory only: carried over before it goes.
        for rel in strays(old, &self.dir, &self.ownership)? {
            let dst = self.dir.join(&rel);
            if let Some(parent) = dst.parent() {
                fs::create_dir_all(parent).map_err(|e| io_error("creating", parent, e))?;
            }
            carry_over(&old.join(&rel), &dst)?;
        }
        remove_tree(old)?;
        checkpoints.pass("removed the previous report")?;
        Ok(())
    }

    /// Refuses to go on when the output directory, or a file of the previous report in it, is
    /// not the one found at the start ([`identity`]).
    fn verify_target(&self) -> Result<()> {
        #[cfg(unix)]
        self.recorded.verify(&self.dir, &self.ownership)?;
        Ok(())
    }

    /// Whether the directory the swap moved from the output path to `path` is the output
    /// directory found at the start.
    fn moved_away_is_recorded(&self, path: &Path) -> bool {
        #[cfg(unix)]
        return self.recorded.is_the_output_directory(path);
        #[cfg(not(unix))]
        return path.is_dir();
    }

    /// The refusal of a target replaced between the last check and the swap, the swap undone.
    fn replaced_at_the_swap(&self) -> Error {
        Error::Input(format!(
            "the output directory {} was replaced during the run, at the moment of the swap; \
             the swap was undone, so the directory there is as it was put",
            self.dir.display()
        ))
    }

    /// The stop when the swap could not be undone: the directory put at the output path is at
    /// `at`, beside it, and nothing may remove it (a crash leaves everything as it is).
    fn stranded(&self, at: &Path, why: Option<std::io::Error>) -> Stop {
        let why = why.map_or("the file system refused it".to_string(), |e| e.to_string());
        Stop::Crashed(Error::Input(format!(
            "the output directory {} was replaced during the run, at the moment of the swap, \
             and undoing the swap failed ({why}): the directory that was put there is now {}; \
             move it back before the next run, which would take it for its own leftover",
            self.dir.display(),
            at.display()
        )))
    }

    /// Output → `.<name>.old-*`, staging → output, rolling the first rename back if the second
    /// fails.
    fn journal_swap(&self, checkpoints: &mut Checkpoints) -> std::result::Result<(), Stop> {
        fs::rename(&self.dir, &self.old).map_err(|e| io_error("moving aside", &self.dir, e))?;
        if !self.moved_away_is_recorded(&self.old) {
            // As after the exchange: a directory put in place after the last check goes back.
            return match fs::rename(&self.old, &self.dir) {
                Ok(()) => Err(self.replaced_at_the_swap().into()),
                Err(e) => Err(self.stranded(&self.old, Some(e))),
            };
        }
        let second = checkpoints
            .pass("moved the previous report aside")
            .and_then(|()| {
                fs::rename(&self.staging, &self.dir)
                    .map_err(|e| Stop::Failed(io_error("moving into place", &self.dir, e)))
            });
        match second {
            Ok(()) => {
                checkpoints.swapped = true;
                checkpoints.pass("moved the new report into place")
            }
            Err(Stop::Failed(e)) => match fs::rename(&self.old, &self.dir) {
                Ok(()) => Err(Stop::Failed(e)),
                Err(r) => Err(Stop::Crashed(Error::Input(format!(
                    "{e}; putting the previous report back from {} failed ({r}): the next run \
                     does it",
                    self.old.display()
                )))),
            },
            crashed => crashed,
        }
    }
}

/// `dir` absolute, its symbolic links resolved where it exists.
fn resolved(dir: &Path) -> Result<PathBuf> {
    match fs::canonicalize(dir) {
        Ok(real) => Ok(real),
        Err(_) => std::path::absolute(dir).map_err(|e| io_error("resolving", dir, e)),
    }
}

/// The lock [`ReportTarget::open`] takes for a report directory, held by another writer inside
/// it (`timing` into `report/timing`) so that it never writes while a report run replaces the
/// directory (and its files with it); released when dropped.
#[derive(Debug)]
pub struct DirectoryLock {
    _lock: Lock,
}

/// Takes the lock of the report directory `dir` ([`DirectoryLock`]), as a report run would;
/// `None` where the directory holding `dir` does not exist, so that no report run can be
/// writing it (a report's output needs an existing parent).
pub fn lock_report_directory(dir: &Path) -> Result<Option<DirectoryLock>> {
    let dir = resolved(dir)?;
    if dir.file_name().is_none() || !dir.parent().is_some_and(Path::is_dir) {
        return Ok(None);
    }
    Ok(Some(DirectoryLock {
        _lock: Lock::acquire(&sibling(&dir, "lock"), &dir)?,
    }))
}

/// The lock a writer of the directory `out` holds for its run (`timing` into `report/timing`,
/// `report_long` into `report/long`): the lock of the report directory holding `out` when its
/// parent is one (it holds a report's manifest), so that no report run replaces it meanwhile;
/// else the lock of `out` itself, beside it, in a directory the user chose.
pub fn lock_for_output(out: &Path) -> Result<Option<DirectoryLock>> {
    let absolute = std::path::absolute(out).map_err(|e| io_error("resolving", out, e))?;
    match absolute.parent() {
        Some(holder) if holder.join(MANIFEST).exists() => lock_report_directory(holder),
        _ => lock_report_directory(&absolute),
    }
}

/// Whether `path` holds a previous report set aside by the journal: empty (an empty output
/// directory was replaced), with the report's manifest, or a report from before manifests.
fn is_previous_report(path: &Path) -> bool {
    match read_manifest(path) {
        Ok(Manifest::Ours(_)) => true,
        Ok(Manifest::Missing) => {
            sorted_entries(path).is_ok_and(|e| e.is_empty())
                || fs::read_to_string(path.join("REPORT.md"))
                    .is_ok_and(|r| r.starts_with(REPORT_TITLE))
        }
        _ => false,
    }
}

/// What a crashed run left beside `dir`: the previous report set aside (put back when `dir` is
/// missing), staging directories and previous reports (removed). Only directories (not links)
/// whose names have the journal's exact shape count, and a set-aside report must be one; what
/// cannot be removed is left with a note. Runs under the lock.
fn recover(dir: &Path) -> Result<Vec<String>> {
    let parent = dir.parent().unwrap_or(Path::new("/"));
    let prefix = |kind: &str| {
        sibling(dir, kind)
            .file_name()
            .unwrap_or_default()
            .to_owned()
    };
    let (tmp, old) = (prefix("tmp-"), prefix("old-"));
    let mut notes = Vec::new();
    let mut leftovers = Vec::new();
    for name in sorted_entries(parent)? {
        let path = parent.join(&name);
        if !fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir()) {
            continue;
        }
        if is_journal_name(&name, &old) && is_previous_report(&path) {
            if !dir.exists() {
                fs::rename(&path, dir).map_err(|e| io_error("putting back", &path, e))?;
                notes.push(format!(
                    "put the previous report back from {} (a run was interrupted)",
                    path.display()
                ));
                continue;
            }
            leftovers.push(path);
        } else if is_journal_name(&name, &tmp) {
            leftovers.push(path);
        }
    }
    for path in leftovers {
        notes.push(match remove_tree(&path) {
            Ok(()) => format!("removed {} (left by an interrupted run)", path.display()),
            Err(e) => format!(
                "left {} (from an interrupted run) in place: {e}; remove it yourself",
                path.display()
            ),
        });
    }
    Ok(notes)
}

/// Locks, checks and replaces `dir` by `files` in one go (see [`ReportTarget`]).
pub fn write_report(dir: &Path, files: &[OutputFile]) -> Result<()> {
    ReportTarget::open(dir)?.publish(files)
}

/// A synthetic report of `count` data files whose every byte names `tag`, for the interruption
/// tests of the real binary (`report --fixture TAG`).
#[doc(hidden)]
pub fn fixture(tag: &str, count: usize) -> Vec<OutputFile> {
    let mut files = vec![OutputFile::text(
        "REPORT.md",
        format!("{REPORT_TITLE} — fixture {tag}\n\n{count} data files\n"),
    )];
    files.extend((0..count).map(|i| {
        OutputFile::text(
            format!("data/f{i:05}.csv"),
            format!("{tag},{i}\n").repeat(16),
        )
    }));
    files
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Entries added to the target while the new report was staged (after its foreign entries
    /// were listed) are strays of the previous directory, carried over before it is removed: a
    /// file at the top and one inside a foreign directory already carried, not the previous
    /// report's files nor what is already in the new one. Without the step (the code before
    /// it), both would go with the previous directory.
    #[test]
    fn entries_added_while_the_report_is_staged_are_carried_over() {
        let base = std::env::temp_dir().join(format!("mss-strays-{}", std::process::id()));
        let _ = fs::remove_dir_all(&base);
        let (old, new) = (base.join("old"), base.join("new"));
        for dir in [&old, &new] {
            fs::create_dir_all(dir.join("notes")).unwrap();
            fs::write(dir.join("REPORT.md"), "report").unwrap();
            fs::write(dir.join("notes/a.txt"), "carried").unwrap();
        }
        fs::write(old.join(MANIFEST), "").unwrap();
        fs::write(old.join("late.txt"), "mine").unwrap();
        fs::write(old.join("notes/b.txt"), "mine too").unwrap();
        let ownership = Ownership::Listed([PathBuf::from("REPORT.md")].into_iter().collect());
        let found = strays(&old, &new, &ownership).unwrap();
        assert_eq!(
            found,
            vec![PathBuf::from("late.txt"), PathBuf::from("notes/b.txt")]
        );
        fs::remove_dir_all(&base).unwrap();
    }

    /// The output directory replaced after the last check, just before the journal's first
    /// rename: that rename moves the user's directory aside, the check after it finds it is not
    /// the one recorded, and it is put back, its files intact, the previous report untouched.
    #[cfg(unix)]
    #[test]
    fn a_directory_put_in_place_after_the_last_check_is_put_back_by_the_swap() {
        let base = std::env::temp_dir().join(format!("mss-swap-undo-{}", std::process::id()));
        let _ = fs::remove_dir_all(&base);
        fs::create_dir_all(&base).unwrap();
        let out = base.join("out");
        write_report(&out, &fixture("A", 2)).unwrap();
        let target = ReportTarget::open(&out).unwrap();
        let moved = base.join("out.moved");
        fs::rename(&out, &moved).unwrap();
        fs::create_dir(&out).unwrap();
        fs::write(out.join("REPORT.md"), "mine").unwrap();
        let mut checkpoints = Checkpoints {
            passed: 0,
            fault: None,
            swapped: false,
        };
        let stopped = target.journal_swap(&mut checkpoints);
        let Err(Stop::Failed(e)) = stopped else {
            panic!("the swap went on into a replaced directory");
        };
        assert!(e.to_string().contains("the swap was undone"), "{e}");
        assert!(!checkpoints.swapped);
        assert_eq!(fs::read_to_string(out.join("REPORT.md")).unwrap(), "mine");
        assert!(moved.join(MANIFEST).exists());
        drop(target);
        fs::remove_dir_all(&base).unwrap();
    }
}

//! The memory this process may still take, read from `/proc` and the control group before a
//! run, so that a scene or a run too large for the machine is refused before it allocates.

/// The memory this process may still take, in bytes: the least of the system's available
/// memory (`MemAvailable`), the address-space limit (`RLIMIT_AS`) less what is mapped already,
/// and the control group's limit less its use; `None` where none of them is known.
pub fn available_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let available = meminfo
        .as_deref()
        .and_then(|m| kib_field(m, "MemAvailable:"));
    [available, address_space_left(), cgroup_left()]
        .into_iter()
        .flatten()
        .min()
}

/// `<name> <n> kB` of a `/proc` status file, in bytes.
fn kib_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

#[cfg(unix)]
fn address_space_left() -> Option<u64> {
    let limit = rustix::process::getrlimit(rustix::process::Resource::As).current?;
    let status = std::fs::read_to_string("/proc/self/status").ok();
    let mapped = status
        .as_deref()
        .and_then(|s| kib_field(s, "VmSize:"))
        .unwrap_or(0);
    Some(limit.saturating_sub(mapped))
}

#[cfg(not(unix))]
fn address_space_left() -> Option<u64> {
    None
}

/// cgroup v2: `memory.max` less `memory.current` of this process's group.
fn cgroup_left() -> Option<u64> {
    let group = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let path = group.lines().find_map(|l| l.strip_prefix("0::"))?;
    let dir = std::path::Path::new("/sys/fs/cgroup").join(path.trim_start_matches('/'));
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
    let max: u64 = read("memory.max")?.trim().parse().ok()?;
    let current: u64 = read("memory.current")?.trim().parse().ok()?;
    Some(max.saturating_sub(current))
}

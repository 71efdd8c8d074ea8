//! The memory this process holds and may still take, from /proc and the cgroup.

/// The resident memory of this process now (VmRSS), where known.
pub fn memory_held() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    proc_field(&status, "VmRSS:", 1024)
}

/// The number after `key` on its line of `text` (a /proc file), times `unit`.
fn proc_field(text: &str, key: &str, unit: u64) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(key))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse::<u64>().ok())
        .map(|n| n.saturating_mul(unit))
}

/// The memory this process may still take, where known: what the system
/// has available, within the address-space limit (RLIMIT_AS, less what is
/// mapped now) and the cgroup's `memory.max` (less its `memory.current`).
pub fn memory_available() -> Option<u64> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let system = read("/proc/meminfo").and_then(|m| proc_field(&m, "MemAvailable:", 1024));
    let mapped = read("/proc/self/status").and_then(|s| proc_field(&s, "VmSize:", 1024));
    let address_space = read("/proc/self/limits")
        .and_then(|l| proc_field(&l, "Max address space", 1))
        .map(|limit| limit.saturating_sub(mapped.unwrap_or(0)));
    let group = read("/proc/self/cgroup")
        .and_then(|c| {
            c.lines()
                .find_map(|l| l.strip_prefix("0::").map(str::to_string))
        })
        .unwrap_or_default();
    let cgroup = [
        format!("/sys/fs/cgroup{group}"),
        "/sys/fs/cgroup".to_string(),
    ]
    .iter()
    .find_map(|dir| {
        let max = read(&format!("{dir}/memory.max"))?
            .trim()
            .parse::<u64>()
            .ok()?;
        let current = read(&format!("{dir}/memory.current"))
            .and_then(|c| c.trim().parse::<u64>().ok())
            .unwrap_or(0);
        Some(max.saturating_sub(current))
    });
    [system, address_space, cgroup].into_iter().flatten().min()
}

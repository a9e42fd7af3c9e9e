//! The `running` status names its process, so a reader can tell a run
//! still going from one whose process died without a final word (kill -9,
//! a second Ctrl-C, the out-of-memory killer, a lost node).

/// The status a writer sets while it steps: `running (pid N on HOST)`.
pub fn running() -> String {
    format!("running (pid {} on {})", std::process::id(), this_host())
}

/// The stored status of the run file `path` as a reader should see it: a
/// `running` status whose process was on this machine and is gone says so
/// (and how to resume); others are as stored.
pub fn describe(stored: &str, path: &std::path::Path) -> String {
    match running_process(stored) {
        Some((pid, host)) if host == this_host() && !alive(pid) => format!(
            "{stored}: that process is gone, so the run stopped without a final snapshot \
             (killed, interrupted twice, or stopped by a write error such as a full disk); resume it from its last checkpoint with \
             `floe run --resume {}`",
            path.display()
        ),
        _ => stored.to_string(),
    }
}

/// The pid and host of a `running (pid N on HOST)` status.
fn running_process(stored: &str) -> Option<(u32, String)> {
    let inner = stored.strip_prefix("running (pid ")?.strip_suffix(')')?;
    let (pid, host) = inner.split_once(" on ")?;
    Some((pid.parse().ok()?, host.to_string()))
}

/// This machine's name (Linux: the kernel's hostname; else `HOSTNAME`).
fn this_host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown host".to_string())
}

/// Whether process `pid` exists; where that cannot be told (no `/proc`),
/// it is taken to be alive.
fn alive(pid: u32) -> bool {
    if !std::path::Path::new("/proc/self").exists() {
        return true;
    }
    std::path::Path::new(&format!("/proc/{pid}")).exists()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn this_process_is_running() {
        let s = running();
        assert_eq!(
            running_process(&s).map(|(p, _)| p),
            Some(std::process::id())
        );
        assert_eq!(describe(&s, Path::new("r.h5")), s);
    }

    #[test]
    fn a_gone_process_is_reported_as_stopped() {
        // A child that has exited and been waited for is gone.
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        let s = format!("running (pid {pid} on {})", this_host());
        let said = describe(&s, Path::new("r.h5"));
        assert!(said.contains("that process is gone"), "{said}");
        assert!(said.contains("`floe run --resume r.h5`"), "{said}");
        // On another machine it cannot be told.
        let elsewhere = format!("running (pid {pid} on some-other-node)");
        assert_eq!(describe(&elsewhere, Path::new("r.h5")), elsewhere);
        assert_eq!(describe("completed", Path::new("r.h5")), "completed");
    }
}

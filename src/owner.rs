//! Who left a file or folder behind: names that record their writer (this host's name
//! and the process id), and the one rule that makes such a leftover provably stale.
//!
//! A writer that may be killed before it cleans up (an atomic write's temporary file,
//! a sharded job's staging folder, a join's lock) names what it leaves as
//! `PREFIX HOST-PID-RANDOM`: the host's name (letters, digits, `-` and `.`; anything
//! else as `_`), the process id, and 64 unpredictable bits. A later run may remove it
//! only when it is provably stale: written on this host by a process that no longer
//! exists (`kill(pid, 0)` fails with `ESRCH`; a process of another user still counts
//! as alive). A leftover of another host cannot be checked from here, and one whose
//! process id has been reused looks alive: both are kept, the safe side. Names are
//! parsed from the right, so a host name may hold `-`.

use std::hash::{BuildHasher, Hasher};
use std::sync::atomic::{AtomicU64, Ordering};

/// This host's name as names record it (module doc); `host` when it cannot be read.
pub(crate) fn host_name() -> String {
    let mut buf = [0u8; 256];
    // SAFETY: the buffer is valid for its length; gethostname writes at most that.
    let ok = unsafe { libc::gethostname(buf.as_mut_ptr().cast(), buf.len()) } == 0;
    let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
    let name = if ok { String::from_utf8_lossy(&buf[..end]).into_owned() } else { String::new() };
    let name: String =
        name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect();
    if name.is_empty() { "host".into() } else { name }
}

/// 64 unpredictable bits: a fresh randomly seeded std hasher over a counter, the
/// process and the time.
pub(crate) fn unpredictable() -> u64 {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(COUNTER.fetch_add(1, Ordering::Relaxed));
    h.write_u32(std::process::id());
    h.write_u128(std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos()));
    h.finish()
}

/// A fresh name `PREFIXHOST-PID-RANDOM` of this process.
pub(crate) fn owned_name(prefix: &str) -> String {
    format!("{prefix}{}-{}-{:016x}", host_name(), std::process::id(), unpredictable())
}

/// The writer `(HOST, PID)` of a name `PREFIXHOST-PID-RANDOM`; `None` for other names.
pub(crate) fn owner<'a>(name: &'a str, prefix: &str) -> Option<(&'a str, i32)> {
    let rest = name.strip_prefix(prefix)?;
    let (rest, random) = rest.rsplit_once('-')?;
    let (host, pid) = rest.rsplit_once('-')?;
    (random.len() == 16 && random.bytes().all(|b| b.is_ascii_hexdigit())).then_some(())?;
    Some((host, pid.parse().ok()?))
}

/// Whether process `pid` exists on this host (one of another user counts).
fn alive(pid: i32) -> bool {
    // SAFETY: signal 0 only checks that the process exists.
    pid > 0
        && (unsafe { libc::kill(pid, 0) } == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM))
}

/// Whether the writer `(host, pid)` is provably gone: this host, no such process.
pub(crate) fn dead_here(host: &str, pid: i32) -> bool {
    host == host_name() && !alive(pid)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owners_are_parsed_from_the_right_so_hosts_may_hold_dashes() {
        assert_eq!(owner("run-my-host-1234-00112233445566ff", "run-"), Some(("my-host", 1234)));
        assert_eq!(owner("run-host-12x-00112233445566ff", "run-"), None);
        assert_eq!(owner("old-h-1-0011", "old-"), None);
        let mine = owned_name("x-");
        assert_eq!(owner(&mine, "x-"), Some((host_name().as_str(), std::process::id() as i32)));
        assert!(!dead_here(&host_name(), std::process::id() as i32));
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id() as i32;
        child.wait().unwrap();
        assert!(dead_here(&host_name(), dead) && !dead_here("elsewhere.example", dead));
        let names: std::collections::HashSet<u64> = (0..1000).map(|_| unpredictable()).collect();
        assert_eq!(names.len(), 1000);
    }
}

//! This process as other stride processes see it: the machine's short name, the tag in
//! temporary file names, and whether a process of this machine still runs.

/// The short name of this machine (up to the first dot), reduced to letters, digits and
/// `-`: it tells apart the temporary files of processes on different cluster nodes.
pub fn this_host() -> &'static str {
    static HOST: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    HOST.get_or_init(|| {
        let mut buf = [0u8; 256];
        // SAFETY: gethostname writes at most buf.len() bytes into the buffer it is given.
        let ok = unsafe { libc::gethostname(buf.as_mut_ptr().cast(), buf.len()) } == 0;
        let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
        let name = String::from_utf8_lossy(&buf[..end]);
        let short: String = name
            .split('.')
            .next()
            .unwrap_or("")
            .chars()
            .filter(|c| c.is_ascii_alphanumeric() || *c == '-')
            .collect();
        if ok && !short.is_empty() {
            short
        } else {
            "host".into()
        }
    })
}

/// This process as named in temporary files: `<host>-<pid>`.
pub fn owner_tag() -> String {
    format!("{}-{}", this_host(), std::process::id())
}

/// Prefix of the temporary files stride writes ([`temp_name`]): no other program's files
/// start with it, and only files of that form are ever removed as stride's leftovers.
pub const TEMP_PREFIX: &str = ".stride-tmp.";

/// A temporary name for `name`, unique on this machine and among machines:
/// `.stride-tmp.<host>.<pid>.<n>.<name>` with `n` counting this process's temporary names.
pub fn temp_name(name: &str) -> String {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    format!(
        "{TEMP_PREFIX}{}.{}.{n}.{name}",
        this_host(),
        std::process::id()
    )
}

/// The host and process id in a temporary name made by [`temp_name`]; `None` for any other
/// name.
pub fn temp_owner(file_name: &str) -> Option<(&str, u32)> {
    let mut parts = file_name.strip_prefix(TEMP_PREFIX)?.splitn(4, '.');
    let host = parts.next().filter(|h| !h.is_empty())?;
    let pid = parts.next()?.parse().ok()?;
    parts.next()?.parse::<u64>().ok()?;
    parts.next().filter(|n| !n.is_empty())?;
    Some((host, pid))
}

/// Whether process `pid` is running (on this machine).
pub fn process_alive(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return false;
    };
    // SAFETY: kill with signal 0 only checks whether the process exists.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_are_unique_and_name_their_owner() {
        let (a, b) = (temp_name("grf.csv"), temp_name("grf.csv"));
        assert_ne!(a, b);
        assert_eq!(temp_owner(&a), Some((this_host(), std::process::id())));
        for user in [
            ".grf.csv.tmp-2024",
            ".stride-tmp.",
            ".stride-tmp.h.x.1.f",
            "grf.csv",
        ] {
            assert_eq!(temp_owner(user), None, "{user}");
        }
    }
}

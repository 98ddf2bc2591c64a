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

/// Whether process `pid` is running (on this machine).
pub fn process_alive(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return false;
    };
    // SAFETY: kill with signal 0 only checks whether the process exists.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

//! What machine and when: the report's header line.

/// The machine a benchmark ran on, and the date.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Machine {
    /// CPU model name (`model name` in `/proc/cpuinfo`), or `unknown CPU`.
    pub cpu: String,
    /// Hardware threads available to this process (`std::thread::available_parallelism`).
    pub cores: usize,
    /// Operating system: `PRETTY_NAME` of `/etc/os-release` and the kernel release, or
    /// Rust's name for the OS.
    pub os: String,
    /// Total memory in bytes (`MemTotal` in `/proc/meminfo`), if known.
    pub memory: Option<u64>,
    /// Date of the run, `YYYY-MM-DD` (UTC).
    pub date: String,
}

impl Machine {
    /// Describes the machine this process runs on, now.
    #[must_use]
    pub fn current() -> Self {
        let read = |path: &str| std::fs::read_to_string(path).unwrap_or_default();
        let field = |text: &str, key: &str| {
            text.lines()
                .find(|l| l.starts_with(key))
                .and_then(|l| l.split_once(['=', ':']))
                .map(|(_, v)| v.trim().trim_matches('"').to_string())
        };
        let cpuinfo = read("/proc/cpuinfo");
        let cpu = field(&cpuinfo, "model name").unwrap_or_else(|| "unknown CPU".into());
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        let kernel = read("/proc/sys/kernel/osrelease").trim().to_string();
        let os = match field(&read("/etc/os-release"), "PRETTY_NAME") {
            Some(name) if kernel.is_empty() => name,
            Some(name) => format!("{name}, kernel {kernel}"),
            None => std::env::consts::OS.to_string(),
        };
        let memory = field(&read("/proc/meminfo"), "MemTotal")
            .and_then(|v| v.split_whitespace().next()?.parse::<u64>().ok())
            .map(|kib| kib * 1024);
        let today = time::OffsetDateTime::now_utc().date();
        let date = format!("{:04}-{:02}-{:02}", today.year(), u8::from(today.month()), today.day());
        Machine { cpu, cores, os, memory, date }
    }
}

//! Counting only the tracing under `perf stat`: a program started by
//! `perf stat --delay=-1 --control fifo:CTL,ACK` (counters off until told) turns the
//! counters on around the work to count by writing `enable` to the control fifo and
//! waiting for perf's `ack`, then `disable` (perf-stat(1), "--control"). The fifos are
//! named by the environment variables [`CTL`] and [`ACK`] (`benches/peers/branch_misses.sh`
//! sets them); without them the work just runs.

use std::io::{BufRead, BufReader, Write};

/// Environment variable naming perf's control fifo.
pub const CTL: &str = "PERF_CTL_FIFO";
/// Environment variable naming perf's acknowledgement fifo.
pub const ACK: &str = "PERF_ACK_FIFO";

/// Sends `command` to perf and waits for its acknowledgement.
fn tell(ctl: &str, ack: &str, command: &str) -> std::io::Result<()> {
    // Opening a fifo blocks until the other end is open: perf holds both open.
    std::fs::OpenOptions::new().write(true).open(ctl)?.write_all(format!("{command}\n").as_bytes())?;
    let mut line = String::new();
    BufReader::new(std::fs::File::open(ack)?).read_line(&mut line)?;
    Ok(())
}

/// Runs `work` with perf's counters on when [`CTL`] and [`ACK`] name perf's fifos;
/// a failure to reach perf is returned as an error after the work has run uncounted.
pub fn counted<T>(work: impl FnOnce() -> T) -> (T, std::io::Result<()>) {
    let (Ok(ctl), Ok(ack)) = (std::env::var(CTL), std::env::var(ACK)) else {
        return (work(), Ok(()));
    };
    if let Err(e) = tell(&ctl, &ack, "enable") {
        return (work(), Err(e));
    }
    let out = work();
    (out, tell(&ctl, &ack, "disable"))
}

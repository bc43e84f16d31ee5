//! Ctrl-C stops a long job cleanly. For the commands that make or draw something, the
//! first SIGINT only sets a flag, which the command's progress bars report as the
//! library's `Progress::cancelled`: the job stops at its next unit of work and returns
//! `Cancelled`, nothing is written (an output being written loses its temporary file),
//! and the command exits with status 130. The handler resets itself, so a second Ctrl-C
//! ends the process at once, as one always did (work that never polls, a server).

use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The handler: one atomic store, which is async-signal-safe.
extern "C" fn on_interrupt(_: libc::c_int) {
    INTERRUPTED.store(true, Ordering::Relaxed);
}

/// Makes the first Ctrl-C set the flag instead of ending the process; leaves SIGINT
/// alone when it was ignored at start (a background job of a shell without job
/// control, which must not stop at the terminal's Ctrl-C).
pub fn stop_jobs_on_ctrl_c() {
    // SAFETY: a zeroed `sigaction` is a valid empty one; reading the current action
    // changes nothing; the handler only stores an atomic; `SA_RESETHAND` restores the
    // default disposition once it has run.
    unsafe {
        let mut current: libc::sigaction = std::mem::zeroed();
        if libc::sigaction(libc::SIGINT, std::ptr::null(), &raw mut current) != 0
            || current.sa_sigaction == libc::SIG_IGN
        {
            return;
        }
        let mut action: libc::sigaction = std::mem::zeroed();
        action.sa_sigaction = on_interrupt as extern "C" fn(libc::c_int) as libc::sighandler_t;
        action.sa_flags = libc::SA_RESETHAND | libc::SA_RESTART;
        libc::sigemptyset(&raw mut action.sa_mask);
        libc::sigaction(libc::SIGINT, &raw const action, std::ptr::null_mut());
    }
}

/// Whether Ctrl-C was pressed since [`stop_jobs_on_ctrl_c`].
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::Relaxed)
}

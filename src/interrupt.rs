//! What a SIGINT, SIGTERM or SIGHUP does: the temporary files that outputs
//! are being written to are removed ([`pointblend::output::remove_temporaries`])
//! and the process exits with 128 + the signal's number (130 for Ctrl-C, 143
//! for SIGTERM), as a shell reports a run a signal ended.
//!
//! Without it the signal ended the process at once: no destructor ran, and a
//! hidden `.tmpXXXXXX` of up to the output's size stayed in the output's
//! folder. The signals are taken by `signal-hook`'s iterator on a thread of
//! its own, so the removal runs as ordinary code, not in a signal handler.
//!
//! A write to a closed pipe (`pointblend info FILE | head`) ends the
//! process quietly, as it ends a C tool: Rust ignores SIGPIPE, and each
//! print to a stdout whose reader had gone panicked with a backtrace.
//! Sockets are not touched by it: the standard library sends with
//! MSG_NOSIGNAL.

/// Installs the handler; a failure to install it is logged, not fatal.
#[cfg(unix)]
pub fn install() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
        Ok(signals) => signals,
        Err(e) => {
            log::warn!("cannot catch SIGINT/SIGTERM ({e}); an interrupted run may leave temporary files");
            return;
        }
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let removed = pointblend::output::remove_temporaries();
            let name = signal_hook::low_level::signal_name(signal).unwrap_or("a signal");
            let files = if removed == 1 { "file" } else { "files" };
            eprintln!("error: interrupted by {name}; {removed} temporary {files} removed");
            std::process::exit(128 + signal);
        }
    });
}

#[cfg(not(unix))]
pub fn install() {}

/// Gives SIGPIPE its default action back: the process ends at a write to a closed pipe.
#[cfg(unix)]
pub fn end_quietly_on_a_closed_pipe() {
    // SAFETY: called at start-up, before any thread is spawned; SIG_DFL is a valid action.
    unsafe { libc::signal(libc::SIGPIPE, libc::SIG_DFL) };
}

#[cfg(not(unix))]
pub fn end_quietly_on_a_closed_pipe() {}

//! Ctrl-C (SIGINT) and SIGTERM as a cancel request, so long runs can stop cleanly and
//! write what they computed instead of losing it.
//!
//! The handlers (from `signal-hook`, which keeps them async-signal-safe) only store to
//! atomics; the work loops poll [`requested`] or the [`cancel_flag`] handed to
//! a renderer's cancel option (`tracer::render::RenderOptions::cancel`). A second signal ends the process at once
//! with status `128 + signal`, so a stuck run can still be force-quit. Elsewhere than
//! unix, [`install`] does nothing and the flag is never set.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// Exit status of a run stopped by Ctrl-C (the shell's `128 + SIGINT`); see
/// [`exit_code`] for the signal that actually arrived.
pub const EXIT_CODE: u8 = 130;

/// The one cancel flag, never dropped (it lives in a static).
static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
/// The number of the last signal received (0: none).
static SIGNAL: OnceLock<Arc<AtomicUsize>> = OnceLock::new();
static INSTALLED: OnceLock<()> = OnceLock::new();

fn flag() -> &'static Arc<AtomicBool> {
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

fn signal() -> &'static Arc<AtomicUsize> {
    SIGNAL.get_or_init(|| Arc::new(AtomicUsize::new(0)))
}

/// Installs the SIGINT/SIGTERM handlers (once; later calls only return the flag) and
/// returns the flag they set. A no-op apart from returning the flag where not unix.
pub fn install() -> &'static AtomicBool {
    let f = flag();
    INSTALLED.get_or_init(|| {
        #[cfg(unix)]
        for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
            // Registered first, so it sees the flag as the earlier signals left it: set
            // means this is the second signal. A failed registration only leaves the
            // default behaviour (the process ends), so it is not reported.
            let code = 128 + sig;
            let _ = signal_hook::flag::register_conditional_shutdown(sig, code, Arc::clone(f));
            let _ = signal_hook::flag::register_usize(sig, Arc::clone(signal()), sig as usize);
            let _ = signal_hook::flag::register(sig, Arc::clone(f));
        }
    });
    f
}

/// Whether a stop was requested (a signal arrived since [`install`]).
pub fn requested() -> bool {
    FLAG.get().is_some_and(|f| f.load(Ordering::SeqCst))
}

/// The exit status of a run stopped by a signal: `128 + signal` (130 for Ctrl-C, 143
/// for SIGTERM), [`EXIT_CODE`] when none has arrived.
pub fn exit_code() -> u8 {
    match SIGNAL.get().map(|s| s.load(Ordering::SeqCst)) {
        Some(s) if s > 0 && s < 128 => 128 + s as u8,
        _ => EXIT_CODE,
    }
}

/// The cancel flag for a renderer's cancel option (`tracer::render::RenderOptions::cancel`) and other loops; installs
/// the handlers if they were not.
pub fn cancel_flag() -> Arc<AtomicBool> {
    install();
    Arc::clone(flag())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One test only: raising twice would force-quit the test process by design.
    #[cfg(unix)]
    #[test]
    fn sigint_sets_the_shared_flag() {
        let f = install();
        let arc = cancel_flag();
        assert!(std::ptr::eq(f, &*arc), "one flag for both views");
        assert!(!requested());
        signal_hook::low_level::raise(signal_hook::consts::SIGINT).unwrap();
        assert!(requested());
        assert!(arc.load(Ordering::SeqCst));
        assert_eq!(exit_code(), 130);
    }
}

//! Ctrl-C (SIGINT) and SIGTERM as a cancel request, so long runs can stop cleanly and
//! write what they computed instead of losing it.
//!
//! No signal crate is allowed, so this is a std-only handler over libc's `signal` (libc is
//! linked by std on unix). The handler only stores to atomics (async-signal-safe); the
//! work loops poll [`requested`] or the [`cancel_flag`] handed to
//! [`crate::render::RenderOptions::cancel`]. A second signal ends the process at once
//! with `_exit(128 + signal)` (also async-signal-safe), so a stuck run can still be
//! force-quit. Elsewhere than unix, [`install`] does nothing and the flag is never set.

use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// Exit status of a run stopped by Ctrl-C (the shell's `128 + SIGINT`).
pub const EXIT_CODE: u8 = 130;

/// The one cancel flag. An `Arc` so it can be given to [`crate::render::RenderOptions`];
/// never dropped (it lives in a static).
static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
/// The flag as a raw pointer for the handler, which must not touch `OnceLock` machinery.
static FLAG_PTR: AtomicPtr<AtomicBool> = AtomicPtr::new(std::ptr::null_mut());
/// Signals received so far.
static COUNT: AtomicUsize = AtomicUsize::new(0);
static INSTALLED: OnceLock<()> = OnceLock::new();

fn flag() -> &'static Arc<AtomicBool> {
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

#[cfg(unix)]
mod sys {
    pub const SIGINT: i32 = 2;
    pub const SIGTERM: i32 = 15;
    extern "C" {
        pub fn signal(signum: i32, handler: extern "C" fn(i32)) -> usize;
        pub fn _exit(status: i32) -> !;
    }
}

/// Async-signal-safe: atomic stores and `_exit` only.
#[cfg(unix)]
extern "C" fn on_signal(sig: i32) {
    let p = FLAG_PTR.load(Ordering::SeqCst);
    if !p.is_null() {
        // SAFETY: `p` points into the `Arc` held by the static `FLAG`, which is never
        // dropped; it was published before the handler was installed.
        unsafe { (*p).store(true, Ordering::SeqCst) };
    }
    if COUNT.fetch_add(1, Ordering::SeqCst) >= 1 {
        // Second signal: the user insists. Nothing is flushed (not safe here).
        // SAFETY: `_exit` is async-signal-safe and never returns.
        unsafe { sys::_exit(128 + sig) };
    }
}

/// Installs the SIGINT/SIGTERM handler (once; later calls only return the flag) and
/// returns the flag it sets. A no-op apart from returning the flag where not unix.
pub fn install() -> &'static AtomicBool {
    let f = flag();
    INSTALLED.get_or_init(|| {
        FLAG_PTR.store(Arc::as_ptr(f).cast_mut(), Ordering::SeqCst);
        #[cfg(unix)]
        for sig in [sys::SIGINT, sys::SIGTERM] {
            // SAFETY: `on_signal` only does async-signal-safe work; glibc's `signal` keeps
            // the handler installed and restarts interrupted system calls. A failure
            // (`SIG_ERR`) only leaves the default behaviour, so it is not checked.
            unsafe { sys::signal(sig, on_signal) };
        }
    });
    f
}

/// Whether a stop was requested (a signal arrived since [`install`]).
pub fn requested() -> bool {
    FLAG.get().is_some_and(|f| f.load(Ordering::SeqCst))
}

/// The cancel flag for [`crate::render::RenderOptions::cancel`] and other loops; installs
/// the handler if it was not.
pub fn cancel_flag() -> Arc<AtomicBool> {
    install();
    Arc::clone(flag())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    extern "C" {
        fn raise(sig: i32) -> i32;
    }

    /// One test only: raising twice would force-quit the test process by design.
    #[cfg(unix)]
    #[test]
    fn sigint_sets_the_shared_flag() {
        let f = install();
        let arc = cancel_flag();
        assert!(std::ptr::eq(f, &*arc), "one flag for both views");
        assert!(!requested());
        // SAFETY: the handler is installed; `raise` runs it on this thread before
        // returning.
        assert_eq!(unsafe { raise(sys::SIGINT) }, 0);
        assert!(requested());
        assert!(arc.load(Ordering::SeqCst));
        assert_eq!(COUNT.load(Ordering::SeqCst), 1);
    }
}

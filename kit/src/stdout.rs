//! Lines on standard output for the binaries: [`out!`](crate::out) for results, which
//! ends the process quietly when the reader has gone (`tracer list | head -3`), and
//! [`say!`](crate::say) for progress lines, which only stop then while the work goes on.

/// `println!` for the binaries: ends the process quietly when stdout has been closed
/// (`tracer list | head -3`: the reader wanted no more) instead of panicking, and with
/// exit code 2 and a message on any other write error.
#[macro_export]
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($t)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            eprintln!("error: cannot write to stdout: {e}");
            std::process::exit(2);
        }
    }};
}

/// Set once [`say!`](crate::say) has met a write error: the process's progress lines stop.
#[doc(hidden)]
pub static SAY_SILENT: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `println!` for progress lines of long work (the previewer's levels): a closed stdout
/// (`tracer preview ... | head -1`) only stops the lines, the work goes on and writes
/// its files; another write error is reported once on stderr, then the lines stop too.
#[macro_export]
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let silent = &$crate::stdout::SAY_SILENT;
        if !silent.load(std::sync::atomic::Ordering::Relaxed) {
            if let Err(e) = writeln!(std::io::stdout(), $($t)*) {
                silent.store(true, std::sync::atomic::Ordering::Relaxed);
                if e.kind() != std::io::ErrorKind::BrokenPipe {
                    eprintln!("warning: cannot write to stdout: {e}; going on without progress lines");
                }
            }
        }
    }};
}

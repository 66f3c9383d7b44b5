//! Standard output and standard error of the commands, written without ever panicking
//! (`println!` panics when stdout is a closed pipe or a full disk).
//!
//! - **A closed pipe** (`matgraph nodes | head -1`): the command stops at its next write,
//!   says nothing, and exits with status [`BROKEN_PIPE_STATUS`] (141, 128 + SIGPIPE: what
//!   a shell reports for `cat` or `ls` cut off the same way), so `set -o pipefail` scripts
//!   see it as they see those, and a failing `check` is never turned into a success.
//! - **Any other write error** (`> /dev/full`): the command stops with the error
//!   `cannot write to standard output: …` (status 1).
//! - **Standard error** that cannot be written is ignored: there is nowhere left to say so.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit status after standard output was found to be a closed pipe: 128 + SIGPIPE (13).
pub const BROKEN_PIPE_STATUS: u8 = 141;

/// Set once a write found standard output to be a closed pipe.
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Set once any write to standard output failed.
static FAILED: AtomicBool = AtomicBool::new(false);

/// Whether standard output was found to be a closed pipe: the command stops, quietly.
pub fn stdout_closed() -> bool {
    CLOSED.load(Ordering::Relaxed)
}

/// Whether a write to standard output failed (a closed pipe or another error): the
/// command stops rather than go on to its next file.
pub fn stdout_failed() -> bool {
    FAILED.load(Ordering::Relaxed)
}

/// The message of a failed write to standard output: empty (nothing to print) for a
/// closed pipe, which is remembered ([`stdout_closed`]).
pub fn stdout_error(e: std::io::Error) -> String {
    FAILED.store(true, Ordering::Relaxed);
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        CLOSED.store(true, Ordering::Relaxed);
        String::new()
    } else {
        format!(
            "cannot write to standard output: {}",
            super::out_dir::io_reason(&e)
        )
    }
}

/// Writes `bytes` to standard output.
pub fn stdout_bytes(bytes: &[u8]) -> Result<(), String> {
    if stdout_closed() {
        return Err(String::new());
    }
    let mut out = std::io::stdout().lock();
    out.write_all(bytes).map_err(stdout_error)
}

/// Writes formatted text to standard output (the `outln!` and `out!` macros).
pub fn stdout_fmt(args: std::fmt::Arguments) -> Result<(), String> {
    if stdout_closed() {
        return Err(String::new());
    }
    // Control and bidirectional characters from user text (file, node, output names)
    // are spelt out, never sent to the terminal (matgraph::visible).
    let text = args.to_string();
    let mut out = std::io::stdout().lock();
    out.write_all(matgraph::visible::visible_lines(&text).as_bytes())
        .map_err(stdout_error)
}

/// Flushes standard output (at the end of a command: what is still buffered).
pub fn flush_stdout() -> Result<(), String> {
    if stdout_closed() {
        return Err(String::new());
    }
    std::io::stdout().flush().map_err(stdout_error)
}

/// Writes formatted text to standard error, ignoring failures.
pub fn stderr_fmt(args: std::fmt::Arguments) {
    let text = args.to_string();
    let _ = std::io::stderr()
        .lock()
        .write_all(matgraph::visible::visible_lines(&text).as_bytes());
}

/// `println!` that returns `Result<(), String>` instead of panicking (see the module doc).
macro_rules! outln {
    () => {
        $crate::cli::out::stdout_fmt(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::cli::out::stdout_fmt(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that returns `Result<(), String>` instead of panicking.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cli::out::stdout_fmt(format_args!($($arg)*))
    };
}

/// `eprintln!` that never panics (a failed write to standard error is ignored).
macro_rules! errln {
    ($($arg:tt)*) => {
        $crate::cli::out::stderr_fmt(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `eprint!` that never panics.
macro_rules! err {
    ($($arg:tt)*) => {
        $crate::cli::out::stderr_fmt(format_args!($($arg)*))
    };
}

//! The process environment the binary prepares before it starts any thread.

/// A private runtime folder for the GPU path, removed when dropped.
pub struct RuntimeDir(#[allow(dead_code)] Option<tempfile::TempDir>);

/// Keeps Mesa quiet on machines without a desktop session: when `XDG_RUNTIME_DIR` is unset
/// or not a folder, Mesa's window-system probing prints "error: XDG_RUNTIME_DIR is invalid
/// or not set" (twice) although a headless render needs no window system. Pointing it at a
/// private, empty temporary folder (mode 0700, removed when the returned guard is dropped)
/// silences that. `std::env::set_var` is `unsafe` in edition 2024 because another thread
/// could read the environment at the same time: this runs in `main`, after argument
/// parsing and before any thread (rayon, wgpu, the progress bar) is started.
pub fn quiet_mesa() -> RuntimeDir {
    let usable = std::env::var_os("XDG_RUNTIME_DIR")
        .map(std::path::PathBuf::from)
        .is_some_and(|p| p.is_absolute() && p.is_dir());
    if usable {
        return RuntimeDir(None);
    }
    let Ok(dir) = tempfile::Builder::new().prefix("matgraph-xdg-").tempdir() else {
        return RuntimeDir(None);
    };
    // SAFETY: single-threaded at this point (see above).
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", dir.path()) };
    RuntimeDir(Some(dir))
}

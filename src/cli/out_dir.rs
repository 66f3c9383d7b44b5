//! The folders commands write into (`render --out-dir`, `report --out`), made with a message
//! that says what is wrong with which path, and I/O errors in words (issue 37: a file given
//! as the folder said "File exists (os error 17)").

use std::path::Path;

/// An I/O error in words, without the "(os error N)" of its Display.
pub fn io_reason(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::NotFound => "no such file or folder".to_owned(),
        K::PermissionDenied => "permission denied".to_owned(),
        K::StorageFull => "the device is full (no space left)".to_owned(),
        K::ReadOnlyFilesystem => "the file system is read-only".to_owned(),
        K::AlreadyExists => "something is already there".to_owned(),
        K::NotADirectory => "a part of the path is not a folder".to_owned(),
        K::IsADirectory => "it is a folder".to_owned(),
        K::QuotaExceeded => "the disk quota is exceeded".to_owned(),
        _ => {
            let text = e.to_string();
            match text.find(" (os error ") {
                Some(k) => text[..k].to_owned(),
                None => text,
            }
        }
    }
}

/// What is at `path` when it is not a folder.
fn what_is(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_file() {
        "a file"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a folder"
    }
}

/// Makes folder `path` (and its parents) for the flag `flag`, or says why not: a file (or
/// device) already at the path or at one of its parents, or the I/O error in words.
pub fn make_out_dir(flag: &str, path: &Path) -> Result<(), String> {
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Ok(());
        }
        return Err(format!(
            "{flag} {}: {} is there, not a folder; name a folder (it is made if missing)",
            path.display(),
            what_is(&meta)
        ));
    }
    std::fs::create_dir_all(path).map_err(|e| {
        let blocker = path
            .ancestors()
            .skip(1)
            .filter(|a| !a.as_os_str().is_empty())
            .find_map(|a| {
                let meta = std::fs::metadata(a).ok()?;
                (!meta.is_dir()).then(|| (a.to_owned(), what_is(&meta)))
            });
        match blocker {
            Some((a, what)) => format!(
                "{flag} {}: cannot make the folder: {} is {what}, not a folder",
                path.display(),
                a.display()
            ),
            None => format!(
                "{flag} {}: cannot make the folder: {}",
                path.display(),
                io_reason(&e)
            ),
        }
    })
}

/// The message of a failed write of `path` (by [`matgraph::io::write_atomic`]): the path
/// once, then what is wrong in words. write_atomic's own refusals already name the file;
/// other errors are said of `path` (a missing folder or a file in its place named, never
/// the temporary file's name).
pub fn write_error(path: &Path, e: &std::io::Error) -> String {
    let text = e.to_string();
    if text.contains("refusing to replace") {
        return text;
    }
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let blocker = parent.ancestors().find_map(|a| {
        let meta = std::fs::metadata(a).ok()?;
        (!meta.is_dir()).then(|| (a.to_owned(), what_is(&meta)))
    });
    let why = match blocker {
        Some((a, what)) => format!("{} is {what}, not a folder", a.display()),
        None if std::fs::metadata(parent).is_err() => {
            format!("the folder {} does not exist", parent.display())
        }
        None => io_reason(e),
    };
    format!("{}: cannot write: {why}", path.display())
}

//! Reading and writing graph files. The only module of the library that touches the disk
//! for graphs (images: [`crate::image_io`]).
//!
//! - **Reading** ([`read_text`]) looks at the file's metadata first and refuses anything
//!   that is not a regular file (a folder, a FIFO, a device) before opening it, so reading
//!   a FIFO never blocks.
//! - **Writing** ([`write_atomic`]) replaces the target atomically and keeps what it
//!   replaces intact: through symlinks (the link's target is written, the link stays),
//!   never over a non-regular file (a device, a FIFO, a folder: refused) nor over one the
//!   user could not write (no write bit, or not writable by this user: refused), keeping
//!   the replaced file's mode and owner; a file with several hard links, or whose owner
//!   cannot be kept, is written in place instead. The temporary file lives in the
//!   target's folder as `.NAME.PID.XXXXXX.matgraph-tmp`; it is removed on every error
//!   path, and one left behind by a killed process is removed by the next write to the
//!   same target once it is [`STALE_TEMP_AGE`] old and its process is gone.
//! - **Identity** ([`file_identity`]): whether two paths name the same file, for commands
//!   that refuse to write over their own inputs.
//! - **Confinement** ([`open_reference`]): files a graph refers to (textures, a scene
//!   file, an environment image, group files) must lie inside the graph file's folder,
//!   after canonicalisation (symlinks followed), unless the caller allows any path. Each is
//!   opened once and what was opened is checked (its own path, from the kernel); the
//!   caller reads that handle, so swapping a symlink between check and read changes
//!   nothing.

use crate::error::{GraphError, GraphErrors};
use crate::graph::Graph;
use crate::registry::Registry;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Why a file could not be read, naming it.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// Nothing at the path (or a dangling symlink).
    #[error("cannot read {}: no such file", path.display())]
    Missing {
        /// The path.
        path: PathBuf,
    },
    /// The path is a folder.
    #[error("cannot read {}: is a directory", path.display())]
    Directory {
        /// The path.
        path: PathBuf,
    },
    /// The path is a FIFO, a device or a socket: refused before opening it.
    #[error("cannot read {}: not a regular file ({kind})", path.display())]
    NotRegular {
        /// The path.
        path: PathBuf,
        /// What it is instead.
        kind: &'static str,
    },
    /// Another I/O error.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}

/// What kind of non-regular file `meta` describes.
fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_dir() {
        "a directory"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else if t.is_symlink() {
        "a symlink"
    } else {
        "a regular file"
    }
}

/// Checks, from its metadata alone (nothing is opened), that `path` is a regular file
/// (symlinks followed).
pub fn check_regular(path: &Path) -> Result<(), ReadError> {
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => ReadError::Missing {
            path: path.to_owned(),
        },
        _ => ReadError::Io {
            path: path.to_owned(),
            source: e,
        },
    })?;
    if meta.is_dir() {
        return Err(ReadError::Directory {
            path: path.to_owned(),
        });
    }
    if !meta.is_file() {
        return Err(ReadError::NotRegular {
            path: path.to_owned(),
            kind: file_kind(&meta),
        });
    }
    Ok(())
}

/// Reads a regular UTF-8 text file; folders, FIFOs and devices are refused before opening.
pub fn read_text(path: &Path) -> Result<String, ReadError> {
    check_regular(path)?;
    std::fs::read_to_string(path).map_err(|e| ReadError::Io {
        path: path.to_owned(),
        source: e,
    })
}

/// Reads and validates a graph file; every error is attributed to `path`. The files its
/// groups name are read from inside its folder ([`FileGroups`]).
pub fn load_graph(path: &Path, registry: &Registry) -> Result<Graph, GraphErrors> {
    load_graph_with(path, registry, PathPolicy::InsideGraphFolder)
}

/// [`load_graph`] with the files its groups name confined by `policy`.
pub fn load_graph_with(
    path: &Path,
    registry: &Registry,
    policy: PathPolicy,
) -> Result<Graph, GraphErrors> {
    let wrap = |errors| GraphErrors {
        source: path.to_owned(),
        errors,
    };
    let text = read_text(path).map_err(|e| {
        wrap(vec![GraphError::Unreadable {
            message: e.to_string(),
        }])
    })?;
    Graph::from_json_in(&text, registry, group_files(path, policy)).map_err(wrap)
}

/// The [`crate::group::GroupFiles`] of the graph file at `path`, remembering what it read.
pub fn group_files(
    path: &Path,
    policy: PathPolicy,
) -> std::sync::Arc<dyn crate::group::GroupFiles> {
    std::sync::Arc::new(crate::group::RememberedFiles::new(std::sync::Arc::new(
        FileGroups::new(path, policy),
    )))
}

/// Reads the files a graph's groups name (`"group": "lib/layers.json#blend"`): paths are
/// relative to the file that writes them and, under [`PathPolicy::InsideGraphFolder`], must
/// lie inside the top graph file's folder after canonicalisation, as textures must.
#[derive(Debug)]
pub struct FileGroups {
    top: PathBuf,
    root: PathBuf,
    policy: PathPolicy,
}

impl FileGroups {
    /// The files of the graph file at `top`.
    pub fn new(top: &Path, policy: PathPolicy) -> FileGroups {
        let folder = match top.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
            _ => PathBuf::from("."),
        };
        FileGroups {
            top: top.to_owned(),
            root: std::fs::canonicalize(&folder).unwrap_or(folder),
            policy,
        }
    }
}

impl crate::group::GroupFiles for FileGroups {
    fn load(&self, from: &str, reference: &str) -> Result<crate::group::GroupFile, String> {
        let from_file = PathBuf::from(from);
        let base = match from_file.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
            _ => PathBuf::from("."),
        };
        let joined = base.join(reference);
        let root = (self.policy == PathPolicy::InsideGraphFolder).then_some(self.root.as_path());
        let opened = match open_checked(&joined, root) {
            Ok(f) => f,
            Err(Refusal::Outside(resolved)) => {
                return Err(format!(
                    "path '{reference}' resolves to {}, outside the graph's folder {} (pass --allow-outside-paths to read it)",
                    resolved.display(),
                    self.root.display()
                ));
            }
            Err(Refusal::Read(e)) => return Err(e.to_string()),
        };
        let resolved =
            opened_path(&joined, &opened).unwrap_or_else(|_| canonical_or_planned(&joined));
        let text = read_opened_text(&joined, &opened).map_err(|e| e.to_string())?;
        let doc = crate::document::GraphDocument::parse(&text).map_err(|errors| {
            let shown: Vec<String> = errors.iter().take(3).map(|e| e.to_string()).collect();
            format!("{}: {}", joined.display(), shown.join("; "))
        })?;
        let label = resolved
            .strip_prefix(&self.root)
            .map(Path::to_path_buf)
            .unwrap_or_else(|_| resolved.clone());
        let folder = match label.parent() {
            Some(d) if !d.as_os_str().is_empty() => format!("{}/", d.display()),
            _ => String::new(),
        };
        Ok(crate::group::GroupFile {
            key: resolved.display().to_string(),
            label: label.display().to_string(),
            folder,
            doc: std::sync::Arc::new(doc),
        })
    }

    fn top_key(&self) -> String {
        canonical_or_planned(&self.top).display().to_string()
    }

    fn top_label(&self) -> String {
        self.top
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    }
}

/// Age after which a temporary file of [`write_atomic`] whose writer is gone is removed by
/// the next write to (or [`sweep_stale_temps`] of) the same target. A writer writes its
/// temporary from bytes it holds, so a live write refreshes the file's modification time
/// far more often than this.
pub const STALE_TEMP_AGE: Duration = Duration::from_secs(60);

/// Suffix of the temporary files of [`write_atomic`].
const TEMP_SUFFIX: &str = ".matgraph-tmp";

/// The file a write to `path` replaces: `path` itself, or the final target of a chain of
/// symlinks (relative links taken from the link's folder; at most 40 links).
fn write_target(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_owned();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// The folder and file name a write to `target` (symlinks resolved) works in.
fn folder_and_name(target: &Path) -> (&Path, String) {
    let dir = target
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = target
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("file")
        .to_owned();
    (dir, name)
}

/// The id of the process that made temporary `file_name` of target `name`, `Some(None)`
/// for one made before temporaries carried it (`.NAME.XXXXXX.matgraph-tmp`), `None` for a
/// file that is not a temporary of `name` (`.NAME.PID.XXXXXX.matgraph-tmp`; the random
/// part has no dot, so another target's temporaries, `.NAME.bak.…`, never match).
fn temp_writer(file_name: &str, name: &str) -> Option<Option<u32>> {
    let rest = file_name
        .strip_prefix('.')?
        .strip_prefix(name)?
        .strip_prefix('.')?
        .strip_suffix(TEMP_SUFFIX)?;
    match rest.split_once('.') {
        None if !rest.is_empty() => Some(None),
        Some((pid, random))
            if !random.is_empty()
                && !random.contains('.')
                && !pid.is_empty()
                && pid.bytes().all(|b| b.is_ascii_digit()) =>
        {
            Some(pid.parse().ok())
        }
        _ => None,
    }
}

/// Whether process `pid` is alive, as far as `/proc` tells (where there is no `/proc`,
/// every writer counts as gone and the age alone decides).
fn process_alive(pid: u32) -> bool {
    Path::new("/proc/self").exists() && Path::new("/proc").join(pid.to_string()).exists()
}

/// Removes the temporaries of `name` in `dir` that are stale: at least [`STALE_TEMP_AGE`]
/// old and not made by a process that is still alive.
fn remove_stale_temps(dir: &Path, name: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(writer) = file_name.to_str().and_then(|n| temp_writer(n, name)) else {
            continue;
        };
        let old = entry
            .metadata()
            .ok()
            .filter(|m| m.is_file())
            .and_then(|m| m.modified().ok())
            .and_then(|t| t.elapsed().ok())
            .is_some_and(|age| age >= STALE_TEMP_AGE);
        let held = writer.is_some_and(|pid| pid != std::process::id() && process_alive(pid));
        if old && !held {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Removes the stale temporaries a killed write to `path` left (see [`write_atomic`])
/// without writing it: what `matgraph fmt` does for a file that is already canonical.
pub fn sweep_stale_temps(path: &Path) {
    if let Ok(target) = write_target(path) {
        let (dir, name) = folder_and_name(&target);
        remove_stale_temps(dir, &name);
    }
}

/// Refuses to replace `target` (described by `meta`) where the user could not write it in
/// place: a file without any write permission bit (refused even for root, as `cp -i` and
/// `rm` ask first), or one this process cannot open for writing (owned by another user).
fn check_writable(target: &Path, meta: &std::fs::Metadata) -> std::io::Result<()> {
    use std::os::unix::fs::MetadataExt;
    let mode = meta.mode() & 0o7777;
    if mode & 0o222 == 0 {
        return Err(std::io::Error::new(
            std::io::ErrorKind::PermissionDenied,
            format!(
                "{} is read-only (mode {mode:04o}); refusing to replace it (make it writable first: chmod u+w)",
                target.display()
            ),
        ));
    }
    // The kernel's own access check: open for writing, without truncating or creating.
    match std::fs::OpenOptions::new().write(true).open(target) {
        Ok(_) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => Err(std::io::Error::new(
            std::io::ErrorKind::PermissionDenied,
            format!(
                "{} is not writable by this user (owner uid {}, mode {mode:04o}); refusing to replace it",
                target.display(),
                meta.uid()
            ),
        )),
        Err(e) => Err(std::io::Error::new(
            e.kind(),
            format!("cannot write {}: {e}", target.display()),
        )),
    }
}

/// Writes `contents` to `path`, so a crash never leaves a half-written file where that can
/// be kept together with what the file is:
///
/// - **Replaced atomically** (the usual case): a temporary file in the target's folder,
///   synced, then renamed over it; the replaced file's mode and owner are kept.
/// - **Written in place** where a rename would change what the file is: a target with more
///   than one hard link (a rename would cut it from the other names), or one whose owner
///   and group this process cannot give the new file (another user's file it may write).
///   The contents are first written and synced to the temporary file, then copied over the
///   target (not truncated first: the file is cut to the new length after the copy) and
///   synced, as vim's `backupcopy=auto` does. A crash during the copy can leave the target
///   part new, part old; the full contents are then in the temporary file.
/// - **Refused**: a non-regular target (a device, a FIFO, a folder); a target without any
///   write permission bit (even for root); a target this process cannot open for writing.
///
/// A symlink is written through (its target is written, the link kept). Temporary files are
/// `.NAME.PID.XXXXXX.matgraph-tmp`; one is removed on every error path, and one left by a
/// killed process is removed by the next write to the same target (or
/// [`sweep_stale_temps`]) once it is [`STALE_TEMP_AGE`] old and its process is gone.
pub fn write_atomic(path: &Path, contents: impl AsRef<[u8]>) -> std::io::Result<()> {
    use std::io::Write;
    write_atomic_with(path, |f| f.write_all(contents.as_ref()))
}

/// [`write_atomic`] with the contents written by `write` into the temporary file.
fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> std::io::Result<()> {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let target = write_target(path)?;
    let existing = match std::fs::metadata(&target) {
        Ok(m) => Some(m),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(e),
    };
    if let Some(m) = &existing {
        if !m.is_file() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!(
                    "{} is {}, not a regular file; refusing to replace it",
                    target.display(),
                    file_kind(m)
                ),
            ));
        }
        check_writable(&target, m)?;
    }
    let (dir, name) = folder_and_name(&target);
    remove_stale_temps(dir, &name);
    // New files get 0666 less the umask, as `File::create` would.
    let prefix = format!(".{name}.{}.", std::process::id());
    let mut tmp = tempfile::Builder::new()
        .prefix(&prefix)
        .suffix(TEMP_SUFFIX)
        .permissions(std::fs::Permissions::from_mode(0o666))
        .tempfile_in(dir)?;
    // From here on, dropping `tmp` on an error removes it.
    write(tmp.as_file_mut())?;
    let mut in_place = false;
    if let Some(m) = &existing {
        let file = tmp.as_file();
        file.set_permissions(std::fs::Permissions::from_mode(m.mode() & 0o7777))?;
        // Keeping the owner needs privileges (or only the group changes, to one of ours).
        let _ = std::os::unix::fs::fchown(file, Some(m.uid()), Some(m.gid()));
        let made = file.metadata()?;
        in_place = m.nlink() > 1 || (made.uid(), made.gid()) != (m.uid(), m.gid());
    }
    tmp.as_file().sync_all()?;
    if in_place {
        copy_in_place(tmp.as_file_mut(), &target)?;
        return Ok(());
    }
    tmp.persist(&target).map_err(|e| e.error)?;
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// Copies all of `from` (rewound) over the start of `target`, cuts `target` to that length
/// and syncs it: the in-place write of [`write_atomic`].
fn copy_in_place(from: &mut std::fs::File, target: &Path) -> std::io::Result<()> {
    use std::io::Seek;
    from.seek(std::io::SeekFrom::Start(0))?;
    let mut out = std::fs::OpenOptions::new().write(true).open(target)?;
    let n = std::io::copy(from, &mut out)?;
    out.set_len(n)?;
    out.sync_all()
}

/// What a path names, to tell whether two paths are the same file: an existing file's
/// device and inode (so symlinks and hard links to one file are one), else where it would
/// be created (symlinks followed, the folders that exist canonicalised).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum FileIdentity {
    /// An existing file.
    Existing {
        /// The device it is on.
        device: u64,
        /// Its inode.
        inode: u64,
    },
    /// A file yet to be written, by its planned canonical path.
    Planned(PathBuf),
}

/// The [`FileIdentity`] of `path`.
pub fn file_identity(path: &Path) -> FileIdentity {
    use std::os::unix::fs::MetadataExt;
    match std::fs::metadata(path) {
        Ok(m) => FileIdentity::Existing {
            device: m.dev(),
            inode: m.ino(),
        },
        Err(_) => {
            let target = write_target(path).unwrap_or_else(|_| path.to_owned());
            FileIdentity::Planned(canonical_or_planned(&target))
        }
    }
}

/// Saves a graph as pretty, deterministic JSON, atomically.
pub fn save_graph(path: &Path, graph: &Graph) -> std::io::Result<()> {
    write_atomic(path, graph.to_json())
}

/// Where the files a graph refers to may lie.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PathPolicy {
    /// Inside the graph file's folder (after canonicalisation, symlinks followed).
    #[default]
    InsideGraphFolder,
    /// Anywhere (the user trusts the graph).
    Anywhere,
}

/// A file reference of a graph that may not be read.
#[derive(Debug, thiserror::Error)]
pub enum PathError {
    /// The reference resolves outside the graph's folder.
    #[error(
        "{}: {by}: path '{reference}' resolves to {}, outside the graph's folder {}",
        file.display(), resolved.display(), folder.display()
    )]
    Outside {
        /// The graph (or scene) file.
        file: PathBuf,
        /// What refers to it: `node 'ID'`, `scene`, `environment image`.
        by: String,
        /// The reference as written.
        reference: String,
        /// Where it leads.
        resolved: PathBuf,
        /// The folder it must stay in.
        folder: PathBuf,
    },
    /// The reference cannot be resolved (missing file, unreadable folder).
    #[error("{}: {by}: path '{reference}': {source}", file.display())]
    Unreadable {
        /// The graph (or scene) file.
        file: PathBuf,
        /// What refers to it.
        by: String,
        /// The reference as written.
        reference: String,
        /// Why.
        source: ReadError,
    },
}

impl PathError {
    /// The message, said of the folder the reference must stay in: the graph's, or, for a
    /// reference written in a file in another folder (a scene file's environment image),
    /// that file's (its Display says "the graph's folder" whatever file wrote it).
    pub fn message_for(&self, graph_file: &Path) -> String {
        let graph_folder = graph_file
            .parent()
            .map(|p| {
                if p.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    p
                }
            })
            .and_then(|p| std::fs::canonicalize(p).ok());
        match self {
            PathError::Outside {
                file,
                by,
                reference,
                resolved,
                folder,
            } if graph_folder.as_deref() != Some(folder.as_path()) => format!(
                "{}: {by}: path '{reference}' resolves to {}, outside the scene's folder {} (a scene file's paths must lie in its own folder)",
                file.display(),
                resolved.display(),
                folder.display()
            ),
            e => e.to_string(),
        }
    }
}

/// The canonical form of `path`, or, when it does not exist, the canonical form of its
/// longest existing ancestor with the rest of it applied lexically: where it would be, so
/// that a missing file outside the folder is reported as outside (not as missing, which
/// would tell whether it exists).
fn canonical_or_planned(path: &Path) -> PathBuf {
    use std::path::Component;
    let parts: Vec<Component> = path.components().collect();
    for keep in (0..=parts.len()).rev() {
        let head: PathBuf = parts[..keep].iter().collect();
        let head = if head.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            head
        };
        let Ok(mut out) = std::fs::canonicalize(&head) else {
            continue;
        };
        for c in &parts[keep..] {
            match c {
                Component::ParentDir => {
                    out.pop();
                }
                Component::CurDir => {}
                c => out.push(c),
            }
        }
        return out;
    }
    path.to_owned()
}

/// A file a graph (or scene) refers to, opened once and checked as opened
/// ([`open_reference`]): read it from [`Self::file`], never by reopening [`Self::path`].
#[derive(Debug)]
pub struct OpenedReference {
    /// The path it was opened by (the reference taken from the referring file's folder), for
    /// messages.
    pub path: PathBuf,
    /// The open file: a regular file, inside the folder where the policy asks for that.
    pub file: std::fs::File,
}

/// Why [`open_checked`] refused a path.
enum Refusal {
    /// What was opened (or would be) lies outside the root, at this canonical path.
    Outside(PathBuf),
    /// It could not be opened, or is not a regular file.
    Read(ReadError),
}

/// The [`ReadError`] of an `open` of `path` that failed with `e`.
fn open_error(path: &Path, e: std::io::Error) -> ReadError {
    match e.kind() {
        std::io::ErrorKind::NotFound => ReadError::Missing {
            path: path.to_owned(),
        },
        _ => ReadError::Io {
            path: path.to_owned(),
            source: e,
        },
    }
}

/// The canonical path of the file `file` (opened by `path`) is, as the kernel sees it now.
///
/// Linux: the link `/proc/self/fd/N` names the opened file itself, whatever happened to
/// `path` since. Elsewhere (or without `/proc`): `path` is canonicalised again after the
/// open and accepted only if the file it now names is the opened file (same device and
/// inode): a file reachable at that canonical path.
fn opened_path(path: &Path, file: &std::fs::File) -> std::io::Result<PathBuf> {
    use std::os::unix::fs::MetadataExt;
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        let link = format!("/proc/self/fd/{}", file.as_raw_fd());
        if let Ok(real) = std::fs::read_link(link)
            && real.is_absolute()
        {
            return Ok(real);
        }
    }
    let canonical = std::fs::canonicalize(path)?;
    let (now, opened) = (std::fs::metadata(&canonical)?, file.metadata()?);
    if (now.dev(), now.ino()) != (opened.dev(), opened.ino()) {
        return Err(std::io::Error::other(
            "the file changed while it was being opened",
        ));
    }
    Ok(canonical)
}

/// Opens `path` for reading once, then checks what was opened: a regular file (a folder,
/// FIFO or device is refused from its metadata before the open, and again from the opened
/// file's; the open does not block on a FIFO swapped in between) and, when `root` is given
/// (canonical), a file whose own canonical path ([`opened_path`]) lies inside `root`. A path
/// that leads outside `root` before it is opened is refused without opening it (a missing
/// file outside is reported as outside, not as missing).
fn open_checked(path: &Path, root: Option<&Path>) -> Result<std::fs::File, Refusal> {
    use std::os::unix::fs::OpenOptionsExt;
    if let Some(root) = root {
        let planned = canonical_or_planned(path);
        if !planned.starts_with(root) {
            return Err(Refusal::Outside(planned));
        }
    }
    // A device, FIFO or folder is refused from its metadata without opening it, as
    // before; the open itself neither blocks (a FIFO swapped in since) nor takes a
    // terminal as the controlling one, and the file opened is checked again below.
    check_regular(path).map_err(Refusal::Read)?;
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY)
        .open(path)
        .map_err(|e| Refusal::Read(open_error(path, e)))?;
    let meta = file.metadata().map_err(|e| {
        Refusal::Read(ReadError::Io {
            path: path.to_owned(),
            source: e,
        })
    })?;
    if let Some(root) = root {
        let real = opened_path(path, &file).map_err(|e| {
            Refusal::Read(ReadError::Io {
                path: path.to_owned(),
                source: e,
            })
        })?;
        if !real.starts_with(root) {
            return Err(Refusal::Outside(real));
        }
    }
    if meta.is_dir() {
        return Err(Refusal::Read(ReadError::Directory {
            path: path.to_owned(),
        }));
    }
    if !meta.is_file() {
        return Err(Refusal::Read(ReadError::NotRegular {
            path: path.to_owned(),
            kind: file_kind(&meta),
        }));
    }
    Ok(file)
}

/// Reads all of an opened file as UTF-8 text; errors name `path`.
pub fn read_opened_text(path: &Path, mut file: &std::fs::File) -> Result<String, ReadError> {
    use std::io::Read;
    let mut text = String::new();
    file.read_to_string(&mut text).map_err(|e| ReadError::Io {
        path: path.to_owned(),
        source: e,
    })?;
    Ok(text)
}

/// Opens the file `reference` (as written in `file`, by `by`) names, once: relative
/// references are taken from `file`'s folder. What was opened is then checked
/// ([`open_checked`]): a regular file and, under [`PathPolicy::InsideGraphFolder`], one whose
/// own canonical path (symlinks followed) lies inside the canonical folder. So a symlink
/// swapped between the check and the read cannot lead the read outside: the check is of
/// the open file, and the caller reads that file.
pub fn open_reference(
    file: &Path,
    by: &str,
    reference: &str,
    policy: PathPolicy,
) -> Result<OpenedReference, PathError> {
    let folder = match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
        _ => PathBuf::from("."),
    };
    let joined = folder.join(reference);
    let unreadable = |source| PathError::Unreadable {
        file: file.to_owned(),
        by: by.to_owned(),
        reference: reference.to_owned(),
        source,
    };
    let root = match policy {
        PathPolicy::InsideGraphFolder => Some(std::fs::canonicalize(&folder).map_err(|e| {
            unreadable(ReadError::Io {
                path: folder.clone(),
                source: e,
            })
        })?),
        PathPolicy::Anywhere => None,
    };
    match open_checked(&joined, root.as_deref()) {
        Ok(opened) => Ok(OpenedReference {
            path: joined,
            file: opened,
        }),
        Err(Refusal::Outside(resolved)) => Err(PathError::Outside {
            file: file.to_owned(),
            by: by.to_owned(),
            reference: reference.to_owned(),
            resolved,
            folder: root.unwrap_or(folder),
        }),
        Err(Refusal::Read(e)) => Err(unreadable(e)),
    }
}

/// The path of the file `reference` (as written in `file`, by `by`) names, checked as
/// [`open_reference`] checks it (the file is opened and closed). For checks only (the
/// editor's): a caller that reads the file must read [`open_reference`]'s handle, since the
/// path may name another file by the time it is reopened.
pub fn resolve_reference(
    file: &Path,
    by: &str,
    reference: &str,
    policy: PathPolicy,
) -> Result<PathBuf, PathError> {
    open_reference(file, by, reference, policy).map(|o| o.path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names in `dir`, sorted.
    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_failed_write_leaves_the_target_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("g.json");
        std::fs::write(&target, "old").unwrap();
        let e = write_atomic_with(&target, |f| {
            use std::io::Write;
            f.write_all(b"half")?;
            Err(std::io::Error::other("disk full"))
        })
        .unwrap_err();
        assert_eq!(e.to_string(), "disk full");
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "old");
        assert_eq!(names(dir.path()), ["g.json"]);
        // A write that succeeds replaces it and leaves nothing else.
        write_atomic(&target, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
        assert_eq!(names(dir.path()), ["g.json"]);
    }

    #[test]
    fn temporaries_are_told_by_target_and_writer() {
        let t = |f: &str| temp_writer(f, "g.json");
        assert_eq!(t(".g.json.4242.Ab3dEf.matgraph-tmp"), Some(Some(4242)));
        assert_eq!(t(".g.json.Ab3dEf.matgraph-tmp"), Some(None));
        // Another target's (g.json.bak), new and old style; other files.
        assert_eq!(t(".g.json.bak.4242.Ab3dEf.matgraph-tmp"), None);
        assert_eq!(t(".g.json.bak.x.Ab3dEf.matgraph-tmp"), None);
        assert_eq!(t(".g.json..matgraph-tmp"), None);
        assert_eq!(t(".g.json.4242.Ab3dEf"), None);
        assert_eq!(t("g.json.4242.Ab3dEf.matgraph-tmp"), None);
        assert_eq!(t(".h.json.4242.Ab3dEf.matgraph-tmp"), None);
    }

    #[test]
    fn identity_sees_through_links_and_plans_new_files() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a");
        std::fs::write(&a, "x").unwrap();
        std::fs::hard_link(&a, dir.path().join("h")).unwrap();
        std::os::unix::fs::symlink("a", dir.path().join("s")).unwrap();
        std::os::unix::fs::symlink("new", dir.path().join("dangling")).unwrap();
        let id = |n: &str| file_identity(&dir.path().join(n));
        assert_eq!(id("a"), id("h"));
        assert_eq!(id("a"), id("s"));
        assert_ne!(id("a"), id("new"));
        assert_eq!(id("new"), id("sub/../new"));
        assert_eq!(id("new"), id("dangling"));
        assert!(matches!(id("new"), FileIdentity::Planned(_)));
    }

    #[test]
    fn missing_references_resolve_where_they_would_be() {
        let dir = tempfile::tempdir().unwrap();
        let root = std::fs::canonicalize(dir.path()).unwrap();
        std::fs::create_dir(root.join("g")).unwrap();
        assert_eq!(
            canonical_or_planned(&root.join("g/../x/./y.png")),
            root.join("x/y.png")
        );
        assert_eq!(
            canonical_or_planned(&root.join("g/a/b")),
            root.join("g/a/b")
        );
        let graph = root.join("g/graph.json");
        let e = resolve_reference(
            &graph,
            "node 't'",
            "../x.png",
            PathPolicy::InsideGraphFolder,
        )
        .unwrap_err();
        assert!(matches!(e, PathError::Outside { .. }), "{e}");
        let e = resolve_reference(&graph, "node 't'", "in.png", PathPolicy::InsideGraphFolder)
            .unwrap_err();
        assert!(e.to_string().ends_with("in.png: no such file"), "{e}");
    }
}

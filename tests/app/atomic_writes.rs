//! What `-o` (through `matgraph::io::write_atomic`) does to the file it replaces: a file
//! without a write bit, or one the user cannot write, is refused and kept; a file with
//! several hard links, or one whose owner the writer cannot keep, is written in place;
//! stale temporaries of a killed write are swept by the next write and by `fmt`.
//!
//! The tests run as root here: the no-write-bit refusal does not rely on root being refused,
//! and the other-user cases run the binary as `nobody` (uid 65534) where the test is root.

use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Output};

/// Runs the binary in `dir`, as user `uid` when given.
fn run_in(dir: &Path, args: &[&str], uid: Option<u32>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_matgraph"));
    c.args(args).current_dir(dir);
    if let Some(uid) = uid {
        c.uid(uid).gid(uid);
    }
    c.output().expect("the matgraph binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Names in `dir`, sorted.
fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Whether this test process runs as root (`/proc/self` belongs to the process's user).
fn is_root() -> bool {
    std::fs::metadata("/proc/self").is_ok_and(|m| m.uid() == 0)
}

/// The schema `matgraph schema` writes.
fn schema() -> String {
    matgraph::document::json_schema()
}

#[test]
fn a_file_without_a_write_bit_is_refused_and_kept() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("locked.json");
    std::fs::write(&target, "old").unwrap();
    std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o444)).unwrap();
    let out = run_in(dir.path(), &["schema", "-o", "locked.json"], None);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        // The path once (issue 37: it was printed twice, "locked.json: locked.json is …").
        "locked.json is read-only (mode 0444); refusing to replace it \
         (make it writable first: chmod u+w)\n"
    );
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "old");
    assert_eq!(std::fs::metadata(&target).unwrap().mode() & 0o7777, 0o444);
    assert_eq!(names_in(dir.path()), ["locked.json"], "no temporary left");
    // Made writable, it is replaced and keeps its mode.
    std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o640)).unwrap();
    let out = run_in(dir.path(), &["schema", "-o", "locked.json"], None);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&target).unwrap(), schema());
    assert_eq!(std::fs::metadata(&target).unwrap().mode() & 0o7777, 0o640);
}

#[test]
fn another_users_file_is_refused_or_written_in_place() {
    if !is_root() {
        eprintln!("SKIPPED another_users_file_is_refused_or_written_in_place: needs root");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A folder anyone may write, as a shared folder is: a rename there needs no right on
    // the file itself.
    std::fs::set_permissions(d, std::fs::Permissions::from_mode(0o777)).unwrap();
    let theirs = d.join("theirs.json");
    std::fs::write(&theirs, "old").unwrap();
    std::fs::set_permissions(&theirs, std::fs::Permissions::from_mode(0o644)).unwrap();
    let nobody = Some(65534);
    let out = run_in(d, &["schema", "-o", "theirs.json"], nobody);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains(
            "theirs.json is not writable by this user (owner uid 0, mode 0644); refusing to replace it"
        ),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read_to_string(&theirs).unwrap(), "old");
    assert_eq!(std::fs::metadata(&theirs).unwrap().uid(), 0);
    // One they may write (0666): written, in place, so it stays root's with its mode.
    let shared = d.join("shared.json");
    std::fs::write(&shared, "old").unwrap();
    std::fs::set_permissions(&shared, std::fs::Permissions::from_mode(0o666)).unwrap();
    let inode = std::fs::metadata(&shared).unwrap().ino();
    let out = run_in(d, &["schema", "-o", "shared.json"], nobody);
    assert!(out.status.success(), "{}", stderr(&out));
    let meta = std::fs::metadata(&shared).unwrap();
    assert_eq!(std::fs::read_to_string(&shared).unwrap(), schema());
    assert_eq!((meta.uid(), meta.gid(), meta.ino()), (0, 0, inode));
    assert_eq!(meta.mode() & 0o7777, 0o666);
    assert_eq!(
        names_in(d),
        ["shared.json", "theirs.json"],
        "no temporary left"
    );
}

#[test]
fn hard_links_are_written_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = d.join("a.json");
    std::fs::write(&a, "old").unwrap();
    std::fs::hard_link(&a, d.join("b.json")).unwrap();
    let inode = std::fs::metadata(&a).unwrap().ino();
    let out = run_in(d, &["schema", "-o", "a.json"], None);
    assert!(out.status.success(), "{}", stderr(&out));
    for name in ["a.json", "b.json"] {
        let p = d.join(name);
        assert_eq!(std::fs::read_to_string(&p).unwrap(), schema(), "{name}");
        let meta = std::fs::metadata(&p).unwrap();
        assert_eq!((meta.ino(), meta.nlink()), (inode, 2), "{name}");
    }
    // A shorter text cuts the file to its length.
    std::fs::write(&a, "x".repeat(schema().len() * 2)).unwrap();
    let out = run_in(d, &["schema", "-o", "b.json"], None);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&a).unwrap(), schema());
    assert_eq!(names_in(d), ["a.json", "b.json"], "no temporary left");
}

/// Sets `path`'s modification time `secs` seconds into the past.
fn age(path: &Path, secs: u64) {
    let t = std::time::SystemTime::now() - std::time::Duration::from_secs(secs);
    std::fs::File::options()
        .write(true)
        .open(path)
        .unwrap()
        .set_modified(t)
        .unwrap();
}

/// The id of a process that was started and killed (SIGKILL), as a writer killed
/// mid-write is.
fn killed_pid() -> u32 {
    let mut child = Command::new("sleep").arg("60").spawn().unwrap();
    let pid = child.id();
    child.kill().unwrap();
    child.wait().unwrap();
    pid
}

#[test]
fn stale_temporaries_are_swept_by_the_next_write_and_by_fmt() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let glass = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/fresnel_glass.json");
    std::fs::copy(&glass, d.join("g.json")).unwrap();
    let dead = killed_pid();
    let live = std::process::id();
    // A temporary of g.json's killed writer two minutes old: stale.
    let stale = format!(".g.json.{dead}.AbCdEf.matgraph-tmp");
    // The same, but written a moment ago: perhaps a write in progress.
    let fresh = format!(".g.json.{dead}.Fresh1.matgraph-tmp");
    // Old, but its writer is alive (this test): a write in progress, kept.
    let held = format!(".g.json.{live}.Held12.matgraph-tmp");
    // Another target's (g.json.bak), old and dead: not g.json's to remove.
    let other = format!(".g.json.bak.{dead}.AbCdEf.matgraph-tmp");
    for (name, secs) in [(&stale, 120), (&fresh, 0), (&held, 7200), (&other, 7200)] {
        std::fs::write(d.join(name), "half").unwrap();
        age(&d.join(name), secs);
    }
    // fmt of a canonical file writes nothing, and still sweeps.
    let out = run_in(d, &["fmt", "g.json"], None);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "g.json: already canonical\n",
        "{}",
        stderr(&out)
    );
    let mut expected = vec![
        fresh.clone(),
        held.clone(),
        other.clone(),
        "g.json".to_owned(),
    ];
    expected.sort();
    assert_eq!(names_in(d), expected);
    // `fmt --check` only reads.
    std::fs::write(d.join(&stale), "half").unwrap();
    age(&d.join(&stale), 120);
    let out = run_in(d, &["fmt", "--check", "g.json"], None);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(d.join(&stale).exists());
    // The next write of an output sweeps that output's stale temporaries.
    let out_stale = format!(".out.wgsl.{dead}.AbCdEf.matgraph-tmp");
    std::fs::write(d.join(&out_stale), "half").unwrap();
    age(&d.join(&out_stale), 61);
    let out = run_in(d, &["wgsl", "g.json", "-o", "out.wgsl"], None);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!d.join(&out_stale).exists());
    assert!(
        d.join(&stale).exists(),
        "g.json's are g.json's writes' to sweep"
    );
}

//! The one way this crate (and the command line) writes a file: atomically, and never over
//! an input.
//!
//! [`write_atomic`] (and [`AtomicFile`], for output that arrives over time) writes to a temporary file in the target's own folder, flushes it to
//! disk, then renames it over the target. A reader (or a crash, or a full disk) therefore
//! sees either the old file or the complete new one, never a file cut short; on any error
//! the temporary file is removed and the target is left as it was.
//!
//! [`check_output`] refuses an output path that is one of the command's inputs, comparing
//! canonical paths, so `--out ./r.csv` is caught for `--record r.csv` as well.
//!
//! Every temporary file alive in the process is listed in one registry, so that a program
//! stopped by a signal removes them all ([`remove_temporary_files`], called by the command
//! line's SIGINT/SIGTERM handler) instead of leaving hidden `.NAME.PID-N.tmp` files behind.
//! A process killed outright (SIGKILL, power loss) cannot clean up: the next writer of the
//! same target removes the temporary files of that target whose process no longer runs.

use crate::DataError;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// The temporary files this process has created and not yet renamed or removed. Creating,
/// renaming and removing a temporary file all happen under this lock, so
/// [`remove_temporary_files`] sees every file that exists.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The registry, even after a panic in another thread while it was held (its list of paths
/// is still valid: every change to it is a single push or removal).
fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Removes every temporary file this process is writing and returns how many there were.
/// For a signal handler about to end the process: the lock stays held until the process
/// exits (the returned guard), so no other thread creates or renames a file meanwhile.
/// Targets are untouched: each keeps its old contents.
pub fn remove_temporary_files() -> (usize, MutexGuard<'static, Vec<PathBuf>>) {
    let mut guard = live();
    let n = guard.len();
    for tmp in guard.drain(..) {
        let _ = std::fs::remove_file(&tmp);
    }
    (n, guard)
}

/// The file a symbolic link names (followed to the end), or `path` itself when it is not a
/// link. A link to nothing is refused: writing through it would create a file elsewhere.
fn resolve_link(path: &Path) -> Result<PathBuf, DataError> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => {
            path.canonicalize().map_err(|_| DataError::NotARegularFile {
                path: path.to_path_buf(),
            })
        }
        _ => Ok(path.to_path_buf()),
    }
}

/// Refuses a target that is a folder, or an existing node that is not a regular file (a
/// device, pipe or socket, which the rename would replace). A symbolic link is judged by
/// what it points to.
fn check_target(path: &Path) -> Result<(), DataError> {
    // a folder on the way that is a file (`--out T.csv/out.json` with T.csv a file): said now,
    // not after the work, when the temporary file cannot be made
    for ancestor in path.ancestors().skip(1) {
        if ancestor.as_os_str().is_empty() {
            break;
        }
        if let Ok(m) = std::fs::metadata(ancestor) {
            if !m.is_dir() {
                return Err(DataError::NotADirectory {
                    path: ancestor.to_path_buf(),
                });
            }
            break;
        }
    }
    if let Some(name) = path.file_name() {
        let len = name.to_string_lossy().len();
        if len > MAX_NAME_BYTES {
            return Err(DataError::Write {
                path: path.to_path_buf(),
                message: format!(
                    "the file name is {len} bytes long; file systems allow {MAX_NAME_BYTES}: \
                     choose a shorter name"
                ),
            });
        }
    }
    if path.is_dir() {
        return Err(DataError::IsADirectory {
            path: path.to_path_buf(),
        });
    }
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(DataError::NotARegularFile {
            path: path.to_path_buf(),
        }),
        _ => Ok(()),
    }
}

/// The longest file name most file systems allow (ext4, XFS, APFS, NTFS: 255 bytes).
const MAX_NAME_BYTES: usize = 255;

/// The part of a target's file name its temporary file repeats: the whole name, or its first
/// 200 bytes for a longer one, so that `.NAME.PID-N.tmp` stays within [`MAX_NAME_BYTES`]
/// whenever the target's own name does.
fn temp_stem(name: &str) -> &str {
    const KEEP: usize = 200;
    if name.len() <= KEEP {
        return name;
    }
    let mut end = KEEP;
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    &name[..end]
}

/// Whether the process `pid` still runs. Only Linux says so cheaply (`/proc/PID`); elsewhere
/// every process is assumed alive and nothing is swept.
fn process_alive(pid: u32) -> bool {
    let proc_root = Path::new("/proc/self");
    if !proc_root.exists() {
        return true;
    }
    Path::new("/proc").join(pid.to_string()).exists()
}

/// Removes the temporary files of `name` in `parent` left by processes that no longer run
/// (killed before they could clean up). Best effort: a file that cannot be read or removed
/// is left alone. Files of a running process (another hxai writing the same target) are kept.
fn sweep_stale(parent: &Path, name: &str) {
    let prefix = format!(".{}.", temp_stem(name));
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(file) = file.to_str() else { continue };
        let Some(rest) = file
            .strip_prefix(&prefix)
            .and_then(|r| r.strip_suffix(".tmp"))
        else {
            continue;
        };
        let Some((pid, n)) = rest.split_once('-') else {
            continue;
        };
        let (Ok(pid), true) = (
            pid.parse::<u32>(),
            !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()),
        ) else {
            continue;
        };
        if pid != std::process::id() && !process_alive(pid) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// A file being written atomically: bytes go to a temporary file in the target's folder,
/// and [`AtomicFile::commit`] syncs it and renames it over the target. Dropped without a
/// commit (an error, a panic), the temporary file is removed and the target is untouched.
/// [`write_atomic`] is the one-call form; `hxai stream` writes through this type directly
/// because its rows arrive over time.
#[derive(Debug)]
pub struct AtomicFile {
    path: PathBuf,
    parent: PathBuf,
    tmp: PathBuf,
    file: Option<File>,
}

impl AtomicFile {
    /// Starts writing `path`: creates missing parent folders and the temporary file.
    ///
    /// # Errors
    /// [`DataError::IsADirectory`] when `path` is a folder, [`DataError::Io`].
    pub fn create(path: &Path) -> Result<Self, DataError> {
        // A symbolic link is written through: the file it names is replaced and the link
        // kept (renaming over the link would replace it, as root even `/dev/stdout`).
        let resolved = resolve_link(path)?;
        let path = resolved.as_path();
        check_target(path)?;
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent).map_err(|e| DataError::io(&parent, e))?;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .ok_or_else(|| DataError::IsADirectory {
                path: path.to_path_buf(),
            })?;
        sweep_stale(&parent, &name);
        let tmp = parent.join(format!(
            ".{}.{}-{}.tmp",
            temp_stem(&name),
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let file = {
            let mut live = live();
            // The error names the target the user gave, not the hidden temporary name.
            let file = File::create_new(&tmp).map_err(|e| DataError::io(path, e))?;
            live.push(tmp.clone());
            file
        };
        Ok(Self {
            path: path.to_path_buf(),
            parent,
            tmp,
            file: Some(file),
        })
    }

    /// The target path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The open temporary file.
    pub fn file(&mut self) -> Result<&mut File, DataError> {
        let path = self.path.clone();
        self.file.as_mut().ok_or_else(|| {
            DataError::io(
                &path,
                std::io::Error::other("the file was already committed"),
            )
        })
    }

    /// Flushes and syncs the temporary file, then renames it over the target.
    ///
    /// # Errors
    /// [`DataError::Io`]; the temporary file is then removed and the target left as it was.
    pub fn commit(mut self) -> Result<(), DataError> {
        let result = (|| {
            let mut file = self.file.take().ok_or_else(|| {
                DataError::io(
                    &self.path,
                    std::io::Error::other("the file was already committed"),
                )
            })?;
            file.flush().map_err(|e| DataError::io(&self.path, e))?;
            file.sync_all().map_err(|e| DataError::io(&self.path, e))?;
            drop(file);
            let mut live = live();
            std::fs::rename(&self.tmp, &self.path).map_err(|e| DataError::io(&self.path, e))?;
            live.retain(|p| p != &self.tmp);
            Ok(())
        })();
        if result.is_ok() {
            // Make the rename itself durable; not all platforms can sync a folder.
            if let Ok(dir) = File::open(&self.parent) {
                let _ = dir.sync_all();
            }
            // Nothing left to remove.
            self.tmp = PathBuf::new();
        }
        result
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self.file.as_mut() {
            Some(f) => f.write(buf),
            None => Err(std::io::Error::other("the file was already committed")),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self.file.as_mut() {
            Some(f) => f.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.tmp.as_os_str().is_empty() {
            self.file.take();
            let mut live = live();
            let _ = std::fs::remove_file(&self.tmp);
            live.retain(|p| p != &self.tmp);
        }
    }
}

/// Writes `path` atomically: `write` fills a temporary file in the same folder, which is
/// synced and renamed over `path`. Missing parent folders are created. On error the
/// temporary file is removed and an existing `path` is unchanged.
///
/// # Errors
/// [`DataError::IsADirectory`] when `path` is a folder, [`DataError::Io`] for the file
/// system, or whatever `write` returns.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut File) -> Result<(), DataError>,
) -> Result<(), DataError> {
    stage(path, write)?.commit()
}

/// [`write_atomic`] without the rename: the file is written in full beside `path` and
/// returned uncommitted. A command with several outputs stages them all and commits them
/// only when every one was written (a full disk then fails before any output is replaced);
/// dropping an uncommitted file removes it.
///
/// # Errors
/// As [`write_atomic`].
pub fn stage(
    path: &Path,
    write: impl FnOnce(&mut File) -> Result<(), DataError>,
) -> Result<AtomicFile, DataError> {
    let mut file = AtomicFile::create(path)?;
    write(file.file()?)?;
    Ok(file)
}

/// Writes bytes to `path` atomically (see [`write_atomic`]).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), DataError> {
    write_atomic(path, |f| {
        f.write_all(bytes).map_err(|e| DataError::io(path, e))
    })
}

/// The canonical form of a path that may not exist yet: its folder canonicalised, joined
/// with its file name. `None` when even the folder cannot be resolved (then it exists
/// nowhere and cannot be an input).
fn canonical(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let name = path.file_name()?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    parent.canonicalize().ok().map(|p| p.join(name))
}

/// Refuses an output path that names one of the inputs (after resolving `.`, `..` and
/// symbolic links), or that is a folder, a device, a pipe or a socket. Each input is `(path, role)`, the role saying in
/// the message what would be destroyed (`"the record"`, `"the manifest of --data"`).
///
/// # Errors
/// [`DataError::OutputIsInput`] or [`DataError::IsADirectory`].
pub fn check_output(output: &Path, inputs: &[(PathBuf, String)]) -> Result<(), DataError> {
    check_target(&resolve_link(output)?)?;
    let Some(out) = canonical(output) else {
        return Ok(());
    };
    for (input, role) in inputs {
        if canonical(input).is_some_and(|i| i == out) {
            return Err(DataError::OutputIsInput {
                output: output.to_path_buf(),
                role: role.clone(),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A fresh scratch folder for `tag` holding one file `name` with `text`: the folder and
    /// the file's path.
    fn dir_with_file(tag: &str, name: &str, text: &str) -> (PathBuf, PathBuf) {
        let d = std::env::temp_dir().join(format!("hxai-atomic-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        (d, p)
    }

    #[test]
    fn failed_write_leaves_old_file_and_no_temp() {
        let (d, p) = dir_with_file("fail", "m.json", "old");
        let r = write_atomic(&p, |f| {
            f.write_all(b"half").unwrap();
            Err(DataError::IsADirectory { path: p.clone() })
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1, "temp file left");
        write_bytes(&p, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn temporary_files_of_dead_processes_are_swept_and_live_ones_kept() {
        let (d, p) = dir_with_file("sweep", "m.json", "old");
        // No process has this id (Linux caps pids at 2^22).
        let dead = d.join(".m.json.999999999-0.tmp");
        let mine = d.join(format!(".m.json.{}-9999.tmp", std::process::id()));
        let other_target = d.join(".n.json.999999999-0.tmp");
        let not_ours = d.join(".m.json.999999999-x.tmp");
        for f in [&dead, &mine, &other_target, &not_ours] {
            std::fs::write(f, "half").unwrap();
        }
        write_bytes(&p, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
        assert_eq!(dead.exists(), !Path::new("/proc/self").exists());
        assert!(mine.exists() && other_target.exists() && not_ours.exists());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_registry_lists_open_temporary_files_until_commit_or_drop() {
        let (d, p) = dir_with_file("registry", "a.csv", "old");
        let registered = |f: &AtomicFile| live().contains(&f.tmp);
        let staged = stage(&p, |f| f.write_all(b"x").map_err(|e| DataError::io(&p, e))).unwrap();
        assert!(registered(&staged));
        let tmp = staged.tmp.clone();
        drop(staged);
        assert!(!tmp.exists() && !live().contains(&tmp));
        let staged = stage(&p, |f| f.write_all(b"y").map_err(|e| DataError::io(&p, e))).unwrap();
        let tmp = staged.tmp.clone();
        staged.commit().unwrap();
        assert!(!live().contains(&tmp));
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "y");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_link_is_written_through_and_kept() {
        let (d, target) = dir_with_file("link", "t.csv", "old");
        let link = d.join("l.csv");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        write_bytes(&link, b"new").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
        let dangling = d.join("d.csv");
        std::os::unix::fs::symlink(d.join("nowhere.csv"), &dangling).unwrap();
        assert!(write_bytes(&dangling, b"x").is_err());
        assert!(!d.join("nowhere.csv").exists());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn devices_and_pipes_are_refused_as_outputs_and_left_alone() {
        // /dev/null is a character device on every Unix; nothing is written to it.
        let null = Path::new("/dev/null");
        if null.exists() {
            assert!(matches!(
                check_output(null, &[]),
                Err(DataError::NotARegularFile { .. })
            ));
            assert!(matches!(
                write_bytes(null, b"x"),
                Err(DataError::NotARegularFile { .. })
            ));
            assert!(std::fs::metadata(null).is_ok_and(|m| !m.is_file()));
        }
    }

    #[test]
    fn output_equal_to_an_input_is_refused_in_any_spelling() {
        let (d, input) = dir_with_file("guard", "r.csv", "x");
        let inputs = vec![(input.clone(), "the record".to_string())];
        let other = d.join("sub").join("..").join("r.csv");
        std::fs::create_dir_all(d.join("sub")).unwrap();
        for out in [input.clone(), other] {
            let e = check_output(&out, &inputs).unwrap_err();
            assert!(e.to_string().contains("the record"), "{e}");
        }
        assert!(check_output(&d.join("new.csv"), &inputs).is_ok());
        assert!(check_output(&d.join("nowhere").join("x.csv"), &inputs).is_ok());
        assert!(matches!(
            check_output(&d, &inputs),
            Err(DataError::IsADirectory { .. })
        ));
        std::fs::remove_dir_all(&d).unwrap();
    }
}

#[cfg(test)]
mod path_tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// Issue 52 item 6: an output below a file, and a name too long for the file system, are
    /// refused by `check_output` (before any work); a legal name of 250 bytes is written,
    /// its temporary name shortened.
    #[test]
    fn outputs_below_a_file_or_with_too_long_a_name_are_refused_early() {
        let d = std::env::temp_dir().join(format!("hxai-atomic-paths-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let file = d.join("T.csv");
        std::fs::write(&file, "x\n1\n").unwrap();
        let e = check_output(&file.join("out.json"), &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("T.csv") && e.contains("is a file, not a folder"),
            "{e}"
        );
        let long = d.join(format!("{}.json", "a".repeat(256)));
        let e = check_output(&long, &[]).unwrap_err().to_string();
        assert!(e.contains("261 bytes long"), "{e}");
        let legal = d.join(format!("{}.json", "b".repeat(245)));
        check_output(&legal, &[]).unwrap();
        write_atomic(&legal, |f| {
            f.write_all(b"ok").map_err(|e| DataError::io(&legal, e))
        })
        .unwrap();
        assert_eq!(std::fs::read_to_string(&legal).unwrap(), "ok");
        let _ = std::fs::remove_dir_all(&d);
    }
}

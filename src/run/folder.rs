//! The output folder of a run: locked for the run's lifetime, and the only
//! place its files are written.
//!
//! * The lock is an advisory `flock` on the file [`LOCK_FILE`] in the
//!   folder, which records the holder's process id. The kernel releases it
//!   when the process ends, however it ends (`kill -9` included), so a stale
//!   lock cannot outlive its run; a second run on the folder (another
//!   process, or another run in the same process) is refused while the
//!   first holds it. `flock` may not be honoured across machines on network
//!   file systems.
//! * Output files are created inside the folder only (their names are plain
//!   file names checked by the scene), and never through a symbolic link
//!   planted in the folder (`O_NOFOLLOW`): nothing is written outside it.
//! * Files that must never be seen half written (the summary, checkpoints)
//!   are written to a temporary file in the folder and renamed over the old
//!   one.

use super::error::RunError;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The lock file in the output folder.
pub const LOCK_FILE: &str = ".quatrot.lock";
/// Name of the summary file in the output directory.
pub const SUMMARY_FILE: &str = "summary.json";
/// Name of the checkpoint file in the output directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.json";
/// Name of the trajectory file in the output directory.
pub const DCD_FILE: &str = "trajectory.dcd";
/// Name of the trajectory's topology file in the output directory.
pub const PDB_FILE: &str = "topology.pdb";
/// Name of the GSD trajectory file in the output directory.
pub const GSD_FILE: &str = "trajectory.gsd";

/// An output folder, locked while this value lives.
#[derive(Debug)]
pub struct OutputFolder {
    dir: PathBuf,
    /// Holds the lock (released when the file is closed).
    _lock: File,
}

impl OutputFolder {
    /// Creates `dir` if missing and locks it, or says which process holds it.
    /// An empty path is refused (it would write into the current directory
    /// unasked).
    pub fn lock(dir: &Path) -> Result<OutputFolder, RunError> {
        if dir.as_os_str().is_empty() {
            return Err(RunError::Io {
                path: "(empty path)".to_string(),
                message:
                    "an output folder's path must not be empty (\".\" is the current directory)"
                        .to_string(),
            });
        }
        std::fs::create_dir_all(dir).map_err(|e| RunError::io(dir, e))?;
        let path = dir.join(LOCK_FILE);
        let mut file = options()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| RunError::io(&path, said_plainly(e)))?;
        if !try_lock(&file).map_err(|e| RunError::io(&path, e))? {
            let mut holder = String::new();
            let _ = file.read_to_string(&mut holder);
            let holder = holder.trim();
            let holder = if holder.chars().all(|c| c.is_ascii_digit()) && !holder.is_empty() {
                format!("process {holder}")
            } else {
                "another run".to_string()
            };
            return Err(RunError::Locked {
                dir: dir.display().to_string(),
                holder,
            });
        }
        file.set_len(0)
            .and_then(|()| file.rewind())
            .and_then(|()| write!(file, "{}", std::process::id()))
            .and_then(|()| file.flush())
            .map_err(|e| RunError::io(&path, e))?;
        Ok(OutputFolder {
            dir: dir.to_path_buf(),
            _lock: file,
        })
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The path of `name` (a plain file name) in the folder.
    pub fn file(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }
}

/// Options that never follow a symbolic link at the last component.
fn options() -> OpenOptions {
    let mut options = OpenOptions::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        let _ = options.custom_flags(libc::O_NOFOLLOW);
    }
    options
}

/// The refusal of `O_NOFOLLOW` said plainly (the system's "Too many levels
/// of symbolic links" misleads).
fn said_plainly(e: std::io::Error) -> std::io::Error {
    #[cfg(unix)]
    if e.raw_os_error() == Some(libc::ELOOP) {
        return std::io::Error::other(
            "is a symbolic link; a run writes only inside its output folder, never through a link",
        );
    }
    e
}

/// Creates (or truncates) the file at `path` for reading and writing,
/// refusing a symbolic link there: every output is created through here.
pub fn create_file(path: &Path) -> std::io::Result<File> {
    options()
        .read(true)
        .write(true)
        .create(true)
        .truncate(true)
        .open(path)
        .map_err(said_plainly)
}

/// Opens the existing file at `path` for reading and writing, refusing a
/// symbolic link there.
pub fn open_existing(path: &Path) -> std::io::Result<File> {
    options()
        .read(true)
        .write(true)
        .open(path)
        .map_err(said_plainly)
}

/// Writes `bytes` to `path` through a temporary file in the same folder and
/// a rename, so that readers (and a run killed meanwhile) see the old file
/// or the new one, never a part; with `durable`, the data reach the disk
/// before the rename. The temporary file is removed when any of it fails
/// (a full disk leaves nothing behind).
pub fn write_atomically(path: &Path, bytes: &[u8], durable: bool) -> Result<(), RunError> {
    let mut partial = path.as_os_str().to_os_string();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    let mut file = create_file(&partial).map_err(|e| RunError::io(&partial, e))?;
    let written = file
        .write_all(bytes)
        .and_then(|()| if durable { file.sync_all() } else { Ok(()) })
        .map_err(|e| RunError::io(&partial, e))
        .and_then(|()| std::fs::rename(&partial, path).map_err(|e| RunError::io(path, e)));
    if written.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    written
}

#[cfg(unix)]
fn try_lock(file: &File) -> std::io::Result<bool> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a descriptor this process owns for the call.
    if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } == 0 {
        return Ok(true);
    }
    let e = std::io::Error::last_os_error();
    if e.raw_os_error() == Some(libc::EWOULDBLOCK) {
        Ok(false)
    } else {
        Err(e)
    }
}

#[cfg(not(unix))]
fn try_lock(_file: &File) -> std::io::Result<bool> {
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A second lock on a held folder is refused naming the holder; the
    /// lock is free again once the first is dropped.
    #[test]
    fn a_held_folder_is_refused_until_released() {
        let dir = tempfile::tempdir().unwrap();
        let first = OutputFolder::lock(dir.path()).unwrap();
        let e = OutputFolder::lock(dir.path()).unwrap_err().to_string();
        let pid = std::process::id();
        assert!(e.contains(&format!("process {pid}")), "{e}");
        drop(first);
        assert!(OutputFolder::lock(dir.path()).is_ok());
    }

    /// An empty path is not taken for the current directory.
    #[test]
    fn an_empty_path_is_refused() {
        let e = OutputFolder::lock(Path::new("")).unwrap_err().to_string();
        assert!(
            e.starts_with("(empty path): an output folder's path must not be empty"),
            "{e}"
        );
    }

    /// A symbolic link planted in the folder is not followed.
    #[cfg(unix)]
    #[test]
    fn symbolic_links_in_the_folder_are_not_followed() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("target.txt");
        std::fs::write(&target, "keep").unwrap();
        let link = dir.path().join("energies.csv");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        assert!(create_file(&link).is_err());
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep");
    }
}

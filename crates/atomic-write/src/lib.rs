//! Write-then-rename: the output path either keeps its old content or gets the complete new
//! file, never a truncated one. Every foamgrain crate that writes files (OpenFOAM fields and
//! meshes, VTK files) goes through [`write_atomically`].

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporaries of concurrent writes from the same process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A temporary file next to the target; removed on drop unless renamed onto the target.
struct Temp {
    path: PathBuf,
    keep: bool,
}

impl Drop for Temp {
    fn drop(&mut self) {
        if !self.keep {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Writes `path` atomically: `body` writes into a temporary file in the same directory (hidden,
/// named after the target), which is flushed, synced and renamed onto `path`. On any error the
/// temporary is removed and `path` is left as it was. The file is created with the usual
/// permissions (subject to the umask), not the private ones of a `mkstemp`-style temporary.
/// The error is the operating system's; callers add the path to their own error type.
pub fn write_atomically(
    path: &Path,
    body: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> io::Result<()> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(io::ErrorKind::InvalidInput, "output path has no file name")
    })?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(name);
    temp_name.push(format!(
        ".{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let temp_path = dir.join(temp_name);
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp_path)?;
    let mut temp = Temp {
        path: temp_path,
        keep: false,
    };
    let mut w = BufWriter::new(file);
    body(&mut w)?;
    let file = w.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()?;
    drop(file);
    fs::rename(&temp.path, path)?;
    temp.keep = true;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn entries(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn failed_write_keeps_old_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.vtu");
        fs::write(&p, "old").unwrap();
        let e = write_atomically(&p, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("disk full"))
        })
        .unwrap_err();
        assert!(e.to_string().contains("disk full"), "{e}");
        assert_eq!(fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(entries(dir.path()), ["out.vtu"]);
    }

    #[test]
    fn successful_write_replaces_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.vtp");
        fs::write(&p, "old").unwrap();
        write_atomically(&p, |w| w.write_all(b"new content")).unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "new content");
        assert_eq!(entries(dir.path()), ["out.vtp"]);
    }

    #[test]
    fn rename_failure_names_path_and_cleans_up() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("taken");
        fs::create_dir(p.join("")).unwrap();
        fs::write(p.join("inner"), "x").unwrap();
        write_atomically(&p, |w| w.write_all(b"data")).unwrap_err();
        assert_eq!(entries(dir.path()), ["taken"]);
    }

    #[test]
    fn missing_directory_is_an_io_error() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no/such/dir/x.vtp");
        let e = write_atomically(&p, |w| w.write_all(b"data")).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::NotFound);
    }
}

//! One output file written whole or not at all (`cardan import -o FILE`): the text goes into a
//! temporary sibling `.FILE.tmp-<pid>` (the same directory, so the same file system), which is
//! flushed, synced and then renamed over `FILE`. A failed write (a full disk) removes the
//! temporary file and leaves `FILE` as it was: no truncated file is ever left under the final
//! name. An output that is the input file itself (the same file by identity: device and inode,
//! not by name, so `./m.asmt`, a hard link or a symbolic link to it are caught) is refused
//! before anything is written.

use cardan_model::diag::{describe_io, Error};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Whether `a` and `b` name the same existing file (device and inode on Unix; the canonical
/// paths elsewhere). False when either does not exist.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (a.canonicalize(), b.canonicalize()) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
    }
}

/// The temporary sibling of `path`: `.NAME.tmp-<pid>` in its directory.
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// Writes `path` through a temporary sibling renamed into place (module docs); `write` writes
/// the contents.
///
/// # Errors
/// An output error naming `path` and the cause (the previous `path`, if any, unchanged).
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), Error> {
    let tmp = temporary(path);
    let result = (|| {
        let mut file = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        write(&mut file)?;
        let file = file.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::output(format!(
            "cannot write {}: {}; nothing was written under that name (a file there before is \
             unchanged)",
            path.display(),
            describe_io(&e)
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cardan-single-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// A write that fails half-way (as on a full disk) leaves the previous file whole and no
    /// temporary file behind.
    #[test]
    fn a_failed_write_leaves_the_previous_file() {
        let d = scratch("fail");
        let path = d.join("m.toml");
        std::fs::write(&path, "previous").unwrap();
        let e = write_atomically(&path, |w| {
            w.write_all(&[b'x'; 100_000])?;
            Err(std::io::Error::new(
                std::io::ErrorKind::StorageFull,
                "no space left on device",
            ))
        })
        .unwrap_err();
        assert!(e.message.contains("m.toml"), "{}", e.message);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "previous");
        let left: Vec<_> = std::fs::read_dir(&d).unwrap().collect();
        assert_eq!(left.len(), 1, "{left:?}");
        write_atomically(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn the_same_file_by_identity() {
        let d = scratch("same");
        let a = d.join("m.asmt");
        std::fs::write(&a, "x").unwrap();
        assert!(same_file(&a, &d.join(".").join("m.asmt")));
        std::fs::hard_link(&a, d.join("link.asmt")).unwrap();
        assert!(same_file(&a, &d.join("link.asmt")));
        assert!(!same_file(&a, &d.join("other.toml")));
        let _ = std::fs::remove_dir_all(&d);
    }
}

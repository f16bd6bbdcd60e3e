//! The one way the core writes an output file: whole or not at all. The bytes go to a
//! temporary file beside the target, are flushed to disk, and the temporary file is renamed
//! over the target; on any error it is removed and the target is untouched. An output that is
//! one of the inputs is refused, a folder is refused, and a device or FIFO (`/dev/stdout`, a
//! named pipe) is written into, since a rename would replace it.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// What tells files apart: device and inode where there are such, else the canonical path.
#[cfg(unix)]
pub(crate) fn file_key(p: &Path) -> Result<(u64, u64, PathBuf)> {
    use std::os::unix::fs::MetadataExt;
    let m = std::fs::metadata(p).map_err(|e| Error::io(p, e))?;
    Ok((m.dev(), m.ino(), PathBuf::new()))
}

#[cfg(not(unix))]
pub(crate) fn file_key(p: &Path) -> Result<(u64, u64, PathBuf)> {
    let c = std::fs::canonicalize(p).map_err(|e| Error::io(p, e))?;
    Ok((0, 0, c))
}

/// Runs `f` on a buffered writer into `path`, atomically (see the module documentation),
/// refusing a `path` that is one of `inputs`.
pub fn write_atomic<T>(
    path: &Path,
    inputs: &[&Path],
    f: impl FnOnce(&mut dyn Write) -> Result<T>,
) -> Result<T> {
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(Error::Invalid(format!(
                "{}: the output is a folder",
                path.display()
            )));
        }
        let target = file_key(path)?;
        if inputs
            .iter()
            .any(|i| file_key(i).is_ok_and(|k| k == target))
        {
            return Err(Error::Invalid(format!(
                "{}: the output is one of the inputs; give another output file",
                path.display()
            )));
        }
        if !meta.is_file() {
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(|e| Error::io(path, e))?;
            let mut w = std::io::BufWriter::with_capacity(1 << 20, file);
            let v = f(&mut w).map_err(|e| name_output(e, path))?;
            w.flush().map_err(|e| Error::io(path, e))?;
            return Ok(v);
        }
    }
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| Error::Invalid(format!("{}: not a file name", path.display())))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = dir.join(tmp_name);
    let file = std::fs::File::create(&tmp).map_err(|e| Error::io(&tmp, e))?;
    let mut w = std::io::BufWriter::with_capacity(1 << 20, file);
    let r = f(&mut w).and_then(|v| {
        let file = w
            .into_inner()
            .map_err(|e| Error::io(path, e.into_error()))?;
        file.sync_all().map_err(|e| Error::io(path, e))?;
        std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))?;
        Ok(v)
    });
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r.map_err(|e| name_output(e, path))
}

/// An I/O error of the writer (named `<output>`) named by the file written.
fn name_output(e: Error, path: &Path) -> Error {
    match e {
        Error::Io { source, path: p } if p.as_os_str() == "<output>" => Error::io(path, source),
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::write_atomic;
    use crate::error::Error;

    #[test]
    fn whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("foon-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("out.txt");
        write_atomic(&out, &[], |w| crate::write::put(w, b"one")).unwrap();
        assert_eq!(std::fs::read(&out).unwrap(), b"one");
        // A failing writer leaves the old file and no temporary file.
        let r: crate::Result<()> = write_atomic(&out, &[], |w| {
            crate::write::put(w, b"partial")?;
            Err(Error::Invalid("stop".into()))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&out).unwrap(), b"one");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        // Never over an input; never a folder.
        let e = write_atomic(&out, &[out.as_path()], |_| Ok(())).unwrap_err();
        assert!(e.to_string().contains("one of the inputs"), "{e}");
        assert!(write_atomic(&dir, &[], |_| Ok(())).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

//! Opening files with the checks every reader and writer needs, and small
//! attribute helpers.

use std::io::Read;
use std::path::Path;

use hdf5::types::VarLenUnicode;
use hdf5::{H5Type, Location};

use crate::error::{Context, IoError};
use crate::layout;

/// The 8-byte HDF5 signature.
const SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// Whether `path` holds the HDF5 signature at one of the offsets where the
/// superblock may start (0, 512, 1024, 2048, ...).
fn has_hdf5_signature(path: &Path) -> Result<bool, IoError> {
    let os = |source| IoError::Os {
        path: path.to_path_buf(),
        source,
    };
    let mut file = std::fs::File::open(path).map_err(os)?;
    let len = file.metadata().map_err(os)?.len();
    let mut offset = 0u64;
    let mut buf = [0u8; 8];
    while offset + 8 <= len {
        use std::io::Seek;
        file.seek(std::io::SeekFrom::Start(offset)).map_err(os)?;
        file.read_exact(&mut buf).map_err(os)?;
        if &buf == SIGNATURE {
            return Ok(true);
        }
        offset = if offset == 0 { 512 } else { offset * 2 };
    }
    Ok(false)
}

/// File access without HDF5's file locks, so that a run can be inspected
/// while it is written (the writer flushes after each record), and so that
/// a file whose writer was killed opens at once.
fn builder() -> hdf5::FileBuilder {
    let mut b = hdf5::File::with_options();
    b.with_fapl(|p| p.file_locking(false));
    b
}

/// Opens an existing floe run file, read-only or read-write, after checking
/// that it exists, is HDF5 and was written by floe.
pub(crate) fn open_run(path: &Path, write: bool) -> Result<hdf5::File, IoError> {
    match std::fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(IoError::NotFound {
                path: path.to_path_buf(),
            })
        }
        Err(source) => {
            return Err(IoError::Os {
                path: path.to_path_buf(),
                source,
            })
        }
        Ok(m) if m.is_dir() => {
            return Err(crate::error::invalid(
                path,
                "is a directory, not a run file",
            ))
        }
        Ok(_) => {}
    }
    if !has_hdf5_signature(path)? {
        return Err(IoError::NotHdf5 {
            path: path.to_path_buf(),
        });
    }
    let file = if write {
        builder().open_rw(path)
    } else {
        builder().open(path)
    }
    .at(path, || {
        format!(
            "cannot open {} (damaged HDF5 file?)",
            if write { "for writing" } else { "for reading" }
        )
    })?;
    check_floe_file(&file, path)?;
    Ok(file)
}

/// Creates a new file; fails if it exists.
pub(crate) fn create_file(path: &Path) -> hdf5::Result<hdf5::File> {
    let mut b = builder();
    // Only the virtual file driver allocates space: freed space is never
    // handed out again before the next flush, so a process killed between
    // flushes cannot leave flushed metadata pointing at overwritten bytes.
    b.with_fcpl(|p| p.file_space_strategy(hdf5::plist::file_create::FileSpaceStrategy::None));
    b.create_excl(path)
}

fn check_floe_file(file: &hdf5::File, path: &Path) -> Result<(), IoError> {
    let not_floe = |reason: String| IoError::NotFloeFile {
        path: path.to_path_buf(),
        reason,
    };
    let creator = file
        .group(&format!("{}/creator", layout::H5MD))
        .map_err(|_| not_floe("no /h5md/creator group (not an H5MD file)".into()))?;
    let name = read_str(&creator, "name")
        .map_err(|_| not_floe("/h5md/creator has no name attribute".into()))?;
    if name != layout::CREATOR {
        return Err(not_floe(format!("written by {name:?}, not by floe")));
    }
    let params = file
        .group(layout::PARAMETERS)
        .map_err(|_| not_floe("no /parameters group".into()))?;
    let version: u32 = params
        .attr("layout_version")
        .and_then(|a| a.read_scalar())
        .map_err(|_| not_floe("/parameters has no layout_version attribute".into()))?;
    if version > layout::LAYOUT_VERSION {
        return Err(not_floe(format!(
            "layout version {version} is newer than this floe reads ({}); use a newer floe",
            layout::LAYOUT_VERSION
        )));
    }
    for group in [
        layout::FLOES,
        layout::CONTACTS,
        layout::OBSERVABLES,
        layout::CHECKPOINT,
    ] {
        if !file.link_exists(group) {
            return Err(not_floe(format!("no /{group} group")));
        }
    }
    Ok(())
}

/// A string as an HDF5 variable-length UTF-8 string.
pub(crate) fn vlen(s: &str) -> hdf5::Result<VarLenUnicode> {
    s.parse::<VarLenUnicode>()
        .map_err(|e| hdf5::Error::from(format!("string {s:?} cannot be stored: {e}")))
}

/// Creates a scalar string attribute.
pub(crate) fn write_str(loc: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    loc.new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&vlen(value)?)
}

/// Creates a string-array attribute.
pub(crate) fn write_strs(loc: &Location, name: &str, values: &[&str]) -> hdf5::Result<()> {
    let v = values
        .iter()
        .map(|s| vlen(s))
        .collect::<hdf5::Result<Vec<_>>>()?;
    loc.new_attr::<VarLenUnicode>()
        .shape(v.len())
        .create(name)?
        .write_raw(&v)
}

/// Creates a scalar attribute.
pub(crate) fn write_scalar<T: H5Type>(loc: &Location, name: &str, value: T) -> hdf5::Result<()> {
    loc.new_attr::<T>().create(name)?.write_scalar(&value)
}

/// Creates a 1-D attribute.
pub(crate) fn write_array<T: H5Type>(loc: &Location, name: &str, values: &[T]) -> hdf5::Result<()> {
    loc.new_attr::<T>()
        .shape(values.len())
        .create(name)?
        .write_raw(values)
}

/// Reads a scalar attribute.
pub(crate) fn read_scalar<T: H5Type>(loc: &Location, name: &str) -> hdf5::Result<T> {
    loc.attr(name)?.read_scalar::<T>()
}

/// Reads a scalar string attribute.
pub(crate) fn read_str(loc: &Location, name: &str) -> hdf5::Result<String> {
    Ok(loc
        .attr(name)?
        .read_scalar::<VarLenUnicode>()?
        .as_str()
        .to_string())
}

/// Reads a string-array attribute.
pub(crate) fn read_strs(loc: &Location, name: &str) -> hdf5::Result<Vec<String>> {
    Ok(loc
        .attr(name)?
        .read_raw::<VarLenUnicode>()?
        .iter()
        .map(|s| s.as_str().to_string())
        .collect())
}

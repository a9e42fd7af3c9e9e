//! How long a NetCDF-3 file (classic `CDF\x01`, 64-bit offset `CDF\x02`,
//! 64-bit data `CDF\x05`) must be, from its header.
//!
//! The C library reads a classic file that was cut short (an interrupted
//! copy or download) without a word: the missing values come back as
//! zeros. Reading the header here (the format is a few pages of the
//! NetCDF User's Guide, "File Format Specification") gives where each
//! variable's data begins and how long it is, so that such a file is
//! refused instead. A header that cannot be read is left to the library,
//! whose own message then names what is wrong.

use std::fs::File;
use std::io::{BufReader, Read, Seek};
use std::path::Path;

/// Header tags.
const NC_DIMENSION: u32 = 0x0A;
const NC_VARIABLE: u32 = 0x0B;
const NC_ATTRIBUTE: u32 = 0x0C;
/// `numrecs` of a file being written by a streaming writer.
const STREAMING: u64 = 0xFFFF_FFFF;

/// What the header says about the file's length.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Extent {
    /// Not a NetCDF-3 file, or a header this reader does not follow.
    Unknown,
    /// The header itself is cut short.
    HeaderCut,
    /// The file must be at least this many bytes long.
    AtLeast(u64),
}

/// The extent of the NetCDF-3 file at `path` (see [`Extent`]).
///
/// # Errors
/// The file cannot be opened or read (other than ending early).
pub fn extent(path: &Path) -> std::io::Result<Extent> {
    let file = File::open(path)?;
    let len = file.metadata()?.len();
    let mut r = Header {
        inner: BufReader::new(file),
        len,
        wide: false,
    };
    let mut magic = [0u8; 4];
    if !r.read_exact(&mut magic)? {
        return Ok(Extent::Unknown);
    }
    let version = match &magic {
        b"CDF\x01" => 1,
        b"CDF\x02" => 2,
        b"CDF\x05" => 5,
        _ => return Ok(Extent::Unknown),
    };
    r.wide = version == 5;
    Ok(match parse(&mut r, version) {
        Ok(Some(need)) => Extent::AtLeast(need),
        Ok(None) => Extent::Unknown,
        Err(Cut) => Extent::HeaderCut,
    })
}

/// The header ended before it was complete.
struct Cut;

struct Header {
    inner: BufReader<File>,
    len: u64,
    /// CDF-5: counts and sizes are 8 bytes.
    wide: bool,
}

type Step<T> = Result<Option<T>, Cut>;

impl Header {
    /// `Ok(false)` at the end of the file; I/O errors other than that are
    /// taken as the end too (the library reports them).
    fn read_exact(&mut self, buf: &mut [u8]) -> std::io::Result<bool> {
        match self.inner.read_exact(buf) {
            Ok(()) => Ok(true),
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => Ok(false),
            Err(e) => Err(e),
        }
    }

    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], Cut> {
        let mut b = [0u8; N];
        match self.read_exact(&mut b) {
            Ok(true) => Ok(b),
            _ => Err(Cut),
        }
    }

    fn u32(&mut self) -> Result<u32, Cut> {
        Ok(u32::from_be_bytes(self.bytes()?))
    }

    fn u64(&mut self) -> Result<u64, Cut> {
        Ok(u64::from_be_bytes(self.bytes()?))
    }

    /// A count or size: 4 bytes, 8 in CDF-5.
    fn non_neg(&mut self) -> Result<u64, Cut> {
        if self.wide {
            self.u64()
        } else {
            Ok(u64::from(self.u32()?))
        }
    }

    /// Skips `n` bytes (padded to 4); `None` if that is beyond the file
    /// (a count that is not one: left to the library).
    fn skip_padded(&mut self, n: u64) -> Step<()> {
        let n = match n.checked_add(3) {
            Some(m) => m & !3,
            None => return Ok(None),
        };
        let at = self.inner.stream_position().map_err(|_| Cut)?;
        if at.saturating_add(n) > self.len {
            return Ok(None);
        }
        self.inner.seek_relative(n as i64).map_err(|_| Cut)?;
        Ok(Some(()))
    }

    /// A name: its length and padded bytes.
    fn name(&mut self) -> Step<()> {
        let n = self.non_neg()?;
        self.skip_padded(n)
    }

    /// A list's tag and count (`ABSENT` is two zeros): the count, or `None`
    /// for another tag.
    fn list(&mut self, tag: u32) -> Step<u64> {
        let t = self.u32()?;
        let n = self.non_neg()?;
        if t == 0 && n == 0 {
            return Ok(Some(0));
        }
        if t != tag {
            return Ok(None);
        }
        Ok(Some(n))
    }

    fn attributes(&mut self) -> Step<()> {
        let Some(n) = self.list(NC_ATTRIBUTE)? else {
            return Ok(None);
        };
        for _ in 0..n {
            if self.name()?.is_none() {
                return Ok(None);
            }
            let Some(size) = type_size(self.u32()?) else {
                return Ok(None);
            };
            let count = self.non_neg()?;
            let Some(bytes) = count.checked_mul(size) else {
                return Ok(None);
            };
            if self.skip_padded(bytes)?.is_none() {
                return Ok(None);
            }
        }
        Ok(Some(()))
    }
}

/// Bytes per value of an external type.
fn type_size(nc_type: u32) -> Option<u64> {
    Some(match nc_type {
        1 | 2 | 7 => 1,   // byte, char, ubyte
        3 | 8 => 2,       // short, ushort
        4 | 5 | 9 => 4,   // int, float, uint
        6 | 10 | 11 => 8, // double, int64, uint64
        _ => return None,
    })
}

/// One variable: where its data begins, its bytes per record (or in all,
/// for a fixed-size variable) and whether it is a record variable.
struct Var {
    begin: u64,
    bytes: u64,
    record: bool,
    vsize: u64,
}

/// The least length the header asks for, after the magic number.
fn parse(r: &mut Header, version: u8) -> Step<u64> {
    let numrecs = r.non_neg()?;
    let Some(ndims) = r.list(NC_DIMENSION)? else {
        return Ok(None);
    };
    let mut dims = Vec::new();
    for _ in 0..ndims {
        if r.name()?.is_none() || dims.len() > 1 << 20 {
            return Ok(None);
        }
        dims.push(r.non_neg()?);
    }
    if r.attributes()?.is_none() {
        return Ok(None);
    }
    let Some(nvars) = r.list(NC_VARIABLE)? else {
        return Ok(None);
    };
    let mut vars = Vec::new();
    for _ in 0..nvars {
        if r.name()?.is_none() || vars.len() > 1 << 20 {
            return Ok(None);
        }
        let rank = r.non_neg()?;
        let (mut values, mut record) = (1u64, false);
        for k in 0..rank {
            let id = r.non_neg()?;
            let Some(&len) = dims.get(id as usize) else {
                return Ok(None);
            };
            if len == 0 && k == 0 {
                record = true;
            } else {
                let Some(v) = values.checked_mul(len) else {
                    return Ok(None);
                };
                values = v;
            }
        }
        if r.attributes()?.is_none() {
            return Ok(None);
        }
        let Some(size) = type_size(r.u32()?) else {
            return Ok(None);
        };
        let vsize = r.non_neg()?;
        let begin = if version == 1 {
            u64::from(r.u32()?)
        } else {
            r.u64()?
        };
        let Some(bytes) = values.checked_mul(size) else {
            return Ok(None);
        };
        vars.push(Var {
            begin,
            bytes,
            record,
            vsize,
        });
    }
    // Sizes past 4 GiB do not fit a classic vsize: leave those to the library.
    if vars
        .iter()
        .any(|v| !r.wide && v.vsize == u64::from(u32::MAX))
    {
        return Ok(None);
    }
    let records: Vec<&Var> = vars.iter().filter(|v| v.record).collect();
    let record_size = match records.as_slice() {
        [only] => only.bytes,
        many => many.iter().map(|v| v.vsize).sum(),
    };
    let mut need = 0u64;
    for v in &vars {
        let end = if !v.record {
            v.begin.checked_add(v.bytes)
        } else if numrecs == 0 || numrecs == STREAMING {
            Some(0)
        } else {
            (numrecs - 1)
                .checked_mul(record_size)
                .and_then(|s| s.checked_add(v.begin))
                .and_then(|s| s.checked_add(v.bytes))
        };
        let Some(end) = end else {
            return Ok(None);
        };
        need = need.max(end);
    }
    Ok(Some(need))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_classic_file_cut_short_is_told_from_a_whole_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.nc");
        {
            let mut f = netcdf::create_with(&path, netcdf::Options::empty()).unwrap();
            f.add_unlimited_dimension("time").unwrap();
            f.add_dimension("x", 5).unwrap();
            f.add_variable::<f64>("x", &["x"]).unwrap();
            f.add_variable::<i16>("h", &["time", "x"]).unwrap();
            f.add_variable::<f32>("t", &["time"]).unwrap();
            f.add_attribute("title", "a classic file").unwrap();
            f.enddef().unwrap();
            f.variable_mut("x")
                .unwrap()
                .put_values(&[0.0, 1.0, 2.0, 3.0, 4.0], ..)
                .unwrap();
            f.variable_mut("h")
                .unwrap()
                .put_values(&[1i16; 15], (0..3, ..))
                .unwrap();
            f.variable_mut("t")
                .unwrap()
                .put_values(&[0.0f32, 1.0, 2.0], ..)
                .unwrap();
        }
        let bytes = std::fs::read(&path).unwrap();
        let Extent::AtLeast(need) = extent(&path).unwrap() else {
            panic!("a classic file's extent");
        };
        assert!(need <= bytes.len() as u64, "{need} > {}", bytes.len());
        // The last record's last value ends the data.
        assert!(need + 4 >= bytes.len() as u64, "{need} vs {}", bytes.len());
        std::fs::write(&path, &bytes[..bytes.len() - 2]).unwrap();
        assert!(matches!(extent(&path).unwrap(), Extent::AtLeast(n) if n > bytes.len() as u64 - 2));
        std::fs::write(&path, &bytes[..18]).unwrap();
        assert_eq!(extent(&path).unwrap(), Extent::HeaderCut);
        std::fs::write(&path, b"\x89HDF\r\n\x1a\n").unwrap();
        assert_eq!(extent(&path).unwrap(), Extent::Unknown);
    }
}

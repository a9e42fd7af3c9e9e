//! The SHA-256 of an input file, for the run file's provenance (the same
//! digest `sha256sum` prints).

use std::io::Read;
use std::path::Path;

use sha2::{Digest, Sha256};

use crate::error::BasinError;

/// The lowercase hex SHA-256 of the file at `path`, read in 1 MiB blocks.
///
/// # Errors
/// [`BasinError::File`] when it cannot be read.
pub fn sha256_file(path: &Path) -> Result<String, BasinError> {
    let fail = |e: std::io::Error| BasinError::File {
        path: path.to_path_buf(),
        why: format!("cannot read it: {e}"),
    };
    let mut file = std::fs::File::open(path).map_err(fail)?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    loop {
        let n = file.read(&mut buf).map_err(fail)?;
        if n == 0 {
            break;
        }
        hasher.update(&buf[..n]);
    }
    Ok(hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

#[cfg(test)]
mod tests {
    #[test]
    fn digest_of_abc_is_the_fips_180_2_example() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("abc");
        std::fs::write(&p, b"abc").unwrap();
        assert_eq!(
            super::sha256_file(&p).unwrap(),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}

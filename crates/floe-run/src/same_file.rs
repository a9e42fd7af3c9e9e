//! Whether an output would overwrite an input: the same path, a link to
//! it, or (on Unix) another name of the same file.

use std::path::Path;

use crate::error::Error;

/// Whether `a` and `b` name the same existing file.
pub fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if (ma.dev(), ma.ino()) == (mb.dev(), mb.ino()) {
            return true;
        }
    }
    let _ = (ma, mb);
    matches!(
        (std::fs::canonicalize(a), std::fs::canonicalize(b)),
        (Ok(ca), Ok(cb)) if ca == cb
    )
}

/// Refuses, with or without `--force`, an output among `outputs` that is
/// the input `input` (named `what` in the message).
pub fn refuse_overwriting_input<'a>(
    input: &Path,
    what: &str,
    outputs: impl IntoIterator<Item = &'a Path>,
) -> Result<(), Error> {
    for out in outputs {
        if same_file(input, out) {
            return Err(Error::Usage(format!(
                "{}: the output would overwrite the {what} {}; write it elsewhere \
                 (--force does not allow this)",
                out.display(),
                input.display()
            )));
        }
    }
    Ok(())
}

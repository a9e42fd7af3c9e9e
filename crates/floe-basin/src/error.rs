//! What can go wrong reading a basin's files; every message names the file
//! (and the variable or feature) it is about.

use std::path::PathBuf;

/// An error of floe-basin.
#[derive(Debug, thiserror::Error)]
pub enum BasinError {
    /// A map projection that cannot be built or used.
    #[error("map projection \"{definition}\": {why}")]
    Projection {
        /// The definition as given.
        definition: String,
        /// What was wrong.
        why: String,
    },
    /// A file that cannot be read, or whose content is not what floe needs.
    #[error("{}: {why}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What was wrong, naming the variable or feature.
        why: String,
    },
}

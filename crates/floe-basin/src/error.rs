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

/// Longest text from a file or the library quoted in a message, characters.
const MAX_SHOWN_CHARS: usize = 200;

/// `text` as a message may quote it: control characters escaped (a NUL
/// must not reach the terminal), cut to [`MAX_SHOWN_CHARS`].
pub(crate) fn shown(text: &str) -> String {
    let escaped: String = text
        .chars()
        .flat_map(|c| {
            let e: Vec<char> = if c.is_control() {
                c.escape_default().collect()
            } else {
                vec![c]
            };
            e
        })
        .collect();
    if escaped.chars().count() <= MAX_SHOWN_CHARS {
        return escaped;
    }
    let head: String = escaped.chars().take(MAX_SHOWN_CHARS).collect();
    format!("{head}...")
}

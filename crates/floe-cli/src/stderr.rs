//! Lines to standard error that never stop the program: a closed or full
//! stderr (`floe run s.toml 2>&1 | head -1`) must not end a run half-way.

use std::io::Write;

/// Writes `line` and a newline to standard error, ignoring failure.
pub fn line(line: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

//! proptest's settings for the tests: its defaults, with the seeds of past
//! failures kept beside the test file (`<file stem>.proptest-regressions`).
//! proptest's own default looks up from the test file for a `main.rs` and
//! keeps them in a `proptest-regressions` folder beside that one's folder
//! (`tests/proptest-regressions/<file stem>.txt`, for every crate at once).

use proptest::test_runner::{Config, FileFailurePersistence};

/// proptest's default settings, failures kept beside the test file.
pub fn default() -> Config {
    Config {
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        ..Config::default()
    }
}

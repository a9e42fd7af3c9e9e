//! Scenario files (TOML) for `floe run`.

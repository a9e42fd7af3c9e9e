//! The packs floe's benches, examples and tests share, built in one place so
//! that a figure in docs/performance.md and the test that checks the same
//! pack measure the same floes (development only; not published).
//!
//! * [`channel`]: a channel of 1 km diamonds, periodic along x, sheared
//!   across (the DEM step benchmark's pack, 1e3 to 1e6 floes).
//! * [`wind_pack`]: 30 square floes pushed by wind against a moving wall,
//!   with contact memory (checkpoint and run-file tests).
#![deny(missing_docs)]

pub mod channel;
pub mod wind_pack;

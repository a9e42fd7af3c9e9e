//! floe-io: run files read back bitwise, checkpoints of every format,
//! errors naming the file, `kill -9` at any moment, and h5py reading them.

mod checkpoint_formats;
mod errors;
mod h5py;
mod kill;
mod roundtrip;
mod segments;
mod support;

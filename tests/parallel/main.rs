//! floe-parallel: a world spread over processes (threads standing in for
//! MPI ranks) steps bitwise as one process.

mod equivalence;
#[path = "../support/shape.rs"]
mod shape_support;

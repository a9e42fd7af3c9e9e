//! floe across processes: a world spread over MPI processes by spatial
//! domain decomposition (recursive coordinate bisection weighted by
//! contacts, LAMMPS' tiled style), with ghost floes, migration that carries
//! each floe's contact history, and the whole gathered to one writer. The
//! result is bitwise the single process's for any process and thread
//! count ([`distributed_world`] says how).
//!
//! | file | job |
//! |---|---|
//! | [`comm`] | the collectives a run needs ([`Communicator`]) |
//! | [`thread_comm`] | those collectives between threads, for tests |
//! | `mpi_comm` | those collectives over MPI (feature `mpi`) |
//! | [`distributed_world`] | the distributed world and its step |
//! | `distributed_world/placement.rs` | a floe's owner and the processes it reaches |
//! | `distributed_world/migration.rs` | floes handed to their new holders, rebalancing |
//! | `distributed_world/halo.rs` | every step's exchange of the ghosts' motion |
//! | `distributed_world/gather.rs` | the whole world on process 0 |
//! | `reach` | distances to subdomains and walls |
//! | `wire` | what is sent |

#![deny(missing_docs)]

pub mod comm;
pub mod distributed_world;
pub mod error;
#[cfg(feature = "mpi")]
pub mod mpi_comm;
mod reach;
pub mod thread_comm;
mod wire;

pub use comm::{Communicator, SoloComm, Traffic};
pub use distributed_world::{DecompositionStats, DistributedWorld, Settings};
pub use error::ParallelError;
pub use thread_comm::ThreadComm;

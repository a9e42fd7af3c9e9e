//! The collectives over MPI (rsmpi, binding the system's MPI library):
//! `MPI_Alltoall(v)` for migration and gathering, non-blocking sends and
//! receives between neighbours for the halo of every step, `MPI_Allreduce`
//! for the sums and maxima.

use std::cell::Cell;

use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::{Communicator as _, CommunicatorCollectives, Destination, Source};
use mpi::Threading;

use crate::comm::{Communicator, Traffic};

/// MPI, initialised for the life of this value (dropping it finalises).
pub struct Mpi {
    universe: Universe,
}

impl Mpi {
    /// Initialises MPI, or says why it cannot. The run loop calls MPI from
    /// one thread at a time, which may not be the thread that initialised
    /// it (`MPI_THREAD_SERIALIZED`); a panic on any process then aborts
    /// the job.
    pub fn initialize() -> Result<Mpi, String> {
        let (universe, level) = mpi::initialize_with_threading(Threading::Serialized)
            .ok_or_else(|| "MPI could not be initialised (or was already)".to_string())?;
        if level < Threading::Serialized {
            return Err(format!(
                "the MPI library gives thread level {level:?}; floe calls MPI from a worker \
                 thread, one at a time, and needs MPI_THREAD_SERIALIZED: use an MPI built \
                 with thread support"
            ));
        }
        // A panic on one process would leave the others waiting in a
        // collective; end the whole job instead.
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            previous(info);
            mpi::topology::SimpleCommunicator::world().abort(101);
        }));
        Ok(Mpi { universe })
    }

    /// The communicator of every process of the job.
    pub fn world(&self) -> MpiComm {
        MpiComm {
            comm: self.universe.world(),
            traffic: Cell::new(Traffic::default()),
        }
    }
}

/// The processes of `MPI_COMM_WORLD`.
pub struct MpiComm {
    comm: SimpleCommunicator,
    traffic: Cell<Traffic>,
}

// SAFETY: MPI is initialised with MPI_THREAD_SERIALIZED, and a run calls
// these collectives from one thread at a time (the thread running the
// stepping loop; rayon's workers never call MPI), which is what that level
// allows. The handle is an opaque pointer MPI owns for the job's life.
#[allow(unsafe_code)]
unsafe impl Send for MpiComm {}
// SAFETY: as above: the traffic counter and the handle are used by one
// thread at a time.
#[allow(unsafe_code)]
unsafe impl Sync for MpiComm {}

impl MpiComm {
    fn count(&self, bytes: usize, messages: usize) {
        let mut t = self.traffic.get();
        t.bytes += bytes as u64;
        t.messages += messages as u64;
        self.traffic.set(t);
    }
}

/// A message length as MPI's count (`int`).
fn count(n: usize) -> i32 {
    i32::try_from(n).unwrap_or_else(|_| {
        panic!("a message of {n} bytes between two processes: more than MPI's 2 GiB count; run on more processes")
    })
}

/// Refuses messages whose lengths add up past MPI's `int` offsets.
fn total_count(counts: &[i32]) {
    let total: i64 = counts.iter().map(|&c| i64::from(c)).sum();
    if total > i64::from(i32::MAX) {
        panic!("{total} bytes in one exchange: more than MPI's 2 GiB of offsets; run on more processes or write fewer contacts")
    }
}

impl Communicator for MpiComm {
    fn rank(&self) -> usize {
        self.comm.rank() as usize
    }

    fn size(&self) -> usize {
        self.comm.size() as usize
    }

    fn all_to_all(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        let k = self.size();
        assert_eq!(outgoing.len(), k, "one message per process");
        let send_counts: Vec<i32> = outgoing.iter().map(|m| count(m.len())).collect();
        let mut recv_counts = vec![0i32; k];
        self.comm
            .all_to_all_into(&send_counts[..], &mut recv_counts[..]);
        let displs = |counts: &[i32]| -> Vec<i32> {
            counts
                .iter()
                .scan(0i32, |at, &c| {
                    let here = *at;
                    *at += c;
                    Some(here)
                })
                .collect()
        };
        total_count(&send_counts);
        total_count(&recv_counts);
        let (send_displs, recv_displs) = (displs(&send_counts), displs(&recv_counts));
        let me = self.rank();
        let others = outgoing
            .iter()
            .enumerate()
            .filter(|(r, m)| *r != me && !m.is_empty());
        let (bytes, messages) = others.fold((0, 0), |(b, n), (_, m)| (b + m.len(), n + 1));
        self.count(bytes + 4 * k, messages);
        // Never empty: two empty buffers share one dangling address, which
        // Open MPI refuses as a send buffer that is also the receive buffer.
        let mut send: Vec<u8> = outgoing.concat();
        send.push(0);
        let total: usize = recv_counts.iter().map(|&c| c as usize).sum();
        let mut recv = vec![0u8; total + 1];
        {
            let s = Partition::new(&send[..], &send_counts[..], &send_displs[..]);
            let mut r = PartitionMut::new(&mut recv[..], &recv_counts[..], &recv_displs[..]);
            self.comm.all_to_all_varcount_into(&s, &mut r);
        }
        recv_displs
            .iter()
            .zip(&recv_counts)
            .map(|(&d, &c)| recv[d as usize..(d + c) as usize].to_vec())
            .collect()
    }

    fn exchange(&self, sends: Vec<(usize, Vec<u8>)>, receives: &[(usize, usize)]) -> Vec<Vec<u8>> {
        let mut incoming: Vec<Vec<u8>> = receives.iter().map(|&(_, n)| vec![0u8; n]).collect();
        let bytes: usize = sends.iter().map(|(_, b)| b.len()).sum();
        self.count(bytes, sends.len());
        mpi::request::multiple_scope(sends.len() + receives.len(), |scope, requests| {
            for ((r, _), buf) in receives.iter().zip(incoming.iter_mut()) {
                let from = self.comm.process_at_rank(*r as i32);
                requests.add(from.immediate_receive_into(scope, &mut buf[..]));
            }
            for (r, buf) in &sends {
                let to = self.comm.process_at_rank(*r as i32);
                requests.add(to.immediate_send(scope, &buf[..]));
            }
            let mut done = Vec::with_capacity(sends.len() + receives.len());
            requests.wait_all(&mut done);
        });
        incoming
    }

    fn all_gather(&self, mine: Vec<u8>) -> Vec<Vec<u8>> {
        let k = self.size();
        let mut counts = vec![0i32; k];
        self.comm
            .all_gather_into(&count(mine.len()), &mut counts[..]);
        let displs: Vec<i32> = counts
            .iter()
            .scan(0i32, |at, &c| {
                let here = *at;
                *at += c;
                Some(here)
            })
            .collect();
        self.count(mine.len() + 4, 2);
        let total: usize = counts.iter().map(|&c| c as usize).sum();
        // Distinct from the send buffer even when both are empty.
        let mut send = mine;
        let n = send.len();
        send.push(0);
        let mut recv = vec![0u8; total + 1];
        {
            let mut r = PartitionMut::new(&mut recv[..], &counts[..], &displs[..]);
            self.comm.all_gather_varcount_into(&send[..n], &mut r);
        }
        displs
            .iter()
            .zip(&counts)
            .map(|(&d, &c)| recv[d as usize..(d + c) as usize].to_vec())
            .collect()
    }

    fn sum_i64(&self, values: &mut [i64]) {
        let send = values.to_vec();
        self.count(8 * values.len(), 1);
        self.comm
            .all_reduce_into(&send[..], values, SystemOperation::sum());
    }

    fn max_f64(&self, values: &mut [f64]) {
        let send = values.to_vec();
        self.count(8 * values.len(), 1);
        self.comm
            .all_reduce_into(&send[..], values, SystemOperation::max());
    }

    fn traffic(&self) -> Traffic {
        self.traffic.get()
    }

    fn abort(&self, code: i32) -> ! {
        self.comm.abort(code)
    }
}

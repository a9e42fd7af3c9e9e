//! What a distributed run needs from its processes' communication: an
//! all-to-all exchange of bytes and a few reductions. MPI provides it under
//! `mpirun` ([`crate::mpi_comm`], feature `mpi`); [`crate::ThreadComm`]
//! runs the same collectives between threads of one process, for tests.
//!
//! Every call is collective: each process calls it, in the same order.

/// The collectives of a distributed run.
pub trait Communicator {
    /// This process's index, `0..size()`.
    fn rank(&self) -> usize;

    /// The number of processes.
    fn size(&self) -> usize;

    /// Sends `outgoing[k]` to process `k` (one entry per process, empty
    /// for none) and returns what each process sent to this one, by
    /// sender.
    fn all_to_all(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>>;

    /// Sends each `(process, bytes)` of `sends` and receives from each
    /// `(process, length)` of `receives` a message of that length: an
    /// exchange among neighbours only (the halo's), whose sizes both sides
    /// know. Returns the received messages in `receives`' order.
    fn exchange(&self, sends: Vec<(usize, Vec<u8>)>, receives: &[(usize, usize)]) -> Vec<Vec<u8>> {
        let mut outgoing = vec![Vec::new(); self.size()];
        for (r, bytes) in sends {
            outgoing[r] = bytes;
        }
        let mut incoming = self.all_to_all(outgoing);
        receives
            .iter()
            .map(|&(r, _)| std::mem::take(&mut incoming[r]))
            .collect()
    }

    /// Every process's `mine`, on every process, by rank.
    fn all_gather(&self, mine: Vec<u8>) -> Vec<Vec<u8>> {
        self.all_to_all(vec![mine; self.size()])
    }

    /// Element-wise integer sum over the processes, in place.
    fn sum_i64(&self, values: &mut [i64]) {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let all = self.all_to_all(vec![bytes; self.size()]);
        values.fill(0);
        for part in &all {
            for (v, b) in values.iter_mut().zip(part.chunks_exact(8)) {
                *v = v.wrapping_add(i64::from_le_bytes(b.try_into().expect("8 bytes")));
            }
        }
    }

    /// Element-wise maximum over the processes, in place (exact, so any
    /// order gives the same bits).
    fn max_f64(&self, values: &mut [f64]) {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let all = self.all_to_all(vec![bytes; self.size()]);
        values.fill(f64::NEG_INFINITY);
        for part in &all {
            for (v, b) in values.iter_mut().zip(part.chunks_exact(8)) {
                *v = v.max(f64::from_le_bytes(b.try_into().expect("8 bytes")));
            }
        }
    }

    /// Every process's `mine`, on process 0, by rank (empty elsewhere).
    fn gather_to_root(&self, mine: Vec<u8>) -> Vec<Vec<u8>> {
        let mut outgoing = vec![Vec::new(); self.size()];
        outgoing[0] = mine;
        let all = self.all_to_all(outgoing);
        if self.rank() == 0 {
            all
        } else {
            Vec::new()
        }
    }

    /// Process 0's `bytes` on every process.
    fn broadcast_from_root(&self, bytes: Vec<u8>) -> Vec<u8> {
        let outgoing = if self.rank() == 0 {
            vec![bytes; self.size()]
        } else {
            vec![Vec::new(); self.size()]
        };
        self.all_to_all(outgoing).swap_remove(0)
    }

    /// Bytes and messages this process sent so far (diagnostics).
    fn traffic(&self) -> Traffic {
        Traffic::default()
    }

    /// Ends every process of the run at once with exit `code`: for an
    /// error on one process that the others, waiting in a collective,
    /// cannot learn of.
    fn abort(&self, code: i32) -> ! {
        std::process::exit(code)
    }
}

impl<C: Communicator + ?Sized> Communicator for &C {
    fn rank(&self) -> usize {
        (**self).rank()
    }
    fn size(&self) -> usize {
        (**self).size()
    }
    fn all_to_all(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        (**self).all_to_all(outgoing)
    }
    fn exchange(&self, sends: Vec<(usize, Vec<u8>)>, receives: &[(usize, usize)]) -> Vec<Vec<u8>> {
        (**self).exchange(sends, receives)
    }
    fn all_gather(&self, mine: Vec<u8>) -> Vec<Vec<u8>> {
        (**self).all_gather(mine)
    }
    fn sum_i64(&self, values: &mut [i64]) {
        (**self).sum_i64(values)
    }
    fn max_f64(&self, values: &mut [f64]) {
        (**self).max_f64(values)
    }
    fn gather_to_root(&self, mine: Vec<u8>) -> Vec<Vec<u8>> {
        (**self).gather_to_root(mine)
    }
    fn broadcast_from_root(&self, bytes: Vec<u8>) -> Vec<u8> {
        (**self).broadcast_from_root(bytes)
    }
    fn traffic(&self) -> Traffic {
        (**self).traffic()
    }
    fn abort(&self, code: i32) -> ! {
        (**self).abort(code)
    }
}

/// What a process sent: bytes and messages to other processes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Bytes sent to other processes.
    pub bytes: u64,
    /// Non-empty messages sent to other processes.
    pub messages: u64,
}

/// One process alone: every collective returns its own input.
#[derive(Debug, Clone, Copy, Default)]
pub struct SoloComm;

impl Communicator for SoloComm {
    fn rank(&self) -> usize {
        0
    }
    fn size(&self) -> usize {
        1
    }
    fn all_to_all(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        outgoing
    }
}

//! The collectives between threads of one process: `K` threads stand in
//! for `K` MPI processes, so that the decomposition's bitwise equality is
//! tested by `cargo test` without `mpirun` (the MPI tests then check the
//! transport).

use std::sync::{Arc, Barrier, Mutex};

use crate::comm::{Communicator, Traffic};

/// What the threads share: one mailbox per sender, and a barrier.
struct Shared {
    mail: Mutex<Vec<Vec<Vec<u8>>>>,
    barrier: Barrier,
}

/// One thread's end of an in-process group of `size` "processes".
pub struct ThreadComm {
    rank: usize,
    size: usize,
    shared: Arc<Shared>,
    traffic: Mutex<Traffic>,
}

impl ThreadComm {
    /// Runs `body` on `size` threads, each with its communicator, and
    /// returns their results by rank. A panic on one thread is re-raised.
    pub fn run<R: Send>(size: usize, body: impl Fn(ThreadComm) -> R + Sync) -> Vec<R> {
        let shared = Arc::new(Shared {
            mail: Mutex::new(vec![Vec::new(); size]),
            barrier: Barrier::new(size),
        });
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..size)
                .map(|rank| {
                    let comm = ThreadComm {
                        rank,
                        size,
                        shared: Arc::clone(&shared),
                        traffic: Mutex::new(Traffic::default()),
                    };
                    let body = &body;
                    scope.spawn(move || body(comm))
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                .collect()
        })
    }
}

impl Communicator for ThreadComm {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    fn all_to_all(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        assert_eq!(outgoing.len(), self.size, "one message per process");
        {
            let mut t = self.traffic.lock().expect("traffic");
            for (k, m) in outgoing.iter().enumerate() {
                if k != self.rank && !m.is_empty() {
                    t.bytes += m.len() as u64;
                    t.messages += 1;
                }
            }
        }
        self.shared.mail.lock().expect("mail")[self.rank] = outgoing;
        self.shared.barrier.wait();
        let incoming = {
            let mail = self.shared.mail.lock().expect("mail");
            mail.iter().map(|from| from[self.rank].clone()).collect()
        };
        self.shared.barrier.wait();
        incoming
    }

    fn traffic(&self) -> Traffic {
        *self.traffic.lock().expect("traffic")
    }
}

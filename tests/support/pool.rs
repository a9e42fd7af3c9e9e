//! Running a world's steps on a one-thread rayon pool, for tests.

/// Runs `f` on a one-thread rayon pool: stepping a world from outside a
/// pool hands every parallel loop to another thread (~0.1 ms per step).
pub fn pooled<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(f)
}

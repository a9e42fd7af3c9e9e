//! Runs the cases a few at a time and checks each.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use super::cases::Case;
use super::outcome::problems;
use super::report::Results;
use super::runner::execute;

/// Cases run at a time (each floe process uses one thread).
const WORKERS: usize = 2;

/// Runs the cases on `WORKERS` threads.
pub fn run_all(cases: &[&Case]) -> Results {
    let next = AtomicUsize::new(0);
    let results = Mutex::new(Results::default());
    std::thread::scope(|scope| {
        for _ in 0..WORKERS {
            scope.spawn(|| {
                while let Some(case) = cases.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let out = execute(case);
                    let found = problems(case, &out);
                    results.lock().unwrap().record(case, &out, &found);
                }
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.failures.sort_by_key(|f| f.index);
    results
}

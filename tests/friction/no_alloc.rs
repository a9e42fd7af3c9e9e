//! The per-contact update must not allocate: the DEM calls it for every
//! contact of every step. Counted per thread with a global allocator in this
//! test binary.
#![allow(unsafe_code)] // a counting global allocator needs `unsafe impl GlobalAlloc`

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use floe_friction::*;

struct Counting;

// Per thread: the test harness's own threads allocate while the test runs
// (a global count failed once with 4 allocations that were not the law's).
thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        System.realloc(ptr, layout, new_size)
    }
}

fn allocations() -> usize {
    ALLOCATIONS.with(|c| c.get())
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn contact_updates_do_not_allocate() {
    let laws = [
        Law::Amontons(Amontons { mu: 0.4 }),
        Law::RateDependent(RateDependent::lishman_2011(-0.072)),
        Law::RateState(RateState::new(
            RateStateParams::lishman_2011_lab(),
            Form::Published,
            StateLaw::Slip,
        )),
        Law::RateState(RateState::new(
            RateStateParams::lishman_2011_lab(),
            Form::Regularized,
            StateLaw::Aging,
        )),
    ];
    let velocities = [1e-4, 1e-3, 0.0, -1e-3, 1e-4];
    let before = allocations();
    let mut total = 0.0;
    for law in &laws {
        let mut state = law.steady_state(1e-4, 2e3);
        for &v in &velocities {
            let load = ContactLoad {
                load_point_velocity_m_per_s: v,
                stiffness_n_per_m: 2e7,
                normal_load_n: 2e3,
            };
            for _ in 0..2000 {
                total += law.step(&mut state, &load, 1e-3).mu;
            }
        }
    }
    let after = allocations();
    assert!(total.is_finite());
    assert_eq!(
        after - before,
        0,
        "allocations during 40 000 contact updates"
    );
}

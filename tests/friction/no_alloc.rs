//! The per-contact update must not allocate: the DEM calls it for every
//! contact of every step. Counted per thread by the test binary's global
//! allocator (`counting_allocator`).

use floe_friction::*;

use crate::counting_allocator::allocations;

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

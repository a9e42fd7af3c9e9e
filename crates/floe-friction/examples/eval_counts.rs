//! Residual evaluations per update in the benchmark's cases (docs/performance.md).
use floe_friction::*;
fn main() {
    for form in [Form::Published, Form::Regularized] {
        let law = Law::RateState(RateState::new(
            RateStateParams::lishman_2011_lab(),
            form,
            StateLaw::Slip,
        ));
        let load = |v| ContactLoad {
            load_point_velocity_m_per_s: v,
            stiffness_n_per_m: 20e6,
            normal_load_n: 2e3,
        };
        let mut s = law.steady_state(1e-4, 2e3);
        for _ in 0..10_000 {
            law.step(&mut s, &load(0.0), 1e-3);
        }
        let hold = law.step(&mut s.clone(), &load(0.0), 1e-3).iterations;
        let after_step = law
            .step(&mut law.steady_state(1e-4, 2e3), &load(1e-3), 1e-3)
            .iterations;
        println!("{form:?}: hold {hold}, first step after velocity step {after_step}");
    }
}

use floe_friction::experiments::*;
use floe_friction::*;
fn main() {
    for preset in [Preset::Lab, Preset::Tank] {
        for form in [Form::Published, Form::Regularized] {
            for sl in [StateLaw::Slip, StateLaw::Aging] {
                let law = Law::RateState(RateState::new(preset.params(), form, sl));
                let t = std::time::Instant::now();
                let r: Vec<_> = preset
                    .paper_hold_times_s()
                    .iter()
                    .map(|&h| hold_test(law, preset.apparatus(1e-3), preset.speed_m_per_s(), h))
                    .collect();
                println!("{preset:?} {form:?} {sl:?} ({:?})", t.elapsed());
                for h in r {
                    println!(
                        "  hold {:6} mu_ss {:.6} peak {:.6} dmu {:.6} min {:.4}",
                        h.hold_s, h.mu_ss, h.mu_peak, h.delta_mu, h.mu_min_hold
                    );
                }
            }
        }
    }
    let law = Law::RateState(RateState::new(
        Preset::Lab.params(),
        Form::Published,
        StateLaw::Slip,
    ));
    let mut ap = Preset::Lab.apparatus(1e-3);
    ap.stiffness_n_per_m = 1e12;
    println!("{:?}", velocity_step(law, ap, 1e-4, 1e-3));
    println!(
        "{:?}",
        velocity_step(law, Preset::Lab.apparatus(1e-3), 1e-4, 1e-3)
    );
}

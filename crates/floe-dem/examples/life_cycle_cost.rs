//! What the floe life cycle adds to a step (docs/performance.md, "The life
//! cycle's cost"):
//! `cargo run --release -p floe-dem --example life_cycle_cost -- N STEPS MODE`
//! steps the sheared channel of `N` diamonds (1 km sides, the channel of
//! `step_profile`) `STEPS` times through `Stepper::step` (the stages, then
//! ridging, welding and fracture) and prints the splits made, the contacts
//! and a fingerprint. `MODE`:
//! * `plain`: no life cycle;
//! * `check`: floe stress and the anchors' Mohr-Coulomb cone checked every
//!   step (no floe of the channel reaches it: the cost of watching);
//! * `break`: the cone at a compressive strength of `SIGMA_C` Pa (the 4th
//!   argument, default 10), low enough that floes break, the stress
//!   averaged over 1 s: the cost of the splits, less the watching, over
//!   the splits made;
//! * `bonded`: every contact bonded at once (cohesion, no bond breaking);
//! * `weld-watch`: `bonded` with welding checked after every step, every
//!   bond old enough and every hull computed, then refused by its area
//!   (at most 1 m^2): the most a welding check costs when nothing welds.
//!
//! Instructions are counted by running it under
//! `valgrind --tool=callgrind` at two step counts and taking the
//! difference (the set-up cancels).

use std::sync::atomic::AtomicBool;

use floe_dem::fracture::criteria::{FractureCriterion, MohrCoulomb};
use floe_dem::fracture::rule::{FractureRule, Fracturing, StrengthThickness};
use floe_dem::fracture::split::SplitRule;
use floe_dem::run::Stepper;
use floe_fixtures::channel as channel_pack;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let number = |i: usize, default: f64| {
        args.get(i)
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(default)
    };
    let n = number(1, 10_000.0) as usize;
    let steps = number(2, 20.0) as usize;
    let mode = args.get(3).map_or("plain", String::as_str);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    pool.install(|| {
        let mut w = channel_pack::sheared_channel(n);
        let sigma_c_pa = match mode {
            "plain" => None,
            "check" => Some(MohrCoulomb::default().sigma_c_pa),
            "break" => Some(number(4, 10.0)),
            "bonded" | "weld-watch" => None,
            other => panic!("mode {other}: plain, check, break, bonded or weld-watch"),
        };
        if mode == "bonded" || mode == "weld-watch" {
            w.set_cohesion(Some(floe_dem::cohesion::Cohesion {
                quiet_speed_m_per_s: 1e3,
                bond_after_s: 0.0,
                tensile_strength_n_per_m: 1e15,
                shear_strength_n_per_m: 1e15,
                growth_time_s: 0.0,
            }))
            .expect("cohesion");
        }
        if mode == "weld-watch" {
            w.set_welding(Some(floe_dem::welding::Welding {
                after_s: 0.0,
                max_area_m2: 1.0,
                check_every_s: 0.0,
                ..Default::default()
            }))
            .expect("welding");
        }
        if mode == "break" {
            // A short average, so that floes break within a few steps: the
            // cost of a split does not depend on it.
            w.set_stress_filter(Some(
                floe_dem::pipeline::floe_stress::StressFilter::new(1.0).expect("filter"),
            ));
        }
        if let Some(sigma_c_pa) = sigma_c_pa {
            let d = MohrCoulomb::default();
            let criterion = MohrCoulomb {
                sigma_c_pa,
                sigma_11_pa: d.sigma_11_pa / d.sigma_c_pa * sigma_c_pa,
                ..d
            };
            let f = w.floes();
            let area: f64 = f.area_m2.iter().sum();
            w.set_fracturing(Some(Fracturing {
                rule: FractureRule {
                    criterion: FractureCriterion::MohrCoulomb(criterion),
                    check_every_steps: 1,
                    min_floe_area_m2: 1e5,
                    split: SplitRule {
                        pieces: 2,
                        min_piece_area_m2: 2e4,
                        attempts: 10,
                    },
                    strength_thickness: StrengthThickness::Own,
                    seed: 1,
                },
                domain_area_m2: area,
            }))
            .expect("fracture");
        }
        let never = AtomicBool::new(false);
        let floes0 = w.floes().len();
        let mut splits = 0;
        for _ in 0..steps {
            let report = Stepper::step(&mut w, &never);
            assert!(report.blow_up.is_none(), "{:?}", report.blow_up);
            splits += report
                .fractures
                .iter()
                .filter(|e| !e.piece_ids.is_empty())
                .count();
        }
        println!(
            "{mode}: {} floes ({floes0} at the start), {} contacts, {} bonds, {splits} splits in {steps} steps of {:.3} s",
            w.floes().len(),
            w.contacts().len(),
            w.bonds().iter().filter(|b| b.formed).count(),
            w.dt_s()
        );
    });
}

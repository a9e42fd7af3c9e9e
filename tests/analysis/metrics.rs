//! floe-analysis metrics on constructed cases with known answers, and the
//! streaming slip-event detector against a brute-force recount.

use std::collections::BTreeMap;

use crate::proptest_settings;
use crate::union_support;
use floe_analysis::profile::{shear_band, velocity_profile};
use floe_analysis::slip_events::{log_histogram, SlipEvent, SlipEventDetector, SlipEventRule};
use floe_analysis::stress::{channel_stress, invariants, peak_to_steady};
use proptest::prelude::*;

/// `per_bin` evenly spaced samples in each of `bins` bins of [0, w): each
/// bin's mean position is its centre.
fn samples(w: f64, bins: usize, per_bin: usize) -> Vec<f64> {
    let n = bins * per_bin;
    (0..n).map(|j| (j as f64 + 0.5) * w / n as f64).collect()
}

#[test]
fn uniform_shear_spans_the_channel() {
    let (w, bins) = (25_000.0, 50);
    let y = samples(w, bins, 8);
    let u: Vec<f64> = y.iter().map(|y| 0.2 * y / w - 0.1).collect();
    let p = velocity_profile(&y, &u, &vec![1.0; y.len()], 0.0, w, bins).unwrap();
    assert_eq!(p.centre_m.len(), bins);
    let band = shear_band(&p).unwrap();
    let h = w / bins as f64;
    assert!(
        (band.equivalent_width_m - (w - h)).abs() < 1e-6 * w,
        "{band:?}"
    );
    assert!(
        (band.width_10_90_m - 0.8 * (w - h)).abs() < 1e-6 * w,
        "{band:?}"
    );
    assert!((band.peak_shear_rate_per_s - 0.2 / w).abs() < 1e-9 * 0.2 / w);
}

#[test]
fn tanh_band_has_width_two_delta() {
    let (w, bins) = (100_000.0, 400);
    let delta = w / 20.0;
    let y = samples(w, bins, 10);
    let u: Vec<f64> = y
        .iter()
        .map(|y| 0.3 * ((y - w / 2.0) / delta).tanh())
        .collect();
    let p = velocity_profile(&y, &u, &vec![1.0; y.len()], 0.0, w, bins).unwrap();
    let band = shear_band(&p).unwrap();
    // Bin averaging and finite differences err by O((h/δ)²) = O(0.04²).
    let rel = |got: f64, want: f64| (got - want).abs() / want;
    assert!(rel(band.equivalent_width_m, 2.0 * delta) < 2e-3, "{band:?}");
    assert!(
        rel(band.width_10_90_m, 2.0 * 0.8f64.atanh() * delta) < 2e-3,
        "{band:?}"
    );
    assert!((band.peak_at_m - w / 2.0).abs() <= w / bins as f64);
}

#[test]
fn profile_is_weighted_and_skips_empty_bins() {
    let p = velocity_profile(
        &[1.0, 1.5, 7.0, -1.0, 10.0],
        &[0.0, 4.0, 1.0, 99.0, 99.0],
        &[1.0, 3.0, 2.0, 1.0, 1.0],
        0.0,
        10.0,
        5,
    )
    .unwrap();
    // Bins of 2 m: [0,2) holds the first two, [6,8) the third; the rest empty;
    // y = -1 and y = 10 are outside [0, 10).
    assert_eq!(p.centre_m, vec![1.0, 7.0]);
    assert_eq!(p.velocity_m_per_s, vec![3.0, 1.0]);
    assert_eq!(p.weight, vec![4.0, 2.0]);
    assert!(velocity_profile(&[1.0], &[], &[], 0.0, 1.0, 1).is_err());
    assert!(velocity_profile(&[], &[], &[], 1.0, 1.0, 1).is_err());
    let flat = velocity_profile(&[0.5, 1.5], &[1.0, 1.0], &[1.0, 1.0], 0.0, 2.0, 2).unwrap();
    assert!(shear_band(&flat).is_err(), "no jump, no band");
}

/// A snapshot: its time and its (pair, slip rate) contacts, sorted by pair.
type Snapshot = (f64, Vec<([u32; 2], f64)>);
type History = Vec<Snapshot>;

/// Snapshot `k` of a constructed history: (pair, slip rate) sorted by pair.
fn history() -> History {
    (0..12)
        .map(|k| {
            let t = 10.0 * k as f64;
            let mut c = Vec::new();
            // Healed, then fails for snapshots 5..=7, then heals again.
            c.push(([1, 2], if (5..=7).contains(&k) { 1e-2 } else { 1e-6 }));
            // Slides steadily: never an event.
            c.push(([3, 4], 1e-2));
            // Appears already sliding at snapshot 4: not an event.
            if k >= 4 {
                c.push(([5, 6], 1e-2));
            }
            // Accelerates fivefold: below the jump factor.
            c.push(([7, 8], if k >= 6 { 5e-3 } else { 1e-3 }));
            // Fails at snapshot 9 and the contact breaks after snapshot 10.
            if k <= 10 {
                c.push(([9, 10], if k >= 9 { 2e-2 } else { 1e-5 }));
            }
            // Two periodic images of one pair: the faster one counts; jumps at 3..=3.
            let v = if k == 3 { 4e-3 } else { 1e-5 };
            c.push(([11, 12], 1e-7));
            c.push(([11, 12], v));
            (t, c)
        })
        .collect()
}

fn detect(rule: SlipEventRule, h: &[Snapshot]) -> Vec<SlipEvent> {
    let mut d = SlipEventDetector::new(rule).unwrap();
    for (t, c) in h {
        let pairs: Vec<[u32; 2]> = c.iter().map(|x| x.0).collect();
        let rates: Vec<f64> = c.iter().map(|x| x.1).collect();
        d.push(*t, &pairs, &rates).unwrap();
    }
    let mut e = d.finish();
    e.sort_by(|a, b| a.pair.cmp(&b.pair).then(a.start_s.total_cmp(&b.start_s)));
    e
}

#[test]
fn slip_events_in_a_constructed_history() {
    let events = detect(SlipEventRule::default(), &history());
    let summary: Vec<([u32; 2], f64, f64, f64)> = events
        .iter()
        .map(|e| (e.pair, e.start_s, e.end_s, e.slip_m))
        .collect();
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert_eq!(events.len(), 3, "{summary:?}");
    assert_eq!(events[0].pair, [1, 2]);
    assert!(close(events[0].start_s, 50.0) && close(events[0].end_s, 70.0));
    assert!(close(events[0].slip_m, 3.0 * 1e-2 * 10.0));
    assert_eq!(events[1].pair, [9, 10]);
    assert!(close(events[1].slip_m, 2.0 * 2e-2 * 10.0), "{summary:?}");
    assert_eq!(events[2].pair, [11, 12]);
    assert!(close(events[2].slip_m, 4e-3 * 10.0));
    assert!(close(events[2].peak_rate_m_per_s, 4e-3));
}

/// The rule applied directly to each pair's full rate history.
fn brute_force(rule: SlipEventRule, h: &[Snapshot]) -> Vec<SlipEvent> {
    let mut series: BTreeMap<[u32; 2], Vec<Option<f64>>> = BTreeMap::new();
    for (k, (_, c)) in h.iter().enumerate() {
        for &(p, v) in c {
            let s = series.entry(p).or_insert_with(|| vec![None; h.len()]);
            s[k] = Some(s[k].map_or(v.abs(), |old: f64| old.max(v.abs())));
        }
    }
    let mut events = Vec::new();
    for (pair, s) in series {
        let mut open: Option<SlipEvent> = None;
        for k in 0..h.len() {
            let (t, dt) = (h[k].0, if k > 0 { h[k].0 - h[k - 1].0 } else { 0.0 });
            match (open.take(), s[k]) {
                (Some(mut e), Some(v)) if v >= rule.min_rate_m_per_s => {
                    e.end_s = t;
                    e.slip_m += v * dt;
                    e.peak_rate_m_per_s = e.peak_rate_m_per_s.max(v);
                    open = Some(e);
                }
                (Some(e), _) => events.push(e),
                (None, Some(v)) => {
                    if let Some(prev) = k.checked_sub(1).and_then(|j| s[j]) {
                        if v >= rule.min_rate_m_per_s && v >= rule.jump_factor * prev {
                            open = Some(SlipEvent {
                                pair,
                                start_s: t,
                                end_s: t,
                                slip_m: v * dt,
                                peak_rate_m_per_s: v,
                            });
                        }
                    }
                }
                (None, None) => {}
            }
        }
        events.extend(open);
    }
    events
}

proptest! {
    #![proptest_config(proptest_settings::default())]
    #[test]
    fn detector_agrees_with_a_brute_force_recount(
        raw in prop::collection::vec(
            prop::collection::vec((0u32..6, 0u32..6, -7.0f64..-1.0), 0..25), 2..15),
        dts in prop::collection::vec(0.5f64..20.0, 15),
    ) {
        let mut t = 0.0;
        let h: History = raw
            .into_iter()
            .enumerate()
            .map(|(k, c)| {
                t += dts[k];
                let mut c: Vec<([u32; 2], f64)> =
                    c.into_iter().map(|(a, b, e)| ([a, b], 10f64.powf(e))).collect();
                c.sort_by_key(|x| x.0);
                (t, c)
            })
            .collect();
        let rule = SlipEventRule { jump_factor: 5.0, min_rate_m_per_s: 1e-4 };
        let mut want = brute_force(rule, &h);
        want.sort_by(|a, b| a.pair.cmp(&b.pair).then(a.start_s.total_cmp(&b.start_s)));
        prop_assert_eq!(detect(rule, &h), want);
    }
}

#[test]
fn detector_refuses_bad_input() {
    assert!(SlipEventDetector::new(SlipEventRule {
        jump_factor: 1.0,
        min_rate_m_per_s: 1.0
    })
    .is_err());
    let mut d = SlipEventDetector::new(SlipEventRule::default()).unwrap();
    assert!(
        d.push(0.0, &[[2, 3], [1, 2]], &[0.0, 0.0]).is_err(),
        "unsorted"
    );
    assert!(d.push(0.0, &[[1, 2]], &[]).is_err(), "lengths");
    d.push(1.0, &[], &[]).unwrap();
    assert!(d.push(1.0, &[], &[]).is_err(), "time must increase");
}

#[test]
fn log_histogram_counts_per_decade() {
    let h = log_histogram(&[1.5e-3, 2e-3, 5e-2, 0.9, 0.0, -1.0], 1);
    let counts: Vec<usize> = h.iter().map(|b| b.2).collect();
    assert_eq!(counts, vec![2, 1, 1]);
    assert!((h[0].0 - 1e-3).abs() < 1e-15 && (h[2].1 - 1.0).abs() < 1e-12);
    assert_eq!(
        log_histogram(&[1.5e-3, 2e-3, 5e-2, 0.9], 2)
            .iter()
            .map(|b| b.2)
            .sum::<usize>(),
        4
    );
    assert!(log_histogram(&[], 3).is_empty());
}

#[test]
fn peak_to_steady_of_an_exponential_overshoot() {
    // s(t) = s_ss (1 + a exp(-t/τ)): peak s_ss (1 + a) at t = 0, steady s_ss.
    let (s_ss, a, tau) = (-5e3, 0.8, 100.0);
    let t: Vec<f64> = (0..=2000).map(|k| k as f64).collect();
    let s: Vec<f64> = t
        .iter()
        .map(|t| s_ss * (1.0 + a * (-t / tau).exp()))
        .collect();
    let r = peak_to_steady(&t, &s, 0.25).unwrap();
    assert_eq!(r.peak_at_s, 0.0);
    assert!((r.ratio - (1.0 + a)).abs() < 1e-6, "{r:?}");
    assert!((r.steady - s_ss).abs() < 1e-6 * s_ss.abs());
    assert!(peak_to_steady(&t, &vec![0.0; t.len()], 0.5).is_err());
    assert!(peak_to_steady(&t, &s, 0.0).is_err());
}

#[test]
fn channel_components_of_a_simple_shear() {
    // Pure shear plus confinement: σxy = σyx = 2, σyy = -3 (compressive).
    let c = channel_stress([0.0, 2.0, 2.0, -3.0]);
    assert_eq!(c.shear_n_per_m, 2.0);
    assert_eq!(c.normal_n_per_m, 3.0);
    let i = invariants([-1.0, 0.0, 0.0, -3.0]);
    assert_eq!(i.pressure_n_per_m, 2.0);
    assert_eq!(i.max_shear_n_per_m, 1.0);
}

proptest! {
    #![proptest_config(proptest_settings::default())]
    #[test]
    fn invariants_do_not_depend_on_the_frame(
        xx in -1e5f64..1e5, xy in -1e5f64..1e5, yy in -1e5f64..1e5, angle in 0.0f64..6.3,
    ) {
        let (c, s) = (angle.cos(), angle.sin());
        // σ' = R σ Rᵀ for a symmetric σ.
        let rxx = c * c * xx + 2.0 * c * s * xy + s * s * yy;
        let ryy = s * s * xx - 2.0 * c * s * xy + c * c * yy;
        let rxy = (c * c - s * s) * xy + c * s * (yy - xx);
        let (a, b) = (invariants([xx, xy, xy, yy]), invariants([rxx, rxy, rxy, ryy]));
        let tol = 1e-9 * (xx.abs() + xy.abs() + yy.abs() + 1.0);
        prop_assert!((a.pressure_n_per_m - b.pressure_n_per_m).abs() < tol);
        prop_assert!((a.max_shear_n_per_m - b.max_shear_n_per_m).abs() < tol);
    }
}

#[test]
fn restart_response_of_a_constructed_overshoot() {
    // Steady at -2 kN/m, nothing during the pause [3600, 7200), then
    // s = -2 (1 + a (u/τ) exp(1 - u/τ)) with u = t - 7200: peak -2 (1 + a) at u = τ.
    let (a, tau) = (0.6, 600.0);
    let t: Vec<f64> = (0..=14400).step_by(10).map(f64::from).collect();
    let s: Vec<f64> = t
        .iter()
        .map(|&t| {
            if t < 3600.0 {
                -2e3
            } else if t < 7200.0 {
                0.0
            } else {
                let u = (t - 7200.0) / tau;
                -2e3 * (1.0 + a * u * (1.0 - u).exp())
            }
        })
        .collect();
    let r = floe_analysis::stress::restart_response(&t, &s, 3600.0, 7200.0, 3600.0).unwrap();
    assert!((r.before - 2e3).abs() < 1e-9);
    assert!((r.ratio - (1.0 + a)).abs() < 1e-9, "{r:?}");
    assert_eq!(r.peak_delay_s, tau);
    assert!(floe_analysis::stress::restart_response(&t, &s, 3600.0, 7200.0, 0.0).is_err());
    assert!(floe_analysis::stress::restart_response(&t, &s, 7200.0, 3600.0, 10.0).is_err());
}

/// A square floe of side `s` centred at `(x, y)`.
fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
    let h = 0.5 * s;
    vec![
        [x - h, y - h],
        [x + h, y - h],
        [x + h, y + h],
        [x - h, y + h],
    ]
}

#[test]
fn a_floe_squeezed_and_sheared_between_two_walls() {
    use floe_analysis::love_weber::ContactForces;
    use floe_analysis::rheology::{cell_sample, CellSnapshot};
    // One free 400 m square between a bottom wall (touching at y = 0) and a
    // top wall (at y = 400), in a cell 2 km long. The bottom wall pushes it
    // up with 3 MN and drags it along +x with 1 MN; the top wall the
    // reverse: P = 3e6 / 2000 = 1500 N/m, tau = 1e6 / 2000 = 500 N/m, and
    // the Love-Weber sum over the free floe must give the same.
    let length = 2000.0;
    let position = [[1000.0, -300.0], [1000.0, 200.0], [1000.0, 700.0]];
    let velocity = [[0.0, 0.0], [0.25, 0.0], [0.5, 0.0]];
    let area = [2000.0 * 600.0, 400.0 * 400.0, 2000.0 * 600.0];
    let mass = [1e9, 1.5e8, 1e9];
    let prescribed = [true, false, true];
    let vertices = [
        vec![[0.0, -600.0], [2000.0, -600.0], [2000.0, 0.0], [0.0, 0.0]],
        square(1000.0, 200.0, 400.0),
        vec![
            [0.0, 400.0],
            [2000.0, 400.0],
            [2000.0, 1000.0],
            [0.0, 1000.0],
        ],
    ];
    // Forces on b are `n F_n + perp(n) F_t` with perp(n) = (-n_y, n_x) =
    // (-1, 0). Contact 0: a = bottom wall, b = floe; on the floe
    // (-1e6, 3e6). Contact 1: a = floe, b = top wall; on the wall
    // (-1e6, 3e6), the ice holding it back. Its point is given at the
    // periodic image x + L of x = 950 m.
    let pair = [[0, 1], [1, 2]];
    let point = [[1000.0, 0.0], [950.0 + length, 400.0]];
    let normal = [[0.0, 1.0], [0.0, 1.0]];
    let tangential_force = [1e6, 1e6];
    // The snapshot with the contacts' normal forces `normal_force`.
    let sample = |normal_force: &[f64]| {
        cell_sample(&CellSnapshot {
            period_x_m: length,
            position: &position,
            velocity: &velocity,
            area_m2: &area,
            mass_kg: &mass,
            prescribed: &prescribed,
            vertices: &vertices,
            contacts: ContactForces {
                pair: &pair,
                point: &point,
                normal: &normal,
                normal_force_n: normal_force,
                tangential_force_n: &tangential_force,
            },
        })
        .unwrap()
    };
    let s = sample(&[3e6, 3e6]);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1.0);
    assert!(close(s.height_m, 400.0), "{s:?}");
    assert!(close(s.wall_normal_stress_n_per_m, 1500.0), "{s:?}");
    assert!(close(s.wall_shear_stress_n_per_m, 500.0), "{s:?}");
    assert!(close(s.bulk_normal_stress_n_per_m(), 1500.0), "{s:?}");
    // sigma_xy = (1/LH) sum f_x arm_y = (-1e6 * -200 + 1e6 * 200) / (2000 * 400)
    // = 500; sigma_yx = f_y arm_x: the top contact's -3e6 at -50 m (its
    // image brought back), 187.5 (the constructed floe feels a net torque,
    // so the two differ).
    let c = s.contact_stress_n_per_m;
    assert!(close(c[1], 500.0), "{c:?}");
    assert!(close(c[2], 187.5), "{c:?}");
    assert!(
        close(s.bulk_shear_stress_n_per_m(), 0.5 * (500.0 + 187.5)),
        "{s:?}"
    );
    // The floe's middle half (y from 100 to 300) is 400 m of a 2 km strip:
    // solid fraction 0.2.
    assert!(close(s.solid_fraction, 0.2), "{s:?}");
    assert!(close(s.wall_shear_rate_per_s, 0.5 / 400.0), "{s:?}");
    assert!(close(s.floe_size_m, 400.0), "{s:?}");
    let [bottom, top] = s.wall_normal_stress_bottom_top_n_per_m;
    assert!(close(bottom, 1500.0) && close(top, 1500.0), "{s:?}");
    // The bottom wall pushing harder (4 MN: the floe accelerating upwards,
    // as a dilating layer's middle does): each wall's own stress, and their
    // mean on the walls.
    let s = sample(&[4e6, 3e6]);
    let [bottom, top] = s.wall_normal_stress_bottom_top_n_per_m;
    assert!(close(bottom, 2000.0) && close(top, 1500.0), "{s:?}");
    assert!(close(s.wall_normal_stress_n_per_m, 1750.0), "{s:?}");
}

#[test]
fn mu_of_i_fit_recovers_the_curve_it_was_sampled_from() {
    use floe_analysis::rheology::{fit_mu_of_i, MuOfI};
    for truth in [
        MuOfI {
            mu_s: 0.38,
            mu_2: 0.64,
            i_0: 0.279,
            rms_residual: 0.0,
            resolved: true,
        },
        // Weakening with I, as a velocity-weakening contact law may give.
        MuOfI {
            mu_s: 0.55,
            mu_2: 0.30,
            i_0: 3e-3,
            rms_residual: 0.0,
            resolved: true,
        },
    ] {
        let i: Vec<f64> = (0..9)
            .map(|k| truth.i_0 * 10f64.powf(-2.0 + 0.5 * k as f64))
            .collect();
        let mu: Vec<f64> = i.iter().map(|&x| truth.mu(x)).collect();
        let fit = fit_mu_of_i(&i, &mu).unwrap();
        assert!((fit.mu_s - truth.mu_s).abs() < 1e-6, "{fit:?}");
        assert!((fit.mu_2 - truth.mu_2).abs() < 1e-6, "{fit:?}");
        assert!((fit.i_0 / truth.i_0 - 1.0).abs() < 1e-5, "{fit:?}");
        assert!(fit.rms_residual < 1e-8, "{fit:?}");
        assert!(fit.resolved, "{fit:?}");
    }
    // A flat friction shows no transition: the fit says so.
    let flat = fit_mu_of_i(&[1e-3, 1e-2, 1e-1, 1.0], &[0.42, 0.43, 0.42, 0.43]).unwrap();
    assert!(!flat.resolved, "{flat:?}");
    assert!(fit_mu_of_i(&[0.1, 0.1, 0.1], &[0.3, 0.4, 0.5]).is_err());
    assert!(fit_mu_of_i(&[0.1, -0.2, 0.3], &[0.3, 0.4, 0.5]).is_err());
    assert!(fit_mu_of_i(&[0.1, 0.2], &[0.3, 0.4]).is_err());
}

/// A pack that speeds up over 10 min, then stops: kinetic energy decaying
/// as exp(-t/tau) after its peak, dissipation saturating.
#[test]
fn a_decaying_pack_is_jammed_and_a_steady_one_is_not() {
    use floe_analysis::jam::{jam_state, JamRule};
    let (tau, peak_t, end) = (600.0, 600.0, 21_600.0);
    let time: Vec<f64> = (0..=720).map(|k| k as f64 * 30.0).collect();
    assert_eq!(*time.last().unwrap(), end);
    let ke: Vec<f64> = time
        .iter()
        .map(|&t| {
            if t <= peak_t {
                1e9 * t / peak_t
            } else {
                1e9 * (-(t - peak_t) / tau).exp()
            }
        })
        .collect();
    // Dissipation rate proportional to the energy: cumulative, exact.
    let diss: Vec<f64> = time
        .iter()
        .map(|&t| {
            if t <= peak_t {
                0.5 * t * t / peak_t
            } else {
                0.5 * peak_t + tau * (1.0 - (-(t - peak_t) / tau).exp())
            }
        })
        .collect();
    let rule = JamRule::default();
    let s = jam_state(&time, &ke, &diss, 1e-5, 0.16, &rule).unwrap();
    assert!(s.jammed, "{s:?}");
    assert_eq!(s.peak_kinetic_j, 1e9);
    assert!(s.kinetic_ratio < 1e-10, "{s:?}");
    // exp(-(t - 600)/600) < 0.01 from t = 600 + 600 ln 100 = 3363 s: the
    // first sample after, 3390 s.
    assert_eq!(s.below_since_s, Some(3390.0));
    assert!(s.dissipation_rate_ratio < 1e-10, "{s:?}");
    // Moving floes at the end: not jammed, whatever the energy says.
    let moving = jam_state(&time, &ke, &diss, 0.01, 0.16, &rule).unwrap();
    assert!(!moving.jammed);
    assert!((moving.speed_ratio - 0.0625).abs() < 1e-12);

    // Steady flow after the ramp: energy at its peak, dissipation linear.
    let ke: Vec<f64> = time.iter().map(|&t| 1e9 * (t / peak_t).min(1.0)).collect();
    let diss: Vec<f64> = time.iter().map(|&t| 2.0 * t).collect();
    let s = jam_state(&time, &ke, &diss, 0.1, 0.16, &rule).unwrap();
    assert!(!s.jammed);
    assert_eq!(s.kinetic_ratio, 1.0);
    assert_eq!(s.below_since_s, None);
    assert!((s.dissipation_rate_ratio - 1.0).abs() < 1e-12, "{s:?}");
}

#[test]
fn jam_state_refuses_bad_input() {
    use floe_analysis::jam::{jam_state, JamRule};
    use floe_analysis::AnalysisError;
    let t = [0.0, 1.0, 2.0];
    let rule = JamRule::default();
    assert!(matches!(
        jam_state(&t, &[1.0, 2.0], &[0.0; 3], 0.0, 1.0, &rule),
        Err(AnalysisError::LengthMismatch { .. })
    ));
    assert!(matches!(
        jam_state(&t, &[1.0; 3], &[0.0; 3], 0.0, 0.0, &rule),
        Err(AnalysisError::InvalidParameter { .. })
    ));
    let wide = JamRule {
        final_fraction: 1.5,
        ..rule
    };
    assert!(matches!(
        jam_state(&t, &[1.0; 3], &[0.0; 3], 0.0, 1.0, &wide),
        Err(AnalysisError::InvalidParameter { .. })
    ));
    assert!(matches!(
        jam_state(&t, &[0.0; 3], &[0.0; 3], 0.0, 1.0, &rule),
        Err(AnalysisError::NotEnoughData(_))
    ));
}

/// Squares of side `side` on a lattice turned by `angle` (they tile the
/// plane), centred at `offset + m e1 + n e2`, covering `[-margin, extent + margin]^2`.
fn tiled_squares(side: f64, angle: f64, offset: [f64; 2], extent: f64) -> Vec<Vec<[f64; 2]>> {
    let (s, c) = angle.sin_cos();
    let (e1, e2) = ([side * c, side * s], [-side * s, side * c]);
    let reach = (2.0 * extent / side) as i64 + 4;
    let mut out = Vec::new();
    for m in -reach..=reach {
        for n in -reach..=reach {
            let x = [
                offset[0] + m as f64 * e1[0] + n as f64 * e2[0],
                offset[1] + m as f64 * e1[1] + n as f64 * e2[1],
            ];
            if x[0] < -2.0 * side
                || x[1] < -2.0 * side
                || x[0] > extent + 2.0 * side
                || x[1] > extent + 2.0 * side
            {
                continue;
            }
            let corner = |a: f64, b: f64| {
                [
                    x[0] + 0.5 * (a * e1[0] + b * e2[0]),
                    x[1] + 0.5 * (a * e1[1] + b * e2[1]),
                ]
            };
            out.push(vec![
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ]);
        }
    }
    out
}

fn centroid(poly: &[[f64; 2]]) -> [f64; 2] {
    let n = poly.len() as f64;
    [
        poly.iter().map(|p| p[0]).sum::<f64>() / n,
        poly.iter().map(|p| p[1]).sum::<f64>() / n,
    ]
}

/// Grid fields of `polys` with velocities from `field(centroid)` and spin `spin`.
fn fields_of(
    grid: &floe_analysis::grid_fields::Grid,
    polys: &[Vec<[f64; 2]>],
    field: impl Fn([f64; 2]) -> [f64; 2],
    spin: f64,
) -> floe_analysis::grid_fields::GridFields {
    use floe_analysis::grid_fields::{grid_fields, FloeSnapshot};
    let position: Vec<[f64; 2]> = polys.iter().map(|p| centroid(p)).collect();
    let velocity: Vec<[f64; 2]> = position.iter().map(|&x| field(x)).collect();
    let spin = vec![spin; polys.len()];
    let thickness = vec![1.5; polys.len()];
    grid_fields(
        grid,
        &FloeSnapshot {
            vertices: polys,
            position: &position,
            velocity: &velocity,
            angular_velocity: &spin,
            thickness_m: &thickness,
            stress_moment_n_m: None,
        },
    )
    .unwrap()
}

#[test]
fn gridded_concentration_integrates_to_the_ice_area_and_stress_is_conserved() {
    use floe_analysis::grid_fields::{grid_fields, FloeSnapshot, Grid};
    // Pentagons of several sizes and turns at scattered places inside a
    // 10 km grid of 1 km cells, overlapping in pairs, triples and more.
    let grid = Grid {
        origin_m: [0.0, 0.0],
        cell_m: [1000.0, 1250.0],
        shape: [10, 8],
    };
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut polys = Vec::new();
    for _ in 0..60 {
        let (r, turn) = (100.0 + 600.0 * next(), 6.3 * next());
        let c = [
            r + (10000.0 - 2.0 * r) * next(),
            r + (10000.0 - 2.0 * r) * next(),
        ];
        polys.push(
            (0..5)
                .map(|k| {
                    let a = turn + k as f64 * std::f64::consts::TAU / 5.0;
                    [c[0] + r * a.cos(), c[1] + r * a.sin()]
                })
                .collect::<Vec<_>>(),
        );
    }
    let shoelace = |p: &[[f64; 2]]| {
        0.5 * (0..p.len())
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % p.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
            .abs()
    };
    let floes_area: f64 = polys.iter().map(|p| shoelace(p)).sum();
    // The ice is the union: the floes' area minus their overlaps'.
    let ice = union_support::union_area(&polys);
    assert!(ice < 0.95 * floes_area, "the pentagons overlap");
    let position: Vec<[f64; 2]> = polys.iter().map(|p| centroid(p)).collect();
    let zeros2 = vec![[0.0; 2]; polys.len()];
    let moments: Vec<[f64; 4]> = (0..polys.len())
        .map(|k| [-1e9 * (k + 1) as f64, 2e8, 2e8, -3e9])
        .collect();
    let f = grid_fields(
        &grid,
        &FloeSnapshot {
            vertices: &polys,
            position: &position,
            velocity: &zeros2,
            angular_velocity: &vec![0.0; polys.len()],
            thickness_m: &vec![2.0; polys.len()],
            stress_moment_n_m: Some(&moments),
        },
    )
    .unwrap();
    let cell = 1000.0 * 1250.0;
    let integral: f64 = f.concentration.iter().sum::<f64>() * cell;
    assert!(
        (integral - ice).abs() < 1e-12 * ice,
        "{integral} against {ice}"
    );
    // Each cell's ice is the union of the floes' parts in it.
    for j in 0..8 {
        for i in 0..10 {
            let lo = [1000.0 * i as f64, 1250.0 * j as f64];
            let part =
                union_support::union_area_in_box(&polys, lo, [lo[0] + 1000.0, lo[1] + 1250.0]);
            let c = f.concentration[grid.index(i, j)];
            assert!(
                (c - part / cell).abs() < 1e-12,
                "cell ({i}, {j}): {c} against {}",
                part / cell
            );
        }
    }
    for k in 0..4 {
        let total: f64 = f.stress_n_per_m.iter().map(|s| s[k]).sum::<f64>() * cell;
        let expected: f64 = moments.iter().map(|m| m[k]).sum();
        assert!(
            (total - expected).abs() < 1e-9 * expected.abs(),
            "{k}: {total} {expected}"
        );
    }
    // The volume is every floe's own: ice of one thickness is that thick
    // where floes do not overlap, and thicker where they do.
    let mut volume = 0.0;
    for (c, h) in f.concentration.iter().zip(&f.thickness_m) {
        if *c > 0.0 {
            assert!(*h >= 2.0 * (1.0 - 1e-12), "{h}");
            volume += c * h * cell;
        } else {
            assert!(h.is_nan());
        }
    }
    assert!(
        (volume - 2.0 * floes_area).abs() < 1e-12 * volume,
        "{volume}"
    );
    // Floes partly outside the grid: only the part inside counts.
    let half_out = vec![vec![
        [-500.0, 0.0],
        [500.0, 0.0],
        [500.0, 1000.0],
        [-500.0, 1000.0],
    ]];
    let f = fields_of(&grid, &half_out, |_| [0.0, 0.0], 0.0);
    assert!((f.concentration.iter().sum::<f64>() * cell - 5e5).abs() < 1e-6);
}

#[test]
fn a_uniform_expansion_has_its_divergence_and_a_rigid_rotation_no_deformation() {
    use floe_analysis::grid_fields::Grid;
    let grid = Grid {
        origin_m: [0.0, 0.0],
        cell_m: [1000.0, 1000.0],
        shape: [8, 8],
    };
    let a = 1e-6; // 1/s: v = a x, divergence 2a, no shear
                  // Square floes one per cell, and shifted by half a cell.
    for offset in [[500.0, 500.0], [0.0, 0.0]] {
        let polys = tiled_squares(1000.0, 0.0, offset, 8000.0);
        let f = fields_of(&grid, &polys, |x| [a * x[0], a * x[1]], 0.0);
        for k in 0..grid.len() {
            assert!((f.concentration[k] - 1.0).abs() < 1e-12);
            assert!(
                (f.divergence_per_s[k] - 2.0 * a).abs() < 1e-12 * a,
                "{k}: {}",
                f.divergence_per_s[k]
            );
            assert!(f.shear_per_s[k] < 1e-9 * a, "{k}: {}", f.shear_per_s[k]);
        }
    }
    // A pack turning as one body (each floe with the body's spin), on a
    // lattice turned 30 degrees against the grid: no deformation anywhere.
    let w = 2e-6;
    let polys = tiled_squares(700.0, 0.52, [123.0, -45.0], 8000.0);
    let centre = [4000.0, 4000.0];
    let f = fields_of(
        &grid,
        &polys,
        |x| [-w * (x[1] - centre[1]), w * (x[0] - centre[0])],
        w,
    );
    for k in 0..grid.len() {
        assert!((f.concentration[k] - 1.0).abs() < 1e-9);
        assert!(
            f.total_deformation_per_s[k] < 1e-9 * w,
            "{k}: {}",
            f.total_deformation_per_s[k]
        );
    }
    // The same floes in pure shear v = (g y, 0): divergence 0, shear g.
    let g = 3e-6;
    let f = fields_of(
        &grid,
        &tiled_squares(1000.0, 0.0, [500.0, 500.0], 8000.0),
        |x| [g * x[1], 0.0],
        0.0,
    );
    for k in 0..grid.len() {
        assert!(f.divergence_per_s[k].abs() < 1e-12 * g);
        assert!((f.shear_per_s[k] - g).abs() < 1e-12 * g);
    }
    // Cells without ice have no velocity.
    let one = vec![vec![[0.0, 0.0], [900.0, 0.0], [900.0, 900.0], [0.0, 900.0]]];
    let f = fields_of(&grid, &one, |_| [0.1, 0.0], 0.0);
    assert_eq!(f.velocity[0], [0.1, 0.0]);
    assert!(f.velocity[1][0].is_nan() && f.divergence_per_s[0].is_nan());
}

#[test]
fn grid_fields_refuse_bad_input() {
    use floe_analysis::grid_fields::{grid_fields, FloeSnapshot, Grid};
    let poly = vec![vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
    let snap = FloeSnapshot {
        vertices: &poly,
        position: &[[0.3, 0.3]],
        velocity: &[],
        angular_velocity: &[0.0],
        thickness_m: &[1.0],
        stress_moment_n_m: None,
    };
    let grid = Grid {
        origin_m: [0.0, 0.0],
        cell_m: [1.0, 1.0],
        shape: [2, 2],
    };
    assert!(grid_fields(&grid, &snap).is_err());
    let snap = FloeSnapshot {
        velocity: &[[0.0, 0.0]],
        ..snap
    };
    assert!(grid_fields(&grid, &snap).is_ok());
    let bad = Grid {
        cell_m: [0.0, 1.0],
        ..grid
    };
    assert!(grid_fields(&bad, &snap).is_err());
    let empty = Grid {
        shape: [0, 3],
        ..grid
    };
    assert!(grid_fields(&empty, &snap).is_err());
}

//! Fracture in the world (`World::fracture`): a square floe squeezed
//! between closing walls breaks at the first check after its averaged
//! stress crosses the criterion's uniaxial compressive strength, under
//! Mohr-Coulomb and under Hibler; its pieces keep its mass and momentum
//! and take new ids; small floes and floes without stress are left alone.

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{Floes, Motion};
use floe_dem::forcing::NoForcing;
use floe_dem::fracture::criteria::{FractureCriterion, HiblerEllipse, MohrCoulomb};
use floe_dem::fracture::rule::{FractureRule, StrengthThickness};
use floe_dem::fracture::split::SplitRule;
use floe_dem::periodicity::Periodicity;
use floe_dem::pipeline::floe_stress::{principal, StressFilter};
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;

const SIDE_M: f64 = 100.0;

fn rect(x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<Vec2> {
    [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        .map(|(x, y)| Vec2::new(x, y))
        .to_vec()
}

/// A free 100 m square, 1 m thick, between two walls closing on it at
/// 2 cm/s each (just touching at the start); stress averaged over 2 s.
fn closing_walls() -> World<NoForcing> {
    let h = 0.5 * SIDE_M;
    let polys = [
        rect(-h - 100.0, -h, -2.0 * h, 2.0 * h),
        rect(-h, h, -h, h),
        rect(h, h + 100.0, -2.0 * h, 2.0 * h),
    ];
    let mut floes = Floes::from_polygons(&polys, &[1.0; 3], 917.0).unwrap();
    for (wall, vx) in [(0, 0.02), (2, -0.02)] {
        floes.set_motion(
            wall,
            Motion::Prescribed {
                velocity: Vec2::new(vx, 0.0),
            },
        );
    }
    let model = ContactModel::default();
    // Room for pieces a fifth of the square.
    let dt = 0.2 * stable_time_step(&floes, &model).0;
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    w.set_stress_filter(Some(StressFilter::new(2.0).unwrap()));
    w
}

fn rule(criterion: FractureCriterion, check_every_steps: u64) -> FractureRule {
    FractureRule {
        criterion,
        check_every_steps,
        min_floe_area_m2: 1000.0,
        split: SplitRule {
            pieces: 3,
            min_piece_area_m2: 0.05 * SIDE_M * SIDE_M,
            attempts: 10,
        },
        strength_thickness: StrengthThickness::Own,
        seed: 4,
    }
}

/// The uniaxial compressive strength of `criterion` for a 1 m floe, Pa:
/// where `(0, -S)` leaves it, by bisection.
fn uniaxial_strength(criterion: &FractureCriterion) -> f64 {
    let (mut lo, mut hi) = (0.0, 1e7);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if criterion.breaks((0.0, -mid), 1.0, 1.0) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

#[test]
fn a_squeezed_floe_breaks_at_the_first_check_past_its_uniaxial_strength() {
    let hibler = HiblerEllipse {
        p_star_pa_per_m: 1.0e5,
        c: 20.0,
    };
    for (criterion, strength) in [
        (
            FractureCriterion::MohrCoulomb(MohrCoulomb::default()),
            40.75e3,
        ),
        // Hibler: 2P/5 in uniaxial compression.
        (FractureCriterion::Hibler(hibler), 0.4 * 1.0e5),
    ] {
        let s = uniaxial_strength(&criterion);
        assert!(
            (s - strength).abs() < 0.01 * strength,
            "{s} against {strength}"
        );
        let mut w = closing_walls();
        let every = 4;
        let rule = rule(criterion, every);
        let mut before = (0.0, 0.0);
        let events = loop {
            w.step();
            let now = principal(w.floe_stress()[1]);
            let events = w.fracture(&rule, 1e6).unwrap();
            if !events.is_empty() {
                break events;
            }
            if rule.due(w.steps()) {
                before = now;
            }
            assert!(w.time_s() < 3600.0, "no fracture in an hour");
        };
        let e = &events[0];
        assert_eq!(events.len(), 1, "only the free floe");
        assert_eq!(e.parent_id, 1);
        assert!(e.step.is_multiple_of(every));
        // Inside at the previous check, outside at this one: the filtered
        // stress crossed the strength within one check interval.
        let (s1, s2) = e.principal_pa;
        assert!(-before.1 <= s && -s2 > s, "{before:?} then {s2} across {s}");
        assert!(s1.abs() < 0.01 * s, "uniaxial: {s1}");
        assert_eq!(e.piece_ids, vec![3, 4, 5], "new ids after the largest, 2");
        assert!(e.whole_because.is_none());
        assert_eq!(w.state().next_floe_id, 6);
        let f = w.floes();
        assert_eq!(f.len(), 5);
        let pieces: Vec<usize> = [3, 4, 5].map(|id| f.handle_of(id).unwrap()).to_vec();
        let mass: f64 = pieces.iter().map(|&i| f.mass_kg[i]).sum();
        assert!((mass - 917.0 * SIDE_M * SIDE_M).abs() < 1e-9 * mass);
        // The pieces start unstressed; the walls keep pressing.
        assert!(pieces.iter().all(|&i| w.floe_stress()[i] == [0.0; 3]));
        w.step();
        assert!(w.contacts().len() >= 2);
    }
}

#[test]
fn small_floes_and_off_cycle_steps_do_not_break_and_stress_must_be_on() {
    let mut w = closing_walls();
    let mut r = rule(FractureCriterion::MohrCoulomb(MohrCoulomb::default()), 1);
    r.min_floe_area_m2 = 2.0 * SIDE_M * SIDE_M;
    for _ in 0..4000 {
        w.step();
        assert!(w.fracture(&r, 1e6).unwrap().is_empty());
    }
    let s = principal(w.floe_stress()[1]);
    assert!(-s.1 > 1e5, "well past its strength: {s:?}");
    // The same floe, large enough, breaks at a due step only.
    r.min_floe_area_m2 = 0.0;
    r.check_every_steps = 1000;
    w.step();
    assert!(!r.due(w.steps()));
    assert!(w.fracture(&r, 1e6).unwrap().is_empty());
    let mut off = closing_walls();
    off.set_stress_filter(None);
    let e = off.fracture(&r, 1e6).expect_err("needs stress");
    assert!(e.to_string().contains("floe stress"), "{e}");
    // A rule that cannot be used is refused by its check.
    let mut bad = r;
    bad.check_every_steps = 0;
    assert!(bad.check().is_err());
    bad = r;
    bad.split.pieces = 1;
    assert!(bad.check().is_err());
    assert!(r.check().is_ok());
}

#[test]
fn hiblers_pack_strength_uses_the_packs_thickness_and_concentration() {
    let hibler = FractureCriterion::Hibler(HiblerEllipse {
        p_star_pa_per_m: 1.0e5,
        c: 20.0,
    });
    let first_break = |thickness: StrengthThickness, domain_area_m2: f64| {
        let mut w = closing_walls();
        let r = FractureRule {
            strength_thickness: thickness,
            ..rule(hibler, 4)
        };
        loop {
            w.step();
            if let Some(e) = w.fracture(&r, domain_area_m2).unwrap().first() {
                return e.step;
            }
        }
    };
    // One free floe 1 m thick filling the domain: the pack's mean is its own.
    let own = first_break(StrengthThickness::Own, 1e6);
    assert_eq!(first_break(StrengthThickness::Pack, SIDE_M * SIDE_M), own);
    // At concentration 0.8, P is e^-4 of it: the floe breaks far sooner.
    let loose = first_break(StrengthThickness::Pack, SIDE_M * SIDE_M / 0.8);
    assert!(loose < own / 3, "{loose} against {own}");
}

#[test]
fn a_run_that_fractured_resumes_bitwise() {
    let r = rule(FractureCriterion::MohrCoulomb(MohrCoulomb::default()), 4);
    let broken = || {
        let mut w = closing_walls();
        loop {
            w.step();
            if !w.fracture(&r, 1e6).unwrap().is_empty() {
                return w;
            }
        }
    };
    let (state, model, forcing, periodicity) = broken().into_parts();
    assert_eq!(state.next_floe_id, 6);
    let mut resumed = World::resume(state, model, forcing, periodicity).unwrap();
    let mut straight = broken();
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..3000 {
        resumed.step();
        straight.step();
        a.extend(resumed.fracture(&r, 1e6).unwrap());
        b.extend(straight.fracture(&r, 1e6).unwrap());
    }
    assert!(!a.is_empty(), "the pieces break in turn");
    assert!(
        a.iter().all(|e| e.piece_ids.iter().all(|&id| id >= 6)),
        "no id reused"
    );
    assert_eq!(a, b);
    assert_eq!(
        format!("{:?}", resumed.state()),
        format!("{:?}", straight.state())
    );
}

//! A friction law defined outside floe-friction (the `custom_law` example
//! of floe-scenario: linear slip weakening), registered, read from a
//! scenario file and run in the DEM: the block of the double shear weakens
//! as the law says, and scenarios without the registration refuse the law.

use crate::custom_law_example as custom_law;

use std::path::Path;

use floe_friction::FrictionLaw;
use floe_scenario::Scenario;

/// The law runs in the DEM as it says. Friction on the block's faces is
/// `mu(D)` of the slip `D` the law accumulated (its one state slot, carried
/// from step to step): from `mu_static` through the weakening to
/// `mu_dynamic`. The faces' slip trails the block's travel by the stretch
/// of their tangential springs only (tens of micrometres at 1 kN), and
/// never leads it.
#[test]
fn a_registered_law_runs_in_the_dem_as_it_says() {
    let mut w = custom_law::world();
    assert_eq!(w.model().law.name(), "slip-weakening");
    assert_eq!(w.model().law.state_slots(), 1);
    let law = custom_law::SlipWeakening {
        mu_static: 0.8,
        mu_dynamic: 0.5,
        critical_slip_m: 2e-4,
    };
    let steps = (5.0 / w.dt_s()) as usize;
    let history = custom_law::friction_history(&mut w, steps, steps / 60);
    let (mut weakening, mut weakened) = (0, 0);
    for &(travel, slip, mu) in &history {
        let lag = travel - slip;
        assert!(
            (-1e-9..5e-5).contains(&lag),
            "travel {travel:.3e} m, slip {slip:.3e} m"
        );
        if slip == 0.0 {
            assert!(mu <= 0.8 + 1e-12, "sticking below the static cap: {mu}");
            continue;
        }
        // The step's coefficient is that of the slip at its start: one
        // step's slip (3e-9 m at 0.1 mm/s) behind.
        let expected = law.mu_at(slip);
        assert!(
            (mu - expected).abs() < 1e-5,
            "slip {slip:.4e} m: mu {mu:.6} vs {expected:.6}"
        );
        if slip < 2e-4 {
            weakening += 1;
        } else {
            weakened += 1;
        }
    }
    assert!(weakening >= 5 && weakened >= 5, "{weakening} {weakened}");
    let (_, _, last) = history.last().copied().unwrap();
    assert!((last - 0.5).abs() < 1e-9, "mu after weakening {last}");
}

/// The law's name is unknown to a reader that did not register it, and its
/// parameters are checked against its own table.
#[test]
fn an_unregistered_or_misused_law_is_refused_with_its_location() {
    let origin = Path::new("custom.toml");
    let e = Scenario::from_text(custom_law::SCENARIO, origin).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("unknown law `slip-weakening`"), "{msg}");
    assert!(msg.contains("`friction.law`"), "{msg}");
    let registry = custom_law::registry();
    let bad = custom_law::SCENARIO.replace("mu_dynamic = 0.5", "mu_dynamic = -0.5");
    let e = Scenario::from_text_with(&bad, origin, &registry).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("`friction.mu_dynamic`") && msg.contains(">= 0"),
        "{msg}"
    );
    let missing = custom_law::SCENARIO.replace("mu_static = 0.8\n", "");
    let e = Scenario::from_text_with(&missing, origin, &registry).unwrap_err();
    assert!(e.to_string().contains("needs `mu_static`"), "{e}");
}

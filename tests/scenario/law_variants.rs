//! The law variants of a comparison (`floe compare`, `floe rheology`):
//! every registered law with a rule matching it to the rate-and-state
//! reference is accepted, a law registered outside floe-friction too, and
//! each variant is matched as its registry entry says. The steady states
//! are computed here from the published formulas, independently of the
//! laws' code.

use std::path::Path;

use floe_friction::{
    Amontons, DerivedMatch, FrictionLaw, Law, LawEntry, LawRegistry, RateStateParams,
    ReferenceMatch,
};
use floe_scenario::law_variants::{reference_law, variant, LawChoice, Matching};
use floe_scenario::{Scenario, ScenarioError};

const SMALL: &str = include_str!("../data/run_small.toml");

fn origin() -> &'static Path {
    Path::new("small.toml")
}

/// The law a scenario text builds with `registry`.
fn law_of(text: &str, registry: &LawRegistry) -> Law {
    Scenario::from_text_with(text, origin(), registry)
        .unwrap()
        .contact_model()
        .law
        .clone()
}

/// The reference of `SMALL` (regularized rate-and-state, tank preset) and
/// its scenario text.
fn reference(registry: &LawRegistry) -> (Law, String) {
    reference_law(SMALL, origin(), |t| Ok(law_of(t, registry))).unwrap()
}

/// The law of `choice`'s variant of `SMALL`.
fn variant_law(choice: LawChoice, matching: Matching, registry: &LawRegistry) -> Law {
    let (law, text) = reference(registry);
    let (variant_text, _) = variant(SMALL, origin(), choice, &law, &text, matching).unwrap();
    law_of(&variant_text, registry)
}

fn params(law: &Law) -> RateStateParams {
    let Law::RateState(rs) = law else {
        panic!("the reference is rate-and-state, got {law:?}")
    };
    rs.params
}

/// Steady state of the published form, `mu0 + (A - B) ln(V/V*)`.
fn published_steady(p: &RateStateParams, v: f64) -> f64 {
    p.mu0 + (p.a - p.b) * (v / p.v_star_m_per_s).ln()
}

/// Steady state of the regularized form: `A asinh(V/(2 V*) exp((mu0 +
/// theta)/A))` at `theta = B ln(V*/V)`.
fn regularized_steady(p: &RateStateParams, v: f64) -> f64 {
    let theta = p.b * (p.v_star_m_per_s / v).ln();
    p.a * (v / (2.0 * p.v_star_m_per_s) * ((p.mu0 + theta) / p.a).exp()).asinh()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs()
}

#[test]
fn every_builtin_law_is_matched_to_the_reference_as_its_entry_says() {
    let registry = LawRegistry::builtin();
    let (reference, _) = reference(&registry);
    let p = params(&reference);
    let mut names = Vec::new();
    for v in [1e-3, 1e-2, 0.1] {
        let matching = Matching {
            reference_slip_m_per_s: v,
            amontons_mu: None,
        };
        for entry in registry.entries() {
            let choice = LawChoice::named(entry.name, &registry)
                .unwrap_or_else(|| panic!("law `{}` cannot be compared", entry.name));
            let law = variant_law(choice, matching, &registry);
            assert_eq!(law.name(), entry.name);
            match entry.name {
                // The reference's steady state at the reference speed.
                "amontons" => {
                    assert!(close(law.mu_steady(v), regularized_steady(&p, v)), "{v}");
                    // ... at any speed.
                    assert_eq!(law.mu_steady(10.0 * v), law.mu_steady(v));
                }
                // The published form's steady state at every speed above V*
                // (below 1.8 m/s, where it clips at zero).
                "rate" => {
                    for s in [v, 10.0 * v] {
                        assert!(close(law.mu_steady(s), published_steady(&p, s)), "{s}");
                    }
                }
                // The reference itself.
                "rate-state" => {
                    assert_eq!(law, reference);
                    assert!(close(law.mu_steady(v), regularized_steady(&p, v)), "{v}");
                }
                other => panic!("law `{other}`: say here how it is matched"),
            }
            if !names.contains(&entry.name) {
                names.push(entry.name);
            }
        }
    }
    assert_eq!(names, ["amontons", "rate", "rate-state"]);

    // An explicit Amontons mu replaces the matched one.
    let given = Matching {
        reference_slip_m_per_s: 1e-2,
        amontons_mu: Some(0.45),
    };
    let amontons = LawChoice::named("amontons", &registry).unwrap();
    assert_eq!(
        variant_law(amontons, given, &registry),
        Law::Amontons(Amontons { mu: 0.45 })
    );
    let all = LawChoice::parse_list("rate-state, rate,amontons", &registry).unwrap();
    let all: Vec<&str> = all.into_iter().map(LawChoice::name).collect();
    assert_eq!(all, ["rate-state", "rate", "amontons"]);
}

/// Coulomb friction under another name, matched to the reference's
/// published steady state at the reference speed.
const COULOMB: LawEntry = LawEntry {
    name: "coulomb",
    summary: "Amontons under another name",
    params: floe_friction::amontons::PARAMS,
    build: |p| Ok(Law::custom("coulomb", Amontons::from_params(p))),
    reference_match: ReferenceMatch::Derived(DerivedMatch {
        params: |reference, v| vec![("mu", reference.params.mu_steady_published(v))],
        note: |_, _, _| "Coulomb: the published steady state.".into(),
    }),
};

#[test]
fn a_law_registered_elsewhere_is_compared_by_its_entry_or_refused_by_name() {
    let mut registry = LawRegistry::builtin();
    registry.register(COULOMB).unwrap();
    registry
        .register(LawEntry {
            name: "unmatched",
            reference_match: ReferenceMatch::Unmatched,
            ..COULOMB
        })
        .unwrap();
    let v = 1e-2;
    let matching = Matching {
        reference_slip_m_per_s: v,
        amontons_mu: Some(0.45),
    };
    let choices = LawChoice::parse_list("coulomb,rate-state", &registry).unwrap();
    let p = params(&reference(&registry).0);
    let law = variant_law(choices[0], matching, &registry);
    assert_eq!(law.name(), "coulomb");
    // `--amontons-mu` is Amontons' alone.
    assert!(close(law.mu_steady(v), published_steady(&p, v)));
    let (reference, _) = reference(&registry);
    assert_eq!(
        choices[0].note(&reference, matching).as_deref(),
        Some("Coulomb: the published steady state.")
    );
    assert_eq!(choices[1].note(&reference, matching), None);

    let usage = |list: &str| match LawChoice::parse_list(list, &registry) {
        Err(ScenarioError::Usage(m)) => m,
        other => panic!("{list}: {other:?}"),
    };
    assert_eq!(
        usage("rate,unmatched"),
        "--laws: law `unmatched` has no rule matching it to the rate-and-state reference; \
         a comparison takes `amontons`, `rate`, `rate-state` or `coulomb`"
    );
    assert_eq!(
        usage("coulomb,friction"),
        "--laws: unknown law `friction`, expected `amontons`, `rate`, `rate-state`, \
         `coulomb` or `unmatched`"
    );
    assert_eq!(usage("rate,rate"), "--laws: `rate` given twice");
}

//! Fracture criteria against the anchors' own numbers (Subzero.jl
//! test_fractures.jl) and the uniaxial strengths the inequalities imply.

use floe_dem::fracture::criteria::{
    principal_stresses, FractureCriterion, HiblerEllipse, MohrCoulomb,
};

fn close(a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
    (a[0] - b[0]).abs() < tol && (a[1] - b[1]).abs() < tol
}

#[test]
fn principal_stresses_of_a_rotated_tensor_are_its_diagonal() {
    for k in 0..12 {
        let t = 0.3 * k as f64;
        let (c, s) = (t.cos(), t.sin());
        let (a, b) = (-3.0e4, 1.2e4);
        // R diag(a, b) R^T
        let xx = a * c * c + b * s * s;
        let yy = a * s * s + b * c * c;
        let xy = (a - b) * c * s;
        let (s1, s2) = principal_stresses([xx, xy, xy, yy]);
        assert!(
            (s1 - b).abs() < 1e-9 && (s2 - a).abs() < 1e-9,
            "{t}: {s1} {s2}"
        );
    }
    // Only the symmetric part counts.
    assert_eq!(principal_stresses([1.0, 3.0, -3.0, 1.0]), (1.0, 1.0));
}

#[test]
fn the_mohr_coulomb_cone_has_subzeros_vertices() {
    let has = |m: MohrCoulomb, expected: [[f64; 2]; 3]| {
        let v = m.vertices();
        for e in expected {
            assert!(v.iter().any(|p| close(*p, e, 1e-3)), "{e:?} not in {v:?}");
        }
    };
    // Subzero.jl test_fractures.jl, "Mohr's Cone".
    has(
        MohrCoulomb::default(),
        [
            [59523.809, 59523.809],
            [33750.0, -74500.0],
            [-74500.0, 33750.0],
        ],
    );
    has(
        MohrCoulomb {
            sigma_11_pa: 1.5e5,
            ..MohrCoulomb::default()
        },
        [
            [59523.809, 59523.809],
            [-150000.0, -1.03e6],
            [-1.03e6, -150000.0],
        ],
    );
}

#[test]
fn the_mohr_coulomb_cone_breaks_at_its_uniaxial_strengths() {
    let m = MohrCoulomb::default();
    // Uniaxial compression meets the cap, s1 + s2 = 33750 - 74500.
    let compressive = 74500.0 - 33750.0;
    assert!(!m.breaks((0.0, -compressive * 0.999)));
    assert!(m.breaks((0.0, -compressive * 1.001)));
    // Uniaxial tension meets the edge from the apex to (-74500, 33750).
    let (apex, end): ([f64; 2], [f64; 2]) =
        ([59523.80952380953, 59523.80952380953], [-74500.0, 33750.0]);
    let t = apex[0] / (apex[0] - end[0]);
    let tensile = apex[1] + t * (end[1] - apex[1]);
    assert!((tensile - 48077.0).abs() < 1.0, "{tensile}");
    assert!(!m.breaks((0.0, tensile * 0.999)));
    assert!(m.breaks((0.0, tensile * 1.001)));
    // Inside: no stress; outside: equal biaxial compression past the cap.
    assert!(!m.breaks((0.0, 0.0)));
    assert!(m.breaks((-25_000.0, -25_000.0)));
}

#[test]
fn hibler_at_a_quarter_metre_breaks_subzeros_fracturing_floe() {
    let h = HiblerEllipse::default();
    let p = h.strength_pa(0.25, 1.0);
    assert!((p - 56_250.0).abs() < 1e-9);
    // Subzero.jl test_fractures.jl, "Fractures Floes": this stress fractures.
    let stress = [-29955.396, -3428.008, -3428.008, -1942.0464];
    let principal = principal_stresses(stress);
    assert!(FractureCriterion::Hibler(h).breaks(principal, 0.25, 1.0));
    // The same stress a tenth as large does not; neither does a floe of
    // four times the thickness.
    let tenth = (principal.0 / 10.0, principal.1 / 10.0);
    assert!(!FractureCriterion::Hibler(h).breaks(tenth, 0.25, 1.0));
    assert!(!FractureCriterion::Hibler(h).breaks(principal, 1.0, 1.0));
    // Open water weakens the pack: at 90 % concentration P is e^-2 as large.
    assert!((h.strength_pa(0.25, 0.9) - 56_250.0 * (-2f64).exp()).abs() < 1e-9);
}

#[test]
fn hibler_is_the_ellipse_subzero_draws_and_breaks_at_two_fifths_of_p() {
    // Subzero.jl draws the ellipse as a 100-gon: its extreme vertices lie
    // within 0.2 % of the closed form's extremes, -P/2 -+ P sqrt(5)/4.
    for (h, p_star, c, drawn) in [
        (0.5, 5e5, -1.0, [-264743.588, 14727.999]),
        (0.25, 2.25e5, 20.0, [-59567.307, 3313.799]),
    ] {
        let e = HiblerEllipse {
            p_star_pa_per_m: p_star,
            c,
        };
        let p = e.strength_pa(h, 1.0);
        let half = p * 5f64.sqrt() / 4.0;
        let (lo, hi) = (-p / 2.0 - half, -p / 2.0 + half);
        assert!((lo - drawn[0]).abs() < 2e-3 * p && (hi - drawn[1]).abs() < 2e-3 * p);
        // The drawn polygon is inscribed.
        assert!(lo <= drawn[0] && hi >= drawn[1]);
        // The extremes lie on the curve: just inside holds, just outside breaks.
        for x in [lo, hi] {
            // On the ellipse the tangent at the x-extreme is vertical, at
            // y = -P/2 + (x + P/2) * (a^2 - b^2) / (a^2 + b^2) = -P/2 + 3/5 (x + P/2).
            let y = -p / 2.0 + 0.6 * (x + p / 2.0);
            let inward = |f: f64| (-p / 2.0 + f * (x + p / 2.0), -p / 2.0 + f * (y + p / 2.0));
            assert!(!e.breaks(inward(0.999), p));
            assert!(e.breaks(inward(1.001), p));
        }
        // Uniaxial compression breaks at 2P/5; the curve passes through
        // the origin: no tensile strength.
        assert!(!e.breaks((0.0, -0.399 * p), p) && e.breaks((0.0, -0.401 * p), p));
        assert!(!e.breaks((0.0, 0.0), p) && e.breaks((1e-6 * p, 0.0), p));
    }
}

#[test]
fn parameters_that_put_the_unstressed_floe_outside_are_refused() {
    assert!(MohrCoulomb::default().check().is_ok());
    assert!(HiblerEllipse::default().check().is_ok());
    let cone = |q, sigma_c_pa, sigma_11_pa| MohrCoulomb {
        q,
        sigma_c_pa,
        sigma_11_pa,
    };
    // No internal friction (q = 1) divides by zero; q < 1 flips the cone.
    assert!(cone(1.0, 2.5e5, -3.375e4)
        .check()
        .unwrap_err()
        .contains("q = 1"));
    assert!(cone(0.5, 2.5e5, -3.375e4).check().is_err());
    assert!(cone(5.2, 0.0, -3.375e4)
        .check()
        .unwrap_err()
        .contains("sigma_c"));
    // A cap beyond the apex (sigma_c / (1 - q) = -59524 Pa) would leave
    // the unstressed floe outside: refused, and the check is what the
    // inequality says.
    let beyond = cone(5.2, 2.5e5, -7.0e4);
    assert!(beyond.check().unwrap_err().contains("sigma_11"));
    assert!(beyond.breaks((0.0, 0.0)));
    assert!(HiblerEllipse {
        p_star_pa_per_m: 0.0,
        c: 20.0
    }
    .check()
    .is_err());
    assert!(HiblerEllipse {
        p_star_pa_per_m: 2.25e5,
        c: -1.0
    }
    .check()
    .is_err());
}

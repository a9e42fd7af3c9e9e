//! `floe sweep`'s grid: parsing `--set`, the cartesian product, and editing
//! a scenario's text without disturbing the rest of it.

use std::path::Path;

use floe_scenario::settings::{apply, cartesian, label, parse_setting};
use floe_scenario::{Scenario, AUTO_DT_FRACTION};

#[test]
fn set_values_split_at_top_level_commas_only() {
    let s = parse_setting("wind.velocity_m_per_s=[5.0, 0.0],[10.0,0.0]").unwrap();
    assert_eq!(s.key, vec!["wind", "velocity_m_per_s"]);
    assert_eq!(s.values, vec!["[5.0, 0.0]", "[10.0,0.0]"]);
    let s = parse_setting("friction.preset=\"lab\",\"tank\"").unwrap();
    assert_eq!(s.values, vec!["\"lab\"", "\"tank\""]);
    let s = parse_setting(" friction.a = 0.25, 0.31 ,0.37").unwrap();
    assert_eq!(s.values, vec!["0.25", "0.31", "0.37"]);
    for bad in [
        "friction.a",
        "friction.a=",
        "friction.a=0.3,",
        "friction..a=1",
        "x=lab",
    ] {
        let e = parse_setting(bad).unwrap_err().to_string();
        assert!(e.contains(bad.trim()), "{bad}: {e}");
    }
}

#[test]
fn cartesian_product_counts_and_orders() {
    let a = parse_setting("friction.a=1,2,3").unwrap();
    let b = parse_setting("seed=7,8").unwrap();
    let combos = cartesian(&[a.clone(), b.clone()]);
    assert_eq!(combos.len(), 6);
    assert_eq!(combos[0], vec![0, 0]);
    assert_eq!(combos[1], vec![0, 1], "last setting fastest");
    assert_eq!(combos[5], vec![2, 1]);
    let mut unique = combos.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), 6);
    assert_eq!(label(&[a, b], &combos[3]), "friction.a=2 seed=8");
}

#[test]
fn apply_replaces_only_the_swept_keys() {
    let text = "# my channel\nseed = 1\n\n[friction]\nlaw = \"rate-state\" # tank\na = 0.31\n\n[ice]\nthickness_m = 1.0\n";
    let settings = [
        parse_setting("friction.a=0.25,0.37").unwrap(),
        parse_setting("seed=5").unwrap(),
        parse_setting("output.snapshot_every_s=60").unwrap(),
    ];
    let out = apply(text, Path::new("x.toml"), &settings, &[1, 0, 0]).unwrap();
    assert!(
        out.contains("# my channel") && out.contains("# tank"),
        "comments kept:\n{out}"
    );
    let v: toml::Table = out.parse().unwrap();
    assert_eq!(v["friction"]["a"].as_float(), Some(0.37));
    assert_eq!(v["friction"]["law"].as_str(), Some("rate-state"));
    assert_eq!(v["seed"].as_integer(), Some(5));
    assert_eq!(v["ice"]["thickness_m"].as_float(), Some(1.0));
    assert_eq!(v["output"]["snapshot_every_s"].as_integer(), Some(60));
    let not_a_table = parse_setting("seed.x=1").unwrap();
    let e = apply(text, Path::new("x.toml"), &[not_a_table], &[0]).unwrap_err();
    assert!(e.to_string().contains("seed.x"), "{e}");
}

/// `dt_fraction` sets the time step as a fraction of the stable limit; a
/// sweep over it (`--set dt_fraction=...`) edits the file like any key.
#[test]
fn dt_fraction_scales_the_stable_step_and_a_quarter_is_half_the_automatic_step() {
    let text = "duration_s = 100.0\n\n[domain]\nsize_m = [4000.0, 4000.0]\n\n\
                [tessellation]\nkind = \"grid\"\ncolumns = 2\nrows = 2\ngap_m = 100.0\n";
    let build = |text: &str| {
        Scenario::from_text(text, Path::new("s.toml"))
            .unwrap()
            .build()
            .unwrap()
    };
    let auto = build(text);
    let sweep = [parse_setting("dt_fraction=0.25,0.5,1.0").unwrap()];
    let with = |k: usize| build(&apply(text, Path::new("s.toml"), &sweep, &[k]).unwrap());
    let (quarter, half, whole) = (with(0), with(1), with(2));
    // The limit does not depend on the fraction.
    for s in [&quarter, &half, &whole] {
        assert_eq!(s.stable_limit_s, auto.stable_limit_s);
    }
    assert_eq!(quarter.dt_s, half.dt_s / 2.0);
    assert_eq!(AUTO_DT_FRACTION, 0.5);
    assert_eq!(
        quarter.dt_s,
        auto.dt_s / 2.0,
        "omitting dt is dt_fraction 0.5"
    );
    assert_eq!(half.dt_s, auto.dt_s);
    assert_eq!(whole.dt_s, auto.stable_limit_s);
    assert_eq!(quarter.world.dt_s(), quarter.dt_s);
    // The report names the fraction used.
    let dt_line = |s: &floe_scenario::Setup| {
        s.report
            .iter()
            .find(|l| l.starts_with("dt: "))
            .cloned()
            .unwrap()
    };
    assert!(
        dt_line(&quarter).contains("(dt_fraction 0.25 x the stable limit"),
        "{}",
        dt_line(&quarter)
    );
    assert!(
        dt_line(&auto).contains("(auto: 0.5 x the stable limit"),
        "{}",
        dt_line(&auto)
    );
}

#[test]
fn apply_reaches_keys_inside_inline_tables_and_get_reads_them_back() {
    let origin = Path::new("inline.toml");
    let text =
        "duration_s = 10.0\n[wind]\nshear = { y_min_m = 0.0, y_max_m = 100.0 } # the shear\n";
    let settings = [
        parse_setting("wind.shear.y_min_m=25.0").unwrap(),
        parse_setting("wind.shear.new_table.k=1").unwrap(),
    ];
    let out = apply(text, origin, &settings, &[0, 0]).unwrap();
    // The edited table stays inline, its comment with it.
    assert!(out.contains("shear = {"), "{out}");
    assert!(out.contains("# the shear"), "{out}");
    let key = |k: &str| k.split('.').map(String::from).collect::<Vec<_>>();
    let get = |k: &str| floe_scenario::settings::get(&out, origin, &key(k)).unwrap();
    assert_eq!(get("wind.shear.y_min_m").unwrap().as_float(), Some(25.0));
    assert_eq!(get("wind.shear.y_max_m").unwrap().as_float(), Some(100.0));
    assert_eq!(get("wind.shear.new_table.k").unwrap().as_integer(), Some(1));
    assert!(get("wind.shear.absent").is_none());
    // A key under a value that is not a table is refused, naming it.
    let bad = parse_setting("duration_s.x=1").unwrap();
    let err = apply(text, origin, &[bad], &[0]).unwrap_err().to_string();
    assert!(err.contains("`duration_s` is not a table"), "{err}");
}

//! A small wind-driven pack against a moving wall, shared by the floe-io
//! tests, and helpers to compare states bitwise.
#![allow(dead_code)]

use floe_dem::contact_model::ContactModel;
use floe_dem::forcing::Forcing;
use floe_dem::state::WorldState;
use floe_dem::world::World;
use floe_dem::Vec2;
use floe_io::{DomainBox, RunMetadata};

pub use floe_fixtures::wind_pack::Parts;

/// The shared wind pack (`floe_fixtures::wind_pack`) under the default
/// contact model: 30 square floes pushed by wind against a 400 m wall floe
/// that moves at a prescribed velocity, with contact memory.
pub fn pack() -> (World<Forcing>, Parts) {
    floe_fixtures::wind_pack::wind_pack(ContactModel::default())
}

/// The domain the pack lives in, m.
pub const DOMAIN: DomainBox = DomainBox {
    min_m: [-100.0, -100.0],
    size_m: [1300.0, 700.0],
    periodic: [false, true],
};

pub fn domain_area() -> f64 {
    DOMAIN.size_m[0] * DOMAIN.size_m[1]
}

pub fn metadata() -> RunMetadata {
    RunMetadata {
        scenario_toml: "# test pack\n[run]\nduration_s = 100.0\n\"ünïcode\" = 'ok'\n".into(),
        scenario_path: "tests/pack.toml".into(),
        floe_version: "0.1.0-test".into(),
        git_commit: "0123abc".into(),
        command_line: vec!["floe".into(), "run".into(), "pack toml".into()],
        threads: 3,
        processes: 2,
        author: "tester".into(),
        domain: DOMAIN,
        inputs: Vec::new(),
    }
}

/// A state's full content as text: `{:?}` prints every f64 with enough
/// digits to round-trip and keeps the sign of zero, so equal text is
/// bitwise-equal state (NaNs aside, which a valid state does not hold).
pub fn fingerprint(s: &WorldState) -> String {
    format!("{s:?}")
}

pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

pub fn bits2(v: &[[f64; 2]]) -> Vec<[u64; 2]> {
    v.iter().map(|p| [p[0].to_bits(), p[1].to_bits()]).collect()
}

pub fn vec2_bits(v: &[Vec2]) -> Vec<[u64; 2]> {
    v.iter().map(|p| [p.x.to_bits(), p.y.to_bits()]).collect()
}

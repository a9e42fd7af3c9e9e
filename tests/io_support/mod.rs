//! A small wind-driven pack against a moving wall, shared by the floe-io
//! tests, and helpers to compare states bitwise.
#![allow(dead_code)]

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{Floe, Floes};
use floe_dem::forcing::{Forcing, VelocityField};
use floe_dem::geometry::FloeShape;
use floe_dem::periodicity::Periodicity;
use floe_dem::state::WorldState;
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;
use floe_io::{DomainBox, RunMetadata};

fn square(c: Vec2, s: f64) -> Vec<Vec2> {
    let h = 0.5 * s;
    vec![
        c + Vec2::new(-h, -h),
        c + Vec2::new(h, -h),
        c + Vec2::new(h, h),
        c + Vec2::new(-h, h),
    ]
}

/// The scenario's fixed parts (what a checkpoint does not hold).
#[derive(Clone)]
pub struct Parts {
    pub model: ContactModel,
    pub forcing: Forcing,
    pub dt: f64,
}

impl Parts {
    pub fn resume(&self, state: WorldState) -> World<Forcing> {
        assert_eq!(
            state.dt_s.to_bits(),
            self.dt.to_bits(),
            "the checkpoint's dt"
        );
        World::resume(
            state,
            self.model.clone(),
            self.forcing.clone(),
            Periodicity::default(),
        )
        .expect("resumable state")
    }
}

/// 30 square floes (slightly staggered, of different thickness) pushed by
/// wind against a 400 m wall floe that moves at a prescribed velocity, with
/// contact memory, so contacts form, slip and break within a few hundred steps.
pub fn pack() -> (World<Forcing>, Parts) {
    let mut polys = Vec::new();
    for j in 0..5 {
        for i in 0..6 {
            let c = Vec2::new(i as f64 * 100.0 + 3.0 * j as f64, j as f64 * 99.5);
            polys.push(square(c, 100.0));
        }
    }
    let thickness: Vec<f64> = (0..polys.len()).map(|i| 1.0 + 0.05 * i as f64).collect();
    let mut floes = Floes::from_polygons(&polys, &thickness, 917.0).unwrap();
    let (wall, c) = FloeShape::from_world(0, &square(Vec2::new(900.0, 200.0), 400.0)).unwrap();
    floes
        .insert(Floe::new(999, &wall, c, 1.0, 917.0).prescribed(Vec2::new(0.0, 0.01)))
        .unwrap();
    let model = ContactModel {
        memory_s: 50.0,
        ..ContactModel::default()
    };
    let forcing = Forcing {
        wind: VelocityField::Uniform(Vec2::new(15.0, 3.0)),
        ..Forcing::default()
    };
    let dt = 0.5 * stable_time_step(&floes, &model).0;
    let world = World::new(
        floes,
        model.clone(),
        forcing.clone(),
        Periodicity::default(),
        dt,
    )
    .unwrap();
    (world, Parts { model, forcing, dt })
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

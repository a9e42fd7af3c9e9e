//! 30 square floes of 100 m (slightly staggered, of different thickness)
//! pushed by a 15 m/s wind against a 400 m wall floe (id 999) that moves
//! at 1 cm/s, with contact memory: contacts form, slip and break within a
//! few hundred steps, and the forces depend on the half-step velocity
//! through the drag.

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{Floe, Floes};
use floe_dem::forcing::{Forcing, VelocityField};
use floe_dem::geometry::FloeShape;
use floe_dem::periodicity::Periodicity;
use floe_dem::state::WorldState;
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;

/// A square of side `s` centred at `c`, counter-clockwise.
pub fn square(c: Vec2, s: f64) -> Vec<Vec2> {
    let h = 0.5 * s;
    vec![
        c + Vec2::new(-h, -h),
        c + Vec2::new(h, -h),
        c + Vec2::new(h, h),
        c + Vec2::new(-h, h),
    ]
}

/// What a checkpoint does not hold: the contact model, the forcing and dt.
#[derive(Clone)]
pub struct Parts {
    /// The contact model the pack was built with.
    pub model: ContactModel,
    /// The wind.
    pub forcing: Forcing,
    /// Half the stable time step, s.
    pub dt: f64,
}

impl Parts {
    /// The world that continues from `state` (taken with these parts).
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

/// The pack under `model` (its `memory_s` set to 50 s), not periodic.
pub fn wind_pack(model: ContactModel) -> (World<Forcing>, Parts) {
    let mut polys = Vec::new();
    for j in 0..5 {
        for i in 0..6 {
            let c = Vec2::new(i as f64 * 100.0 + 3.0 * j as f64, j as f64 * 99.5);
            polys.push(square(c, 100.0));
        }
    }
    let thickness: Vec<f64> = (0..polys.len()).map(|i| 1.0 + 0.05 * i as f64).collect();
    let mut floes = Floes::from_polygons(&polys, &thickness, 917.0).expect("floes");
    let (wall, c) =
        FloeShape::from_world(0, &square(Vec2::new(900.0, 200.0), 400.0)).expect("wall");
    floes
        .insert(Floe::new(999, &wall, c, 1.0, 917.0).prescribed(Vec2::new(0.0, 0.01)))
        .expect("wall floe");
    let model = ContactModel {
        memory_s: 50.0,
        ..model
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
    .expect("world");
    (world, Parts { model, forcing, dt })
}

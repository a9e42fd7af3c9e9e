//! A channel of ~n diamonds of 1 km side (60 degrees, 1 m thick), periodic
//! along x, four times as long as wide, with a linear shear velocity profile
//! (0.1 m/s across the channel, and a slight compression).

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::Floes;
use floe_dem::forcing::NoForcing;
use floe_dem::periodicity::{Period, Periodicity};
use floe_dem::tessellation::{DiamondLattice, Rect, ThicknessDistribution};
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;
use floe_friction::{Amontons, Law};

/// The channel's floes and where they live.
pub struct Channel {
    /// The floes, moving with the shear profile.
    pub floes: Floes,
    /// Periodic along x over the channel's length.
    pub periodicity: Periodicity,
    /// The domain, m.
    pub domain: Rect,
}

impl Channel {
    /// Half the stable time step of these floes under `model`, s.
    pub fn dt_s(&self, model: &ContactModel) -> f64 {
        0.5 * stable_time_step(&self.floes, model).0
    }
}

/// ~`n` diamonds whose corners are jittered by `jitter_fraction` of a side.
pub fn channel(n: usize, jitter_fraction: f64) -> Channel {
    let side = 1000.0;
    let cell_area = side * side * 60f64.to_radians().sin();
    let width = (n as f64 * cell_area / 4.0).sqrt();
    let domain = Rect {
        min: Vec2::new(0.0, 0.0),
        max: Vec2::new(4.0 * width, width),
    };
    let lattice = DiamondLattice {
        domain,
        side_m: side,
        acute_angle_deg: 60.0,
        orientation_deg: 0.0,
        thickness: ThicknessDistribution::Uniform { thickness_m: 1.0 },
        jitter_fraction,
        seed: 1,
    };
    let t = lattice.build().expect("the channel's lattice");
    let mut floes = Floes::from_polygons(&t.polygons, &t.thickness_m, 917.0).expect("floes");
    for i in 0..floes.len() {
        let y = floes.position[i].y / width - 0.5;
        floes.set_velocity(i, Vec2::new(0.1 * y, -0.001 * y), floes.angular_velocity[i]);
    }
    let periodicity = Periodicity {
        x: Some(Period {
            min_m: 0.0,
            length_m: 4.0 * width,
        }),
        y: None,
    };
    Channel {
        floes,
        periodicity,
        domain,
    }
}

/// The unjittered channel under the default contact model (regularised
/// rate-and-state), after 20 warm-up steps so that contacts have formed
/// and slide: the DEM step benchmark's pack.
pub fn sheared_channel(n: usize) -> World<NoForcing> {
    sheared_channel_with(n, ContactModel::default())
}

/// [`sheared_channel`] under `model`.
pub fn sheared_channel_with(n: usize, model: ContactModel) -> World<NoForcing> {
    let c = channel(n, 0.0);
    let dt = c.dt_s(&model);
    let mut w = World::new(c.floes, model, NoForcing, c.periodicity, dt).expect("world");
    for _ in 0..20 {
        w.step();
    }
    w
}

/// The default contact model with Amontons friction (mu = 0.5) instead of
/// rate-and-state: the step without the friction solve.
pub fn amontons_model() -> ContactModel {
    ContactModel::default().with_law(Law::Amontons(Amontons { mu: 0.5 }))
}

//! The rectangle a run covers and its periodic axes.

use floe_dem::periodicity::{Period, Periodicity};
use floe_dem::Vec2;

/// The rectangle the run covers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// Lower-left corner, m.
    pub min_m: Vec2,
    /// Width and height, m.
    pub size_m: Vec2,
    /// Periodic along x, along y.
    pub periodic: [bool; 2],
}

impl Domain {
    /// Area, m^2.
    pub fn area_m2(&self) -> f64 {
        self.size_m.x * self.size_m.y
    }

    /// The engine's periodicity for this domain.
    pub fn periodicity(&self) -> Periodicity {
        let period = |axis: usize| {
            self.periodic[axis].then(|| Period {
                min_m: self.min_m[axis],
                length_m: self.size_m[axis],
            })
        };
        Periodicity {
            x: period(0),
            y: period(1),
        }
    }
}

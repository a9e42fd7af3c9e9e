//! Each floe's Love-Weber stress moment from one snapshot's contacts: the
//! sum over its contacts of `f (x) (x_c - x)`, the force on the floe times
//! its arm from the centroid to the contact point. Over an area `A` the sum
//! of the moments is the mean stress times `A` (tension positive); one
//! floe's moment over its own area is its stress.

/// One snapshot's contacts, as stored in a run file.
#[derive(Debug, Clone, Copy)]
pub struct ContactForces<'a> {
    /// Floe indices `(a, b)` of each contact.
    pub pair: &'a [[u32; 2]],
    /// Contact points (in the frame where `a` sits at its position), m.
    pub point: &'a [[f64; 2]],
    /// Unit normals from `a` to `b`.
    pub normal: &'a [[f64; 2]],
    /// Normal force on `b`, N.
    pub normal_force_n: &'a [f64],
    /// Tangential force on `b` along `perp(normal) = (-n_y, n_x)`, N.
    pub tangential_force_n: &'a [f64],
}

impl ContactForces<'_> {
    /// The force on the second floe of contact `k`, N.
    pub fn force_on_b(&self, k: usize) -> [f64; 2] {
        let [nx, ny] = self.normal[k];
        let (f_n, f_t) = (self.normal_force_n[k], self.tangential_force_n[k]);
        [nx * f_n - ny * f_t, ny * f_n + nx * f_t]
    }
}

/// The moment `[xx, xy, yx, yy]` (force component first, arm second), N m,
/// of each of the `position.len()` floes; floes without contacts get zero.
/// `period` gives the domain's period along each periodic axis, so an arm
/// across a periodic boundary is taken to the nearest image. Contacts must
/// name floes below `position.len()`.
pub fn stress_moments(
    position: &[[f64; 2]],
    contacts: &ContactForces,
    period: [Option<f64>; 2],
) -> Vec<[f64; 4]> {
    let nearest = |d: f64, axis: usize| match period[axis] {
        Some(p) => d - p * (d / p).round(),
        None => d,
    };
    let mut moment = vec![[0.0; 4]; position.len()];
    for k in 0..contacts.pair.len() {
        let on_b = contacts.force_on_b(k);
        let [a, b] = contacts.pair[k].map(|i| i as usize);
        for (i, f) in [(a, [-on_b[0], -on_b[1]]), (b, on_b)] {
            let arm = [
                nearest(contacts.point[k][0] - position[i][0], 0),
                nearest(contacts.point[k][1] - position[i][1], 1),
            ];
            let m = &mut moment[i];
            m[0] += f[0] * arm[0];
            m[1] += f[0] * arm[1];
            m[2] += f[1] * arm[0];
            m[3] += f[1] * arm[1];
        }
    }
    moment
}

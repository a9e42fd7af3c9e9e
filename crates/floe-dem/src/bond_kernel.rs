//! The bond kernel: forces of a frozen joint between two floes.
//!
//! A bond ([`Bond`]) ties an anchor point fixed in each floe (both at the
//! contact point when it formed) with three springs per its length `l`,
//! as a parallel bond of bonded-particle models (Potyondy & Cundall 2004)
//! in two dimensions:
//! * normal, along the formation normal `n` (turning with `a`), in tension
//!   only (compression is the overlap contact's, which goes on beside the
//!   bond): `k_n = kappa l`, the contact's normal stiffness at that length
//!   when the bond formed ([`overlap_stiffness`]), kept for its life;
//! * shear, along `t = perp(n)`: `k_t = k_n / (2 (1 + nu))`;
//! * bending, on the relative rotation `phi`: `k_r = k_n l^2 / 12` (a
//!   beam section of length `l`).
//!
//! Energy `U = k_n max(d_n, 0)^2 / 2 + k_t d_t^2 / 2 + k_r phi^2 / 2` for
//! the anchors' separation `d = (d_n, d_t)`; the forces and torques are
//! its exact gradient (including the turning of `n` with `a`), so linear
//! and angular momentum are conserved to round-off and the bond is
//! conservative. Dashpots of the contact's damping ratio act on the
//! relative velocity at the anchors' midpoint (the normal one in tension
//! only) and on the relative spin, and dissipate exactly
//! `c_n v_n^2 + c_t v_t^2 + c_r w^2`.
//!
//! The bond's loads per unit length, `tension = k_n max(d_n, 0) / l + 6
//! |M| / l^2` (pull plus the beam's edge stress in bending, `M = k_r
//! phi`) and `shear = k_t |d_t| / l`, are what its strength is compared
//! with.

use crate::bonds::Bond;
use crate::contact_kernel::{overlap_stiffness, Body};
use crate::contact_model::ContactModel;
use crate::contacts::ContactRecord;
use crate::geometry::{cross, perp, rotate};
use crate::Vec2;

/// What the bond kernel needs of one floe.
#[derive(Debug, Clone, Copy)]
pub struct BondEnd {
    /// The floe as the contact kernel sees it (position: the image that
    /// touches the other floe, for `b`).
    pub body: Body,
    /// Its angle, rad.
    pub angle_rad: f64,
    /// `(sin, cos)` of its angle.
    pub sin_cos: (f64, f64),
    /// Its moment of inertia about the centroid, kg m^2.
    pub inertia_kg_m2: f64,
}

impl BondEnd {
    /// Floe `h` of `f` at `offset` (an image), whose angle's `(sin, cos)`
    /// is `sin_cos`.
    #[inline]
    pub fn of(f: &crate::floes::FloeColumns, h: usize, offset: Vec2, sin_cos: (f64, f64)) -> Self {
        BondEnd {
            body: Body::of(f, h, offset),
            angle_rad: f.angle[h],
            sin_cos,
            inertia_kg_m2: f.inertia_kg_m2[h],
        }
    }

    /// `v` from the floe's body frame to the world's orientation.
    #[inline]
    fn to_world(self, v: Vec2) -> Vec2 {
        rotate(v, self.sin_cos.1, self.sin_cos.0)
    }

    /// `v` from the world's orientation to the floe's body frame.
    #[inline]
    fn to_body(self, v: Vec2) -> Vec2 {
        rotate(v, self.sin_cos.1, -self.sin_cos.0)
    }

    /// The velocity of the floe's material point at `p`, m/s.
    #[inline]
    fn velocity_at(self, p: Vec2) -> Vec2 {
        self.body.velocity + perp(p - self.body.position) * self.body.angular_velocity
    }
}

/// The bond that the quiet contact `c` between `a` and `b` forms at
/// `time_s`: anchors at the contact point, its normal and length.
pub fn form_bond(
    model: &ContactModel,
    candidate: &Bond,
    c: &ContactRecord,
    a: &BondEnd,
    b: &BondEnd,
    time_s: f64,
) -> Bond {
    Bond {
        stiffness_n_per_m: overlap_stiffness(model, &a.body, &b.body) * c.length_m,
        formed: true,
        formed_at_s: time_s,
        anchor_a: a.to_body(c.point - a.body.position),
        anchor_b: b.to_body(c.point - b.body.position),
        normal_a: a.to_body(c.normal),
        rest_angle_rad: b.angle_rad - a.angle_rad,
        length_m: c.length_m,
        ..*candidate
    }
}

/// `x` in `(-pi, pi]` when it is outside (untouched inside, so that a small
/// angle keeps its bits).
#[inline]
fn wrapped_angle(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    if x > PI || x <= -PI {
        x - TAU * ((x + PI) / TAU).floor()
    } else {
        x
    }
}

/// Evaluates `bond` between `a` and `b`: sets its anchors in the world,
/// its force and torques, stored energy, damping power and loads per unit
/// length. `damping_ratio` is the contact model's.
pub fn evaluate_bond(
    model: &ContactModel,
    damping_ratio: f64,
    a: &BondEnd,
    b: &BondEnd,
    bond: &mut Bond,
) {
    let l = bond.length_m.max(f64::MIN_POSITIVE);
    let k_n = bond.stiffness_n_per_m;
    let k_t = k_n / (2.0 * (1.0 + model.poisson_ratio));
    let k_r = k_n * l * l / 12.0;

    let pa = a.body.position + a.to_world(bond.anchor_a);
    let pb = b.body.position + b.to_world(bond.anchor_b);
    let (ra, rb) = (pa - a.body.position, pb - b.body.position);
    let n = a.to_world(bond.normal_a);
    let t = perp(n);
    let d = pb - pa;
    let (d_n, d_t) = (d.dot(n), d.dot(t));
    let stretch = d_n.max(0.0);
    let phi = wrapped_angle(b.angle_rad - a.angle_rad - bond.rest_angle_rad);

    // Elastic: the gradient of U. G = dU/d(pb); the turning of n with a
    // adds -(k_n stretch - k_t d_n) d_t to a's torque.
    let g = n * (k_n * stretch) + t * (k_t * d_t);
    let moment = k_r * phi;
    let mut on_b = -g;
    let mut torque_b = cross(rb, -g) - moment;
    let mut torque_a = cross(ra, g) - (k_n * stretch - k_t * d_n) * d_t + moment;

    // Dashpots at the anchors' midpoint (equal and opposite at one point:
    // no net torque), and on the relative spin.
    let (free_a, free_b) = (a.body.free, b.body.free);
    let harmonic = |x: f64, y: f64| match (free_a, free_b) {
        (true, true) => x * y / (x + y),
        (true, false) => x,
        (false, true) => y,
        (false, false) => 0.0,
    };
    let m_star = harmonic(a.body.mass_kg, b.body.mass_kg);
    let i_star = harmonic(a.inertia_kg_m2, b.inertia_kg_m2);
    let mid = 0.5 * (pa + pb);
    let v_rel = b.velocity_at(mid) - a.velocity_at(mid);
    let (v_n, v_t) = (v_rel.dot(n), v_rel.dot(t));
    let spin = b.body.angular_velocity - a.body.angular_velocity;
    let c_n = if d_n > 0.0 {
        2.0 * damping_ratio * (k_n * m_star).sqrt()
    } else {
        0.0
    };
    let c_t = 2.0 * damping_ratio * (k_t * m_star).sqrt();
    let c_r = 2.0 * damping_ratio * (k_r * i_star).sqrt();
    let damping = -(n * (c_n * v_n) + t * (c_t * v_t));
    on_b += damping;
    torque_b += cross(mid - b.body.position, damping) - c_r * spin;
    torque_a += cross(mid - a.body.position, -damping) + c_r * spin;

    bond.point_a = pa;
    bond.point_b = pb;
    bond.force_on_b = on_b;
    bond.torque_on_a = torque_a;
    bond.torque_on_b = torque_b;
    bond.energy_j = 0.5 * (k_n * stretch * stretch + k_t * d_t * d_t + k_r * phi * phi);
    bond.damping_power_w = c_n * v_n * v_n + c_t * v_t * v_t + c_r * spin * spin;
    bond.tension_n_per_m = k_n * stretch / l + 6.0 * moment.abs() / (l * l);
    bond.shear_n_per_m = k_t * d_t.abs() / l;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn end(position: Vec2, angle: f64, free: bool) -> BondEnd {
        BondEnd {
            body: Body {
                position,
                velocity: Vec2::ZERO,
                angular_velocity: 0.0,
                mass_kg: 9.17e6,
                thickness_m: 1.0,
                area_m2: 1e4,
                free,
            },
            angle_rad: angle,
            sin_cos: angle.sin_cos(),
            inertia_kg_m2: 1.5e10,
        }
    }

    /// A bond formed between two floes, evaluated after they moved to `q`
    /// (`[xa, ya, angle_a, xb, yb, angle_b]`).
    fn at(q: [f64; 6], free_a: bool) -> Bond {
        let model = ContactModel::default();
        let (a0, b0) = (
            end(Vec2::new(0.0, 0.0), 0.3, free_a),
            end(Vec2::new(100.0, 10.0), -0.2, true),
        );
        let contact = ContactRecord::new_contact(
            &model,
            Default::default(),
            &crate::geometry::Overlap {
                area_m2: 1.0,
                centroid: Vec2::new(50.0, 7.0),
                normal: Vec2::new(0.98, 0.2).normalize(),
                length_m: 80.0,
            },
            &a0.body,
            &b0.body,
            (0, 1),
            Vec2::ZERO,
        );
        let mut c = contact;
        c.point = Vec2::new(50.0, 7.0);
        c.normal = Vec2::new(0.98, 0.2).normalize();
        c.length_m = 80.0;
        let mut bond = form_bond(&model, &Bond::candidate(0, 1, 0.0), &c, &a0, &b0, 0.0);
        let (a, b) = (
            end(Vec2::new(q[0], q[1]), q[2], free_a),
            end(Vec2::new(q[3], q[4]), q[5], true),
        );
        evaluate_bond(&model, model.damping_ratio(), &a, &b, &mut bond);
        bond
    }

    #[test]
    fn forces_and_torques_are_the_energys_exact_gradient() {
        // Stretched, sheared and bent; then compressed (normal spring slack).
        for q in [
            [0.01, -0.02, 0.3 + 2e-4, 100.05, 10.03, -0.2 - 1e-4],
            [0.0, 0.0, 0.3, 99.9, 10.02, -0.2 + 3e-4],
        ] {
            let bond = at(q, true);
            assert!(bond.energy_j > 0.0);
            // -dU/dq_k by central differences.
            let grad = |k: usize| {
                let h = if k % 3 == 2 { 1e-7 } else { 1e-5 };
                let (mut up, mut down) = (q, q);
                up[k] += h;
                down[k] -= h;
                -(at(up, true).energy_j - at(down, true).energy_j) / (2.0 * h)
            };
            let scale = bond.force_on_b.length() + 1.0;
            let expected = [
                -bond.force_on_b.x,
                -bond.force_on_b.y,
                bond.torque_on_a,
                bond.force_on_b.x,
                bond.force_on_b.y,
                bond.torque_on_b,
            ];
            for (k, e) in expected.into_iter().enumerate() {
                let g = grad(k);
                let tol = if k % 3 == 2 {
                    1e-6 * scale * 100.0
                } else {
                    1e-6 * scale
                };
                assert!((g - e).abs() < tol, "q {q:?}, coordinate {k}: {g} vs {e}");
            }
        }
    }

    #[test]
    fn a_bond_at_rest_carries_nothing_and_its_loads_follow_the_springs() {
        let rest = at([0.0, 0.0, 0.3, 100.0, 10.0, -0.2], true);
        assert!(rest.energy_j < 1e-20 && rest.force_on_b.length() < 1e-6);
        // Pulled straight along the normal by 1 cm: tension k_n d / l.
        let n = Vec2::new(0.98, 0.2).normalize();
        let pulled = at(
            [0.0, 0.0, 0.3, 100.0 + 0.01 * n.x, 10.0 + 0.01 * n.y, -0.2],
            true,
        );
        let k_n = pulled.stiffness_n_per_m;
        assert!((pulled.tension_n_per_m - k_n * 0.01 / 80.0).abs() < 1e-6 * k_n * 0.01 / 80.0);
        assert!(pulled.shear_n_per_m < 1e-9 * pulled.tension_n_per_m);
        assert!((pulled.energy_j - 0.5 * k_n * 1e-4).abs() < 1e-9 * k_n * 1e-4);
        // Pushed: the normal spring is slack (the overlap contact's job).
        let pushed = at(
            [0.0, 0.0, 0.3, 100.0 - 0.01 * n.x, 10.0 - 0.01 * n.y, -0.2],
            true,
        );
        assert!(pushed.energy_j < 1e-12 * pulled.energy_j && pushed.tension_n_per_m < 1e-9);
        // Bent by 1e-4 rad about b's anchor: the beam's edge tension k_n phi / 2.
        let bent = at([0.0, 0.0, 0.3, 100.0, 10.0, -0.2 + 1e-4], true);
        assert!(
            bent.tension_n_per_m > 0.49 * k_n * 1e-4
                && bent.tension_n_per_m < 0.51 * k_n * 1e-4 + k_n * 1e-3 / 80.0
        );
    }
}

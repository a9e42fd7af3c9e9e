//! The contact kernel: forces between two overlapping floes.
//!
//! * Normal force: elastic, proportional to the overlap area, as in
//!   Subzero.jl (Manucharyan & Montemuro 2022): `F_el = kappa A_overlap`,
//!   `kappa = E h_a h_b / (h_a r_b + h_b r_a)` with `r = sqrt(floe area)`
//!   (two springs `E h / r` in series); against a floe with prescribed
//!   motion (a wall), `kappa = E h / r` of the free floe. With `A_overlap ~
//!   l delta` for contact length `l` and penetration `delta`, the normal
//!   stiffness is `k_n = kappa l`. A linear dashpot `c = 2 zeta sqrt(k_n m*)`
//!   (reduced mass `m*`, damping ratio from the restitution coefficient)
//!   acts on the normal approach speed; the total is clipped at zero (no
//!   adhesion).
//! * Tangential force: a spring `k_t = k_n / (2 (1 + nu))` (the shear-to-
//!   Young's modulus ratio, as Subzero.jl's `G = E / (2 (1 + nu))`) whose
//!   force the friction law limits, advanced by the same
//!   [`floe_friction::FrictionLaw::step`] as the spring-slider, with the relative
//!   tangential velocity at the contact point as the load-point velocity
//!   and the normal force as the normal load.

use floe_friction::{BatchItem, ContactLoad, ContactState};

use crate::contact_model::ContactModel;
use crate::contacts::ContactRecord;
use crate::geometry::{cross, perp, Overlap};
use crate::Vec2;

/// What the kernel needs of one floe.
#[derive(Debug, Clone, Copy)]
pub struct Body {
    /// Centroid position (image position for `b` across a periodic boundary), m.
    pub position: Vec2,
    /// Centroid velocity, m/s.
    pub velocity: Vec2,
    /// Angular velocity, rad/s.
    pub angular_velocity: f64,
    /// Mass, kg (infinite for prescribed motion).
    pub mass_kg: f64,
    /// Thickness, m.
    pub thickness_m: f64,
    /// Area, m^2.
    pub area_m2: f64,
    /// Whether the floe moves under forces.
    pub free: bool,
}

impl Body {
    /// Floe `h` of `f`, at `offset` from its stored position (an image
    /// across a periodic boundary).
    #[inline(always)]
    pub fn of(f: &crate::floes::FloeColumns, h: usize, offset: Vec2) -> Self {
        Body {
            position: f.position[h] + offset,
            velocity: f.velocity[h],
            angular_velocity: f.angular_velocity[h],
            mass_kg: f.mass_kg[h],
            thickness_m: f.thickness_m[h],
            area_m2: f.area_m2[h],
            free: f.is_free(h),
        }
    }
}

/// Normal force per unit overlap area, `kappa`, Pa, for two floes.
#[inline]
pub fn overlap_stiffness(model: &ContactModel, a: &Body, b: &Body) -> f64 {
    let e = model.youngs_modulus_pa;
    let (ra, rb) = (a.area_m2.sqrt(), b.area_m2.sqrt());
    match (a.free, b.free) {
        (true, true) => {
            e * a.thickness_m * b.thickness_m / (a.thickness_m * rb + b.thickness_m * ra)
        }
        (true, false) => e * a.thickness_m / ra,
        (false, true) => e * b.thickness_m / rb,
        (false, false) => 0.0,
    }
}

impl ContactRecord {
    /// The record of a contact that has just formed between `a` and `b`
    /// (the second at `image_offset`), holding what
    /// [`contact_before_friction`] carries into its first step: the new
    /// contact's friction state `friction`
    /// ([`crate::pipeline::friction::new_contact_state`]), and
    /// as stored energy that of a strip overlap, `F_el^2 / (2 kappa l)`:
    /// exact for edge-to-edge overlaps and negligible for any contact that
    /// forms during a run (it forms at a tiny overlap); it matters only for
    /// floes placed overlapping at the start.
    pub fn new_contact(
        model: &ContactModel,
        friction: ContactState,
        ov: &Overlap,
        a: &Body,
        b: &Body,
        (a_handle, b_handle): (u32, u32),
        image_offset: Vec2,
    ) -> Self {
        let kappa = overlap_stiffness(model, a, b);
        let elastic = kappa * ov.area_m2;
        let k_n = kappa * ov.length_m.max(f64::MIN_POSITIVE);
        Self {
            a: a_handle,
            b: b_handle,
            image_offset,
            friction,
            age_steps: 0,
            overlap_m2: 0.0,
            point: Vec2::ZERO,
            normal: Vec2::ZERO,
            length_m: 0.0,
            normal_force_n: 0.0,
            slip_rate_m_per_s: 0.0,
            friction_power_w: 0.0,
            damping_power_w: 0.0,
            elastic_force_n: elastic,
            normal_energy_j: if k_n > 0.0 {
                0.5 * elastic * elastic / k_n
            } else {
                0.0
            },
            tangential_energy_j: 0.0,
        }
    }
}

/// The first of a contact's three calls in a step: sets the overlap and
/// the normal force of `record` and returns the friction step's load and
/// the power of the elastic normal force on the approach (W). `record`
/// comes in as the previous step left it (or as
/// [`ContactRecord::new_contact`] made it): its friction state, elastic
/// force and stored energies are what the contact carries. The force on
/// `b` is `normal_force n + tangential_force t` applied at `point`; `a`
/// gets the opposite. `damping_ratio` is `model.damping_ratio()`, which the
/// caller computes once per step: a logarithm and a square root per
/// contact were 1 % of a step.
///
/// Then the law's step on the returned load and `record.friction`
/// (`FrictionLaw::step`, or `Law::step_batch` for many contacts at once, as
/// the world does), then [`finish_friction`]. The record is updated in
/// place, not returned: copying the 168 B record and the friction step's
/// items in and out was about 1 % of a step's instructions.
#[inline]
pub fn contact_before_friction(
    model: &ContactModel,
    damping_ratio: f64,
    a: &Body,
    b: &Body,
    ov: &Overlap,
    record: &mut ContactRecord,
) -> (ContactLoad, f64) {
    let n = ov.normal;
    let t = perp(n);
    let (ra, rb) = (ov.centroid - a.position, ov.centroid - b.position);
    let va = a.velocity + perp(ra) * a.angular_velocity;
    let vb = b.velocity + perp(rb) * b.angular_velocity;
    let v_rel = vb - va;
    let (v_n, v_t) = (v_rel.dot(n), v_rel.dot(t));

    let kappa = overlap_stiffness(model, a, b);
    let elastic = kappa * ov.area_m2;
    let k_n = kappa * ov.length_m.max(f64::MIN_POSITIVE);
    let reduced_mass = match (a.free, b.free) {
        (true, true) => a.mass_kg * b.mass_kg / (a.mass_kg + b.mass_kg),
        (true, false) => a.mass_kg,
        (false, true) => b.mass_kg,
        (false, false) => 0.0,
    };
    let damping = 2.0 * damping_ratio * (k_n * reduced_mass).sqrt();
    // v_n > 0 is separation: the dashpot resists it, and the contact never pulls.
    let normal = (elastic - damping * v_n).max(0.0);
    // >= 0 whichever way.
    let damping_power = (elastic - normal) * v_n;
    // Work of the elastic force over the step (trapezoid in the force,
    // penetration rate -v_n): exact storage for any overlap shape.
    let elastic_power = 0.5 * (record.elastic_force_n + elastic) * (-v_n);

    let k_t = k_n / (2.0 * (1.0 + model.poisson_ratio));
    record.overlap_m2 = ov.area_m2;
    record.point = ov.centroid;
    record.normal = n;
    record.length_m = ov.length_m;
    record.normal_force_n = normal;
    record.slip_rate_m_per_s = 0.0;
    record.friction_power_w = 0.0;
    record.damping_power_w = damping_power.max(0.0);
    record.elastic_force_n = elastic;
    let load = ContactLoad {
        load_point_velocity_m_per_s: v_t,
        stiffness_n_per_m: k_t,
        normal_load_n: normal,
    };
    (load, elastic_power)
}

/// Completes a record from its friction step: `item` holds the step's load
/// and, unless `dt` is zero (no step taken), the state and outcome the
/// law's step wrote; `elastic_power_w` is [`contact_before_friction`]'s.
#[inline]
pub fn finish_friction(
    record: &mut ContactRecord,
    item: &BatchItem,
    elastic_power_w: f64,
    dt: f64,
) {
    let old_force = record.friction.tangential_force_n;
    let (state, slip) = if dt > 0.0 {
        (item.state, item.outcome.slip_rate_m_per_s)
    } else {
        (record.friction, 0.0)
    };
    // The load point's velocity is the relative tangential velocity.
    let v_t = item.load.load_point_velocity_m_per_s;
    // The kicks apply the old spring force over the first half step and the
    // new one over the second: energy accounting uses their mean. Of the
    // work it does on the relative tangential motion, the part on the slip is
    // dissipated and the rest is stored in the spring (integrated, not
    // F^2/2k: k_t follows the contact length, which changes under the force).
    let mean_tangential = 0.5 * (old_force + state.tangential_force_n);
    record.friction = state;
    record.slip_rate_m_per_s = slip;
    record.friction_power_w = mean_tangential * slip;
    record.tangential_energy_j += mean_tangential * (v_t - slip) * dt;
    record.normal_energy_j += elastic_power_w * dt;
}

/// Force on `b` and the torques on `a` and `b` of a contact record.
#[inline]
pub fn force_and_torques(
    c: &ContactRecord,
    a_position: Vec2,
    b_position: Vec2,
) -> (Vec2, f64, f64) {
    let f = contact_force_on_b(c);
    let torque_b = cross(c.point - b_position, f);
    let torque_a = cross(c.point - a_position, -f);
    (f, torque_a, torque_b)
}

/// Force on `b` of a contact record, N.
#[inline(always)]
pub fn contact_force_on_b(c: &ContactRecord) -> Vec2 {
    c.normal * c.normal_force_n + perp(c.normal) * c.tangential_force_n()
}

//! The integrator: velocity Verlet (kick-drift-kick), second order for
//! position-dependent forces, and the stable time step.
//!
//! A step is `v += a dt/2; x += v dt` (`drift`), then the forces at the
//! new positions (with the half-step velocity for drag, damping and
//! friction), then `v += a dt/2` (`kick`). Floes with prescribed motion
//! drift at their velocity and are never kicked.

use rayon::prelude::*;

use super::broad_phase::BroadPhase;
use super::energy_accounting::{forcing_power, ENERGY_CHUNK};
use crate::contact_kernel::{overlap_stiffness, Body};
use crate::contact_model::ContactModel;
use crate::floes::{FloeColumns, Motion};
use crate::periodicity::Periodicity;
use crate::Vec2;

/// Safety factor on the undamped single-contact limit `2 / omega`: a floe in
/// a packed tessellation has up to about six contacts, and the dashpot and
/// tangential spring shorten the limit further.
pub const STABILITY_SAFETY: f64 = 0.3;

/// The first half kick and the drift of every floe, and in the same pass
/// what the contact detection needs per floe: its rotation as `(sin, cos)`
/// in `trig`, and whether it moved beyond the broad phase's allowance.
/// Returns whether any floe did (the candidate list must be rebuilt). One
/// parallel region instead of three: at 1e3 floes waking the pool's
/// threads for each region was a visible part of a two-thread step.
pub(crate) fn drift(
    f: &mut FloeColumns,
    (force, torque): (&[Vec2], &[f64]),
    trig: &mut Vec<(f64, f64)>,
    broad_phase: &BroadPhase,
    periodicity: Periodicity,
    dt: f64,
) -> bool {
    let n = f.len();
    trig.resize(n, (0.0, 1.0));
    let FloeColumns {
        position,
        velocity,
        angle,
        angular_velocity,
        motion,
        mass_kg,
        inertia_kg_m2,
        ..
    } = f;
    (
        &mut position[..],
        &mut velocity[..],
        (&mut angle[..], &mut angular_velocity[..]),
        &mut trig[..],
    )
        .into_par_iter()
        .enumerate()
        .map(|(i, (x, v, (theta, omega), trig))| {
            if let Motion::Free = motion[i] {
                *v += force[i] / mass_kg[i] * (0.5 * dt);
                *omega += torque[i] / inertia_kg_m2[i] * (0.5 * dt);
            }
            *x = periodicity.wrap(*x + *v * dt);
            *theta += *omega * dt;
            *trig = theta.sin_cos();
            broad_phase.moved_beyond_allowance(i, *x, *theta, periodicity)
        })
        .reduce(|| false, |a, b| a || b)
}

/// The second half kick of every free floe, and in the same pass the power
/// of the external forces over the step, summed over fixed blocks of floes
/// into `forcing_partials` (see [`forcing_power`]).
#[allow(clippy::too_many_arguments)] // the step's arrays, each read once
pub(crate) fn kick(
    f: &mut FloeColumns,
    (force, torque): (&[Vec2], &[f64]),
    external: (&[Vec2], &[f64]),
    previous_external: (&[Vec2], &[f64]),
    forcing_partials: &mut Vec<f64>,
    dt: f64,
) {
    let FloeColumns {
        velocity,
        angular_velocity,
        motion,
        mass_kg,
        inertia_kg_m2,
        ..
    } = f;
    (
        velocity.par_chunks_mut(ENERGY_CHUNK),
        angular_velocity.par_chunks_mut(ENERGY_CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(block, (vs, omegas))| {
            let mut power_w = 0.0;
            for (k, (v, omega)) in vs.iter_mut().zip(omegas).enumerate() {
                let i = block * ENERGY_CHUNK + k;
                if let Motion::Free = motion[i] {
                    *v += force[i] / mass_kg[i] * (0.5 * dt);
                    *omega += torque[i] / inertia_kg_m2[i] * (0.5 * dt);
                    power_w += forcing_power(
                        (previous_external.0[i], previous_external.1[i]),
                        (external.0[i], external.1[i]),
                        *v,
                        *omega,
                    );
                }
            }
            power_w
        })
        .collect_into_vec(forcing_partials);
}

/// The largest stable time step and the floe that sets it: the smallest
/// of [`floe_stable_step`] over the free floes.
pub fn stable_time_step(floes: &FloeColumns, model: &ContactModel) -> (f64, usize) {
    let mut best = (f64::INFINITY, 0);
    for i in 0..floes.len() {
        if !floes.is_free(i) {
            continue;
        }
        let limit = floe_stable_step(
            floes.mass_kg[i],
            floes.inertia_kg_m2[i],
            floes.thickness_m[i],
            floes.area_m2[i],
            floes.radius_m[i],
            model,
        );
        if limit < best.0 {
            best = (limit, i);
        }
    }
    best
}

/// The largest stable time step of a free floe: `0.3 x 2/omega` with
/// `omega^2 = k / m_eff` for the stiffest contact it can have with a like
/// neighbour: contact length a diameter, `k = kappa 2 r`,
/// `m_eff = min(m/2, I / r^2)` (translation or rotation at the rim).
pub fn floe_stable_step(
    mass_kg: f64,
    inertia_kg_m2: f64,
    thickness_m: f64,
    area_m2: f64,
    radius_m: f64,
    model: &ContactModel,
) -> f64 {
    let body = Body {
        position: Vec2::ZERO,
        velocity: Vec2::ZERO,
        angular_velocity: 0.0,
        mass_kg,
        thickness_m,
        area_m2,
        free: true,
    };
    let k = overlap_stiffness(model, &body, &body) * 2.0 * radius_m;
    let r = radius_m;
    let m_eff = (0.5 * mass_kg).min(inertia_kg_m2 / (r * r));
    STABILITY_SAFETY * 2.0 * (m_eff / k).sqrt()
}

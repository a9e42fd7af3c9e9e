//! The integrator: velocity Verlet (kick-drift-kick), second order for
//! position-dependent forces, and the stable time step.
//!
//! A step is `v += a dt/2; x += v dt` (`drift`), then the forces at the
//! new positions (with the half-step velocity for drag, damping and
//! friction), then `v += a dt/2` (`kick`). The second kick is implicit in
//! the external forces (drag, Coriolis: `implicit_half_kick`), so
//! forcing that depends on velocity is second order in time too. Floes with
//! prescribed motion drift at their velocity and are never kicked.

use rayon::prelude::*;

use super::broad_phase::BroadPhase;
use super::energy_accounting::{counted_here, forcing_power, ENERGY_CHUNK};
use crate::contact_kernel::{overlap_stiffness, Body};
use crate::contact_model::ContactModel;
use crate::exact_sum::ExactSum;
use crate::floes::{FloeColumns, Motion};
use crate::forcing::ForceRates;
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
                (*v, *omega) = half_kicked(
                    (*v, *omega),
                    (force[i], torque[i]),
                    (mass_kg[i], inertia_kg_m2[i]),
                    dt,
                );
            }
            *x = periodicity.wrap(*x + *v * dt);
            *theta += *omega * dt;
            *trig = theta.sin_cos();
            broad_phase.moved_beyond_allowance(i, *x, *theta, periodicity)
        })
        .reduce(|| false, |a, b| a || b)
}

/// A free floe's velocity and angular velocity after the first half kick:
/// `v + F dt / 2m`, `omega + T dt / 2I`.
#[inline(always)]
pub(crate) fn half_kicked(
    (v, omega): (Vec2, f64),
    (force, torque): (Vec2, f64),
    (mass, inertia): (f64, f64),
    dt: f64,
) -> (Vec2, f64) {
    (
        v + force / mass * (0.5 * dt),
        omega + torque / inertia * (0.5 * dt),
    )
}

/// The step's forces as the second half kick reads and corrects them.
pub(crate) struct KickForces<'a> {
    /// Total force on each floe, N (its external part re-evaluated at the
    /// new velocity by the kick).
    pub(crate) force: &'a mut [Vec2],
    /// Total torque, N m.
    pub(crate) torque: &'a mut [f64],
    /// External force, N.
    pub(crate) external_force: &'a mut [Vec2],
    /// External torque, N m.
    pub(crate) external_torque: &'a mut [f64],
    /// The external forces' rates with the floe's velocity.
    pub(crate) rates: &'a [ForceRates],
}

/// The second half kick of every free floe, implicit in the external
/// forces (see [`implicit_half_kick`]), and in the same pass the power of
/// the external forces over the step, summed exactly over blocks of floes
/// into `forcing_partials` (see [`forcing_power`]), less the `ghost` floes.
pub(crate) fn kick(
    f: &mut FloeColumns,
    forces: KickForces<'_>,
    previous_external: (&[Vec2], &[f64]),
    (forcing_partials, ghost): (&mut Vec<ExactSum>, &[bool]),
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
    let KickForces {
        force,
        torque,
        external_force,
        external_torque,
        rates,
    } = forces;
    (
        (
            velocity.par_chunks_mut(ENERGY_CHUNK),
            angular_velocity.par_chunks_mut(ENERGY_CHUNK),
        ),
        (
            force.par_chunks_mut(ENERGY_CHUNK),
            torque.par_chunks_mut(ENERGY_CHUNK),
        ),
        (
            external_force.par_chunks_mut(ENERGY_CHUNK),
            external_torque.par_chunks_mut(ENERGY_CHUNK),
        ),
    )
        .into_par_iter()
        .enumerate()
        .map(|(block, ((vs, omegas), (fs, ts), (efs, ets)))| {
            let mut power_w = ExactSum::new();
            for (k, (v, omega)) in vs.iter_mut().zip(omegas).enumerate() {
                let i = block * ENERGY_CHUNK + k;
                if let Motion::Free = motion[i] {
                    let (v_half, omega_half) = (*v, *omega);
                    let (dv, dw) = implicit_half_kick(
                        (fs[k], ts[k]),
                        &rates[i],
                        (mass_kg[i], inertia_kg_m2[i]),
                        dt,
                    );
                    *v += dv;
                    *omega += dw;
                    // The external forces at the new velocity, to first
                    // order: what the next step's first half kick uses.
                    if rates[i] != ForceRates::ZERO {
                        let df = times(&rates[i].force_per_velocity, dv);
                        let dt_torque = rates[i].torque_per_angular_velocity * dw;
                        fs[k] += df;
                        efs[k] += df;
                        ts[k] += dt_torque;
                        ets[k] += dt_torque;
                    }
                    if counted_here(ghost, i as u32) {
                        power_w.add(forcing_power(
                            (previous_external.0[i], previous_external.1[i]),
                            (efs[k], ets[k]),
                            v_half,
                            omega_half,
                        ));
                    }
                }
            }
            power_w
        })
        .collect_into_vec(forcing_partials);
}

/// The velocity and angular velocity change of the second half kick:
/// `dv = dt/2m [F + J dv]` with `F` the force at the half-step velocity
/// and `J = ∂F_ext/∂u` (and likewise for the rotation), one Newton step of
/// the trapezoidal rule `v' = v + dt/2m [F(v) + F(v')]`. The forces the
/// drift used were evaluated at the start of the step, so the step is
/// second order in velocity-dependent forcing (`tests/dem/time_order.rs`).
/// The first half kick stays explicit, so drag far stiffer than the step
/// (`ρ C_d A |u_rel| dt / m` beyond about 2) still throws floes off.
/// With zero rates it is the explicit kick, bit for bit.
#[inline(always)]
pub(crate) fn implicit_half_kick(
    (force, torque): (Vec2, f64),
    rates: &ForceRates,
    (mass_kg, inertia_kg_m2): (f64, f64),
    dt: f64,
) -> (Vec2, f64) {
    let explicit_v = force / mass_kg * (0.5 * dt);
    let explicit_w = torque / inertia_kg_m2 * (0.5 * dt);
    if *rates == ForceRates::ZERO {
        return (explicit_v, explicit_w);
    }
    // (I - h J) dv = h F, h = dt / 2m.
    let h = 0.5 * dt / mass_kg;
    let j = &rates.force_per_velocity;
    let (a, b) = (1.0 - h * j[0][0], -h * j[0][1]);
    let (c, d) = (-h * j[1][0], 1.0 - h * j[1][1]);
    let det = a * d - b * c;
    let dv = if det.is_finite() && det > 0.0 {
        Vec2::new(
            (d * explicit_v.x - b * explicit_v.y) / det,
            (a * explicit_v.y - c * explicit_v.x) / det,
        )
    } else {
        explicit_v
    };
    let denominator = 1.0 - 0.5 * dt / inertia_kg_m2 * rates.torque_per_angular_velocity;
    let dw = if denominator.is_finite() && denominator > 0.0 {
        explicit_w / denominator
    } else {
        explicit_w
    };
    (dv, dw)
}

/// `m v` for a 2 x 2 matrix given row by row.
#[inline(always)]
fn times(m: &[[f64; 2]; 2], v: Vec2) -> Vec2 {
    Vec2::new(m[0][0] * v.x + m[0][1] * v.y, m[1][0] * v.x + m[1][1] * v.y)
}

/// The largest stable time step and the floe that sets it: the smallest
/// of [`floe_stable_step`] over the free floes.
pub fn stable_time_step(floes: &FloeColumns, model: &ContactModel) -> (f64, usize) {
    let mut best = (f64::INFINITY, 0);
    let damping = damping_step_factor(model);
    for i in 0..floes.len() {
        if !floes.is_free(i) {
            continue;
        }
        let limit = damping
            * undamped_stable_step(
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
/// `m_eff = min(m/2, I / r^2)` (translation or rotation at the rim), times
/// [`damping_step_factor`].
pub fn floe_stable_step(
    mass_kg: f64,
    inertia_kg_m2: f64,
    thickness_m: f64,
    area_m2: f64,
    radius_m: f64,
    model: &ContactModel,
) -> f64 {
    damping_step_factor(model)
        * undamped_stable_step(
            mass_kg,
            inertia_kg_m2,
            thickness_m,
            area_m2,
            radius_m,
            model,
        )
}

/// How much a strong dashpot shortens the stable step. An explicit
/// damped oscillator is stable for `omega dt < 2 (sqrt(1 + zeta^2) - zeta)`
/// (`1/zeta` for a strong dashpot). The safety factor was set for `zeta <=
/// 1`, all the textbook restitution mapping ever gave; a clipped dashpot
/// needs `zeta > 1` for restitution below `e^-2 = 0.135` (2 at 0.05), and
/// the step then shrinks by `(sqrt(1 + zeta^2) - zeta) / (sqrt 2 - 1)`.
/// 1 (no root search) at restitution `e^-2` and above.
pub fn damping_step_factor(model: &ContactModel) -> f64 {
    if model.restitution >= (-2.0f64).exp() {
        return 1.0;
    }
    let zeta = model.damping_ratio();
    (((1.0 + zeta * zeta).sqrt() - zeta) / (std::f64::consts::SQRT_2 - 1.0)).min(1.0)
}

/// [`floe_stable_step`] before [`damping_step_factor`].
fn undamped_stable_step(
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

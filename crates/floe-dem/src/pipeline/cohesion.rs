//! The cohesion stage (when on): bonds formed from contacts that stayed
//! quiet long enough, every bond's forces at the drifted positions and
//! half-step velocities, and the bonds whose load exceeds the strength of
//! their age broken, their stored energy counted as released. Runs after
//! the narrow phase; the force gathering then adds the bonds' forces in
//! bond order ([`add_bond_forces`]), after each floe's contacts, so the
//! sums are the same for any thread count and any split over processes.

use rayon::prelude::*;

use crate::bond_kernel::{evaluate_bond, form_bond, BondEnd};
use crate::bonds::Bond;
use crate::cohesion::Cohesion;
use crate::contact_model::ContactModel;
use crate::contacts::ContactRecord;
use crate::exact_sum::ExactSum;
use crate::floes::FloeColumns;
use crate::geometry::rotate;
use crate::periodicity::Periodicity;
use crate::Vec2;

use super::energy_accounting::{counted_here, BondPower};

/// What the cohesion stage reads.
pub(crate) struct CohesionInput<'a> {
    pub(crate) cohesion: &'a Cohesion,
    pub(crate) model: &'a ContactModel,
    pub(crate) damping_ratio: f64,
    pub(crate) floes: &'a FloeColumns,
    pub(crate) trig: &'a [(f64, f64)],
    pub(crate) periodicity: Periodicity,
    pub(crate) contacts: &'a [ContactRecord],
    /// Simulated time at the end of the step, s.
    pub(crate) time_s: f64,
    /// Per floe, whether it is another process's (empty: none is).
    pub(crate) ghost: &'a [bool],
}

/// Floe `h` as the bond kernel sees it, at `offset` (an image of it).
fn end(f: &FloeColumns, trig: &[(f64, f64)], h: usize, offset: Vec2) -> BondEnd {
    BondEnd::of(f, h, offset, trig[h])
}

/// The relative speed of `c`'s floes at its contact point, m/s.
fn contact_speed(f: &FloeColumns, c: &ContactRecord) -> f64 {
    let (a, b) = (c.a as usize, c.b as usize);
    let at = |h: usize, centroid: Vec2| {
        f.velocity[h] + crate::geometry::perp(c.point - centroid) * f.angular_velocity[h]
    };
    (at(b, f.position[b] + c.image_offset) - at(a, f.position[a])).length()
}

/// Updates `bonds` for the step: candidates from the quiet contacts,
/// bonds formed, every bond evaluated, the overloaded broken. Returns the
/// number broken; adds the step's energies to `power`. `fresh` is scratch
/// for the pairs that turned quiet this step.
pub(crate) fn update_bonds(
    input: &CohesionInput<'_>,
    bonds: &mut Vec<Bond>,
    fresh: &mut Vec<(usize, usize)>,
    power: &mut BondPower,
) -> usize {
    let f = input.floes;
    let cohesion = input.cohesion;
    let t = input.time_s;
    // Candidates and formations: a walk over the contacts and the bonds,
    // both sorted by pair, compacting the list in place (an entry is
    // written at or before where it was read). A formed bond stays; a
    // candidate stays while its contact is quiet, and forms once it has
    // been quiet long enough; a contact that turned quiet is noted in
    // `fresh` with where its candidate goes, and merged in afterwards (a
    // second list of every bond would double the memory bonds take).
    let formed_from = |candidate: &Bond, c: &ContactRecord| {
        let (ha, hb) = (c.a as usize, c.b as usize);
        let (ea, eb) = (
            end(f, input.trig, ha, Vec2::ZERO),
            end(f, input.trig, hb, c.image_offset),
        );
        form_bond(input.model, candidate, c, &ea, &eb, t)
    };
    let quiet = |c: &ContactRecord| {
        let (ha, hb) = (c.a as usize, c.b as usize);
        (f.is_free(ha) || f.is_free(hb)) && contact_speed(f, c) < cohesion.quiet_speed_m_per_s
    };
    fresh.clear();
    let (n, mut read, mut write) = (bonds.len(), 0, 0);
    let key = |b: &Bond| (b.a, b.b);
    for (k, c) in input.contacts.iter().enumerate() {
        let pair = (c.a, c.b);
        while read < n && key(&bonds[read]) < pair {
            if bonds[read].formed {
                bonds[write] = bonds[read];
                write += 1;
            }
            read += 1;
        }
        let previous = (read < n && key(&bonds[read]) == pair).then(|| {
            read += 1;
            bonds[read - 1]
        });
        if let Some(b) = previous.filter(|b| b.formed) {
            bonds[write] = b;
            write += 1;
            continue;
        }
        if !quiet(c) {
            continue;
        }
        match previous {
            Some(candidate) => {
                bonds[write] = if t - candidate.quiet_since_s >= cohesion.bond_after_s {
                    formed_from(&candidate, c)
                } else {
                    candidate
                };
                write += 1;
            }
            None => fresh.push((write, k)),
        }
    }
    while read < n {
        if bonds[read].formed {
            bonds[write] = bonds[read];
            write += 1;
        }
        read += 1;
    }
    bonds.truncate(write);
    // The new candidates into their places, from the back.
    let kept = bonds.len();
    let placeholder = Bond::candidate(0, 0, 0.0);
    bonds.resize(kept + fresh.len(), placeholder);
    let mut from = kept;
    for (j, &(at, k)) in fresh.iter().enumerate().rev() {
        let shift = j + 1;
        while from > at {
            from -= 1;
            bonds[from + shift] = bonds[from];
        }
        let c = &input.contacts[k];
        let candidate = Bond::candidate(c.a, c.b, t);
        bonds[at + j] = if t - candidate.quiet_since_s >= cohesion.bond_after_s {
            formed_from(&candidate, c)
        } else {
            candidate
        };
    }

    // Every bond's forces, then the breaks.
    bonds.par_iter_mut().filter(|b| b.formed).for_each(|bond| {
        let (ha, hb) = (bond.a as usize, bond.b as usize);
        let offset = input
            .periodicity
            .nearest_image(f.position[ha], f.position[hb]);
        let (ea, eb) = (
            end(f, input.trig, ha, Vec2::ZERO),
            end(f, input.trig, hb, offset),
        );
        evaluate_bond(input.model, input.damping_ratio, &ea, &eb, bond);
    });
    let before = bonds.len();
    bonds.retain(|bond| {
        if !bond.formed {
            return true;
        }
        let counted = counted_here(input.ghost, bond.a);
        let age = bond.age_s(t);
        let strength = cohesion.strength_fraction(age);
        // A bond formed this step carries only the round-off of its
        // anchors' rotation (about 1e-13 m), against a strength of zero
        // at age zero: it is judged from its next step on.
        let broken = age > 0.0
            && (bond.tension_n_per_m > strength * cohesion.tensile_strength_n_per_m
                || bond.shear_n_per_m > strength * cohesion.shear_strength_n_per_m);
        if counted {
            if broken {
                power.released_j.add(bond.energy_j);
            } else {
                power.damping_w.add(bond.damping_power_w);
                add_boundary_power(f, bond, &mut power.boundary_w);
            }
        }
        !broken
    });
    before - bonds.len()
}

/// The power a prescribed floe puts into the ice through `bond`, W:
/// minus the power of the bond's force and torque on it.
fn add_boundary_power(f: &FloeColumns, bond: &Bond, sum: &mut ExactSum) {
    let (a, b) = (bond.a as usize, bond.b as usize);
    if !f.is_free(a) {
        sum.add(bond.force_on_b.dot(f.velocity[a]) - bond.torque_on_a * f.angular_velocity[a]);
    }
    if !f.is_free(b) {
        sum.add(-bond.force_on_b.dot(f.velocity[b]) - bond.torque_on_b * f.angular_velocity[b]);
    }
}

/// Adds every formed bond's force and torques to its floes', in bond order.
pub(crate) fn add_bond_forces(bonds: &[Bond], force: &mut [Vec2], torque: &mut [f64]) {
    for bond in bonds.iter().filter(|b| b.formed) {
        let (a, b) = (bond.a as usize, bond.b as usize);
        force[a] -= bond.force_on_b;
        force[b] += bond.force_on_b;
        torque[a] += bond.torque_on_a;
        torque[b] += bond.torque_on_b;
    }
}

/// Adds every formed bond's Love-Weber moment (its force on the floe
/// times the arm from the centroid to its anchor, unnormalised, `[xx, xy
/// + yx, yy]` as [`super::floe_stress`] sums them) to its free floes'
/// entries of `moments`, in bond order.
pub(crate) fn add_bond_moments(
    f: &FloeColumns,
    trig: &[(f64, f64)],
    bonds: &[Bond],
    moments: &mut [[f64; 3]],
) {
    for bond in bonds.iter().filter(|b| b.formed) {
        let (a, b) = (bond.a as usize, bond.b as usize);
        let arm = |h: usize, anchor: Vec2| rotate(anchor, trig[h].1, trig[h].0);
        for (h, force, arm) in [
            (a, -bond.force_on_b, arm(a, bond.anchor_a)),
            (b, bond.force_on_b, arm(b, bond.anchor_b)),
        ] {
            if f.is_free(h) {
                let m = &mut moments[h];
                m[0] += force.x * arm.x;
                m[1] += force.x * arm.y + force.y * arm.x;
                m[2] += force.y * arm.y;
            }
        }
    }
}

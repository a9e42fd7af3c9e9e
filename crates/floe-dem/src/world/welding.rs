//! Welding between steps ([`crate::welding`]): pairs whose bond is old
//! enough become one floe, the convex hull of the two. This file: welding
//! on and off, the welds' records, the plan (one candidate per old bond)
//! and the choice among candidates; `welding_apply.rs` makes them.

use super::World;
use crate::bonds::Bond;
use crate::contacts::ContactRecord;
use crate::error::DemError;
use crate::floes::{Floe, Motion};
use crate::forcing::ExternalForces;
use crate::geometry::shape::{area_and_centroid, FloeShape};
use crate::geometry::{cross, rotate};
use crate::geometry::{overlap, ClipScratch, Placed};
use crate::welding::{Welding, WeldingLedger};
use crate::Vec2;

/// A pair welded into one floe, or a candidate for it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Weld {
    /// The step after which it welded.
    pub step: u64,
    /// Simulated time, s.
    pub time_s: f64,
    /// The two floes' ids, the smaller first.
    pub ids: [u64; 2],
    /// Their areas, m^2.
    pub areas_m2: [f64; 2],
    /// Their stored positions, m.
    pub positions_m: [Vec2; 2],
    /// Their angles, rad.
    pub angles_rad: [f64; 2],
    /// The welded floe (its id 0 until numbered; vertices about its
    /// centroid in world orientation, angle 0).
    pub floe: Floe,
    /// The second floe's centroid (its image touching the first) from the
    /// first's, m.
    pub second_offset_m: Vec2,
    /// The welded floe's centroid from the first's, m.
    pub centroid_offset_m: Vec2,
    /// The two floes' vertices from the first's centroid, in the world, m.
    pub outlines: [Vec<Vec2>; 2],
    /// The largest overlap the welded floe would add to a third floe's
    /// (beyond the pair's), over that floe's area (set when chosen).
    pub new_overlap_fraction: f64,
    /// How far the centre of mass moved (to the hull's centroid), m.
    pub centre_shift_m: f64,
    /// Kinetic energy lost in the merge, J.
    pub kinetic_energy_lost_j: f64,
    /// Elastic energy of the contacts and bonds the weld ended, J (set
    /// when made).
    pub released_j: f64,
}

/// What a floe's owner knows of it for a weld: every contact and bond it
/// has (named by ids) and its last forces. A distributed run gathers these
/// from the owners, so that every process merges the same records.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WeldRecords {
    /// The floe's id.
    pub id: u64,
    /// Its contacts.
    pub contacts: Vec<([u64; 2], ContactRecord)>,
    /// Its bonds and quiet pairs on their way to one.
    pub bonds: Vec<([u64; 2], Bond)>,
    /// Total force from the last evaluation, N.
    pub force: Vec2,
    /// Total torque, N m.
    pub torque: f64,
    /// External part of the force, N.
    pub external_force: Vec2,
    /// External part of the torque, N m.
    pub external_torque: f64,
}

impl WeldRecords {
    /// The ids of the floes it touches or is bonded to.
    fn partners(&self) -> impl Iterator<Item = u64> + '_ {
        let other = move |[x, y]: [u64; 2]| if x == self.id { y } else { x };
        (self.contacts.iter().map(move |(p, _)| other(*p)))
            .chain(self.bonds.iter().map(move |(p, _)| other(*p)))
    }
}

impl<F: ExternalForces> World<F> {
    /// Welds bonded floes from the next step on (`Some`; needs cohesion,
    /// which makes the bonds), or stops (`None`). The ledger is kept.
    pub fn set_welding(&mut self, welding: Option<Welding>) -> Result<(), DemError> {
        if let Some(w) = &welding {
            w.check()?;
            if self.cohesion.is_none() {
                return Err(DemError::InvalidModel {
                    reason: "welding joins bonded floes: turn cohesion on first".into(),
                });
            }
        }
        self.welding = welding;
        Ok(())
    }

    /// The welding parameters, if on.
    pub fn welding(&self) -> Option<Welding> {
        self.welding
    }

    /// What welding did since the start of the run.
    pub fn welding_ledger(&self) -> &WeldingLedger {
        &self.state.welding
    }

    /// Welding after a step, if on: plans, chooses and makes this step's
    /// welds, the welded floes numbered from the next free id.
    pub fn weld(&mut self) -> Result<Vec<Weld>, DemError> {
        let Some(welding) = self.welding else {
            return Ok(Vec::new());
        };
        if !welding.due(self.state.steps, self.state.dt_s) {
            return Ok(Vec::new());
        }
        let mut plans = self.plan_welding(&welding)?;
        if plans.is_empty() {
            return Ok(plans);
        }
        let fractions = self.new_overlap_fractions(&plans);
        for (p, x) in plans.iter_mut().zip(fractions) {
            p.new_overlap_fraction = x;
        }
        let ids = candidate_ids(&plans);
        let records = self.weld_records(&ids);
        let chosen = choose_welds(plans, &records);
        let first = self.first_free_id();
        let welds = self.apply_welding(chosen, &records, first)?;
        self.book_welds(&welds);
        Ok(welds)
    }

    /// Adds `welds` (every process's, the same list on each) to the ledger
    /// and moves the next free id past their floes.
    pub fn book_welds(&mut self, welds: &[Weld]) {
        let s = &mut self.state;
        for w in welds {
            s.welding.events += 1;
            s.welding.area_added_m2 += w.floe.area_m2 - (w.areas_m2[0] + w.areas_m2[1]);
            s.welding.kinetic_energy_lost_j += w.kinetic_energy_lost_j;
            s.welding.contact_energy_released_j += w.released_j;
            s.next_floe_id = s.next_floe_id.max(w.floe.id + 1);
        }
    }

    /// The candidates `welding` finds now, by pair: every formed bond at
    /// least `after_s` old between two free floes (the first this world's
    /// own, not on a load point) whose convex hull has at most 32 vertices,
    /// adds at most the allowed area, is at most the largest area, moves
    /// the centre of mass at most the allowed shift and is stable at the
    /// time step. Nothing changes.
    pub fn plan_welding(&self, welding: &Welding) -> Result<Vec<Weld>, DemError> {
        if self.pipeline.next != crate::pipeline::Stage::Drift {
            return Err(DemError::InvalidModel {
                reason: "welding runs between steps".into(),
            });
        }
        let f = self.state.floes.columns();
        let driven: Vec<u64> = self.state.load_points.iter().map(|l| l.floe_id).collect();
        let time_s = self.state.time_s;
        let mut plans = Vec::new();
        for bond in self.state.bonds.iter().filter(|b| b.formed) {
            let (a, b) = (bond.a as usize, bond.b as usize);
            if bond.age_s(time_s) < welding.after_s
                || !(f.is_free(a) && f.is_free(b))
                || self.is_ghost(a)
                || driven.contains(&f.id[a])
                || driven.contains(&f.id[b])
            {
                continue;
            }
            if let Some(plan) = self.plan_weld(welding, a, b) {
                plans.push(plan);
            }
        }
        Ok(plans)
    }

    /// The weld of floes `a` and `b` (handles), if the rule allows it.
    fn plan_weld(&self, welding: &Welding, a: usize, b: usize) -> Option<Weld> {
        let f = self.state.floes.columns();
        let (pa, pb) = (f.position[a], f.position[b]);
        let d = pb + self.periodicity.nearest_image(pa, pb) - pa;
        let oriented = |h: usize, at: Vec2| {
            let (sin, cos) = f.angle[h].sin_cos();
            f.local_vertices(h)
                .iter()
                .map(move |&v| at + rotate(v, cos, sin))
        };
        let outlines: [Vec<Vec2>; 2] =
            [oriented(a, Vec2::ZERO).collect(), oriented(b, d).collect()];
        let points = [&outlines[0][..], &outlines[1][..]].concat();
        let hull = parry2d_f64::transformation::convex_hull(&points);
        if hull.len() > crate::geometry::MAX_VERTICES {
            return None;
        }
        let (shape, c) = FloeShape::from_world(0, &hull).ok()?;
        let pair_area = f.area_m2[a] + f.area_m2[b];
        if shape.area_m2 > welding.max_area_m2
            || shape.area_m2 > pair_area * (1.0 + welding.max_added_area_fraction)
        {
            return None;
        }
        let (ma, mb) = (f.mass_kg[a], f.mass_kg[b]);
        let mass = ma + mb;
        let mass_centre = d * (mb / mass);
        let shift = c - mass_centre;
        if shift.length() > welding.max_centre_shift_fraction * shape.radius_m {
            return None;
        }
        let (va, vb) = (f.velocity[a], f.velocity[b]);
        let (wa, wb) = (f.angular_velocity[a], f.angular_velocity[b]);
        let (ia, ib) = (f.inertia_kg_m2[a], f.inertia_kg_m2[b]);
        let velocity = (va * ma + vb * mb) / mass;
        // Angular momentum about the pair's centre of mass, then about the
        // hull's centroid, where the welded floe's spin is taken.
        let about_mass_centre =
            ia * wa + ib * wb + ma * cross(-mass_centre, va) + mb * cross(d - mass_centre, vb);
        let inertia = mass / shape.area_m2 * shape.polar_moment_m4;
        let angular_velocity = (about_mass_centre - mass * cross(shift, velocity)) / inertia;
        let volume = f.area_m2[a] * f.thickness_m[a] + f.area_m2[b] * f.thickness_m[b];
        let kinetic = |m: f64, v: Vec2, i: f64, w: f64| 0.5 * (m * v.length_squared() + i * w * w);
        let floe = Floe {
            id: 0,
            position: self.periodicity.wrap(pa + c),
            angle: 0.0,
            velocity,
            angular_velocity,
            thickness_m: volume / shape.area_m2,
            mass_kg: mass,
            inertia_kg_m2: inertia,
            area_m2: shape.area_m2,
            radius_m: shape.radius_m,
            r3_moment_m5: crate::geometry::polygon_r3_moment(&shape.vertices),
            motion: Motion::Free,
            vertices: shape.vertices,
        };
        if self.state.dt_s > self.stable_step_of(&floe) {
            return None;
        }
        let lost = kinetic(ma, va, ia, wa) + kinetic(mb, vb, ib, wb)
            - kinetic(mass, velocity, inertia, angular_velocity);
        Some(Weld {
            step: self.state.steps,
            time_s: self.state.time_s,
            ids: [f.id[a], f.id[b]],
            areas_m2: [f.area_m2[a], f.area_m2[b]],
            positions_m: [pa, pb],
            angles_rad: [f.angle[a], f.angle[b]],
            floe,
            second_offset_m: d,
            centroid_offset_m: c,
            outlines,
            new_overlap_fraction: 0.0,
            centre_shift_m: shift.length(),
            kinetic_energy_lost_j: lost,
            released_j: 0.0,
        })
    }

    /// For each of `plans`, the largest overlap its welded floe would add
    /// to a floe of this world (owner or ghost, the pair's two apart) over
    /// that floe's area: the overlap with the hull less those with the two
    /// floes. Every process holding a floe finds the same number for it,
    /// so a distributed run takes the largest over processes.
    pub fn new_overlap_fractions(&self, plans: &[Weld]) -> Vec<f64> {
        let f = self.state.floes.columns();
        let mut scratch = ClipScratch::default();
        plans
            .iter()
            .map(|plan| {
                let weld = &plan.floe;
                let first = weld.position - plan.centroid_offset_m;
                let about = |outline: &[Vec2]| -> (Vec<Vec2>, Vec2, f64) {
                    let (_, centre) = area_and_centroid(outline);
                    let v: Vec<Vec2> = outline.iter().map(|&p| p - centre).collect();
                    let r = v.iter().map(|p| p.length()).fold(0.0, f64::max);
                    (v, first + centre, r)
                };
                let parts = [about(&plan.outlines[0]), about(&plan.outlines[1])];
                let mut worst = 0.0f64;
                for c in 0..f.len() {
                    if plan.ids.contains(&f.id[c]) {
                        continue;
                    }
                    let at = f.position[c]
                        + self.periodicity.nearest_image(weld.position, f.position[c]);
                    if (at - weld.position).length() >= f.radius_m[c] + weld.radius_m {
                        continue;
                    }
                    let (sin, cos) = f.angle[c].sin_cos();
                    let other = Placed {
                        vertices: f.local_vertices(c),
                        position: at,
                        cos,
                        sin,
                        radius_m: f.radius_m[c],
                    };
                    let mut area =
                        |p: Placed| overlap(p, other, &mut scratch).map_or(0.0, |o| o.area_m2);
                    let hull = area(upright(&weld.vertices, weld.position, weld.radius_m));
                    if hull == 0.0 {
                        continue;
                    }
                    let before: f64 = parts.iter().map(|(v, p, r)| area(upright(v, *p, *r))).sum();
                    worst = worst.max((hull - before) / f.area_m2[c]);
                }
                worst
            })
            .collect()
    }

    /// [`WeldRecords`] of the floes of `ids` this world owns (not ghosts),
    /// in id order.
    pub fn weld_records(&self, ids: &[u64]) -> Vec<WeldRecords> {
        let s = &self.state;
        let f = s.floes.columns();
        let named = |a: u32, b: u32| [f.id[a as usize], f.id[b as usize]];
        ids.iter()
            .filter_map(|&id| f.id.binary_search(&id).ok().map(|h| (id, h)))
            .filter(|&(_, h)| !self.is_ghost(h))
            .map(|(id, h)| {
                let touches = |a: u32, b: u32| a as usize == h || b as usize == h;
                WeldRecords {
                    id,
                    contacts: (s.contacts.iter())
                        .filter(|c| touches(c.a, c.b))
                        .map(|c| (named(c.a, c.b), *c))
                        .collect(),
                    bonds: (s.bonds.iter())
                        .filter(|b| touches(b.a, b.b))
                        .map(|b| (named(b.a, b.b), *b))
                        .collect(),
                    force: s.force[h],
                    torque: s.torque[h],
                    external_force: s.external_force[h],
                    external_torque: s.external_torque[h],
                }
            })
            .collect()
    }
}

/// A polygon in world orientation (`vertices` about `position`) for the clipper.
fn upright(vertices: &[Vec2], position: Vec2, radius_m: f64) -> Placed<'_> {
    Placed {
        vertices,
        position,
        cos: 1.0,
        sin: 0.0,
        radius_m,
    }
}

/// The floes of `plans`, sorted, each once.
pub fn candidate_ids(plans: &[Weld]) -> Vec<u64> {
    let mut ids: Vec<u64> = plans.iter().flat_map(|p| p.ids).collect();
    ids.sort_unstable();
    ids.dedup();
    ids
}

/// The most overlap a weld may add to a third floe, as a fraction of that
/// floe's area: a hull reaching over a floe in the notch between the pair
/// (or over a neighbour the pair was tilted against) would press it with a
/// force out of all proportion to its contacts' (1e-3 of a 100 m square is
/// a 10 cm deep overlap along a side).
pub const MAX_NEW_OVERLAP_FRACTION: f64 = 1e-3;

/// The welds made this step among the candidates `plans`, in pair order:
/// a candidate is taken unless its hull would press on a third floe
/// ([`MAX_NEW_OVERLAP_FRACTION`]) or one of its floes touches or is bonded
/// to a floe of a weld already taken (or is one), so that no weld changes a
/// contact another reads; the rest wait for a later step. `records`
/// (sorted by id) must hold both floes of every candidate.
pub fn choose_welds(mut plans: Vec<Weld>, records: &[WeldRecords]) -> Vec<Weld> {
    plans.sort_by_key(|p| p.ids);
    let find = |id: u64| {
        records
            .binary_search_by_key(&id, |r| r.id)
            .ok()
            .map(|k| &records[k])
    };
    // Floes of welds taken, and those next to them.
    let mut taken: Vec<u64> = Vec::new();
    let mut near: Vec<u64> = Vec::new();
    let mut chosen = Vec::new();
    for plan in plans {
        let (Some(ra), Some(rb)) = (find(plan.ids[0]), find(plan.ids[1])) else {
            continue;
        };
        let mut reach: Vec<u64> = ra.partners().chain(rb.partners()).chain(plan.ids).collect();
        reach.sort_unstable();
        reach.dedup();
        if plan.new_overlap_fraction > MAX_NEW_OVERLAP_FRACTION {
            continue;
        }
        let clash = plan.ids.iter().any(|id| near.binary_search(id).is_ok())
            || reach.iter().any(|id| taken.binary_search(id).is_ok());
        if clash {
            continue;
        }
        for id in plan.ids {
            let at = taken.partition_point(|&t| t < id);
            taken.insert(at, id);
        }
        near.extend(reach);
        near.sort_unstable();
        near.dedup();
        chosen.push(plan);
    }
    chosen
}

//! Welds made ([`crate::welding`]): the two floes taken out, the welded
//! floe put in with their contacts and bonds moved to it; where both had a
//! contact (or a bond) with the same third floe, one is kept.

use super::edits::DetachedFloe;
use super::split::{piece_forces, rekey, rekey_bond};
use super::welding::{Weld, WeldRecords};
use super::World;
use crate::bonds::Bond;
use crate::contacts::ContactRecord;
use crate::error::DemError;
use crate::forcing::ExternalForces;
use crate::geometry::{cross, rotate};
use crate::Vec2;

/// A record of one of the pair's floes for the welded floe: which of the
/// two it came from (0 or 1) and the other floe's id.
struct Moved<T> {
    from: usize,
    other: u64,
    record: T,
}

/// Which of two records of the same third floe the welded floe keeps: the
/// contact (or bond) along the longer length, the first floe's on a tie;
/// a formed bond before a quiet pair, and of two quiet pairs the one quiet
/// longer.
trait Kept {
    fn better_than(&self, other: &Self) -> bool;
    fn energy_j(&self) -> f64;
}

impl Kept for ContactRecord {
    fn better_than(&self, other: &Self) -> bool {
        self.length_m > other.length_m
    }
    fn energy_j(&self) -> f64 {
        self.elastic_energy_j()
    }
}

impl Kept for Bond {
    fn better_than(&self, other: &Self) -> bool {
        match (self.formed, other.formed) {
            (true, false) => true,
            (false, true) => false,
            (true, true) => self.length_m > other.length_m,
            (false, false) => self.quiet_since_s < other.quiet_since_s,
        }
    }
    fn energy_j(&self) -> f64 {
        if self.formed {
            self.energy_j
        } else {
            0.0
        }
    }
}

/// The pair's records with third floes, one per third floe (by id), and
/// the elastic energy of those dropped and of the pair's own, J.
fn merged<T: Kept + Copy>(ids: [u64; 2], lists: [&[([u64; 2], T)]; 2]) -> (Vec<Moved<T>>, f64) {
    let mut released = 0.0;
    let mut all: Vec<Moved<T>> = Vec::new();
    for (from, list) in lists.into_iter().enumerate() {
        for &([x, y], record) in list {
            if [x, y] == ids {
                // The pair's own: inside the welded floe now. Counted once.
                if from == 0 {
                    released += record.energy_j();
                }
                continue;
            }
            let other = if x == ids[from] { y } else { x };
            all.push(Moved {
                from,
                other,
                record,
            });
        }
    }
    all.sort_by_key(|m| (m.other, m.from));
    let mut kept: Vec<Moved<T>> = Vec::with_capacity(all.len());
    for m in all {
        match kept.last_mut() {
            Some(last) if last.other == m.other => {
                if m.record.better_than(&last.record) {
                    released += last.record.energy_j();
                    *last = m;
                } else {
                    released += m.record.energy_j();
                }
            }
            _ => kept.push(m),
        }
    }
    (kept, released)
}

impl<F: ExternalForces> World<F> {
    /// Makes `welds` (chosen by [`super::welding::choose_welds`], in that
    /// order) on the floes this world holds, the welded floes numbered from
    /// `first_id`; `records` (sorted by id) are the pairs' owners'. Every
    /// weld is returned with its id and released energy, whether or not
    /// this world holds its floes (a distributed run's processes each make
    /// those they hold, and all return the same list).
    pub fn apply_welding(
        &mut self,
        welds: Vec<Weld>,
        records: &[WeldRecords],
        first_id: u64,
    ) -> Result<Vec<Weld>, DemError> {
        let find = |id: u64| {
            records
                .binary_search_by_key(&id, |r| r.id)
                .map(|k| &records[k])
                .map_err(|_| DemError::InvalidModel {
                    reason: format!("welding: no records of floe {id}"),
                })
        };
        let mut made = Vec::with_capacity(welds.len());
        for (k, mut weld) in welds.into_iter().enumerate() {
            weld.floe.id = first_id + k as u64;
            let pair = [find(weld.ids[0])?, find(weld.ids[1])?];
            let (contacts, from_contacts) =
                merged(weld.ids, [&pair[0].contacts[..], &pair[1].contacts[..]]);
            let (bonds, from_bonds) = merged(weld.ids, [&pair[0].bonds[..], &pair[1].bonds[..]]);
            weld.released_j = from_contacts + from_bonds;
            let held = weld
                .ids
                .iter()
                .any(|&id| self.state.floes.handle_of(id).is_some());
            if held {
                self.make_weld(&weld, pair, contacts, bonds)?;
            }
            made.push(weld);
        }
        Ok(made)
    }

    /// Replaces the pair of `weld` by its welded floe, with the `contacts`
    /// and `bonds` of the two (the owners' `pair` records, merged) whose
    /// other floe this world holds.
    fn make_weld(
        &mut self,
        weld: &Weld,
        pair: [&WeldRecords; 2],
        contacts: Vec<Moved<ContactRecord>>,
        bonds: Vec<Moved<Bond>>,
    ) -> Result<(), DemError> {
        // Each floe's stored position and angle, and its centroid from the
        // welded floe's: from the plan, the same on every process.
        let c = weld.centroid_offset_m;
        let frames: [(Vec2, f64, Vec2); 2] = [0, 1].map(|k| {
            let centre = [Vec2::ZERO, weld.second_offset_m][k];
            (weld.positions_m[k], weld.angles_rad[k], centre - c)
        });
        for id in weld.ids {
            if self.state.floes.handle_of(id).is_some() {
                self.remove_floe(id)?;
            }
        }
        // Every kept record in the welded floe's frame (its forces, for the
        // next half kick, are theirs on every process); only those whose
        // other floe this world holds go in.
        let held = |w: &Self, id: u64| w.state.floes.handle_of(id);
        let floe = &weld.floe;
        let mut moved_contacts = Vec::new();
        for m in contacts {
            let (position, _, offset) = frames[m.from];
            let parent_is_b = m.other < weld.ids[m.from];
            moved_contacts.push(rekey(
                m.record,
                parent_is_b,
                m.other,
                floe,
                position,
                -offset,
            ));
        }
        moved_contacts.sort_by_key(|(ids, _)| *ids);
        let mut moved_bonds: Vec<(([u64; 2], Bond), Vec2)> = Vec::new();
        for m in bonds {
            let (_, angle, offset) = frames[m.from];
            let parent_is_b = m.other < weld.ids[m.from];
            let anchor = if parent_is_b {
                m.record.anchor_b
            } else {
                m.record.anchor_a
            };
            let (sin, cos) = angle.sin_cos();
            let in_weld = rotate(anchor, cos, sin) + offset;
            // The other floe's angle places its anchor: needed only where
            // the bond goes in, that is where the other floe is held.
            let other_angle = held(self, m.other).map_or(0.0, |h| self.state.floes.angle[h]);
            let bond = rekey_bond(
                m.record,
                (parent_is_b, angle),
                (floe.id, in_weld),
                (m.other, other_angle),
            );
            moved_bonds.push((bond, -offset));
        }
        moved_bonds.sort_by_key(|(b, _)| b.0);
        // The external forces, their torques taken about the welded centroid.
        let mut external_force = Vec2::ZERO;
        let mut external_torque = 0.0;
        for (r, (_, _, offset)) in pair.iter().zip(frames) {
            external_force += r.external_force;
            external_torque += r.external_torque + cross(offset, r.external_force);
        }
        let (force, torque) = piece_forces(
            floe,
            &moved_contacts,
            moved_bonds.iter().map(|(b, offset)| (b, *offset)),
            (external_force, external_torque),
        );
        let other = |[x, y]: [u64; 2]| if x == floe.id { y } else { x };
        moved_contacts.retain(|(ids, _)| held(self, other(*ids)).is_some());
        let moved_bonds: Vec<([u64; 2], Bond)> = moved_bonds
            .into_iter()
            .map(|(b, _)| b)
            .filter(|(ids, _)| held(self, other(*ids)).is_some())
            .collect();
        self.insert_detached(DetachedFloe {
            floe: floe.clone(),
            force,
            torque,
            external_force,
            external_torque,
            contacts: moved_contacts,
            broken: Vec::new(),
            bonds: moved_bonds,
            stress: None,
        })
    }
}

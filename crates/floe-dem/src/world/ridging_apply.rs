//! Ridging's events made ([`crate::ridging`]): every loser's cut (in
//! place) or removal, then every gain, so that a floe that both loses and
//! gains in a step ends the same on any process; where ice given to a
//! floe that went whole ends.

use super::ridging::{PlannedRidge, RidgedIce, RidgingTally};
use super::World;
use crate::error::DemError;
use crate::floes::Floe;
use crate::forcing::ExternalForces;
use crate::geometry::shape::FloeShape;
use crate::geometry::{cross, perp, rotate};
use crate::Vec2;

impl<F: ExternalForces> World<F> {
    /// Makes `plans` (sorted by loser id, each loser once) on the floes this
    /// world holds: every loser's cut (or removal, when it goes whole),
    /// then every gain, in that order ([`final_gainers`] says where each
    /// ridged ice goes when its gainer went whole itself). The tally counts
    /// the events of this world's own floes (the loser's, or for the
    /// kinetic energy of a merge the gainer's).
    pub fn apply_ridging(&mut self, plans: &[PlannedRidge]) -> Result<RidgingTally, DemError> {
        let mut tally = RidgingTally::default();
        if plans.is_empty() {
            return Ok(tally);
        }
        let targets = final_gainers(plans);
        // Who is whose (a distributed run marks ghosts), before removals.
        let own = |w: &Self, id: u64| w.state.floes.handle_of(id).is_some_and(|h| !w.is_ghost(h));
        let owned: Vec<(bool, bool)> = plans
            .iter()
            .zip(&targets)
            .map(|(p, t)| (own(self, p.loser_id), own(self, t.id)))
            .collect();
        self.reshape_losers(plans)?;
        for ((p, t), &(loser_own, _)) in plans.iter().zip(&targets).zip(&owned) {
            if self.state.floes.handle_of(p.loser_id).is_none() {
                continue;
            }
            let released = if p.kept.is_empty() {
                self.crush(p.loser_id)?
            } else {
                self.cut_contact_energy(p)
            };
            if !loser_own {
                continue;
            }
            tally.events += 1;
            tally.sums[6].add(released);
            // Counted where the ice ends (see `final_gainers`).
            let ice = &p.ice;
            if t.free {
                tally.sums[0].add(ice.volume_m3);
            } else {
                let momentum = ice.velocity_m_per_s * ice.mass_kg;
                tally.sums[1].add(ice.volume_m3);
                tally.sums[2].add(momentum.x);
                tally.sums[3].add(momentum.y);
                tally.sums[4].add(
                    cross(ice.position_m, momentum) + ice.inertia_kg_m2 * ice.angular_velocity,
                );
                tally.sums[5].add(kinetic(
                    ice.mass_kg,
                    ice.velocity_m_per_s,
                    ice.inertia_kg_m2,
                    ice.angular_velocity,
                ));
            }
        }
        for ((p, t), &(loser_own, target_own)) in plans.iter().zip(&targets).zip(&owned) {
            if !t.free {
                continue;
            }
            // The loser's share first (its kept part holds it), then the
            // rest to the gainer; no share: all of it, unscaled.
            let to_gainer = if p.loser_share > 0.0 {
                let share = p.ice.scaled(p.loser_share);
                self.gain_if_held(p.loser_id, share, p.loser_arm_m, loser_own, &mut tally);
                p.ice.scaled(1.0 - p.loser_share)
            } else {
                p.ice
            };
            self.gain_if_held(t.id, to_gainer, t.arm_m, target_own, &mut tally);
        }
        Ok(tally)
    }

    /// Replaces each held loser of `plans` by its kept part, in place: its
    /// id, handle, angle, thickness and rigid motion (`v + omega x r` at
    /// its new centroid); mass by area; its contacts (a new stored
    /// position a period away moves their frame), bonds (anchors about the
    /// new centroid) and last forces (torque about the new centroid, the
    /// external share by mass) follow. The candidate list stays (the floe
    /// only shrank; the broad phase counts the centroid's shift as
    /// motion) but forgets the separating edges of the floes cut.
    fn reshape_losers(&mut self, plans: &[PlannedRidge]) -> Result<(), DemError> {
        let mut changes: Vec<(usize, Floe)> = Vec::new();
        let mut shifts: Vec<(usize, Vec2, Vec2, f64)> = Vec::new();
        for p in plans {
            if p.kept.is_empty() {
                continue;
            }
            let Some(h) = self.state.floes.handle_of(p.loser_id) else {
                continue;
            };
            let parent = self.state.floes.get(h);
            let (shape, offset) = FloeShape::from_world(0, &p.kept)?;
            let (sin, cos) = parent.angle.sin_cos();
            let body: Vec<Vec2> = shape
                .vertices
                .iter()
                .map(|&v| rotate(v, cos, -sin))
                .collect();
            let mass = parent.mass_kg * (shape.area_m2 / (shape.area_m2 + p.removed_area_m2));
            let position = self.periodicity.wrap(parent.position + offset);
            let floe = Floe {
                position,
                velocity: parent.velocity + perp(offset) * parent.angular_velocity,
                mass_kg: mass,
                inertia_kg_m2: mass / shape.area_m2 * shape.polar_moment_m4,
                area_m2: shape.area_m2,
                radius_m: shape.radius_m,
                r3_moment_m5: crate::geometry::polygon_r3_moment(&body),
                vertices: body,
                ..parent
            };
            let wrap = position - (parent.position + offset);
            shifts.push((h, offset, wrap, mass / parent.mass_kg));
            changes.push((h, floe));
        }
        if changes.is_empty() {
            return Ok(());
        }
        changes.sort_by_key(|(h, _)| *h);
        self.state.floes.replace_in_place(changes);
        let s = &mut self.state;
        let mut reshaped = vec![false; s.floes.len()];
        for &(h, offset, wrap, share) in &shifts {
            reshaped[h] = true;
            if wrap != Vec2::ZERO {
                for c in s.contacts.iter_mut() {
                    if c.a as usize == h {
                        c.point += wrap;
                        c.image_offset += wrap;
                    } else if c.b as usize == h {
                        c.image_offset -= wrap;
                    }
                }
            }
            let (sin, cos) = s.floes.angle[h].sin_cos();
            let in_body = rotate(offset, cos, -sin);
            for b in s.bonds.iter_mut() {
                if b.a as usize == h {
                    b.anchor_a -= in_body;
                }
                if b.b as usize == h {
                    b.anchor_b -= in_body;
                }
            }
            let (external, external_torque) = (s.external_force[h], s.external_torque[h]);
            let inside = s.force[h] - external;
            s.torque[h] =
                s.torque[h] - external_torque - cross(offset, inside) + external_torque * share;
            s.external_force[h] = external * share;
            s.external_torque[h] = external_torque * share;
            s.force[h] = inside + s.external_force[h];
            self.pipeline.broad_phase.add_slack(h, offset.length());
        }
        let p = &mut self.pipeline;
        p.narrow_phase
            .forget_shapes(&p.broad_phase.pairs, &reshaped);
        Ok(())
    }

    /// Takes floe `id` out whole (crushed into the ridge): the energy its
    /// contacts and bonds held, J.
    fn crush(&mut self, id: u64) -> Result<f64, DemError> {
        let d = self.remove_floe(id)?;
        let contacts: f64 = d.contacts.iter().map(|(_, c)| c.elastic_energy_j()).sum();
        let bonds: f64 = d
            .bonds
            .iter()
            .filter(|(_, b)| b.formed)
            .map(|(_, b)| b.energy_j)
            .sum();
        Ok(contacts + bonds)
    }

    /// The ridging contact's stored normal energy after the cut (that of
    /// the overlap left as a strip, `F d / 2`: an overlap-area force has no
    /// potential, so the integrated energy is reset to it), its elastic
    /// force the cap; the energy it no longer holds, J.
    fn cut_contact_energy(&mut self, p: &PlannedRidge) -> f64 {
        let (Some(x), Some(y)) = (
            self.state.floes.handle_of(p.loser_id.min(p.gainer_id)),
            self.state.floes.handle_of(p.loser_id.max(p.gainer_id)),
        ) else {
            return 0.0;
        };
        let pair = (x as u32, y as u32);
        let contacts = &mut self.state.contacts;
        let Ok(k) = contacts.binary_search_by(|c| (c.a, c.b).cmp(&pair)) else {
            return 0.0;
        };
        let c = &mut contacts[k];
        let before = c.normal_energy_j;
        c.normal_energy_j = p.stored_after_j;
        c.elastic_force_n = p.elastic_after_n;
        before - c.normal_energy_j
    }

    /// Floe `id`, if this world holds it, takes `ice` with its centroid at
    /// `arm_m` from the floe's ([`Self::gain`]); the kinetic energy lost
    /// goes to `tally` if `counted` (the floe is this world's own).
    fn gain_if_held(
        &mut self,
        id: u64,
        ice: RidgedIce,
        arm_m: Vec2,
        counted: bool,
        tally: &mut RidgingTally,
    ) {
        if let Some(h) = self.state.floes.handle_of(id) {
            let lost = self.gain(h, &RidgedIce { arm_m, ..ice });
            if counted {
                tally.sums[5].add(lost);
            }
        }
    }

    /// Floe `h` takes the ridged ice: its volume spread over the floe as
    /// thickness (centroid unchanged), momentum and angular momentum
    /// conserved; the kinetic energy lost in the merge, J.
    fn gain(&mut self, h: usize, ice: &RidgedIce) -> f64 {
        let f = self.state.floes.columns_mut();
        let (m, i, v, w) = (
            f.mass_kg[h],
            f.inertia_kg_m2[h],
            f.velocity[h],
            f.angular_velocity[h],
        );
        let mass = m + ice.mass_kg;
        let inertia = i * (mass / m);
        let velocity = (v * m + ice.velocity_m_per_s * ice.mass_kg) / mass;
        let spin = i * w
            + ice.inertia_kg_m2 * ice.angular_velocity
            + ice.mass_kg * cross(ice.arm_m, ice.velocity_m_per_s);
        let angular_velocity = spin / inertia;
        let before = kinetic(m, v, i, w)
            + kinetic(
                ice.mass_kg,
                ice.velocity_m_per_s,
                ice.inertia_kg_m2,
                ice.angular_velocity,
            );
        f.thickness_m[h] += ice.volume_m3 / f.area_m2[h];
        f.mass_kg[h] = mass;
        f.inertia_kg_m2[h] = inertia;
        f.velocity[h] = velocity;
        f.angular_velocity[h] = angular_velocity;
        before - kinetic(mass, velocity, inertia, angular_velocity)
    }
}

/// Kinetic energy of a rigid body, J.
fn kinetic(mass: f64, v: Vec2, inertia: f64, w: f64) -> f64 {
    0.5 * (mass * v.length_squared() + inertia * w * w)
}

/// Where a plan's ice ends: the floe (or wall) that takes it, whether it
/// moves under forces, and the ice's centroid from that floe's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IceTarget {
    /// The id of the floe or wall that takes the ice.
    pub id: u64,
    /// Whether it moves under forces (else the ice goes to the coast).
    pub free: bool,
    /// The ice's centroid from its centroid, m.
    pub arm_m: Vec2,
}

/// Each plan's [`IceTarget`]: its gainer, unless the gainer itself went
/// whole in this step; then that floe's own gainer, and so on (each step of
/// the chain goes to a thicker floe or a wall, so it ends), the arm moved
/// along.
pub fn final_gainers(plans: &[PlannedRidge]) -> Vec<IceTarget> {
    let whole = |id: u64| {
        plans
            .binary_search_by_key(&id, |p| p.loser_id)
            .ok()
            .map(|k| &plans[k])
            .filter(|p| p.kept.is_empty())
    };
    plans
        .iter()
        .map(|p| {
            let mut t = IceTarget {
                id: p.gainer_id,
                free: p.gainer_free,
                arm_m: p.ice.arm_m,
            };
            for _ in 0..plans.len() {
                let Some(q) = whole(t.id).filter(|_| t.free) else {
                    break;
                };
                // q's ice arm is q's centroid from its gainer's.
                t = IceTarget {
                    id: q.gainer_id,
                    free: q.gainer_free,
                    arm_m: t.arm_m + q.ice.arm_m,
                };
            }
            t
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(loser: u64, gainer: u64, free: bool, whole: bool, arm: Vec2) -> PlannedRidge {
        PlannedRidge {
            step: 1,
            loser_id: loser,
            gainer_id: gainer,
            gainer_free: free,
            kept: if whole {
                Vec::new()
            } else {
                vec![Vec2::ZERO; 3]
            },
            loser_area_m2: 1.0,
            removed_area_m2: 1.0,
            ice: RidgedIce {
                mass_kg: 1.0,
                volume_m3: 1.0,
                arm_m: arm,
                position_m: Vec2::ZERO,
                velocity_m_per_s: Vec2::ZERO,
                inertia_kg_m2: 1.0,
                angular_velocity: 0.0,
            },
            loser_share: 0.0,
            loser_arm_m: Vec2::ZERO,
            elastic_before_n: 1.0,
            elastic_after_n: 1.0,
            stored_after_j: 0.0,
        }
    }

    #[test]
    fn ice_given_to_a_floe_that_goes_whole_follows_it_to_its_gainer() {
        // 1 cuts onto 2; 2 goes whole onto 3; 3 goes whole onto wall 9; 4
        // cuts onto 5, which stays.
        let plans = vec![
            plan(1, 2, true, false, Vec2::new(1.0, 0.0)),
            plan(2, 3, true, true, Vec2::new(0.0, 10.0)),
            plan(3, 9, false, true, Vec2::new(100.0, 0.0)),
            plan(4, 5, true, false, Vec2::new(-1.0, 0.0)),
        ];
        let t = final_gainers(&plans);
        assert_eq!(
            t[0],
            IceTarget {
                id: 9,
                free: false,
                arm_m: Vec2::new(101.0, 10.0)
            }
        );
        assert_eq!(
            (t[1].id, t[1].free, t[1].arm_m),
            (9, false, Vec2::new(100.0, 10.0))
        );
        assert_eq!((t[2].id, t[2].free), (9, false));
        assert_eq!(
            (t[3].id, t[3].free, t[3].arm_m),
            (5, true, Vec2::new(-1.0, 0.0))
        );
    }
}

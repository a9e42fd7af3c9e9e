//! Ridging between steps ([`crate::ridging`]): each floe pressed past its
//! ridging strength loses the ice behind the cut to the thicker floe, or
//! to the coast. This file: the events' records, ridging on and off, and
//! the plan (from the state after a step, one event per loser);
//! `ridging_apply.rs` makes them.

use super::World;
use crate::contact_kernel::{overlap_stiffness, Body};
use crate::error::DemError;
use crate::exact_sum::{ExactSum, EXACT_SUM_WORDS};
use crate::floes::Floe;
use crate::forcing::ExternalForces;
use crate::geometry::shape::{area_and_centroid, polar_moment, FloeShape};
use crate::geometry::{perp, rotate};
use crate::ridging::cut::{ridge_cut, RidgingContact};
use crate::ridging::{Ridging, RidgingLedger, Rubble};
use crate::Vec2;

/// A floe whose kept part would carry, over all its contacts, overlaps at
/// their caps of more than this fraction of its area goes whole: a sliver
/// between pressing neighbours, a few capped penetrations wide, is rubble
/// (and no pair of its overlaps reaches the health check's 25 % of the
/// smaller floe while its contacts stay at or below their caps).
pub const CRUSHED_OVERLAP_FRACTION: f64 = 0.2;

/// The ice a loser gives up to the ridge.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RidgedIce {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Volume, m^3.
    pub volume_m3: f64,
    /// Its centroid from the gainer's (the gainer's touching image), m.
    pub arm_m: Vec2,
    /// Its centroid in the world (from the loser's stored position), m.
    pub position_m: Vec2,
    /// Its centroid's velocity (the loser's rigid motion there), m/s.
    pub velocity_m_per_s: Vec2,
    /// Its moment of inertia about its centroid, kg m^2.
    pub inertia_kg_m2: f64,
    /// Its angular velocity (the loser's), rad/s.
    pub angular_velocity: f64,
}

impl RidgedIce {
    /// The fraction `share` of the ice: mass, volume and moment of inertia
    /// scaled (the same shape at a fraction of the thickness), moving the
    /// same way from the same place.
    pub fn scaled(&self, share: f64) -> Self {
        RidgedIce {
            mass_kg: self.mass_kg * share,
            volume_m3: self.volume_m3 * share,
            inertia_kg_m2: self.inertia_kg_m2 * share,
            ..*self
        }
    }
}

/// A ridging event: a loser cut against a gainer, planned by
/// [`World::plan_ridging`] and made by [`World::apply_ridging`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PlannedRidge {
    /// The step after which it ridged.
    pub step: u64,
    /// The floe that loses ice.
    pub loser_id: u64,
    /// The thicker floe, or the wall, that takes it.
    pub gainer_id: u64,
    /// Whether the gainer moves under forces (else the ice goes to the coast).
    pub gainer_free: bool,
    /// The loser's part kept: vertices about its centroid, world
    /// orientation; empty when the whole floe goes (its kept part would
    /// have been under the smallest area, or too small for the time step).
    pub kept: Vec<Vec2>,
    /// The loser's area before the cut, m^2.
    pub loser_area_m2: f64,
    /// The ridged part's area, m^2.
    pub removed_area_m2: f64,
    /// The ice ridged (all of it, before [`PlannedRidge::loser_share`]
    /// is taken out).
    pub ice: RidgedIce,
    /// The fraction of the ice that stays on the loser's kept part as
    /// thickness ([`crate::ridging::Rubble::Both`]; 0 otherwise).
    pub loser_share: f64,
    /// The ice's centroid from the kept part's, m.
    pub loser_arm_m: Vec2,
    /// The contact's elastic force before the cut, N.
    pub elastic_before_n: f64,
    /// The contact's elastic force after it (the cap), N.
    pub elastic_after_n: f64,
    /// The contact's stored normal energy after it, `F d / 2` of the
    /// overlap left (`d` its mean depth), J.
    pub stored_after_j: f64,
}

/// Ridging's sums over one step's events, exact so that processes add
/// theirs in any order.
#[derive(Debug, Clone, Default)]
pub struct RidgingTally {
    /// Events.
    pub events: u64,
    /// `[volume to floes, volume to coast, momentum x, momentum y,
    /// angular momentum, kinetic energy lost, contact energy released]`.
    pub sums: [ExactSum; 7],
}

impl RidgingTally {
    /// Adds the tally to `ledger`.
    pub fn book(&self, ledger: &mut RidgingLedger) {
        let v = |k: usize| self.sums[k].value();
        ledger.events += self.events;
        ledger.volume_to_floes_m3 += v(0);
        ledger.volume_to_coast_m3 += v(1);
        ledger.momentum_to_coast_n_s += Vec2::new(v(2), v(3));
        ledger.angular_momentum_to_coast += v(4);
        ledger.kinetic_energy_lost_j += v(5);
        ledger.contact_energy_released_j += v(6);
    }

    /// The tally as integer words (the event count, then each sum's exact
    /// words) that add element-wise across processes; [`Self::from_words`]
    /// reads a sum of them back.
    pub fn to_words(&self) -> Vec<i64> {
        let mut words = vec![self.events as i64];
        for s in &self.sums {
            words.extend(s.to_words());
        }
        words
    }

    /// The tally whose words ([`Self::to_words`], perhaps summed over
    /// processes) are `words`.
    pub fn from_words(words: &[i64]) -> Self {
        let mut tally = RidgingTally {
            events: words[0] as u64,
            ..RidgingTally::default()
        };
        for (k, s) in tally.sums.iter_mut().enumerate() {
            let at = 1 + k * EXACT_SUM_WORDS;
            *s = ExactSum::from_words(&words[at..at + EXACT_SUM_WORDS].try_into().expect("words"));
        }
        tally
    }
}

impl<F: ExternalForces> World<F> {
    /// Ridges from the next step on (`Some`; [`Ridging::check`]ed), or
    /// stops (`None`). The ledger is kept either way.
    pub fn set_ridging(&mut self, ridging: Option<Ridging>) -> Result<(), DemError> {
        if let Some(r) = &ridging {
            r.check()?;
        }
        self.ridging = ridging;
        Ok(())
    }

    /// The ridging parameters, if on.
    pub fn ridging(&self) -> Option<Ridging> {
        self.ridging
    }

    /// What ridging has moved since the start of the run.
    pub fn ridging_ledger(&self) -> &RidgingLedger {
        &self.state.ridging
    }

    /// Ridging after a step, if on: plans and makes this step's events and
    /// books them in the ledger.
    pub fn ridge(&mut self) -> Result<Vec<PlannedRidge>, DemError> {
        let Some(ridging) = self.ridging else {
            return Ok(Vec::new());
        };
        let plans = self.plan_ridging(&ridging)?;
        let tally = self.apply_ridging(&plans)?;
        self.book_ridging(&tally);
        Ok(plans)
    }

    /// Adds `tally` (a distributed run's: every process's) to the ledger.
    pub fn book_ridging(&mut self, tally: &RidgingTally) {
        tally.book(&mut self.state.ridging);
    }

    /// The events `ridging` makes now, by loser id: for each of this
    /// world's own free floes (not ghosts, not on a load point, at most
    /// `max_thickness_m` thick) the contact most over its cap (elastic
    /// force over strength times contact length) whose other floe is
    /// thicker (or as thick and larger, or as large with a smaller id) or a
    /// wall, cut by [`ridge_cut`]. A cut whose kept part would be under
    /// `min_floe_area_m2`, not a valid floe or need a shorter time step is
    /// not made (the contact stays elastic this step). Nothing changes.
    pub fn plan_ridging(&self, ridging: &Ridging) -> Result<Vec<PlannedRidge>, DemError> {
        if self.pipeline.next != crate::pipeline::Stage::Drift {
            return Err(DemError::InvalidModel {
                reason: "ridging runs between steps".into(),
            });
        }
        let f = self.state.floes.columns();
        let driven: Vec<u64> = self.state.load_points.iter().map(|l| l.floe_id).collect();
        // Per loser handle: (over the cap by, partner id, contact index).
        let mut worst: Vec<Option<(f64, u64, usize)>> = vec![None; f.len()];
        // Each floe's strength per metre: one power per floe, not per contact.
        let strength: Vec<f64> = f
            .thickness_m
            .iter()
            .map(|&h| ridging.strength_at(h))
            .collect();
        for (k, c) in self.state.contacts.iter().enumerate() {
            let (a, b) = (c.a as usize, c.b as usize);
            let loser = match (f.is_free(a), f.is_free(b)) {
                (true, true) => {
                    let key =
                        |h: usize| (f.thickness_m[h], f.area_m2[h], std::cmp::Reverse(f.id[h]));
                    if key(a).partial_cmp(&key(b)) == Some(std::cmp::Ordering::Greater) {
                        b
                    } else {
                        a
                    }
                }
                (true, false) => a,
                (false, true) => b,
                (false, false) => continue,
            };
            if self.is_ghost(loser)
                || f.thickness_m[loser] > ridging.max_thickness_m
                || driven.contains(&f.id[loser])
            {
                continue;
            }
            let cap = strength[loser] * c.length_m;
            if c.elastic_force_n.partial_cmp(&cap) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            let over = c.elastic_force_n / cap;
            let partner = f.id[if loser == a { b } else { a }];
            let better = match worst[loser] {
                None => true,
                Some((o, p, _)) => over > o || (over == o && partner < p),
            };
            if better {
                worst[loser] = Some((over, partner, k));
            }
        }
        // Per loser: the overlap each of its contacts would hold at its cap,
        // `strength l / kappa`, summed (the crushing rule's measure).
        let mut at_caps = vec![0.0; f.len()];
        for (k, c) in self.state.contacts.iter().enumerate() {
            for (me, other) in [(c.a as usize, c.b as usize), (c.b as usize, c.a as usize)] {
                if worst[me].is_some_and(|(_, _, cut)| cut != k) {
                    let kappa = overlap_stiffness(
                        &self.model,
                        &Body::of(f, me, Vec2::ZERO),
                        &Body::of(f, other, Vec2::ZERO),
                    );
                    at_caps[me] += strength[me] * c.length_m / kappa;
                }
            }
        }
        let mut plans = Vec::new();
        for (loser, found) in worst.iter().enumerate() {
            if let Some((_, _, k)) = *found {
                if let Some(plan) = self.plan_cut(ridging, loser, k, at_caps[loser]) {
                    plans.push(plan);
                }
            }
        }
        Ok(plans)
    }

    /// The cut of floe `loser` at contact `k`, if one can be made.
    /// `others_at_cap_m2`: the overlaps the loser's other contacts would
    /// hold at their caps.
    fn plan_cut(
        &self,
        ridging: &Ridging,
        loser: usize,
        k: usize,
        others_at_cap_m2: f64,
    ) -> Option<PlannedRidge> {
        let f = self.state.floes.columns();
        let c = &self.state.contacts[k];
        let loser_is_a = c.a as usize == loser;
        let gainer = if loser_is_a { c.b } else { c.a } as usize;
        let (gainer_offset, normal) = if loser_is_a {
            (
                f.position[gainer] + c.image_offset - f.position[loser],
                c.normal,
            )
        } else {
            (
                f.position[gainer] - f.position[loser] - c.image_offset,
                -c.normal,
            )
        };
        let oriented = |h: usize| -> Vec<Vec2> {
            let (sin, cos) = f.angle[h].sin_cos();
            f.local_vertices(h)
                .iter()
                .map(|&v| rotate(v, cos, sin))
                .collect()
        };
        let (loser_poly, gainer_poly) = (oriented(loser), oriented(gainer));
        let (l_body, g_body) = (
            Body::of(f, loser, Vec2::ZERO),
            Body::of(f, gainer, Vec2::ZERO),
        );
        let model = &self.model;
        let stiffness = |area: f64| {
            let l = Body {
                area_m2: area,
                ..l_body
            };
            overlap_stiffness(model, &l, &g_body)
        };
        let contact = RidgingContact {
            loser: &loser_poly,
            gainer: &gainer_poly,
            gainer_offset,
            normal,
            strength_n_per_m: ridging.strength_at(f.thickness_m[loser]),
        };
        let cut = ridge_cut(&contact, stiffness)?;
        if cut.kept.len() > crate::geometry::MAX_VERTICES {
            return None;
        }
        let (v, w) = (f.velocity[loser], f.angular_velocity[loser]);
        let mut plan = PlannedRidge {
            step: self.state.steps,
            loser_id: f.id[loser],
            gainer_id: f.id[gainer],
            gainer_free: f.is_free(gainer),
            kept: Vec::new(),
            loser_area_m2: f.area_m2[loser],
            removed_area_m2: f.area_m2[loser],
            ice: RidgedIce {
                mass_kg: f.mass_kg[loser],
                volume_m3: f.area_m2[loser] * f.thickness_m[loser],
                arm_m: -gainer_offset,
                position_m: f.position[loser],
                velocity_m_per_s: v,
                inertia_kg_m2: f.inertia_kg_m2[loser],
                angular_velocity: w,
            },
            loser_share: 0.0,
            loser_arm_m: Vec2::ZERO,
            elastic_before_n: c.elastic_force_n,
            elastic_after_n: 0.0,
            stored_after_j: 0.0,
        };
        // A kept part too small (or too small for the time step, or so thin
        // that its overlaps at their caps would cover a fifth of it) is
        // crushed into the ridge with the rest: the whole floe goes.
        let Some((kept_shape, kept_centroid)) =
            FloeShape::from_world(0, &cut.kept).ok().filter(|(s, _)| {
                s.area_m2 >= ridging.min_floe_area_m2
                    && cut.overlap_after_m2 + others_at_cap_m2
                        <= CRUSHED_OVERLAP_FRACTION * s.area_m2
            })
        else {
            return Some(plan);
        };
        let (removed_area, removed_centroid) = area_and_centroid(&cut.removed);
        if removed_area.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let total = kept_shape.area_m2 + removed_area;
        let mass = f.mass_kg[loser];
        let kept_floe = Floe {
            mass_kg: mass * (kept_shape.area_m2 / total),
            inertia_kg_m2: mass * (kept_shape.area_m2 / total) / kept_shape.area_m2
                * kept_shape.polar_moment_m4,
            area_m2: kept_shape.area_m2,
            radius_m: kept_shape.radius_m,
            ..self.state.floes.get(loser)
        };
        if self.state.dt_s > self.stable_step_of(&kept_floe) {
            return Some(plan);
        }
        let removed_mass = mass * (removed_area / total);
        let about: Vec<Vec2> = cut.removed.iter().map(|&v| v - removed_centroid).collect();
        plan.kept = cut.kept;
        plan.removed_area_m2 = removed_area;
        plan.ice = RidgedIce {
            mass_kg: removed_mass,
            volume_m3: removed_area * f.thickness_m[loser],
            arm_m: removed_centroid - gainer_offset,
            position_m: f.position[loser] + removed_centroid,
            velocity_m_per_s: v + perp(removed_centroid) * w,
            inertia_kg_m2: removed_mass / removed_area * polar_moment(&about),
            angular_velocity: w,
        };
        if ridging.rubble == Rubble::Both && plan.gainer_free {
            // Both thicken by the same amount: shares by area.
            plan.loser_share = kept_shape.area_m2 / (kept_shape.area_m2 + f.area_m2[gainer]);
            plan.loser_arm_m = removed_centroid - kept_centroid;
        }
        plan.elastic_after_n = cut.elastic_after_n;
        plan.stored_after_j = cut.stored_after_j;
        Some(plan)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tallies_added_as_words_are_the_tally_of_all_their_terms() {
        // Two processes' tallies, summed word by word, against one tally
        // that took every term: the same ledger to the bit.
        let terms = [
            1e-300,
            3.5,
            -2.25e12,
            7.0e-3,
            -1.0,
            4.4e8,
            2.0_f64.powi(-60),
        ];
        let (mut p0, mut p1, mut one) = (
            RidgingTally::default(),
            RidgingTally::default(),
            RidgingTally::default(),
        );
        for (i, &x) in terms.iter().enumerate() {
            let part = if i % 2 == 0 { &mut p0 } else { &mut p1 };
            part.events += 1;
            one.events += 1;
            for (k, s) in part.sums.iter_mut().enumerate() {
                s.add(x * (k + 1) as f64);
            }
            for (k, s) in one.sums.iter_mut().enumerate() {
                s.add(x * (k + 1) as f64);
            }
        }
        let mut words = p0.to_words();
        for (w, v) in words.iter_mut().zip(p1.to_words()) {
            *w += v;
        }
        let (mut a, mut b) = (RidgingLedger::default(), RidgingLedger::default());
        RidgingTally::from_words(&words).book(&mut a);
        one.book(&mut b);
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
        assert_eq!(a.events, 7);
    }
}

//! Fracture between steps: the floes whose averaged stress lies outside
//! the criterion split into pieces with new ids, in id order.

use super::World;
use crate::error::DemError;
use crate::exact_sum::ExactSum;
use crate::forcing::ExternalForces;
use crate::fracture::rule::{FractureRule, StrengthThickness};
use crate::fracture::split::{split_polygon, SplitKey};
use crate::geometry::rotate;
use crate::pipeline::floe_stress::principal;
use crate::Vec2;

/// A floe the criterion broke, and what became of it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FractureEvent {
    /// The step after which it broke.
    pub step: u64,
    /// Simulated time, s.
    pub time_s: f64,
    /// The floe's id.
    pub parent_id: u64,
    /// Its principal stresses `(sigma_1, sigma_2)`, Pa.
    pub principal_pa: (f64, f64),
    /// Its area, m^2.
    pub area_m2: f64,
    /// The pieces' ids, in order; empty if it stayed whole.
    pub piece_ids: Vec<u64>,
    /// Why it stayed whole (no split fitted the rule, or a piece needed a
    /// shorter time step); `None` when it split.
    pub whole_because: Option<String>,
}

/// A floe the criterion breaks, with the pieces it will split into (or
/// why it stays whole): what [`World::plan_fracture`] finds and
/// [`World::apply_fracture`] carries out.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PlannedSplit {
    /// The event, its piece ids not yet given.
    pub event: FractureEvent,
    /// The pieces (vertices about the parent's centroid, world
    /// orientation); empty if it stays whole.
    pub pieces: Vec<Vec<Vec2>>,
}

/// The pack's thickness times area and area, over free floes (a distributed
/// run adds every process's).
#[derive(Debug, Clone, Default)]
pub struct PackSums {
    /// `sum h A`, m^3.
    pub thickness_area: ExactSum,
    /// `sum A`, m^2.
    pub area: ExactSum,
}

impl<F: ExternalForces> World<F> {
    /// When `rule` is due at this step: every free floe of at least
    /// `rule.min_floe_area_m2` whose averaged stress lies outside the
    /// criterion splits (`World::split_floe`) into the pieces of
    /// `fracture::split::split_polygon`, keyed on (seed, its id, the step),
    /// in id order, the pieces taking new ids counted up from the largest
    /// id the world has held. `domain_area_m2` gives the pack's
    /// concentration for Hibler's strength with [`StrengthThickness::Pack`].
    /// Needs floe stress on; between steps.
    pub fn fracture(
        &mut self,
        rule: &FractureRule,
        domain_area_m2: f64,
    ) -> Result<Vec<FractureEvent>, DemError> {
        if !rule.due(self.state.steps) {
            // Off the checks nothing changes, the next id included (as on
            // several processes).
            return self
                .plan_fracture(rule, &PackSums::default(), domain_area_m2)
                .map(|_| Vec::new());
        }
        let sums = self.pack_sums();
        let plans = self.plan_fracture(rule, &sums, domain_area_m2)?;
        let first = self.first_free_id();
        let events = self.apply_fracture(plans, first)?;
        let made: u64 = events.iter().map(|e| e.piece_ids.len() as u64).sum();
        self.state.next_floe_id = first + made;
        Ok(events)
    }

    /// The free floes' (not ghosts') thickness times area and area.
    pub fn pack_sums(&self) -> PackSums {
        let f = self.state.floes.columns();
        let mut sums = PackSums::default();
        for i in (0..f.len()).filter(|&i| f.is_free(i) && !self.is_ghost(i)) {
            sums.thickness_area.add(f.thickness_m[i] * f.area_m2[i]);
            sums.area.add(f.area_m2[i]);
        }
        sums
    }

    /// The smallest id no floe of this world has had: where fracture
    /// numbers its pieces from.
    pub fn first_free_id(&self) -> u64 {
        let f = self.state.floes.columns();
        self.state
            .next_floe_id
            .max(f.id.last().map_or(0, |&m| m + 1))
    }

    /// Sets where fracture numbers new floes from (a distributed run sets
    /// every process's to the whole run's).
    pub fn set_next_floe_id(&mut self, next: u64) {
        self.state.next_floe_id = next;
    }

    /// The splits `rule` makes at this step (none off its check steps), of
    /// this world's own free floes (not ghosts: their owners judge them;
    /// nor floes on a load point),
    /// in id order, with the pack's sums `sums` (all processes') for
    /// Hibler's pack strength. Nothing changes; a piece that would need a
    /// shorter time step leaves its floe whole here.
    pub fn plan_fracture(
        &self,
        rule: &FractureRule,
        sums: &PackSums,
        domain_area_m2: f64,
    ) -> Result<Vec<PlannedSplit>, DemError> {
        if self.state.stress_filter.is_none() {
            return Err(DemError::InvalidModel {
                reason: "fracture judges floe stress: turn it on (set_stress_filter)".into(),
            });
        }
        if self.pipeline.next != crate::pipeline::Stage::Drift {
            return Err(DemError::InvalidModel {
                reason: "fracture runs between steps".into(),
            });
        }
        if !rule.due(self.state.steps) {
            return Ok(Vec::new());
        }
        let (thickness_area, area) = (sums.thickness_area.value(), sums.area.value());
        let f = self.state.floes.columns();
        let (step, time_s) = (self.state.steps, self.state.time_s);
        let mut plans = Vec::new();
        // A floe on a load point is apparatus (a driven block): it stays whole.
        let driven: Vec<u64> = self.state.load_points.iter().map(|l| l.floe_id).collect();
        for i in (0..f.len()).filter(|&i| f.is_free(i) && !self.is_ghost(i)) {
            if f.area_m2[i] < rule.min_floe_area_m2 || driven.contains(&f.id[i]) {
                continue;
            }
            let (h, c) = match rule.strength_thickness {
                StrengthThickness::Own => (f.thickness_m[i], 1.0),
                StrengthThickness::Pack => (
                    thickness_area / area,
                    (area / domain_area_m2).clamp(0.0, 1.0),
                ),
            };
            let principal_pa = principal(self.state.floe_stress[i]);
            if !rule.criterion.breaks(principal_pa, h, c) {
                continue;
            }
            let (sin, cos) = f.angle[i].sin_cos();
            let polygon: Vec<Vec2> = f
                .local_vertices(i)
                .iter()
                .map(|&v| rotate(v, cos, sin))
                .collect();
            let key = SplitKey {
                seed: rule.seed,
                floe_id: f.id[i],
                step,
            };
            let mut plan = PlannedSplit {
                event: FractureEvent {
                    step,
                    time_s,
                    parent_id: f.id[i],
                    principal_pa,
                    area_m2: f.area_m2[i],
                    piece_ids: Vec::new(),
                    whole_because: None,
                },
                pieces: Vec::new(),
            };
            match split_polygon(&polygon, &rule.split, key) {
                None => {
                    plan.event.whole_because = Some(format!(
                        "no split into {} pieces of at least {} m^2 in {} attempts",
                        rule.split.pieces, rule.split.min_piece_area_m2, rule.split.attempts
                    ))
                }
                Some((pieces, _)) => match self.too_small_for_the_step(f.id[i], &pieces) {
                    Some(why) => plan.event.whole_because = Some(why),
                    None => plan.pieces = pieces,
                },
            }
            plans.push(plan);
        }
        Ok(plans)
    }

    /// Carries out `plans` (in their order), the pieces numbered from
    /// `first_id` on; the events, with their piece ids.
    pub fn apply_fracture(
        &mut self,
        plans: Vec<PlannedSplit>,
        first_id: u64,
    ) -> Result<Vec<FractureEvent>, DemError> {
        let mut next = first_id;
        let mut events = Vec::with_capacity(plans.len());
        for PlannedSplit { mut event, pieces } in plans {
            if !pieces.is_empty() {
                let ids: Vec<u64> = (next..next + pieces.len() as u64).collect();
                self.split_floe(event.parent_id, &pieces, &ids)?;
                next += ids.len() as u64;
                event.piece_ids = ids;
            }
            events.push(event);
        }
        Ok(events)
    }

    /// Whether floe `h` is another process's (a ghost).
    pub(super) fn is_ghost(&self, h: usize) -> bool {
        self.pipeline.ghost.get(h).copied().unwrap_or(false)
    }
}

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
#[derive(Debug, Clone, PartialEq)]
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
        if self.state.stress_filter.is_none() {
            return Err(DemError::InvalidModel {
                reason: "fracture judges floe stress: turn it on (set_stress_filter)".into(),
            });
        }
        if self.state.floes.is_empty() || !rule.due(self.state.steps) {
            return Ok(Vec::new());
        }
        let first = self.state.floes.id[0];
        self.between_steps(first)?;
        let f = self.state.floes.columns();
        let free: Vec<usize> = (0..f.len()).filter(|&i| f.is_free(i)).collect();
        // Exact sums: the pack's means do not depend on the floes' order
        // (nor, summed per process and merged, on how they are spread).
        let (mut thickness_area, mut area) = (ExactSum::new(), ExactSum::new());
        for &i in &free {
            thickness_area.add(f.thickness_m[i] * f.area_m2[i]);
            area.add(f.area_m2[i]);
        }
        let (thickness_area, area) = (thickness_area.value(), area.value());
        let strength = |i: usize| match rule.strength_thickness {
            StrengthThickness::Own => (f.thickness_m[i], 1.0),
            StrengthThickness::Pack => (
                thickness_area / area,
                (area / domain_area_m2).clamp(0.0, 1.0),
            ),
        };
        let breaking: Vec<(u64, (f64, f64))> = free
            .iter()
            .filter(|&&i| f.area_m2[i] >= rule.min_floe_area_m2)
            .filter_map(|&i| {
                let s = principal(self.state.floe_stress[i]);
                let (h, c) = strength(i);
                rule.criterion.breaks(s, h, c).then_some((f.id[i], s))
            })
            .collect();
        let mut next = self
            .state
            .next_floe_id
            .max(f.id.last().map_or(0, |&m| m + 1));
        let (step, time_s) = (self.state.steps, self.state.time_s);
        let mut events = Vec::with_capacity(breaking.len());
        for (id, principal_pa) in breaking {
            let h = self.handle(id)?;
            let f = self.state.floes.columns();
            let sc = f.angle[h].sin_cos();
            let polygon: Vec<Vec2> = f
                .local_vertices(h)
                .iter()
                .map(|&v| rotate(v, sc.1, sc.0))
                .collect();
            let area_m2 = f.area_m2[h];
            let key = SplitKey {
                seed: rule.seed,
                floe_id: id,
                step,
            };
            let mut event = FractureEvent {
                step,
                time_s,
                parent_id: id,
                principal_pa,
                area_m2,
                piece_ids: Vec::new(),
                whole_because: None,
            };
            match split_polygon(&polygon, &rule.split, key) {
                None => {
                    event.whole_because = Some(format!(
                        "no split into {} pieces of at least {} m^2 in {} attempts",
                        rule.split.pieces, rule.split.min_piece_area_m2, rule.split.attempts
                    ))
                }
                Some((pieces, _)) => {
                    let ids: Vec<u64> = (next..next + pieces.len() as u64).collect();
                    match self.split_floe(id, &pieces, &ids) {
                        Ok(()) => {
                            next += ids.len() as u64;
                            event.piece_ids = ids;
                        }
                        Err(e) => event.whole_because = Some(e.to_string()),
                    }
                }
            }
            events.push(event);
        }
        self.state.next_floe_id = next;
        Ok(events)
    }
}

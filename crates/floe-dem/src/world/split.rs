//! A floe split into pieces between steps: mass, momentum, angular
//! momentum, kinetic energy and area kept to round-off, its contacts moved
//! (with their tangential springs and friction states) to the piece that
//! holds their contact point, its bonds to the piece that holds their
//! anchor.

use super::World;
use crate::bonds::Bond;
use crate::contact_kernel::contact_force_on_b;
use crate::contacts::ContactRecord;
use crate::error::DemError;
use crate::floes::{Floe, Motion};
use crate::forcing::ExternalForces;
use crate::geometry::shape::FloeShape;
use crate::geometry::{cross, perp, rotate};
use crate::Vec2;

use super::edits::DetachedFloe;

impl<F: ExternalForces> World<F> {
    /// Replaces free floe `id`, between steps, by floes of the convex
    /// `pieces` (vertices relative to its centroid, in world orientation,
    /// as [`crate::fracture::split::split_polygon`] makes them) with ids
    /// `piece_ids` (new, and not `id`). Each piece keeps the parent's
    /// thickness and moves with the parent's rigid motion (`v + omega x r`,
    /// `omega`); the masses are the parent's in proportion to area, so
    /// mass, linear and angular momentum and kinetic energy are the
    /// parent's to round-off. Each contact goes to the piece that holds
    /// its contact point (or is nearest it), with its friction state, and
    /// each bond to the piece that holds its anchor, with its age and
    /// stretch (quiet pairs not yet bonded start again); the
    /// pieces do not touch each other yet, their stresses start at zero,
    /// and the parent's remembered broken contacts are forgotten (the
    /// pair is gone). Their last forces are their contacts' and a share of
    /// the parent's external force by mass, for the next half kick.
    /// Refuses (changing nothing) a prescribed floe, fewer than two pieces,
    /// ids in use, a piece that is not a convex polygon or would need a
    /// smaller time step.
    pub fn split_floe(
        &mut self,
        id: u64,
        pieces: &[Vec<Vec2>],
        piece_ids: &[u64],
    ) -> Result<(), DemError> {
        self.between_steps(id)?;
        let h = self.handle(id)?;
        let refuse = |reason: String| Err(DemError::FloeEdit { id, reason });
        let parent = self.state.floes.get(h);
        if !matches!(parent.motion, Motion::Free) {
            return refuse("only a free floe splits".into());
        }
        if pieces.len() < 2 || pieces.len() != piece_ids.len() {
            return refuse(format!(
                "{} pieces with {} ids: a split needs two or more, one id each",
                pieces.len(),
                piece_ids.len()
            ));
        }
        let mut sorted = piece_ids.to_vec();
        sorted.sort_unstable();
        sorted.dedup();
        if sorted.len() != piece_ids.len()
            || piece_ids
                .iter()
                .any(|&p| p == id || self.state.floes.handle_of(p).is_some())
        {
            return refuse("the pieces need new ids, distinct and unused".into());
        }
        let (shapes, mut floes) = piece_floes(&parent, pieces, piece_ids, self.periodicity)?;
        if let Some(why) = self
            .unstable_piece(&floes)
            .or_else(|| self.unstable_bond(h, pieces, &shapes, &floes))
        {
            return refuse(why);
        }
        let detached = self.remove_floe(id)?;
        // Each contact to the piece that holds its point.
        let mut moved: Vec<Vec<([u64; 2], ContactRecord)>> = vec![Vec::new(); floes.len()];
        for ([x, y], record) in detached.contacts {
            let parent_is_b = y == id;
            let other = if parent_is_b { x } else { y };
            let offset = if parent_is_b {
                record.image_offset
            } else {
                Vec2::ZERO
            };
            let at = record.point - offset - parent.position;
            let k = holder(pieces, at);
            moved[k].push(rekey(
                record,
                parent_is_b,
                other,
                &floes[k],
                parent.position,
                shapes[k].1,
            ));
        }
        // Each bond to the piece that holds its anchor.
        let mut bonded: Vec<Vec<([u64; 2], Bond)>> = vec![Vec::new(); floes.len()];
        let parent_angle = parent.angle.sin_cos();
        for ([x, y], bond) in detached.bonds.into_iter().filter(|(_, b)| b.formed) {
            let parent_is_b = y == id;
            let other = if parent_is_b { x } else { y };
            let anchor = if parent_is_b {
                bond.anchor_b
            } else {
                bond.anchor_a
            };
            let at = rotate(anchor, parent_angle.1, parent_angle.0);
            let k = holder(pieces, at);
            let other_angle = self.state.floes.angle[self.handle(other)?];
            bonded[k].push(rekey_bond(
                bond,
                (parent_is_b, parent.angle),
                (floes[k].id, at - shapes[k].1),
                (other, other_angle),
            ));
        }
        // The pieces' last forces: their contacts' and bonds', and the parent's
        // external force shared by mass.
        let share = |f: &Floe| f.mass_kg / parent.mass_kg;
        for (((floe, contacts), bonds), (_, offset)) in
            floes.drain(..).zip(moved).zip(bonded).zip(&shapes)
        {
            let external_torque = detached.external_torque * share(&floe);
            let external_force = detached.external_force * share(&floe);
            let (force, torque) = piece_forces(
                &floe,
                &contacts,
                bonds.iter().map(|b| (b, *offset)),
                (external_force, external_torque),
            );
            self.insert_detached(DetachedFloe {
                external_force,
                external_torque,
                force,
                torque,
                floe,
                contacts,
                broken: Vec::new(),
                bonds,
                stress: None,
            })?;
        }
        Ok(())
    }
}

/// A piece's (or a welded floe's) last forces for its next half kick:
/// `external` (force, torque), its contacts' and its bonds' (each bond's
/// torque, taken about its old floe's centroid, moved to the new floe's,
/// the offset beside it from the old one).
pub(super) fn piece_forces<'a>(
    floe: &Floe,
    contacts: &[([u64; 2], ContactRecord)],
    bonds: impl Iterator<Item = (&'a ([u64; 2], Bond), Vec2)>,
    (external_force, external_torque): (Vec2, f64),
) -> (Vec2, f64) {
    // `0.0 +`: a torque of -0.0 starts at +0.0, as it always has.
    let (mut force, mut torque) = (external_force, 0.0 + external_torque);
    for ([_, b], c) in contacts {
        let (on_this, arm_origin) = if *b == floe.id {
            (contact_force_on_b(c), floe.position + c.image_offset)
        } else {
            (-contact_force_on_b(c), floe.position)
        };
        force += on_this;
        torque += cross(c.point - arm_origin, on_this);
    }
    for (([a, _], bond), offset) in bonds {
        let (on_this, about_parent) = if *a == floe.id {
            (-bond.force_on_b, bond.torque_on_a)
        } else {
            (bond.force_on_b, bond.torque_on_b)
        };
        force += on_this;
        torque += about_parent - cross(offset, on_this);
    }
    (force, torque)
}

/// The piece containing `at` (relative to the parent's centroid), or the
/// one it is least outside of.
fn holder(pieces: &[Vec<Vec2>], at: Vec2) -> usize {
    let depth = |p: &Vec<Vec2>| {
        let n = p.len();
        (0..n)
            .map(|i| {
                let e = p[(i + 1) % n] - p[i];
                cross(e, at - p[i]) / e.length()
            })
            .fold(f64::INFINITY, f64::min)
    };
    (0..pieces.len())
        .max_by(|&i, &j| depth(&pieces[i]).total_cmp(&depth(&pieces[j])))
        .expect("two or more pieces")
}

/// `record`, a contact of the parent (at `parent_position`) with floe
/// `other`, as a contact of `piece` with `other`, named by ids: the smaller
/// id is `a`. Its friction state, age and energies are kept (the
/// tangential force and slip rate, measured on `b` along `perp(normal)`,
/// keep their values when the two floes change roles); its normal, point
/// and image offset are moved to the piece's frame: the piece is stored at
/// `piece.position`, which is `piece_offset` from the parent's centroid up
/// to a period. The next detection recomputes its geometry.
pub(super) fn rekey(
    mut record: ContactRecord,
    parent_was_b: bool,
    other: u64,
    piece: &Floe,
    parent_position: Vec2,
    piece_offset: Vec2,
) -> ([u64; 2], ContactRecord) {
    // As seen from the parent at its stored position: the normal towards
    // `other`, the point, and the offset to `other`'s touching image.
    let (normal, point, offset) = if parent_was_b {
        (
            -record.normal,
            record.point - record.image_offset,
            -record.image_offset,
        )
    } else {
        (record.normal, record.point, record.image_offset)
    };
    // The piece's stored position is a whole period from where it sits by
    // the parent when wrapped: the frame moves with it.
    let wrap = piece.position - (parent_position + piece_offset);
    let (point, offset) = (point + wrap, offset + wrap);
    if piece.id < other {
        (record.normal, record.point, record.image_offset) = (normal, point, offset);
        ([piece.id, other], record)
    } else {
        (record.normal, record.point, record.image_offset) = (-normal, point - offset, -offset);
        ([other, piece.id], record)
    }
}

/// `bond`, of the parent (at angle `parent_angle`, its `b` if
/// `parent_was_b`) with floe `other` (at `other_angle`), as a bond of the
/// piece `piece_id` (at angle 0) whose anchor is `piece_anchor` from the
/// piece's centroid, named by ids: the smaller id is `a`. The physical
/// joint is unchanged (the same anchors in the world, normal, stretch and
/// relative rotation: its energy and loads keep their values), only
/// expressed in the piece's frame, with the roles swapped when the piece's
/// id is above `other`.
pub(super) fn rekey_bond(
    mut bond: Bond,
    (parent_was_b, parent_angle): (bool, f64),
    (piece_id, piece_anchor): (u64, Vec2),
    (other, other_angle): (u64, f64),
) -> ([u64; 2], Bond) {
    let old_a_angle = if parent_was_b {
        other_angle
    } else {
        parent_angle
    };
    let (s, c) = old_a_angle.sin_cos();
    let normal = rotate(bond.normal_a, c, s);
    let other_anchor = if parent_was_b {
        bond.anchor_a
    } else {
        bond.anchor_b
    };
    // The piece at angle 0 is the parent's material at the parent's angle.
    let rest = if parent_was_b {
        bond.rest_angle_rad - parent_angle
    } else {
        bond.rest_angle_rad + parent_angle
    };
    let piece_is_a = piece_id < other;
    if piece_is_a != parent_was_b {
        // Same roles.
        bond.rest_angle_rad = rest;
        if piece_is_a {
            (bond.anchor_a, bond.normal_a) = (piece_anchor, normal);
        } else {
            bond.anchor_b = piece_anchor;
        }
    } else {
        // Swapped roles: the normal from the new `a` to the new `b` is the
        // old one reversed, and the relative rotation changes sign.
        bond.rest_angle_rad = -rest;
        (bond.point_a, bond.point_b) = (bond.point_b, bond.point_a);
        bond.force_on_b = -bond.force_on_b;
        (bond.torque_on_a, bond.torque_on_b) = (bond.torque_on_b, bond.torque_on_a);
        if piece_is_a {
            (bond.anchor_a, bond.anchor_b, bond.normal_a) = (piece_anchor, other_anchor, -normal);
        } else {
            let (so, co) = other_angle.sin_cos();
            (bond.anchor_a, bond.anchor_b) = (other_anchor, piece_anchor);
            bond.normal_a = rotate(-normal, co, -so);
        }
    }
    let ids = if piece_is_a {
        [piece_id, other]
    } else {
        [other, piece_id]
    };
    (ids, bond)
}

impl<F: ExternalForces> World<F> {
    /// Why splitting floe `id` into `pieces` would be refused for the time
    /// step, if it would.
    pub(super) fn too_small_for_the_step(&self, id: u64, pieces: &[Vec<Vec2>]) -> Option<String> {
        let h = self.state.floes.handle_of(id)?;
        let parent = self.state.floes.get(h);
        let ids: Vec<u64> = (0..pieces.len() as u64).collect();
        match piece_floes(&parent, pieces, &ids, self.periodicity) {
            Ok((shapes, floes)) => self
                .unstable_piece(&floes)
                .or_else(|| self.unstable_bond(h, pieces, &shapes, &floes)),
            Err(e) => Some(e.to_string()),
        }
    }

    /// Why a bond of floe `h` (the parent) would need a shorter time step
    /// than the world's on the piece of `pieces` that holds its anchor: a
    /// bond keeps the stiffness it formed with, which a small piece may not
    /// carry (`0.3 x 2/omega` as for contacts, `omega^2` the larger of the
    /// normal spring over the piece's mass and the bending and normal
    /// springs' turning stiffness over its moment of inertia).
    fn unstable_bond(
        &self,
        h: usize,
        pieces: &[Vec<Vec2>],
        shapes: &[PlacedShape],
        floes: &[Floe],
    ) -> Option<String> {
        let s = &self.state;
        let (sin, cos) = s.floes.angle[h].sin_cos();
        let factor = crate::pipeline::integrator::damping_step_factor(&self.model)
            * crate::pipeline::integrator::STABILITY_SAFETY
            * 2.0;
        s.bonds
            .iter()
            .filter(|b| b.formed && (b.a as usize == h || b.b as usize == h))
            .find_map(|b| {
                let anchor = if b.a as usize == h { b.anchor_a } else { b.anchor_b };
                let at = rotate(anchor, cos, sin);
                let k = holder(pieces, at);
                let arm = (at - shapes[k].1).length();
                let k_n = b.stiffness_n_per_m;
                let k_turn = k_n * b.length_m * b.length_m / 12.0 + k_n * arm * arm;
                let omega2 = (k_n / floes[k].mass_kg).max(k_turn / floes[k].inertia_kg_m2);
                let limit = factor / omega2.sqrt();
                (s.dt_s > limit).then(|| {
                    format!(
                        "a bond of {} N/m on a piece of {:.4e} m^2 needs a time step of at most {limit:.4e} s, not {:.4e} s",
                        k_n, floes[k].area_m2, s.dt_s
                    )
                })
            })
    }

    /// Why one of `floes` needs a shorter time step than the world's.
    fn unstable_piece(&self, floes: &[Floe]) -> Option<String> {
        floes.iter().find_map(|f| {
            let limit = self.stable_step_of(f);
            (self.state.dt_s > limit).then(|| {
                format!(
                    "a piece of {:.4e} m^2 needs a time step of at most {limit:.4e} s, not {:.4e} s",
                    f.area_m2, self.state.dt_s
                )
            })
        })
    }
}

/// A piece's shape and its centroid about the parent's.
type PlacedShape = (FloeShape, Vec2);

/// The pieces' shapes (with their centroids about the parent's) and
/// floes: the parent's thickness and rigid motion, masses by area.
fn piece_floes(
    parent: &Floe,
    pieces: &[Vec<Vec2>],
    piece_ids: &[u64],
    periodicity: crate::periodicity::Periodicity,
) -> Result<(Vec<PlacedShape>, Vec<Floe>), DemError> {
    let shapes = pieces
        .iter()
        .enumerate()
        .map(|(k, p)| FloeShape::from_world(k, p))
        .collect::<Result<Vec<_>, _>>()?;
    let total_area: f64 = shapes.iter().map(|(s, _)| s.area_m2).sum();
    // The pieces must tile the parent: their areas add up to its area and
    // their centroids average to its centroid (to round-off).
    let first: Vec2 = shapes.iter().map(|(s, c)| *c * s.area_m2).sum();
    let tol = 1e-9 * parent.area_m2;
    if (total_area - parent.area_m2).abs() > tol || first.length() > tol * parent.radius_m {
        return Err(DemError::FloeEdit {
            id: parent.id,
            reason: format!(
                "the pieces do not tile the floe: area {total_area} m^2 against {} m^2, centroid off by {} m",
                parent.area_m2,
                first.length() / total_area
            ),
        });
    }
    let floes: Vec<Floe> = shapes
        .iter()
        .zip(piece_ids)
        .map(|((shape, c), &pid)| {
            let mass = parent.mass_kg * (shape.area_m2 / total_area);
            Floe {
                id: pid,
                position: periodicity.wrap(parent.position + *c),
                angle: 0.0,
                velocity: parent.velocity + perp(*c) * parent.angular_velocity,
                angular_velocity: parent.angular_velocity,
                thickness_m: parent.thickness_m,
                mass_kg: mass,
                inertia_kg_m2: mass / shape.area_m2 * shape.polar_moment_m4,
                area_m2: shape.area_m2,
                radius_m: shape.radius_m,
                r3_moment_m5: crate::geometry::polygon_r3_moment(&shape.vertices),
                motion: Motion::Free,
                vertices: shape.vertices.clone(),
            }
        })
        .collect();
    Ok((shapes, floes))
}

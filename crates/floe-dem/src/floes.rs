//! The floe set: every floe's state and properties, one array per quantity
//! (structure of arrays), kept sorted by the floes' global ids.
//!
//! A floe is named by its id, which never changes. Its *handle* is its
//! index in the arrays, its rank among the ids present: inserting or
//! removing a floe shifts the handles of the floes after it, and the world
//! moves every buffer that refers to handles with them (contacts, contact
//! memory, forces). Because handle order is id order, everything sorted by
//! handle (the contact list, and with it every per-floe sum of contact
//! forces) is in the same order whichever floes are present and in
//! whatever order they were added.
//!
//! The arrays are read through [`Floes`]'s `Deref` to [`FloeColumns`];
//! they change only through the set's methods (and, inside a world,
//! through [`World`](crate::world::World)'s, which also mark what changed).

use std::ops::Deref;

use crate::error::DemError;
use crate::geometry::shape::FloeShape;
use crate::geometry::{Placed, MAX_VERTICES};
use crate::Vec2;

/// How a floe moves.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Motion {
    /// Moved by forces (the usual case).
    Free,
    /// Moves at a prescribed velocity, whatever the forces: walls, pushers,
    /// the fixed blocks of a double-shear test.
    Prescribed {
        /// Translational velocity, m/s.
        velocity: Vec2,
    },
}

/// Most floes a set holds: handles are `u32`, and `u32::MAX` marks an
/// ended contact inside a step.
pub const MAX_FLOES: usize = u32::MAX as usize - 1;

/// One floe, outside a set: what [`Floes::insert`] takes and
/// [`Floes::get`] returns.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Floe {
    /// Global identifier, unique in a set.
    pub id: u64,
    /// Centroid position, m.
    pub position: Vec2,
    /// Orientation, rad (counter-clockwise).
    pub angle: f64,
    /// Centroid velocity, m/s.
    pub velocity: Vec2,
    /// Angular velocity, rad/s.
    pub angular_velocity: f64,
    /// Thickness, m.
    pub thickness_m: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Moment of inertia about the centroid, kg m^2.
    pub inertia_kg_m2: f64,
    /// Area, m^2.
    pub area_m2: f64,
    /// Bounding radius about the centroid, m.
    pub radius_m: f64,
    /// `int r^3 dA` about the centroid (rotational drag), m^5.
    pub r3_moment_m5: f64,
    /// How the floe moves.
    pub motion: Motion,
    /// Vertices relative to the centroid at angle 0, counter-clockwise, m.
    pub vertices: Vec<Vec2>,
}

impl Floe {
    /// A free floe at rest of the given shape, centroid position (m),
    /// thickness (m) and density (kg/m^3).
    pub fn new(
        id: u64,
        shape: &FloeShape,
        position: Vec2,
        thickness_m: f64,
        density_kg_per_m3: f64,
    ) -> Self {
        let rho_h = density_kg_per_m3 * thickness_m;
        Floe {
            id,
            position,
            angle: 0.0,
            velocity: Vec2::ZERO,
            angular_velocity: 0.0,
            thickness_m,
            mass_kg: rho_h * shape.area_m2,
            inertia_kg_m2: rho_h * shape.polar_moment_m4,
            area_m2: shape.area_m2,
            radius_m: shape.radius_m,
            r3_moment_m5: crate::geometry::polygon_r3_moment(&shape.vertices),
            motion: Motion::Free,
            vertices: shape.vertices.clone(),
        }
    }

    /// The floe moving at `velocity` (m/s) whatever the forces (a wall).
    pub fn prescribed(self, velocity: Vec2) -> Self {
        Floe {
            motion: Motion::Prescribed { velocity },
            velocity,
            ..self
        }
    }

    /// The floe with the given velocity (m/s) and angular velocity (rad/s).
    pub fn with_velocity(self, velocity: Vec2, angular_velocity: f64) -> Self {
        Floe {
            velocity,
            angular_velocity,
            ..self
        }
    }

    /// Checks what the engine relies on (see [`check_floe`]).
    fn validate(&self) -> Result<(), DemError> {
        check_floe(&FloeRef {
            position: self.position,
            angle: self.angle,
            velocity: self.velocity,
            angular_velocity: self.angular_velocity,
            thickness_m: self.thickness_m,
            mass_kg: self.mass_kg,
            inertia_kg_m2: self.inertia_kg_m2,
            area_m2: self.area_m2,
            radius_m: self.radius_m,
            r3_moment_m5: self.r3_moment_m5,
            motion: self.motion,
            vertices: &self.vertices,
        })
        .map_err(|reason| DemError::FloeEdit {
            id: self.id,
            reason,
        })
    }
}

/// One floe's values, borrowed, for [`check_floe`].
struct FloeRef<'a> {
    position: Vec2,
    angle: f64,
    velocity: Vec2,
    angular_velocity: f64,
    thickness_m: f64,
    mass_kg: f64,
    inertia_kg_m2: f64,
    area_m2: f64,
    radius_m: f64,
    r3_moment_m5: f64,
    motion: Motion,
    vertices: &'a [Vec2],
}

/// What the engine relies on of a floe: 3 to [`MAX_VERTICES`] vertices,
/// finite state, positive thickness, mass, inertia and area, and a
/// bounding radius that reaches every vertex (the broad phase's cells and
/// bounds assume it).
fn check_floe(f: &FloeRef<'_>) -> Result<(), String> {
    if !(3..=MAX_VERTICES).contains(&f.vertices.len()) {
        return Err(format!(
            "{} vertices (a floe has 3 to {MAX_VERTICES})",
            f.vertices.len()
        ));
    }
    let finite = f.position.is_finite()
        && f.angle.is_finite()
        && f.velocity.is_finite()
        && f.angular_velocity.is_finite()
        && f.r3_moment_m5.is_finite()
        && f.vertices.iter().all(|v| v.is_finite())
        && match f.motion {
            Motion::Free => true,
            Motion::Prescribed { velocity } => velocity.is_finite(),
        };
    if !finite {
        return Err("a non-finite position, velocity, angle or vertex".into());
    }
    for (name, v) in [
        ("thickness", f.thickness_m),
        ("mass", f.mass_kg),
        ("moment of inertia", f.inertia_kg_m2),
        ("area", f.area_m2),
        ("radius", f.radius_m),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("{name} {v} must be > 0"));
        }
    }
    let reach = f.vertices.iter().map(|v| v.length()).fold(0.0, f64::max);
    if f.radius_m < reach * (1.0 - 1e-12) {
        return Err(format!(
            "bounding radius {} m does not reach its farthest vertex, {reach} m away",
            f.radius_m
        ));
    }
    Ok(())
}

/// The floe arrays, indexed by handle. Read them through [`Floes`]; build
/// a set from them with [`Floes::from_columns`] (checkpoints do).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FloeColumns {
    /// Global identifier, strictly increasing.
    pub id: Vec<u64>,
    /// Centroid position, m.
    pub position: Vec<Vec2>,
    /// Orientation, rad (counter-clockwise).
    pub angle: Vec<f64>,
    /// Centroid velocity, m/s.
    pub velocity: Vec<Vec2>,
    /// Angular velocity, rad/s.
    pub angular_velocity: Vec<f64>,
    /// Thickness, m.
    pub thickness_m: Vec<f64>,
    /// Mass, kg.
    pub mass_kg: Vec<f64>,
    /// Moment of inertia about the centroid, kg m^2.
    pub inertia_kg_m2: Vec<f64>,
    /// Area, m^2.
    pub area_m2: Vec<f64>,
    /// Bounding radius about the centroid, m.
    pub radius_m: Vec<f64>,
    /// `int r^3 dA` about the centroid (rotational drag), m^5.
    pub r3_moment_m5: Vec<f64>,
    /// How each floe moves.
    pub motion: Vec<Motion>,
    /// Start of each floe's vertices in `vertices`; `vertex_start[i + 1]`
    /// ends them (one extra entry at the end).
    pub vertex_start: Vec<u32>,
    /// Vertices of all floes, relative to their centroid, counter-clockwise, m.
    pub vertices: Vec<Vec2>,
}

impl FloeColumns {
    /// Number of floes.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// Whether there are no floes.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Floe `i`'s vertices relative to its centroid.
    #[inline]
    pub fn local_vertices(&self, i: usize) -> &[Vec2] {
        &self.vertices[self.vertex_start[i] as usize..self.vertex_start[i + 1] as usize]
    }

    /// Floe `i`'s vertices in world coordinates.
    pub fn world_vertices(&self, i: usize) -> Vec<Vec2> {
        let (s, c) = self.angle[i].sin_cos();
        self.local_vertices(i)
            .iter()
            .map(|&v| self.position[i] + crate::geometry::rotate(v, c, s))
            .collect()
    }

    /// Whether floe `i` moves under forces.
    #[inline]
    pub fn is_free(&self, i: usize) -> bool {
        matches!(self.motion[i], Motion::Free)
    }

    /// Floe `i` as the narrow phase takes it: its vertices, its position
    /// shifted by `offset` (a periodic image, or zero), and its rotation as
    /// `(sin, cos)` of its angle, which a caller clipping many pairs
    /// computes once per floe.
    #[inline]
    pub fn placed(&self, i: usize, offset: Vec2, (sin, cos): (f64, f64)) -> Placed<'_> {
        Placed {
            vertices: self.local_vertices(i),
            position: self.position[i] + offset,
            cos,
            sin,
            radius_m: self.radius_m[i],
        }
    }

    /// The handle of the floe with global id `id`, if present.
    pub fn handle_of(&self, id: u64) -> Option<usize> {
        self.id.binary_search(&id).ok()
    }
}

/// Every floe's state and properties: the arrays of [`FloeColumns`] (read
/// through `Deref`), sorted by id, changed only through methods.
#[derive(Debug, Clone, PartialEq)]
pub struct Floes {
    columns: FloeColumns,
}

impl Default for Floes {
    /// The empty set.
    fn default() -> Self {
        Floes {
            columns: FloeColumns {
                vertex_start: vec![0],
                ..FloeColumns::default()
            },
        }
    }
}

impl Deref for Floes {
    type Target = FloeColumns;

    #[inline(always)]
    fn deref(&self) -> &FloeColumns {
        &self.columns
    }
}

impl Floes {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Floes from convex polygons in world coordinates with their thickness
    /// and a density (kg/m^3), all free and at rest, with ids `0..n` in the
    /// polygons' order.
    pub fn from_polygons(
        polygons: &[Vec<Vec2>],
        thickness_m: &[f64],
        density_kg_per_m3: f64,
    ) -> Result<Self, DemError> {
        if !(density_kg_per_m3.is_finite() && density_kg_per_m3 > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "density_kg_per_m3",
                value: density_kg_per_m3,
                reason: "must be > 0",
            });
        }
        if polygons.len() != thickness_m.len() {
            return Err(DemError::InvalidFloe {
                index: polygons.len().min(thickness_m.len()),
                reason: format!(
                    "{} polygons but {} thicknesses",
                    polygons.len(),
                    thickness_m.len()
                ),
            });
        }
        let mut f = Floes::new();
        for (i, (poly, &h)) in polygons.iter().zip(thickness_m).enumerate() {
            if !(h.is_finite() && h > 0.0) {
                return Err(DemError::InvalidFloe {
                    index: i,
                    reason: format!("thickness {h} m must be > 0"),
                });
            }
            let (shape, centroid) = FloeShape::from_world(i, poly)?;
            f.insert(Floe::new(i as u64, &shape, centroid, h, density_kg_per_m3))?;
        }
        Ok(f)
    }

    /// A set from its arrays, after checking that they agree in length,
    /// that the ids are strictly increasing and the vertex offsets valid.
    pub fn from_columns(columns: FloeColumns) -> Result<Self, DemError> {
        let c = &columns;
        let n = c.id.len();
        let bad = |reason: String| Err(DemError::InvalidFloeColumns { reason });
        for (name, len) in [
            ("position", c.position.len()),
            ("angle", c.angle.len()),
            ("velocity", c.velocity.len()),
            ("angular_velocity", c.angular_velocity.len()),
            ("thickness_m", c.thickness_m.len()),
            ("mass_kg", c.mass_kg.len()),
            ("inertia_kg_m2", c.inertia_kg_m2.len()),
            ("area_m2", c.area_m2.len()),
            ("radius_m", c.radius_m.len()),
            ("r3_moment_m5", c.r3_moment_m5.len()),
            ("motion", c.motion.len()),
        ] {
            if len != n {
                return bad(format!("{name} has {len} entries for {n} floes"));
            }
        }
        if n > MAX_FLOES {
            return bad(format!("{n} floes, above the limit of {MAX_FLOES}"));
        }
        if c.id.windows(2).any(|w| w[0] >= w[1]) {
            return bad("floe ids are not strictly increasing".into());
        }
        let offsets_valid = (n == 0 && c.vertex_start.len() <= 1 && c.vertices.is_empty())
            || c.vertex_start.len() == n + 1
                && c.vertex_start[0] == 0
                && c.vertex_start.windows(2).all(|w| {
                    (3..=MAX_VERTICES).contains(&(w[1] as usize).wrapping_sub(w[0] as usize))
                })
                && c.vertex_start.last().map(|&v| v as usize) == Some(c.vertices.len());
        if !offsets_valid {
            return bad("vertex offsets do not give each floe 3 or more vertices".into());
        }
        for h in 0..n {
            check_floe(&FloeRef {
                position: c.position[h],
                angle: c.angle[h],
                velocity: c.velocity[h],
                angular_velocity: c.angular_velocity[h],
                thickness_m: c.thickness_m[h],
                mass_kg: c.mass_kg[h],
                inertia_kg_m2: c.inertia_kg_m2[h],
                area_m2: c.area_m2[h],
                radius_m: c.radius_m[h],
                r3_moment_m5: c.r3_moment_m5[h],
                motion: c.motion[h],
                vertices: c.local_vertices(h),
            })
            .map_err(|reason| DemError::InvalidFloeColumns {
                reason: format!("floe id {}: {reason}", c.id[h]),
            })?;
        }
        let mut columns = columns;
        if columns.vertex_start.is_empty() {
            columns.vertex_start.push(0);
        }
        Ok(Floes { columns })
    }

    /// The arrays, for code that writes them out whole (checkpoints).
    pub fn columns(&self) -> &FloeColumns {
        &self.columns
    }

    /// The arrays, for the engine's stages.
    #[inline(always)]
    pub(crate) fn columns_mut(&mut self) -> &mut FloeColumns {
        &mut self.columns
    }

    /// Adds a floe at the place its id takes in the set, and returns its
    /// handle. Refuses an id already present, a floe the engine cannot
    /// step (see [`Floe`]'s checks) and a set of [`MAX_FLOES`].
    pub fn insert(&mut self, floe: Floe) -> Result<usize, DemError> {
        floe.validate()?;
        let c = &mut self.columns;
        if c.len() >= MAX_FLOES {
            return Err(DemError::FloeEdit {
                id: floe.id,
                reason: format!("the set already holds the most floes, {MAX_FLOES}"),
            });
        }
        let h = match c.id.binary_search(&floe.id) {
            Ok(_) => {
                return Err(DemError::FloeEdit {
                    id: floe.id,
                    reason: "a floe with this id is already present".into(),
                })
            }
            Err(h) => h,
        };
        let nv = floe.vertices.len();
        if c.vertices.len() + nv > u32::MAX as usize {
            return Err(DemError::FloeEdit {
                id: floe.id,
                reason: "too many vertices in the set".into(),
            });
        }
        c.id.insert(h, floe.id);
        c.position.insert(h, floe.position);
        c.angle.insert(h, floe.angle);
        c.velocity.insert(h, floe.velocity);
        c.angular_velocity.insert(h, floe.angular_velocity);
        c.thickness_m.insert(h, floe.thickness_m);
        c.mass_kg.insert(h, floe.mass_kg);
        c.inertia_kg_m2.insert(h, floe.inertia_kg_m2);
        c.area_m2.insert(h, floe.area_m2);
        c.radius_m.insert(h, floe.radius_m);
        c.r3_moment_m5.insert(h, floe.r3_moment_m5);
        c.motion.insert(h, floe.motion);
        let at = c.vertex_start[h] as usize;
        c.vertices.splice(at..at, floe.vertices);
        c.vertex_start.insert(h + 1, (at + nv) as u32);
        for s in &mut c.vertex_start[h + 2..] {
            *s += nv as u32;
        }
        Ok(h)
    }

    /// Replaces floes in place, each `(h, floe)` keeping handle `h` and its
    /// id (`floe.id` must be floe `h`'s): shapes, poses, motion and
    /// masses; the vertex array is rebuilt once for all. `changes` sorted
    /// by handle, each handle once.
    pub(crate) fn replace_in_place(&mut self, changes: Vec<(usize, Floe)>) {
        debug_assert!(changes.windows(2).all(|w| w[0].0 < w[1].0));
        let c = &mut self.columns;
        let mut vertices = Vec::with_capacity(c.vertices.len() + changes.len());
        let mut start = Vec::with_capacity(c.vertex_start.len());
        start.push(0u32);
        let mut next = changes.iter().peekable();
        for h in 0..c.id.len() {
            match next.next_if(|(k, _)| *k == h) {
                Some((_, f)) => {
                    debug_assert_eq!(f.id, c.id[h]);
                    vertices.extend_from_slice(&f.vertices);
                    c.position[h] = f.position;
                    c.angle[h] = f.angle;
                    c.velocity[h] = f.velocity;
                    c.angular_velocity[h] = f.angular_velocity;
                    c.thickness_m[h] = f.thickness_m;
                    c.mass_kg[h] = f.mass_kg;
                    c.inertia_kg_m2[h] = f.inertia_kg_m2;
                    c.area_m2[h] = f.area_m2;
                    c.radius_m[h] = f.radius_m;
                    c.r3_moment_m5[h] = f.r3_moment_m5;
                    c.motion[h] = f.motion;
                }
                None => vertices.extend_from_slice(
                    &c.vertices[c.vertex_start[h] as usize..c.vertex_start[h + 1] as usize],
                ),
            }
            start.push(vertices.len() as u32);
        }
        c.vertices = vertices;
        c.vertex_start = start;
    }

    /// Floe `h` as a value.
    pub fn get(&self, h: usize) -> Floe {
        let c = &self.columns;
        Floe {
            id: c.id[h],
            position: c.position[h],
            angle: c.angle[h],
            velocity: c.velocity[h],
            angular_velocity: c.angular_velocity[h],
            thickness_m: c.thickness_m[h],
            mass_kg: c.mass_kg[h],
            inertia_kg_m2: c.inertia_kg_m2[h],
            area_m2: c.area_m2[h],
            radius_m: c.radius_m[h],
            r3_moment_m5: c.r3_moment_m5[h],
            motion: c.motion[h],
            vertices: c.local_vertices(h).to_vec(),
        }
    }

    /// Takes floe `h` out of the set; the floes after it move down one handle.
    pub fn remove(&mut self, h: usize) -> Floe {
        let floe = self.get(h);
        let c = &mut self.columns;
        c.id.remove(h);
        c.position.remove(h);
        c.angle.remove(h);
        c.velocity.remove(h);
        c.angular_velocity.remove(h);
        c.thickness_m.remove(h);
        c.mass_kg.remove(h);
        c.inertia_kg_m2.remove(h);
        c.area_m2.remove(h);
        c.radius_m.remove(h);
        c.r3_moment_m5.remove(h);
        c.motion.remove(h);
        let (from, to) = (c.vertex_start[h] as usize, c.vertex_start[h + 1] as usize);
        c.vertices.drain(from..to);
        c.vertex_start.remove(h + 1);
        for s in &mut c.vertex_start[h + 1..] {
            *s -= (to - from) as u32;
        }
        floe
    }

    /// Sets floe `h`'s velocity (m/s) and angular velocity (rad/s). (A
    /// set inside a world changes through the world's methods.)
    pub fn set_velocity(&mut self, h: usize, velocity: Vec2, angular_velocity: f64) {
        self.columns.velocity[h] = velocity;
        self.columns.angular_velocity[h] = angular_velocity;
    }

    /// Sets floe `h`'s position (m) and angle (rad).
    pub fn set_pose(&mut self, h: usize, position: Vec2, angle: f64) {
        self.columns.position[h] = position;
        self.columns.angle[h] = angle;
    }

    /// Sets how floe `h` moves; a prescribed velocity is also its velocity.
    pub fn set_motion(&mut self, h: usize, motion: Motion) {
        self.columns.motion[h] = motion;
        if let Motion::Prescribed { velocity } = motion {
            self.columns.velocity[h] = velocity;
        }
    }

    /// Bytes held by the floe arrays (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        let c = &self.columns;
        let v2 = size_of::<Vec2>();
        c.id.capacity() * 8
            + (c.position.capacity() + c.velocity.capacity()) * v2
            + (c.angle.capacity()
                + c.angular_velocity.capacity()
                + c.thickness_m.capacity()
                + c.mass_kg.capacity()
                + c.inertia_kg_m2.capacity()
                + c.area_m2.capacity()
                + c.radius_m.capacity()
                + c.r3_moment_m5.capacity())
                * 8
            + c.motion.capacity() * size_of::<Motion>()
            + c.vertex_start.capacity() * 4
            + c.vertices.capacity() * v2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(id: u64, x: f64) -> Floe {
        let poly = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .map(|(a, b)| Vec2::new(x + a, b + id as f64));
        let (shape, c) = FloeShape::from_world(0, &poly).unwrap();
        Floe::new(id, &shape, c, 1.0, 917.0)
    }

    /// Floes inserted in any order end up sorted by id, and removing one
    /// and putting it back gives the same set.
    #[test]
    fn the_set_is_sorted_by_id_whatever_the_order_of_insertion() {
        let mut a = Floes::new();
        let mut b = Floes::new();
        for id in [5, 1, 9, 3] {
            a.insert(square(id, id as f64)).unwrap();
        }
        for id in [1, 3, 5, 9] {
            b.insert(square(id, id as f64)).unwrap();
        }
        assert_eq!(a, b);
        assert_eq!(a.id, vec![1, 3, 5, 9]);
        let floe = a.remove(1);
        assert_eq!(floe.id, 3);
        assert_eq!(a.id, vec![1, 5, 9]);
        assert_eq!(a.local_vertices(1), b.local_vertices(2));
        a.insert(floe).unwrap();
        assert_eq!(a, b);
        assert!(a.insert(square(5, 0.0)).is_err(), "duplicate id refused");
        assert_eq!(a, b, "a refused insertion changes nothing");
        assert_eq!(Floes::from_columns(a.columns().clone()).unwrap(), a);
    }

    /// Arrays a damaged or crafted checkpoint could hold, with a floe the
    /// engine cannot step, are refused: each of these crashed or ran on
    /// before the per-floe checks.
    #[test]
    fn columns_with_impossible_floes_are_refused() {
        let mut a = Floes::new();
        for id in [1, 2] {
            a.insert(square(id, 0.0)).unwrap();
        }
        type Damage = fn(&mut FloeColumns);
        let cases: [(&str, Damage); 5] = [
            ("non-finite", |c| c.position[1].x = f64::INFINITY),
            ("radius", |c| c.radius_m[0] = f64::NAN),
            ("mass", |c| c.mass_kg[1] = -1.0),
            ("farthest vertex", |c| c.radius_m[0] *= 0.5),
            ("vertex", |c| c.vertices[3].y = f64::NAN),
        ];
        for (what, damage) in cases {
            let mut c = a.columns().clone();
            damage(&mut c);
            let e = Floes::from_columns(c).expect_err(what).to_string();
            assert!(e.contains(what), "{what}: {e}");
        }
        // The empty set round-trips.
        let empty = Floes::new();
        assert_eq!(Floes::from_columns(empty.columns().clone()).unwrap(), empty);
        assert_eq!(Floes::from_columns(FloeColumns::default()).unwrap(), empty);
    }

    #[test]
    fn columns_out_of_order_are_refused() {
        let mut a = Floes::new();
        for id in [1, 2] {
            a.insert(square(id, 0.0)).unwrap();
        }
        let mut c = a.columns().clone();
        c.id.swap(0, 1);
        assert!(Floes::from_columns(c).is_err());
        let mut c = a.columns().clone();
        c.mass_kg.pop();
        assert!(Floes::from_columns(c).is_err());
    }
}

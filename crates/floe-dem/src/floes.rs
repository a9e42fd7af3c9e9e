//! Floe storage: one array per quantity (structure of arrays), indexed by
//! floe handle.
//!
//! Floes `0..owned` are integrated here; floes `owned..len()` are ghosts,
//! copies of floes owned by a neighbouring subdomain (for the planned MPI
//! domain decomposition). Ghosts take part in contacts but are not moved by
//! this subdomain. With one subdomain there are no ghosts.

use crate::error::DemError;
use crate::geometry::shape::FloeShape;
use crate::geometry::Placed;
use crate::Vec2;

/// How a floe moves.
#[derive(Debug, Clone, Copy, PartialEq)]
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

/// Every floe's state and properties.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Floes {
    /// Global identifier (stable across subdomains and checkpoints).
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
    /// Floes `0..owned` are integrated by this subdomain; the rest are ghosts.
    pub owned: usize,
}

impl Floes {
    /// Floes from convex polygons in world coordinates with their thickness
    /// and a density (kg/m^3), all free and at rest.
    pub fn from_polygons(
        polygons: &[Vec<Vec2>],
        thickness_m: &[f64],
        density_kg_m3: f64,
    ) -> Result<Self, DemError> {
        if !(density_kg_m3.is_finite() && density_kg_m3 > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "density_kg_m3",
                value: density_kg_m3,
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
        let n = polygons.len();
        let mut f = Floes {
            vertex_start: Vec::with_capacity(n + 1),
            ..Default::default()
        };
        f.vertex_start.push(0);
        for (i, (poly, &h)) in polygons.iter().zip(thickness_m).enumerate() {
            if !(h.is_finite() && h > 0.0) {
                return Err(DemError::InvalidFloe {
                    index: i,
                    reason: format!("thickness {h} m must be > 0"),
                });
            }
            let (shape, centroid) = FloeShape::from_world(i, poly)?;
            f.push(i as u64, &shape, centroid, h, density_kg_m3, Motion::Free);
        }
        f.owned = n;
        Ok(f)
    }

    /// Appends one floe (owned if no ghosts have been added yet).
    pub fn push(
        &mut self,
        id: u64,
        shape: &FloeShape,
        centroid: Vec2,
        thickness_m: f64,
        density_kg_m3: f64,
        motion: Motion,
    ) {
        if self.vertex_start.is_empty() {
            self.vertex_start.push(0);
        }
        let rho_h = density_kg_m3 * thickness_m;
        self.id.push(id);
        self.position.push(centroid);
        self.angle.push(0.0);
        self.velocity.push(match motion {
            Motion::Free => Vec2::ZERO,
            Motion::Prescribed { velocity } => velocity,
        });
        self.angular_velocity.push(0.0);
        self.thickness_m.push(thickness_m);
        self.mass_kg.push(rho_h * shape.area_m2);
        self.inertia_kg_m2.push(rho_h * shape.polar_moment_m4);
        self.area_m2.push(shape.area_m2);
        self.radius_m.push(shape.radius_m);
        self.r3_moment_m5
            .push(crate::forcing::polygon_r3_moment(&shape.vertices));
        self.motion.push(motion);
        self.vertices.extend_from_slice(&shape.vertices);
        self.vertex_start.push(self.vertices.len() as u32);
        if self.owned + 1 == self.id.len() {
            self.owned += 1;
        }
    }

    /// Number of floes, ghosts included.
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

    /// Bytes held by the floe arrays (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        let v2 = size_of::<Vec2>();
        self.id.capacity() * 8
            + (self.position.capacity() + self.velocity.capacity()) * v2
            + (self.angle.capacity()
                + self.angular_velocity.capacity()
                + self.thickness_m.capacity()
                + self.mass_kg.capacity()
                + self.inertia_kg_m2.capacity()
                + self.area_m2.capacity()
                + self.radius_m.capacity()
                + self.r3_moment_m5.capacity())
                * 8
            + self.motion.capacity() * size_of::<Motion>()
            + self.vertex_start.capacity() * 4
            + self.vertices.capacity() * v2
    }
}

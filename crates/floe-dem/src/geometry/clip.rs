//! The overlap of two convex floes: area, centroid, contact normal and
//! contact length.
//!
//! Hand-rolled, not parry's `convex_polygons_intersection_points`, for a
//! measured reason: parry clips in world coordinates, and at basin scale that
//! costs precision. For two diamonds pushed 0.1 mm into each other at 1e6 m,
//! parry 0.31.1 is off by 1.1 % in area, against 1e-6 here
//! (`tests/dem/clip.rs`). The physics notes also report gross failures on
//! exactly collinear tessellation edges (the neighbour's whole polygon
//! returned, overlaps missed). We did not reproduce those with 0.31.1, but
//! the degenerate cases are tested. Both polygons are placed in a
//! frame centred on the first floe, so coordinates are of the floe's size
//! whatever the position in the basin. The clipper also needs the boundary
//! crossings for the contact normal, and must not allocate. The overlap is found by Sutherland-Hodgman
//! clipping, with points on a clip line counted inside, so exactly collinear
//! edges give a degenerate polygon of zero area instead of a spurious contact.
//!
//! Normal and length follow Subzero.jl (Manucharyan & Montemuro 2022): the
//! contact line is the chord between the two points where the floe
//! boundaries cross; the normal is perpendicular to it, pointing from the
//! first floe to the second, and the contact length is the chord's length.
//! Where the boundaries do not cross at two distinct points (one floe inside
//! the other, or degenerate touching), the normal is the overlap's thinnest
//! principal direction and the length its extent across that direction.
//! The crossing points are the overlap vertices the clipper made by cutting
//! an edge of the first floe, which it marks as it goes; only when a vertex
//! fell exactly on a clip line (a crossing may then sit on a vertex, which
//! is not marked) are all pairs of edges searched instead.

use crate::geometry::{cross, perp, rotate, MAX_VERTICES};
use crate::Vec2;

/// A convex polygon placed in the world: local counter-clockwise vertices
/// about the centroid, centroid position and orientation.
#[derive(Debug, Clone, Copy)]
pub struct Placed<'a> {
    /// Vertices relative to the centroid, counter-clockwise, m.
    pub vertices: &'a [Vec2],
    /// Centroid position, m.
    pub position: Vec2,
    /// Cosine of the orientation angle.
    pub cos: f64,
    /// Sine of the orientation angle.
    pub sin: f64,
    /// Bounding radius: the largest distance of a vertex from the centroid
    /// (`Floes::radius_m`, `FloeShape::radius_m`), m. The overlap's
    /// round-off floors scale with it, and the separating-edge shortcut
    /// bounds an overlap's area with it.
    pub radius_m: f64,
}

/// A convex polygon placed in the world with its vertices already turned
/// to its orientation (the narrow phase turns every floe's vertices once per
/// step instead of once per pair it is in): bitwise the same placement as a
/// [`Placed`] of the same floe.
#[derive(Debug, Clone, Copy)]
pub struct Oriented<'a> {
    /// Vertices relative to the centroid, turned to the floe's orientation,
    /// counter-clockwise, m.
    pub vertices: &'a [Vec2],
    /// Centroid position, m.
    pub position: Vec2,
    /// Bounding radius (as [`Placed::radius_m`]), m.
    pub radius_m: f64,
}

/// A floe as the clipper reads it: [`Placed`] (local vertices and a
/// rotation) or [`Oriented`] (vertices already turned).
pub trait PlacedPolygon: Copy {
    /// Centroid position, m.
    fn position(&self) -> Vec2;
    /// Bounding radius about the centroid, m.
    fn radius_m(&self) -> f64;
    /// Number of vertices.
    fn vertex_count(&self) -> usize;
    /// Vertex `j` relative to the centroid, in world orientation, m.
    fn vertex(&self, j: usize) -> Vec2;
    /// The vertices in world orientation, shifted by `shift` if given,
    /// into `slots` (as many as both hold).
    fn place_into(&self, slots: &mut [Vec2], shift: Option<Vec2>);
}

impl PlacedPolygon for Placed<'_> {
    #[inline(always)]
    fn position(&self) -> Vec2 {
        self.position
    }
    #[inline(always)]
    fn radius_m(&self) -> f64 {
        self.radius_m
    }
    #[inline(always)]
    fn vertex_count(&self) -> usize {
        self.vertices.len()
    }
    #[inline(always)]
    fn vertex(&self, j: usize) -> Vec2 {
        rotate(self.vertices[j], self.cos, self.sin)
    }
    #[inline(always)]
    fn place_into(&self, slots: &mut [Vec2], shift: Option<Vec2>) {
        let (cos, sin) = (self.cos, self.sin);
        let slots = slots.iter_mut().zip(self.vertices);
        // No zero shift for the first floe: `-0.0 + 0.0` is `+0.0`, and the
        // coordinates must keep their bits.
        match shift {
            Some(shift) => slots.for_each(|(slot, &v)| *slot = shift + rotate(v, cos, sin)),
            None => slots.for_each(|(slot, &v)| *slot = rotate(v, cos, sin)),
        }
    }
}

impl PlacedPolygon for Oriented<'_> {
    #[inline(always)]
    fn position(&self) -> Vec2 {
        self.position
    }
    #[inline(always)]
    fn radius_m(&self) -> f64 {
        self.radius_m
    }
    #[inline(always)]
    fn vertex_count(&self) -> usize {
        self.vertices.len()
    }
    #[inline(always)]
    fn vertex(&self, j: usize) -> Vec2 {
        self.vertices[j]
    }
    #[inline(always)]
    fn place_into(&self, slots: &mut [Vec2], shift: Option<Vec2>) {
        let slots = slots.iter_mut().zip(self.vertices);
        match shift {
            Some(shift) => slots.for_each(|(slot, &v)| *slot = shift + v),
            None => slots.for_each(|(slot, &v)| *slot = v),
        }
    }
}

/// The overlap of two floes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlap {
    /// Overlap area, m^2.
    pub area_m2: f64,
    /// Centroid of the overlap (the contact point), world coordinates, m.
    pub centroid: Vec2,
    /// Unit contact normal, from the first floe towards the second.
    pub normal: Vec2,
    /// Contact length, m.
    pub length_m: f64,
}

/// A polygon in a fixed buffer.
#[derive(Debug, Clone, Copy)]
struct Poly<const N: usize> {
    v: [Vec2; N],
    len: usize,
}

impl<const N: usize> Default for Poly<N> {
    fn default() -> Self {
        Self {
            v: [Vec2::ZERO; N],
            len: 0,
        }
    }
}

impl<const N: usize> Poly<N> {
    #[inline(always)]
    fn as_slice(&self) -> &[Vec2] {
        &self.v[..self.len]
    }
}

/// Working buffers of the clipper (on the stack; kept as a type so callers
/// can hold one per thread). Every buffer lives here rather than in the
/// functions that use it: a fresh zeroed array per call was a `memset` per
/// candidate pair, about 2 % of a step's instructions.
#[derive(Debug, Clone)]
pub struct ClipScratch {
    /// The placed floes, with one slot beyond the vertices for a copy of
    /// the first (edges then need no wrap-around index).
    a: Poly<{ MAX_VERTICES + 1 }>,
    b: Poly<{ MAX_VERTICES + 1 }>,
    /// Clipped polygons, with one slot beyond the `na + nb` vertices an
    /// overlap can have, for a copy of the first vertex.
    bufs: [Poly<{ 2 * MAX_VERTICES + 1 }>; 2],
    /// Side of each vertex of the polygon being clipped, for one clip edge,
    /// with the same extra slot.
    side: [f64; 2 * MAX_VERTICES + 1],
    /// Per vertex of each clipped polygon: [`ON_FIRST`] and [`CROSSING`] bits.
    tags: [[u8; 2 * MAX_VERTICES + 1]; 2],
    /// Edge vectors of the second polygon, for the boundary crossings.
    edges: [Vec2; MAX_VERTICES],
}

impl Default for ClipScratch {
    fn default() -> Self {
        Self {
            a: Poly::default(),
            b: Poly::default(),
            bufs: [Poly::default(), Poly::default()],
            side: [0.0; 2 * MAX_VERTICES + 1],
            tags: [[0; 2 * MAX_VERTICES + 1]; 2],
            edges: [Vec2::ZERO; MAX_VERTICES],
        }
    }
}

impl ClipScratch {
    /// The placed first floe clipped by the placed second, in these buffers:
    /// which of `bufs` holds the overlap, and whether a vertex fell exactly
    /// on a clip line (see [`clip_convex`]).
    /// `radius_a` bounds the first floe's vertices about the frame's origin
    /// (its centroid).
    #[inline(always)]
    fn clip(&mut self, radius_a: f64) -> (usize, bool) {
        clip_convex(
            &self.a,
            &self.b,
            radius_a,
            &mut self.bufs,
            &mut self.side,
            &mut self.tags,
        )
    }
}

/// The index after `i` in a closed polygon of `n` vertices (a compare
/// instead of the integer division of `(i + 1) % n`).
#[inline(always)]
fn next(i: usize, n: usize) -> usize {
    if i + 1 == n {
        0
    } else {
        i + 1
    }
}

/// The vertices of `p` in world orientation, shifted by `shift` if given,
/// into `poly`: at most [`MAX_VERTICES`] (the floe constructor refuses
/// more), and the first again after the last.
#[inline(always)]
fn place(poly: &mut Poly<{ MAX_VERTICES + 1 }>, p: &impl PlacedPolygon, shift: Option<Vec2>) {
    let n = p.vertex_count().min(MAX_VERTICES);
    p.place_into(&mut poly.v[..n], shift);
    poly.v[n] = poly.v[0];
    poly.len = n;
}

/// Overlaps below this fraction of the smaller floe's squared radius are
/// round-off of touching edges, not contacts.
const AREA_FLOOR: f64 = 1e-12;
/// Penetrations (overlap area over contact length) below this many ulps of
/// the floes' coordinates are round-off too: a floe at 1e6 m has its
/// vertices placed to 1.2e-10 m, and two edge-to-edge neighbours rebuilt
/// from their centroids may overlap by that much (seen: 3.6e-11 m over 56 m
/// in a jittered lattice). 64 ulps is 7 nm at 1e6 m.
const PENETRATION_FLOOR_ULPS: f64 = 64.0;

/// The overlap of `a` and `b`, or `None` if they do not overlap.
pub fn overlap<P: PlacedPolygon>(a: P, b: P, scratch: &mut ClipScratch) -> Option<Overlap> {
    debug_assert!(
        (0..a.vertex_count()).all(|j| a.vertex(j).length() <= a.radius_m() * (1.0 + 1e-12))
            && (0..b.vertex_count()).all(|j| b.vertex(j).length() <= b.radius_m() * (1.0 + 1e-12)),
        "the radius must bound the vertices"
    );
    let offset = b.position() - a.position();
    place(&mut scratch.a, &a, None);
    place(&mut scratch.b, &b, Some(offset));
    let (a_position, b_position) = (a.position(), b.position());
    let (a_radius, b_radius) = (a.radius_m(), b.radius_m());
    let (result, exact_zero) = scratch.clip(a_radius);
    let len = scratch.bufs[result].len;
    if len < 3 {
        return None;
    }
    // The first vertex again after the last (the clipper leaves that slot
    // free), so that the edges below need no wrap-around index.
    scratch.bufs[result].v[len] = scratch.bufs[result].v[0];
    let closed = &scratch.bufs[result].v[..=len];
    let poly = &closed[..len];
    let (area, centroid) = crate::geometry::shape::area_and_centroid(poly);
    let size = a_radius.min(b_radius);
    if area <= AREA_FLOOR * size * size {
        return None;
    }
    // The boundary crossings are the clipper's own crossing vertices, unless
    // a vertex fell exactly on a clip line: then a crossing may sit on a
    // vertex, which the clipper does not mark, and the edges are searched.
    let chord = if exact_zero {
        boundary_chord(
            scratch.a.as_slice(),
            scratch.b.as_slice(),
            &mut scratch.edges,
            size,
        )
    } else {
        marked_chord(poly, &scratch.tags[result][..poly.len()], size)
    };
    let (normal, length) = match chord {
        Some(chord) => (
            perp(snap_to_overlap_edge(chord, closed)).normalize(),
            chord.length(),
        ),
        None => principal_normal(closed, centroid),
    };
    let scale = a_position
        .abs()
        .max_element()
        .max(b_position.abs().max_element());
    if area <= PENETRATION_FLOOR_ULPS * f64::EPSILON * scale * length {
        return None;
    }
    let normal = if normal.dot(offset) < 0.0 {
        -normal
    } else {
        normal
    };
    Some(Overlap {
        area_m2: area,
        centroid: a_position + centroid,
        normal,
        length_m: length,
    })
}

/// An edge that separated two floes at an earlier step, remembered per
/// candidate pair so that a pair that stays apart is rejected by testing
/// that one edge instead of clipping. Most candidate pairs never touch: a
/// rhombus's bounding circle overlaps those of its vertex neighbours.
/// "Separated" includes touching: the other floe may reach past the edge's
/// line by a depth too small for an overlap above the area floor (see
/// `TOUCH_DEPTH` in the source), so that edge-to-edge neighbours that exactly touch,
/// every pair of an unpressed lattice, are not clipped at every step either.
/// Where no edge will do, a corner (two adjacent edges) of either floe may:
/// vertex neighbours pressed a few micrometres into each other's corner,
/// whose overlap is far below the floor but reaches past every edge line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SeparatingEdge(u8);

impl SeparatingEdge {
    /// No edge known: the pair is clipped, and searched for a separating
    /// edge if it does not overlap.
    pub const NONE: Self = Self(0);
    /// Searched without success, and the floes do not overlap (an overlap
    /// below the round-off floors): the pair is clipped and not searched
    /// again until it overlaps.
    const TOUCHING: Self = Self(u8::MAX);
    /// Codes `1..=MAX_VERTICES`: edge `code - 1` of the second floe; then
    /// the edges of the first, the corners (at vertex `k`, between edges
    /// `k - 1` and `k`) of the second, and the corners of the first.
    const SECOND_BASE: u8 = 1;
    const FIRST_BASE: u8 = Self::SECOND_BASE + MAX_VERTICES as u8;
    const SECOND_CORNER_BASE: u8 = Self::FIRST_BASE + MAX_VERTICES as u8;
    const FIRST_CORNER_BASE: u8 = Self::SECOND_CORNER_BASE + MAX_VERTICES as u8;
}

/// How far the other floe may reach past a remembered edge's line for the
/// pair to be rejected without clipping, as a fraction of the area floor.
/// If every vertex of floe `Q` lies within depth `w` of the inner side of an
/// edge of floe `P`, the overlap lies in a strip of width `w` across `Q`,
/// whose area is at most `2 r_Q w`. With `w = TOUCH_DEPTH * AREA_FLOOR *
/// r_min^2 / (2 r_Q)` that is half the floor below which [`overlap`] reports
/// no contact, so the shortcut rejects only pairs that clipping rejects too.
/// A remembered corner is held to the same half of the floor
/// (`corner_apart`). The sides are computed in floating point: `w` is
/// reduced by a bound on their round-off ([`SIDE_ROUND_OFF`]), and the
/// shortcut becomes "beyond the line by that bound" where the bound exceeds
/// `w` (touching a floe roughly 8-16 times larger, or 70-280 times smaller, depending on the
/// offset). The clipper's own round-off on the overlap area, about `eps
/// r_max r_min`, stays below the floor for size ratios up to 1e3 (4.5
/// times below at 1e3); so for floes within a factor 1e3 of each other the
/// results are those of clipping every pair (tested, with sizes a factor 10
/// apart: `no_remembered_edge_rejects_a_pair_that_clipping_keeps`).
const TOUCH_DEPTH: f64 = 0.5;

/// Round-off of the side function `cross(e - s, p - s)` over the edge's
/// length, in units of `eps W`, where `W = |offset| + r_a + r_b` bounds the
/// distance `|p - s|` between a vertex of one floe and a vertex of the
/// other (the only case tested). With `u = eps/2`, the two differences, two
/// products and their difference put the computed side within `u |d x w| +
/// 3.01 u (|d_x w_y| + |d_y w_x|) <= 2.005 eps |d| |w|` of the exact one
/// (`d = e - s`, `w = p - s`, Cauchy-Schwarz), and `|d|` is the edge's
/// length to within an ulp or two: 4 leaves room to spare. (A first bound, `16 eps X^2` with `X = |offset| + r_a + 2 r_b`,
/// ignored that the error scales with the edge's length: for the long thin
/// floes that clipping leaves along a channel's walls it exceeded the
/// allowed depth 200 times over, and every touching pair of them was
/// clipped at every step, a third of all clipping at 2,113 floes.)
const SIDE_ROUND_OFF: f64 = 4.0;

/// `true` if every one of `points` lies beyond the line of the edge
/// `s -> e` of a counter-clockwise polygon, or inside it by less than
/// `depth` (m), after allowing `round_off` (m) for the round-off of the
/// side function.
#[inline(always)]
fn all_beyond(
    s: Vec2,
    e: Vec2,
    points: impl Iterator<Item = Vec2>,
    depth: f64,
    round_off: f64,
) -> bool {
    let dir = e - s;
    // Negative where the round-off exceeds the allowed depth: every point
    // must then lie beyond the line by the round-off.
    let limit = (depth - round_off) * dir.length();
    let mut beyond = true;
    for p in points {
        // No early exit: the loop is a few vertices, and branch-free it vectorises.
        beyond &= cross(dir, p - s) < limit;
    }
    beyond
}

/// The depth by which floe `q` (bounding radius `r_q`) may reach past an
/// edge of the other floe without an overlap above the area floor
/// (`r_min`: the smaller bounding radius), m.
#[inline(always)]
fn touch_depth(r_min: f64, r_q: f64) -> f64 {
    TOUCH_DEPTH * AREA_FLOOR * r_min * r_min / (2.0 * r_q)
}

/// [`overlap`], with a shortcut for pairs that stay apart or merely touch:
/// `edge` is the pair's remembered separating edge, updated here. The
/// result is bitwise that of [`overlap`] whatever `edge` holds (see
/// `TOUCH_DEPTH` in the source).
pub fn overlap_cached<P: PlacedPolygon>(
    a: P,
    b: P,
    edge: &mut SeparatingEdge,
    scratch: &mut ClipScratch,
) -> Option<Overlap> {
    let offset = b.position() - a.position();
    let code = edge.0;
    if *edge != SeparatingEdge::NONE && *edge != SeparatingEdge::TOUCHING {
        let apart = still_apart(
            code,
            (a.vertex_count(), |j| a.vertex(j)),
            (b.vertex_count(), |j| offset + b.vertex(j)),
            &Allowance::new(&a, &b, offset),
        );
        if apart {
            return None;
        }
    }
    let result = overlap(a, b, scratch);
    *edge = match (result.is_some(), *edge) {
        (true, _) => SeparatingEdge::NONE,
        (false, SeparatingEdge::TOUCHING) => SeparatingEdge::TOUCHING,
        // Look for a separating edge among both floes' (already placed)
        // vertices: once per pair while it stays apart, not every step.
        (false, _) => find_separating_edge(
            scratch.a.as_slice(),
            scratch.b.as_slice(),
            &Allowance::new(&a, &b, offset),
        ),
    };
    result
}

/// How far each floe may reach past an edge of the other for the pair to
/// count as apart, and the side function's round-off. Computed only where a
/// remembered edge is tested or searched for, not for the pairs that
/// overlap (most of those clipped).
struct Allowance {
    /// Depth allowed to the first floe past an edge of the second, m.
    depth_of_a: f64,
    /// Depth allowed to the second floe past an edge of the first, m.
    depth_of_b: f64,
    /// Round-off of the side function over the edge's length, m.
    round_off: f64,
    /// Largest overlap a corner may bound for the pair to count as apart:
    /// [`TOUCH_DEPTH`] of the area floor, m^2.
    corner_m2: f64,
}

impl Allowance {
    #[inline(always)]
    fn new(a: &impl PlacedPolygon, b: &impl PlacedPolygon, offset: Vec2) -> Self {
        let (r_a, r_b) = (a.radius_m(), b.radius_m());
        let r_min = r_a.min(r_b);
        let extent = offset.length() + r_a + r_b;
        Self {
            depth_of_a: touch_depth(r_min, r_a),
            depth_of_b: touch_depth(r_min, r_b),
            round_off: SIDE_ROUND_OFF * f64::EPSILON * extent,
            corner_m2: TOUCH_DEPTH * AREA_FLOOR * r_min * r_min,
        }
    }
}

/// Whether the pair is still apart by its remembered edge or corner
/// `code`: each floe as its vertex count and its placed vertices, the first
/// then the second (in the same frame). One predicate for the test at each
/// step and for the search ([`find_separating_edge`]), so that what the
/// search finds is what the test accepts.
#[inline(always)]
fn still_apart(
    code: u8,
    (na, a): (usize, impl Fn(usize) -> Vec2),
    (nb, b): (usize, impl Fn(usize) -> Vec2),
    allowed: &Allowance,
) -> bool {
    // Which floe the edge or corner is of, which kind, and its index.
    let (of_first, corner, base) = if code < SeparatingEdge::FIRST_BASE {
        (false, false, SeparatingEdge::SECOND_BASE)
    } else if code < SeparatingEdge::SECOND_CORNER_BASE {
        (true, false, SeparatingEdge::FIRST_BASE)
    } else if code < SeparatingEdge::FIRST_CORNER_BASE {
        (false, true, SeparatingEdge::SECOND_CORNER_BASE)
    } else {
        (true, true, SeparatingEdge::FIRST_CORNER_BASE)
    };
    let k = usize::from(code - base);
    if of_first {
        apart_by(corner, k, (na, a), (nb, b), allowed.depth_of_b, allowed)
    } else {
        apart_by(corner, k, (nb, b), (na, a), allowed.depth_of_a, allowed)
    }
}

/// [`still_apart`] for edge or corner `k` of floe `P`, the other floe `Q`
/// allowed `depth_of_q` past an edge line.
#[inline(always)]
fn apart_by(
    corner: bool,
    k: usize,
    (np, p): (usize, impl Fn(usize) -> Vec2),
    (nq, q): (usize, impl Fn(usize) -> Vec2),
    depth_of_q: f64,
    allowed: &Allowance,
) -> bool {
    if corner {
        corner_apart(
            p(prev(k, np)),
            p(k),
            p(next(k, np)),
            (0..nq).map(q),
            allowed,
        )
    } else {
        all_beyond(
            p(k),
            p(next(k, np)),
            (0..nq).map(q),
            depth_of_q,
            allowed.round_off,
        )
    }
}

/// `true` if the overlap of a convex floe `P` with the polygon of `points`
/// is too small for a contact, judged from the corner of `P` at `at`
/// (edges `prev -> at` and `at -> next`). If `points` reach past the two
/// edge lines by at most `w1` and `w2`, the overlap (inside `P`, so inside
/// both lines, and inside the points' hull) lies where two strips of those
/// widths along the lines cross: a parallelogram of area `w1 w2 / sin(angle)`.
/// Apart if that is at most half the area floor, after the sides' round-off.
#[inline(always)]
fn corner_apart(
    prev: Vec2,
    at: Vec2,
    next: Vec2,
    points: impl Iterator<Item = Vec2>,
    allowed: &Allowance,
) -> bool {
    let (d1, d2) = (at - prev, next - at);
    let (mut m1, mut m2) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in points {
        m1 = m1.max(cross(d1, p - prev));
        m2 = m2.max(cross(d2, p - at));
    }
    let (l1, l2) = (d1.length(), d2.length());
    let w1 = (m1 / l1 + allowed.round_off).max(0.0);
    let w2 = (m2 / l2 + allowed.round_off).max(0.0);
    // A lower bound on the sine: the cross product is within about 2 eps
    // of its terms' size, the lengths and the division add about 2 eps.
    let sine = cross(d1, d2).abs() / (l1 * l2) - 8.0 * f64::EPSILON;
    sine > 0.0 && w1 * w2 * (1.0 + 1e-9) <= allowed.corner_m2 * sine
}

/// The index before `i` in a closed polygon of `n` vertices.
#[inline(always)]
fn prev(i: usize, n: usize) -> usize {
    if i == 0 {
        n - 1
    } else {
        i - 1
    }
}

/// An edge of `b`, then of `a`, then a corner of `b`, then of `a` (both
/// counter-clockwise, same frame) by which the floes are apart (see
/// [`still_apart`]), or [`SeparatingEdge::TOUCHING`].
fn find_separating_edge(a: &[Vec2], b: &[Vec2], allowed: &Allowance) -> SeparatingEdge {
    let (na, nb) = (a.len(), b.len());
    let codes = (0..nb)
        .map(|k| SeparatingEdge::SECOND_BASE + k as u8)
        .chain((0..na).map(|k| SeparatingEdge::FIRST_BASE + k as u8))
        .chain((0..nb).map(|k| SeparatingEdge::SECOND_CORNER_BASE + k as u8))
        .chain((0..na).map(|k| SeparatingEdge::FIRST_CORNER_BASE + k as u8));
    for code in codes {
        if still_apart(code, (na, |j| a[j]), (nb, |j| b[j]), allowed) {
            return SeparatingEdge(code);
        }
    }
    SeparatingEdge::TOUCHING
}

/// The edge leaving a vertex lies on an edge of the subject (the first floe).
const ON_FIRST: u8 = 1;
/// The vertex is a point where the two floes' boundaries cross: a subject
/// edge cut by a clip line.
const CROSSING: u8 = 2;

/// Sutherland-Hodgman: `subject` clipped by every edge of the convex,
/// counter-clockwise `clip`, which must repeat its first vertex after its
/// last (`clip.v[clip.len] == clip.v[0]`, `clip.len < N`: [`place`] does
/// both). Points on a clip line count as inside. The two
/// buffers alternate as source and destination (no copying between them);
/// returns which one holds the result, and whether any vertex fell exactly
/// on a clip line.
///
/// Each vertex carries two bits in `tags`: whether the edge leaving it lies
/// on a subject edge ([`ON_FIRST`]; otherwise on a clip line), and whether
/// it is a boundary crossing ([`CROSSING`]): a point made by cutting a
/// subject edge. Cutting an edge that lies on an earlier clip line makes a
/// vertex of the clip polygon instead. So the contact chord comes with the
/// clipping, where searching every pair of edges for crossings was 13 % of a
/// step's instructions.
// Indexed loops on purpose: see the first comment in the body.
#[allow(clippy::needless_range_loop)]
fn clip_convex<const N: usize, const M: usize>(
    subject: &Poly<N>,
    clip: &Poly<N>,
    subject_radius: f64,
    bufs: &mut [Poly<M>; 2],
    side: &mut [f64; M],
    tags: &mut [[u8; M]; 2],
) -> (usize, bool) {
    // Indexed loops over the fixed buffers, with their lengths bounded
    // first so that no index is checked, and element-wise copies: for the
    // few vertices of a floe, `copy_from_slice`, `fill` and the iterator
    // adaptors were library calls and overhead, a quarter of the clipper's
    // instructions.
    debug_assert!(clip.len < N && clip.v[clip.len] == clip.v[0]);
    let ns = subject.len.min(N - 1).min(M - 1);
    for k in 0..ns {
        bufs[0].v[k] = subject.v[k];
    }
    // All `N` slots, a fixed length the compiler writes inline (a
    // variable one was a `memset` call per pair).
    tags[0][..N.min(M)].fill(ON_FIRST);
    bufs[0].len = ns;
    let n = clip.len.min(N - 1);
    let mut cur = 0;
    let mut exact_zero = false;
    for i in 0..n {
        let m = bufs[cur].len.min(M - 1);
        if m == 0 {
            return (cur, exact_zero);
        }
        // `clip` repeats its first vertex after the last (`place`).
        let (s, e) = (clip.v[i], clip.v[i + 1]);
        let dir = e - s;
        // An edge whose line keeps the subject's whole bounding circle
        // inside, with room to spare, keeps every vertex strictly inside
        // (the polygon being clipped lies in the subject): skipped without
        // computing their sides. The edges of the second floe facing away
        // from the first, about half of them. The margin (on squares: 5e-10
        // of the radius in distance) dwarfs the round-off of the sides while
        // the second floe is less than about 1e5 times the first's size, so
        // no vertex that this skips could have been found exactly on the
        // line: the result is that of testing them.
        let origin_side = cross(dir, -s);
        if origin_side > 0.0
            && origin_side * origin_side
                > (1.0 + 1e-9) * subject_radius * subject_radius * dir.length_squared()
        {
            continue;
        }
        // Side of every vertex once; an edge that keeps all of them (most
        // of the clip polygon's edges) changes nothing and is skipped. A
        // vertex is on the line if it counts as inside but not as strictly
        // inside: two counts, cheaper than a flag updated per vertex.
        let (mut inside, mut strictly) = (0, 0);
        for k in 0..m {
            let d = cross(dir, bufs[cur].v[k] - s);
            side[k] = d;
            inside += usize::from(d >= 0.0);
            strictly += usize::from(d > 0.0);
        }
        exact_zero |= inside != strictly;
        if inside == m {
            continue;
        }
        if inside == 0 {
            bufs[1 - cur].len = 0;
            return (1 - cur, exact_zero);
        }
        // The first vertex again after the last, so that the closing edge
        // needs no wrap-around index in the loop below.
        side[m] = side[0];
        bufs[cur].v[m] = bufs[cur].v[0];
        let (first, second) = bufs.split_at_mut(1);
        let (src, dst) = if cur == 0 {
            (&first[0], &mut second[0])
        } else {
            (&second[0], &mut first[0])
        };
        let (tags_first, tags_second) = tags.split_at_mut(1);
        let (src_tags, dst_tags) = if cur == 0 {
            (&tags_first[0], &mut tags_second[0])
        } else {
            (&tags_second[0], &mut tags_first[0])
        };
        // The output length in a local: a `push` method stored it back to
        // memory after every vertex. Sutherland-Hodgman adds at most one
        // vertex per clip edge, so `M - 1 = na + nb` always suffices for
        // convex input; the guard only matters for inputs made non-convex by
        // round-off, where vertices beyond it are dropped, as before.
        let mut out = 0;
        let mut emit = |p: Vec2, tag: u8| {
            if out < M - 1 {
                dst.v[out] = p;
                dst_tags[out] = tag;
                out += 1;
            }
        };
        for k in 0..m {
            let (p, q, dp, dq) = (src.v[k], src.v[k + 1], side[k], side[k + 1]);
            let tag = src_tags[k];
            // A cut of this edge is a boundary crossing if the edge lies on
            // the subject's boundary.
            let cut = if tag & ON_FIRST != 0 { CROSSING } else { 0 };
            if dp >= 0.0 {
                emit(p, tag);
                if dq < 0.0 {
                    // Leaving: the edge from the cut runs along the clip line.
                    emit(p + (q - p) * (dp / (dp - dq)), cut);
                }
            } else if dq >= 0.0 {
                // Entering: the edge from the cut is the rest of this edge.
                emit(p + (q - p) * (dp / (dp - dq)), cut | (tag & ON_FIRST));
            }
        }
        dst.len = out;
        cur = 1 - cur;
    }
    (cur, exact_zero)
}

/// The chord between the overlap's two vertices marked as boundary
/// crossings, if there are exactly two, further apart than `1e-9 size`.
fn marked_chord(poly: &[Vec2], tags: &[u8], size: f64) -> Option<Vec2> {
    let mut points = [Vec2::ZERO; 2];
    let mut count = 0;
    for (&p, &tag) in poly.iter().zip(tags) {
        if tag & CROSSING != 0 {
            if count == 2 {
                return None;
            }
            points[count] = p;
            count += 1;
        }
    }
    let chord = points[1] - points[0];
    let tol = 1e-9 * size;
    (count == 2 && chord.length_squared() > tol * tol).then_some(chord)
}

/// The chord between the two points where the boundaries of `a` and `b`
/// properly cross, if there are exactly two distinct such points. `edges`
/// receives `b`'s edge vectors, computed once instead of once per edge of `a`.
fn boundary_chord(
    a: &[Vec2],
    b: &[Vec2],
    edges: &mut [Vec2; MAX_VERTICES],
    size: f64,
) -> Option<Vec2> {
    let mut points = [Vec2::ZERO; 2];
    let mut count = 0;
    let tol = 1e-9 * size;
    let edges = &mut edges[..b.len()];
    for (j, s) in edges.iter_mut().enumerate() {
        *s = b[next(j, b.len())] - b[j];
    }
    for i in 0..a.len() {
        let (p, r) = (a[i], a[next(i, a.len())] - a[i]);
        for (&q, &s) in b.iter().zip(edges.iter()) {
            let denom = cross(r, s);
            // Crossing parameters t = tn/denom, u = un/denom in [0, 1],
            // tested without dividing: most edge pairs do not cross, and
            // most already fail on t, before un is computed.
            let tn = cross(q - p, s);
            let (tn, d) = if denom < 0.0 {
                (-tn, -denom)
            } else {
                (tn, denom)
            };
            if tn < 0.0 || tn > d {
                continue;
            }
            let un = cross(q - p, r);
            let un = if denom < 0.0 { -un } else { un };
            if un < 0.0 || un > d {
                continue;
            }
            if d * d <= 1e-28 * r.length_squared() * s.length_squared() {
                continue; // parallel or collinear edges do not cross
            }
            let x = p + r * (tn / d);
            if points[..count].iter().any(|&y| (y - x).length() <= tol) {
                continue; // the same crossing seen from two edges meeting at a vertex
            }
            if count == 2 {
                return None;
            }
            points[count] = x;
            count += 1;
        }
    }
    (count == 2 && (points[1] - points[0]).length() > tol).then(|| points[1] - points[0])
}

/// Largest angle (sine) between the chord and an overlap edge it snaps to.
const SNAP_SINE: f64 = 0.17; // about 10 degrees

/// The chord turned onto the longest edge of the overlap polygon that is
/// within 10 degrees of it. Two floes pressed edge to edge overlap in a thin
/// parallelogram whose boundary crossings are opposite corners: the chord is
/// then the diagonal, off the shared edge by about depth/length, and the
/// pressed edge itself is the right contact line. For a corner pressed into
/// an edge the chord already is an edge of the overlap and is unchanged.
/// `closed` is the overlap polygon with its first vertex repeated at the end.
fn snap_to_overlap_edge(chord: Vec2, closed: &[Vec2]) -> Vec2 {
    // On squares, against the chord as it is: no square root per edge, and
    // none to normalise the chord.
    let chord_len2 = chord.length_squared();
    let mut best = chord;
    let mut best_len2 = 0.25 * chord_len2;
    for edge in closed.windows(2) {
        let e = edge[1] - edge[0];
        let len2 = e.length_squared();
        let c = cross(chord, e);
        if len2 > best_len2 && c * c <= SNAP_SINE * SNAP_SINE * chord_len2 * len2 {
            best = if e.dot(chord) >= 0.0 { e } else { -e };
            best_len2 = len2;
        }
    }
    best
}

/// Normal along the overlap's thinnest principal direction, and the overlap's
/// extent across it. `closed` is the overlap polygon with its first vertex
/// repeated at the end.
fn principal_normal(closed: &[Vec2], centroid: Vec2) -> (Vec2, f64) {
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for edge in closed.windows(2) {
        let (u, v) = (edge[0] - centroid, edge[1] - centroid);
        let w = cross(u, v);
        sxx += w * (u.x * u.x + u.x * v.x + v.x * v.x);
        syy += w * (u.y * u.y + u.y * v.y + v.y * v.y);
        sxy += w * (2.0 * u.x * u.y + u.x * v.y + v.x * u.y + 2.0 * v.x * v.y);
    }
    let (sxx, syy, sxy) = (sxx / 12.0, syy / 12.0, sxy / 24.0);
    // Eigenvector of the smaller eigenvalue of [[sxx, sxy], [sxy, syy]].
    let half_diff = 0.5 * (sxx - syy);
    let radius = (half_diff * half_diff + sxy * sxy).sqrt();
    let normal = if radius <= 1e-9 * (sxx + syy) {
        Vec2::new(1.0, 0.0) // isotropic: any direction; the caller orients it
    } else {
        let major_angle = 0.5 * sxy.atan2(half_diff);
        Vec2::new(-major_angle.sin(), major_angle.cos())
    };
    let tangent = perp(normal);
    let (lo, hi) = closed[..closed.len() - 1].iter().fold(
        (f64::INFINITY, f64::NEG_INFINITY),
        |(lo, hi), &p| {
            let s = tangent.dot(p);
            (lo.min(s), hi.max(s))
        },
    );
    (normal, hi - lo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A convex polygon: points at increasing angles on an ellipse of axes
    /// `scale * (sx, sy)` (an affine image of a circle, so always convex),
    /// counter-clockwise.
    fn convex(scale: f64, angles: &[f64], (sx, sy): (f64, f64)) -> Vec<Vec2> {
        let mut a: Vec<f64> = angles.to_vec();
        a.sort_by(f64::total_cmp);
        a.dedup_by(|x, y| (*x - *y).abs() < 0.3);
        if a.len() >= 2 && a[0] + std::f64::consts::TAU - a[a.len() - 1] < 0.3 {
            a.pop();
        }
        a.iter()
            .map(|&t| Vec2::new(t.cos() * sx, t.sin() * sy) * scale)
            .collect()
    }

    /// Radius of a polygon about its origin (the test polygons are built
    /// about their centre, not their centroid: the bound needs only that
    /// every vertex is within the radius of the placed position).
    fn radius(v: &[Vec2]) -> f64 {
        v.iter().map(|p| p.length()).fold(0.0, f64::max)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, max_global_rejects: 20_000, ..ProptestConfig::default() })]

        /// The shortcut is exact: at every depth from clearly apart through
        /// touching to 1e-15 of the size into each other, no remembered
        /// edge of either floe rejects a pair that clipping keeps, and the
        /// shortcut's result is bitwise the clipper's. Floes up to a factor
        /// 10 apart in size, at the origin or at basin coordinates, meeting
        /// at random angles or edge to edge (antiparallel edges, exactly or
        /// tilted by up to 1e-3 rad): edge to edge, the overlap is a thin
        /// strip and the area floor decides, which is what the allowed
        /// depth is bounded by. With the depth 4 times larger it fails.
        #[test]
        fn no_remembered_edge_rejects_a_pair_that_clipping_keeps(
            angles_a in prop::collection::vec(0.0..std::f64::consts::TAU, 4..7),
            axes_a in (0.3..1.0f64, 0.3..1.0f64),
            angles_b in prop::collection::vec(0.0..std::f64::consts::TAU, 4..7),
            axes_b in (0.3..1.0f64, 0.3..1.0f64),
            scale in 1.0..2000.0f64,
            size_ratio in -1.0..1.0f64,
            base in prop_oneof![Just((0.0, 0.0)), (-1e6..1e6f64, -1e6..1e6f64)],
            edge_to_edge in any::<bool>(),
            (edge_a, edge_b) in (0..16usize, 0..16usize),
            tilt in prop_oneof![Just(0.0), -1e-3..1e-3f64],
            random_turn in 0.0..std::f64::consts::TAU,
            random_heading in 0.0..std::f64::consts::TAU,
            exponent in -15.0..-1.0f64,
            inward in any::<bool>(),
        ) {
            let va = convex(scale, &angles_a, axes_a);
            let vb = convex(scale * 10f64.powf(size_ratio), &angles_b, axes_b);
            prop_assume!(va.len() >= 3 && vb.len() >= 3);
            let edge_angle = |v: &[Vec2], k: usize| {
                let d = v[next(k, v.len())] - v[k];
                d.y.atan2(d.x)
            };
            let (turn, heading) = if edge_to_edge {
                // b's edge turned to face a's edge, b approaching along that
                // edge's outward normal.
                let (i, j) = (edge_a % va.len(), edge_b % vb.len());
                let alpha = edge_angle(&va, i);
                (
                    alpha - edge_angle(&vb, j) + std::f64::consts::PI + tilt,
                    alpha - std::f64::consts::FRAC_PI_2,
                )
            } else {
                (random_turn, random_heading)
            };
            let base = Vec2::new(base.0, base.1);
            let a = Placed { vertices: &va, position: base, cos: 1.0, sin: 0.0, radius_m: radius(&va) };
            let along = Vec2::new(heading.cos(), heading.sin());
            let b_at = |t: f64| Placed {
                vertices: &vb,
                position: base + along * t,
                cos: turn.cos(),
                sin: turn.sin(),
                radius_m: radius(&vb),
            };
            let mut scratch = ClipScratch::default();
            // The distance along `heading` at which the floes stop overlapping.
            let (mut lo, mut hi) = (0.0, a.radius_m + b_at(0.0).radius_m);
            prop_assume!(overlap(a, b_at(lo), &mut scratch).is_some());
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if overlap(a, b_at(mid), &mut scratch).is_some() { lo = mid } else { hi = mid }
            }
            let shift = 10f64.powf(exponent) * scale;
            let t = if inward { lo - shift } else { hi + shift };
            for t in [t, lo, hi] {
                let b = b_at(t);
                let clipped = overlap(a, b, &mut scratch);
                // Every edge and every corner of both floes.
                let bases = [
                    (SeparatingEdge::SECOND_BASE, vb.len()),
                    (SeparatingEdge::FIRST_BASE, va.len()),
                    (SeparatingEdge::SECOND_CORNER_BASE, vb.len()),
                    (SeparatingEdge::FIRST_CORNER_BASE, va.len()),
                ];
                for code in bases.into_iter().flat_map(|(base, n)| base as usize..base as usize + n) {
                    let mut edge = SeparatingEdge(code as u8);
                    let cached = overlap_cached(a, b, &mut edge, &mut scratch);
                    prop_assert_eq!(cached, clipped, "edge code {}, t {}", code, t);
                }
            }
        }

        /// The chord read from the clipper's crossing marks against the
        /// search of every pair of edges for crossings: two independent ways
        /// to the same two points.
        #[test]
        fn the_marked_crossings_are_the_crossings_of_the_edges(
            angles_a in prop::collection::vec(0.0..std::f64::consts::TAU, 4..7),
            axes_a in (0.3..1.0f64, 0.3..1.0f64),
            angles_b in prop::collection::vec(0.0..std::f64::consts::TAU, 4..7),
            axes_b in (0.3..1.0f64, 0.3..1.0f64),
            scale in 1.0..2000.0f64,
            turn in 0.0..std::f64::consts::TAU,
            (dx, dy) in (-1.2..1.2f64, -1.2..1.2f64),
        ) {
            let va = convex(scale, &angles_a, axes_a);
            let vb = convex(scale, &angles_b, axes_b);
            prop_assume!(va.len() >= 3 && vb.len() >= 3);
            let mut scratch = ClipScratch::default();
            let pa = Placed { vertices: &va, position: Vec2::ZERO, cos: 1.0, sin: 0.0, radius_m: radius(&va) };
            let pb = Placed { vertices: &vb, position: Vec2::ZERO, cos: turn.cos(), sin: turn.sin(), radius_m: radius(&vb) };
            place(&mut scratch.a, &pa, None);
            place(&mut scratch.b, &pb, Some(Vec2::new(dx, dy) * scale));
            let (result, exact_zero) = scratch.clip(radius(&va));
            prop_assume!(!exact_zero);
            let poly = scratch.bufs[result].as_slice().to_vec();
            prop_assume!(poly.len() >= 3);
            let size = scale * 0.5;
            let marked = marked_chord(&poly, &scratch.tags[result][..poly.len()], size);
            let searched = boundary_chord(scratch.a.as_slice(), scratch.b.as_slice(), &mut scratch.edges, size);
            match (marked, searched) {
                (Some(m), Some(s)) => {
                    let close = (m - s).length().min((m + s).length());
                    prop_assert!(close <= 1e-9 * scale, "marked {m:?} searched {s:?}");
                }
                (None, None) => {}
                other => prop_assert!(false, "one found a chord, the other not: {other:?}, overlap {poly:?}"),
            }
        }
    }
}

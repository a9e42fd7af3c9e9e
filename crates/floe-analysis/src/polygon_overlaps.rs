//! The overlaps of convex polygons to every order, the terms of the area
//! of their union by inclusion-exclusion:
//! `|U P_i| = sum |P_i| - sum_{i<j} |P_i n P_j| + sum_{i<j<k} |P_i n P_j n P_k| - ...`
//!
//! An intersection of convex polygons is convex, so each term is found
//! exactly by clipping ([`intersect_convex`]). A set of polygons has a
//! common overlap only if every two of them overlap, so the sets are grown
//! one polygon at a time from the overlapping pairs, in increasing index
//! order, each set found once, and a set whose overlap is empty is not
//! grown further. The cost is linear in the number of sets with a common
//! overlap: about the number of contacts in a pack of soft floes, where a
//! place lies under two floes, three at a junction, rarely more.
//! Candidate pairs come from parry's bounding-volume hierarchy over the
//! polygons' bounding boxes (`O(n log n)`, whatever the floes' sizes).

use parry2d_f64::bounding_volume::Aabb;
use parry2d_f64::math::Vector;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy};

use crate::polygon::{bounds, intersect_convex, polygon_area};
use crate::AnalysisError;

/// Most polygons over one place: `2^k` sets of them have a common overlap
/// there, so beyond this the count, not the geometry, would set the cost.
/// Soft contacts of a dense pack put three or four floes over a place.
pub const MAX_OVERLAP_ORDER: usize = 12;

/// Calls `visit(order, overlap)` for every set of two or more of `polys`
/// (convex, either winding) whose common overlap has a positive area, with
/// the set's size and that overlap; sets whose overlap's bounding box
/// `wanted(lo, hi)` refuses are left out, and so are the sets that contain
/// them. Sets come in a fixed order (by their smallest index, then the
/// next), so the sums a caller makes are the same from run to run.
///
/// # Errors
/// [`AnalysisError::TooManyOverlaps`] where more than
/// [`MAX_OVERLAP_ORDER`] polygons share a place.
pub(crate) fn for_each_overlap(
    polys: &[Vec<[f64; 2]>],
    wanted: impl Fn([f64; 2], [f64; 2]) -> bool,
    mut visit: impl FnMut(usize, &[[f64; 2]]),
) -> Result<(), AnalysisError> {
    let neighbours = overlapping_pairs(polys, &wanted);
    let mut grower = Grower {
        polys,
        neighbours: &neighbours,
        wanted: &wanted,
        visit: &mut visit,
    };
    for pairs in &neighbours {
        for (j, overlap) in pairs {
            // Polygons after j that overlap both j and the pair's first.
            let candidates = common(pairs.iter().map(|p| p.0), &neighbours[*j], *j);
            (grower.visit)(2, overlap);
            grower.grow(overlap, &candidates, 2)?;
        }
    }
    Ok(())
}

/// For each polygon, the later polygons it overlaps (positive area), in
/// increasing order, with the overlap.
type Neighbours = Vec<Vec<(usize, Vec<[f64; 2]>)>>;

/// The pairs of `polys` that overlap, with their overlap, as [`Neighbours`].
fn overlapping_pairs(
    polys: &[Vec<[f64; 2]>],
    wanted: &impl Fn([f64; 2], [f64; 2]) -> bool,
) -> Neighbours {
    let boxes: Vec<Aabb> = polys
        .iter()
        .map(|p| {
            let (lo, hi) = bounds(p);
            Aabb::new(Vector::new(lo[0], lo[1]), Vector::new(hi[0], hi[1]))
        })
        .collect();
    let mut neighbours: Neighbours = vec![Vec::new(); polys.len()];
    if polys.len() < 2 {
        return neighbours;
    }
    let tree = Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes);
    for (i, found) in neighbours.iter_mut().enumerate() {
        let mut later: Vec<usize> = tree
            .intersect_aabb(&boxes[i])
            .map(|j| j as usize)
            .filter(|&j| j > i)
            .collect();
        later.sort_unstable();
        for j in later {
            if let Some(overlap) = overlap_of(&polys[i], &polys[j], wanted) {
                found.push((j, overlap));
            }
        }
    }
    neighbours
}

/// The overlap of `a` and `b` if it has a positive area and `wanted` takes
/// its bounding box.
fn overlap_of(
    a: &[[f64; 2]],
    b: &[[f64; 2]],
    wanted: &impl Fn([f64; 2], [f64; 2]) -> bool,
) -> Option<Vec<[f64; 2]>> {
    let overlap = intersect_convex(a, b);
    if overlap.len() < 3 || polygon_area(&overlap) <= 0.0 {
        return None;
    }
    let (lo, hi) = bounds(&overlap);
    wanted(lo, hi).then_some(overlap)
}

/// The entries of the increasing `first` that are in `second` and after
/// `after`.
fn common(
    first: impl Iterator<Item = usize>,
    second: &[(usize, Vec<[f64; 2]>)],
    after: usize,
) -> Vec<usize> {
    first
        .filter(|&k| k > after && second.binary_search_by_key(&k, |p| p.0).is_ok())
        .collect()
}

/// What growing the sets needs.
struct Grower<'a, W, V> {
    polys: &'a [Vec<[f64; 2]>],
    neighbours: &'a Neighbours,
    wanted: &'a W,
    visit: &'a mut V,
}

impl<W, V> Grower<'_, W, V>
where
    W: Fn([f64; 2], [f64; 2]) -> bool,
    V: FnMut(usize, &[[f64; 2]]),
{
    /// Visits the sets made of the current one (`order` polygons, common
    /// overlap `overlap`) and one or more of `candidates`, which overlap
    /// every polygon of it.
    fn grow(
        &mut self,
        overlap: &[[f64; 2]],
        candidates: &[usize],
        order: usize,
    ) -> Result<(), AnalysisError> {
        for (at, &k) in candidates.iter().enumerate() {
            let Some(deeper) = overlap_of(overlap, &self.polys[k], self.wanted) else {
                continue;
            };
            if order + 1 > MAX_OVERLAP_ORDER {
                let (lo, hi) = bounds(&deeper);
                return Err(AnalysisError::TooManyOverlaps {
                    count: order + 1,
                    most: MAX_OVERLAP_ORDER,
                    near: [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])],
                });
            }
            (self.visit)(order + 1, &deeper);
            let next = common(candidates[at + 1..].iter().copied(), &self.neighbours[k], k);
            self.grow(&deeper, &next, order + 1)?;
        }
        Ok(())
    }
}

//! Every floe's vertices turned to its orientation, once per step: the
//! narrow phase clips each floe against about three neighbours, and turning
//! its vertices for each pair repeated the rotation (about 3 % of a step's
//! instructions). The same `rotate` of the same numbers, so the clipper
//! sees bitwise the vertices it would have turned itself.

use rayon::prelude::*;

use crate::floes::FloeColumns;
use crate::geometry::rotate;
use crate::Vec2;

/// Floes per parallel task.
const FLOE_BLOCK: usize = 4096;

/// Fills `out` (laid out as `f.vertices`, by `f.vertex_start`) with each
/// floe's vertices about its centroid turned by its angle, whose `(sin,
/// cos)` is `trig`.
pub(crate) fn orient_vertices(f: &FloeColumns, trig: &[(f64, f64)], out: &mut Vec<Vec2>) {
    debug_assert_eq!(trig.len(), f.len());
    out.resize(f.vertices.len(), Vec2::ZERO);
    let turn = |floes: std::ops::Range<usize>, slots: &mut [Vec2]| {
        let base = f.vertex_start[floes.start] as usize;
        for i in floes {
            let (sin, cos) = trig[i];
            let range = f.vertex_start[i] as usize..f.vertex_start[i + 1] as usize;
            let local = &f.vertices[range.clone()];
            let slots = &mut slots[range.start - base..range.end - base];
            for (slot, &v) in slots.iter_mut().zip(local) {
                *slot = rotate(v, cos, sin);
            }
        }
    };
    let n = f.len();
    if n <= FLOE_BLOCK {
        turn(0..n, out);
        return;
    }
    // Disjoint runs of `out`, one per block of floes.
    let mut blocks = Vec::with_capacity(n.div_ceil(FLOE_BLOCK));
    let mut rest = out.as_mut_slice();
    for lo in (0..n).step_by(FLOE_BLOCK) {
        let hi = (lo + FLOE_BLOCK).min(n);
        let len = (f.vertex_start[hi] - f.vertex_start[lo]) as usize;
        let (head, tail) = rest.split_at_mut(len);
        blocks.push((lo..hi, head));
        rest = tail;
    }
    blocks
        .into_par_iter()
        .for_each(|(floes, slots)| turn(floes, slots));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertices_are_turned_by_their_own_floe_angle_across_blocks() {
        // More floes than a block, with 3 to 6 vertices each, so that the
        // blocks' runs of vertices do not line up with a fixed stride.
        let shapes: Vec<Vec<Vec2>> = (0..FLOE_BLOCK + 77)
            .map(|i| {
                let k = 3 + i % 4;
                (0..k)
                    .map(|j| {
                        let t = std::f64::consts::TAU * j as f64 / k as f64;
                        Vec2::new(t.cos(), t.sin()) * (1.0 + i as f64)
                    })
                    .collect()
            })
            .collect();
        let mut f = FloeColumns::default();
        f.vertex_start.push(0);
        for s in &shapes {
            f.vertices.extend_from_slice(s);
            f.vertex_start.push(f.vertices.len() as u32);
            f.id.push(f.id.len() as u64);
        }
        let trig: Vec<(f64, f64)> = (0..shapes.len())
            .map(|i| (0.001 * i as f64).sin_cos())
            .collect();
        let mut out = Vec::new();
        orient_vertices(&f, &trig, &mut out);
        for (i, s) in shapes.iter().enumerate() {
            let angle = 0.001 * i as f64;
            for (j, v) in s.iter().enumerate() {
                let got = out[f.vertex_start[i] as usize + j];
                // Against the angle's own rotation, written out.
                let want = Vec2::new(
                    v.x * angle.cos() - v.y * angle.sin(),
                    v.x * angle.sin() + v.y * angle.cos(),
                );
                assert!(
                    (got - want).length() <= 1e-12 * v.length(),
                    "floe {i} vertex {j}"
                );
                assert!((got.length() - v.length()).abs() <= 1e-12 * v.length());
            }
        }
    }
}

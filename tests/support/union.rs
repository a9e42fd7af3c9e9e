//! The area of a union of convex polygons inside a box by vertical slabs,
//! a reference for `floe grid`'s concentration independent of its
//! inclusion-exclusion over overlaps: between two consecutive breakpoints
//! (the vertices' x, the x where two edges cross, or where an edge crosses
//! the box's bottom or top) each polygon covers an interval of y whose
//! ends are linear in x and cross neither each other nor the box's edges,
//! so the length of the union of the intervals (cut to the box) is linear
//! in x over the slab: its value at the slab's middle times the slab's
//! width is the slab's area.
#![allow(dead_code)]

/// Area of the part of the union of `polys` (convex, either winding)
/// inside the box `[lo, hi]`.
pub fn union_area_in_box(polys: &[Vec<[f64; 2]>], lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let polys: Vec<&Vec<[f64; 2]>> = polys
        .iter()
        .filter(|p| {
            let (a, b) = extent(p);
            a[0] < hi[0] && b[0] > lo[0] && a[1] < hi[1] && b[1] > lo[1]
        })
        .collect();
    let edges: Vec<([f64; 2], [f64; 2])> = polys
        .iter()
        .flat_map(|p| (0..p.len()).map(|k| (p[k], p[(k + 1) % p.len()])))
        .collect();
    let mut xs = vec![lo[0], hi[0]];
    xs.extend(polys.iter().flat_map(|p| p.iter().map(|v| v[0])));
    for (i, a) in edges.iter().enumerate() {
        for b in &edges[i + 1..] {
            if let Some(x) = crossing_x(*a, *b) {
                xs.push(x);
            }
        }
        for y in [lo[1], hi[1]] {
            let (p, q) = *a;
            if (p[1] - y) * (q[1] - y) < 0.0 {
                xs.push(p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]));
            }
        }
    }
    xs.retain(|x| *x >= lo[0] && *x <= hi[0]);
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let mut area = 0.0;
    for w in xs.windows(2) {
        let (x0, x1) = (w[0], w[1]);
        if x1 <= x0 {
            continue;
        }
        let xm = 0.5 * (x0 + x1);
        let mut spans: Vec<[f64; 2]> = polys
            .iter()
            .filter_map(|p| span_at(p, xm))
            .map(|[a, b]| [a.clamp(lo[1], hi[1]), b.clamp(lo[1], hi[1])])
            .filter(|s| s[1] > s[0])
            .collect();
        spans.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let mut covered = 0.0;
        let mut current: Option<[f64; 2]> = None;
        for s in spans {
            match current {
                Some(ref mut c) if s[0] <= c[1] => c[1] = c[1].max(s[1]),
                _ => {
                    if let Some(c) = current {
                        covered += c[1] - c[0];
                    }
                    current = Some(s);
                }
            }
        }
        if let Some(c) = current {
            covered += c[1] - c[0];
        }
        area += (x1 - x0) * covered;
    }
    area
}

/// Area of the union of `polys`.
pub fn union_area(polys: &[Vec<[f64; 2]>]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in polys {
        let (a, b) = extent(p);
        lo = [lo[0].min(a[0]), lo[1].min(a[1])];
        hi = [hi[0].max(b[0]), hi[1].max(b[1])];
    }
    union_area_in_box(polys, lo, hi)
}

fn extent(p: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let x = p.iter().map(|v| v[0]);
    let y = p.iter().map(|v| v[1]);
    (
        [
            x.clone().fold(f64::INFINITY, f64::min),
            y.clone().fold(f64::INFINITY, f64::min),
        ],
        [
            x.fold(f64::NEG_INFINITY, f64::max),
            y.fold(f64::NEG_INFINITY, f64::max),
        ],
    )
}

/// The x where segments `a` and `b` cross, if they do.
fn crossing_x(a: ([f64; 2], [f64; 2]), b: ([f64; 2], [f64; 2])) -> Option<f64> {
    let (p, r) = (a.0, [a.1[0] - a.0[0], a.1[1] - a.0[1]]);
    let (q, s) = (b.0, [b.1[0] - b.0[0], b.1[1] - b.0[1]]);
    let denom = r[0] * s[1] - r[1] * s[0];
    if denom == 0.0 {
        return None;
    }
    let qp = [q[0] - p[0], q[1] - p[1]];
    let t = (qp[0] * s[1] - qp[1] * s[0]) / denom;
    let u = (qp[0] * r[1] - qp[1] * r[0]) / denom;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some(p[0] + t * r[0])
}

/// The interval of y the convex `poly` covers on the line at `x` (not a
/// vertex's x), if it reaches it.
fn span_at(poly: &[[f64; 2]], x: f64) -> Option<[f64; 2]> {
    let mut ys = (0..poly.len()).filter_map(|k| {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        ((p[0] - x) * (q[0] - x) < 0.0).then(|| p[1] + (x - p[0]) / (q[0] - p[0]) * (q[1] - p[1]))
    });
    let first = ys.next()?;
    let (a, b) = ys.fold((first, first), |(a, b), y| (a.min(y), b.max(y)));
    Some([a, b])
}

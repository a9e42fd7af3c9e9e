//! Who holds which floe: its owner by the decomposition, the processes
//! it reaches as a ghost (`crate::reach`), and the domain the cuts are
//! made in, with its open sides.

use super::*;

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// The prescribed floes' outlines with their owners, on a grid.
    pub(super) fn outline_grid(&self, f: &FloeColumns) -> OutlineGrid {
        let outlines = (0..f.len())
            .filter(|&i| !f.is_free(i))
            .map(|i| Outline {
                owner: self.decomposition.owner_of(f.position[i]),
                vertices: f.world_vertices(i),
            })
            .collect();
        OutlineGrid::new(outlines, self.largest_radius_m + self.skin_m)
    }

    /// Floe `i`'s owner and every process that holds it, sorted.
    pub(super) fn holders(
        &self,
        f: &FloeColumns,
        i: usize,
        grid: &OutlineGrid,
        periodicity: Periodicity,
    ) -> (usize, Vec<usize>) {
        let p = f.position[i];
        let owner = self.decomposition.owner_of(p);
        if !f.is_free(i) {
            return (owner, (0..self.comm.size()).collect());
        }
        let pts = images(p, periodicity);
        let reach = f.radius_m[i] + self.largest_radius_m + self.skin_m;
        let mut ranks: Vec<usize> = (0..self.comm.size())
            .filter(|&k| k == owner || box_distance(self.open_box(k), &pts) < reach)
            .collect();
        grid.owners_near(&pts, f.radius_m[i] + self.skin_m, &mut ranks);
        ranks.sort_unstable();
        ranks.dedup();
        (owner, ranks)
    }

    /// Process `k`'s box, reaching to infinity on open sides.
    pub(super) fn open_box(&self, k: usize) -> Rect {
        open_box(&self.decomposition, k, self.domain, self.periodicity)
    }
}

/// The rectangle the cuts are made in: the period on periodic axes, the
/// points' extent (a metre wider) on open ones.
pub(super) fn cut_domain(points: &[Vec2], periodicity: Periodicity) -> Rect {
    let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    lo -= Vec2::splat(1.0);
    hi += Vec2::splat(1.0);
    if let Some(p) = periodicity.x {
        (lo.x, hi.x) = (p.min_m, p.min_m + p.length_m);
    }
    if let Some(p) = periodicity.y {
        (lo.y, hi.y) = (p.min_m, p.min_m + p.length_m);
    }
    Rect::new(lo, hi)
}

/// Box `k` of `d`, reaching to infinity where it meets an open side of
/// the `domain` it was cut in (floes may drift out of it).
fn open_box(d: &Decomposition, k: usize, domain: Rect, periodicity: Periodicity) -> Rect {
    let b = d.boxes()[k];
    let open = |v: f64, edge: f64, periodic: bool, inf: f64| {
        if !periodic && v == edge {
            inf
        } else {
            v
        }
    };
    let (px, py) = (periodicity.x.is_some(), periodicity.y.is_some());
    Rect::new(
        Vec2::new(
            open(b.min.x, domain.min.x, px, f64::NEG_INFINITY),
            open(b.min.y, domain.min.y, py, f64::NEG_INFINITY),
        ),
        Vec2::new(
            open(b.max.x, domain.max.x, px, f64::INFINITY),
            open(b.max.y, domain.max.y, py, f64::INFINITY),
        ),
    )
}

/// Refuses a subdomain narrower than the largest floe (an open side
/// reaches to infinity).
pub(super) fn check_subdomains(
    d: &Decomposition,
    domain: Rect,
    periodicity: Periodicity,
    largest_radius_m: f64,
) -> Result<(), ParallelError> {
    let diameter_m = 2.0 * largest_radius_m;
    if d.boxes().len() == 1 {
        return Ok(());
    }
    for rank in 0..d.boxes().len() {
        let b = open_box(d, rank, domain, periodicity);
        if b.width_m() < diameter_m || b.height_m() < diameter_m {
            return Err(ParallelError::SubdomainTooSmall {
                rank,
                width_m: b.width_m(),
                height_m: b.height_m(),
                diameter_m,
            });
        }
    }
    Ok(())
}

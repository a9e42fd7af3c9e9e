//! Fields given on a regular grid of the model plane at a sequence of
//! times (wind and current read from NetCDF, sea-surface height): bilinear
//! in space, linear in time, with two time slices held at a time whatever
//! the length of the record.
//!
//! Where the slices come from is a [`SliceSource`] (floe-basin reads CF
//! NetCDF files into them, projecting longitude-latitude grids onto the
//! plane). [`GriddedField::prepare`] is called once a step, before the
//! forces are gathered (the [`ExternalForces::prepare`] hook): it loads the
//! two slices around the step's time when the time has moved past them,
//! and checks that every free floe lies on the grid, on cells without
//! missing values, and mixes the two slices at the step's time. Evaluation
//! ([`GriddedField::vector`], [`GriddedField::value_and_gradient`]) then only reads.
//!
//! Between grid nodes the field is bilinear in the cell; between the slice
//! times `t_i ≤ t ≤ t_{i+1}` it is `(1 − w) F_i + w F_{i+1}`,
//! `w = (t − t_i)/(t_{i+1} − t_i)`. A source with one slice is steady.
//!
//! [`ExternalForces::prepare`]: crate::forcing::ExternalForces::prepare

use std::fmt;
use std::sync::Arc;

pub use crate::error::ForcingFailure;
use crate::floes::FloeColumns;
use crate::{DemError, Vec2};

mod plane_grid;

pub use plane_grid::{CellPosition, PlaneGrid};

/// Where a [`GriddedField`]'s time slices come from. Implementations read
/// files (floe-basin's NetCDF source) or compute them (tests).
pub trait SliceSource: Send + Sync {
    /// What it is, for messages: the file and its variables.
    fn describe(&self) -> &str;
    /// The grid every slice is given on.
    fn grid(&self) -> &PlaneGrid;
    /// Values per node: 2 for a vector (x then y component on the plane),
    /// 1 for a scalar.
    fn components(&self) -> usize;
    /// The slices' times, s of model time, strictly increasing, at least one.
    fn times_s(&self) -> &[f64];
    /// Slice `index` into `out` (`grid().nodes() * components()` values,
    /// node `j nx + i` at `out[(j nx + i) c ..]`), NaN where the source has
    /// no value.
    ///
    /// # Errors
    /// What went wrong reading it, naming the file and variable.
    fn read_slice(&self, index: usize, out: &mut [f64]) -> Result<(), ForcingFailure>;
}

/// One loaded time slice.
#[derive(Clone)]
struct Slot {
    index: Option<usize>,
    values: Vec<f64>,
}

/// A field on a [`PlaneGrid`], linear in time between the two slices it
/// holds. See the module docs.
#[derive(Clone)]
pub struct GriddedField {
    source: Arc<dyn SliceSource>,
    grid: PlaneGrid,
    components: usize,
    slots: [Slot; 2],
    /// The slices in use: `slots[lower]` holds slice `interval`,
    /// `slots[1 − lower]` slice `interval + 1` (when there is one).
    interval: Option<usize>,
    lower: usize,
    /// Per cell, whether all four corners have values in both slices.
    usable: Vec<bool>,
    /// Slices read so far (the memory bound is tested by it).
    reads: u64,
    /// `1/dx, 1/dy`.
    inverse_spacing: Vec2,
    /// The interval's lower time, `1/(t_{i+1} − t_i)`, and whether there
    /// is an upper slice (not for a steady field).
    lower_time_s: f64,
    inverse_interval_s: f64,
    has_upper: bool,
    /// The two slices mixed at `blended_time_s` (the step's time, set by
    /// `prepare`): evaluation at that time reads one array.
    blended: Vec<f64>,
    blended_time_s: f64,
    /// Largest fractional node indices, `nx − 1` and `ny − 1`.
    last_index: Vec2,
}

impl fmt::Debug for GriddedField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "GriddedField({})", self.source.describe())
    }
}

impl PartialEq for GriddedField {
    /// Same source description, grid and times (two loads of one file).
    fn eq(&self, other: &Self) -> bool {
        self.source.describe() == other.source.describe()
            && self.grid == other.grid
            && self.source.times_s() == other.source.times_s()
    }
}

impl GriddedField {
    /// A field over `source`; nothing is read until [`GriddedField::prepare`].
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] for an invalid grid, no times, times
    /// not strictly increasing, or a component count other than 1 or 2.
    pub fn new(source: Arc<dyn SliceSource>) -> Result<Self, DemError> {
        let grid = *source.grid();
        grid.validate()?;
        let components = source.components();
        if !(1..=2).contains(&components) {
            return Err(DemError::InvalidParameter {
                name: "gridded field components",
                value: components as f64,
                reason: "must be 1 (scalar) or 2 (vector)",
            });
        }
        let times = source.times_s();
        if times.is_empty() || times.iter().any(|t| !t.is_finite()) {
            return Err(DemError::InvalidParameter {
                name: "gridded field times_s",
                value: times.len() as f64,
                reason: "needs at least one finite time",
            });
        }
        if times.windows(2).any(|w| w[1] <= w[0]) {
            return Err(DemError::InvalidParameter {
                name: "gridded field times_s",
                value: times.len() as f64,
                reason: "must be strictly increasing",
            });
        }
        let empty = Slot {
            index: None,
            values: Vec::new(),
        };
        Ok(GriddedField {
            source,
            grid,
            components,
            slots: [empty.clone(), empty],
            interval: None,
            lower: 0,
            usable: Vec::new(),
            reads: 0,
            inverse_spacing: Vec2::new(1.0 / grid.spacing_m.x, 1.0 / grid.spacing_m.y),
            lower_time_s: 0.0,
            inverse_interval_s: 0.0,
            has_upper: false,
            blended: Vec::new(),
            blended_time_s: f64::NAN,
            last_index: Vec2::new((grid.nx - 1) as f64, (grid.ny - 1) as f64),
        })
    }

    /// The grid.
    pub fn grid(&self) -> &PlaneGrid {
        &self.grid
    }

    /// What it is (file and variables).
    pub fn describe(&self) -> &str {
        self.source.describe()
    }

    /// The slices' times, s.
    pub fn times_s(&self) -> &[f64] {
        self.source.times_s()
    }

    /// Slices read from the source so far.
    pub fn slices_read(&self) -> u64 {
        self.reads
    }

    /// Values held in memory (the two slices), whatever the record's length.
    pub fn values_held(&self) -> usize {
        self.slots.iter().map(|s| s.values.len()).sum()
    }

    /// The interval `i` with `t_i ≤ t ≤ t_{i+1}` (0 for a steady field).
    fn interval_of(&self, t_s: f64) -> Result<usize, ForcingFailure> {
        let times = self.source.times_s();
        let n = times.len();
        if n == 1 {
            return Ok(0);
        }
        if !(t_s >= times[0] && t_s <= times[n - 1]) {
            return Err(ForcingFailure(format!(
                "{}: the run reaches t = {t_s} s but the file's times cover {} s to {} s \
                 of model time; give a file that covers the run, or a shorter duration_s",
                self.source.describe(),
                times[0],
                times[n - 1]
            )));
        }
        Ok(times
            .partition_point(|&x| x <= t_s)
            .saturating_sub(1)
            .min(n - 2))
    }

    /// Makes the field ready for time `t_s`: loads the slices around it
    /// (reading only those not already held) and checks that every free
    /// floe of `floes` is on the grid, on a cell whose corners have values.
    ///
    /// # Errors
    /// A time outside the source's times, a failed read, a floe off the
    /// grid or over missing values: each message names the source.
    pub fn prepare(&mut self, t_s: f64, floes: &FloeColumns) -> Result<(), ForcingFailure> {
        let interval = self.interval_of(t_s)?;
        if self.interval != Some(interval) {
            self.load(interval)?;
        }
        self.blend(t_s);
        self.check_floes(floes)
    }

    fn load(&mut self, interval: usize) -> Result<(), ForcingFailure> {
        let n = self.source.times_s().len();
        let wanted = [interval, (interval + 1).min(n - 1)];
        let len = self.grid.nodes() * self.components;
        // Keep a slot that already holds a wanted slice.
        let lower = match self.slots.iter().position(|s| s.index == Some(wanted[0])) {
            Some(k) => k,
            None => {
                let k = usize::from(self.slots[0].index == Some(wanted[1]));
                self.fill(k, wanted[0], len)?;
                k
            }
        };
        if wanted[1] != wanted[0] && self.slots[1 - lower].index != Some(wanted[1]) {
            self.fill(1 - lower, wanted[1], len)?;
        }
        self.lower = lower;
        self.interval = Some(interval);
        let times = self.source.times_s();
        self.lower_time_s = times[interval];
        self.has_upper = wanted[1] != wanted[0];
        self.inverse_interval_s = if self.has_upper {
            1.0 / (times[interval + 1] - times[interval])
        } else {
            0.0
        };
        self.mark_usable_cells();
        Ok(())
    }

    /// Mixes the two slices at `t_s` into `blended` (grid-sized work, once
    /// a step, instead of a time interpolation per floe and component).
    fn blend(&mut self, t_s: f64) {
        let lo = &self.slots[self.lower].values;
        self.blended.clear();
        if self.has_upper {
            let w = ((t_s - self.lower_time_s) * self.inverse_interval_s).clamp(0.0, 1.0);
            let hi = &self.slots[1 - self.lower].values;
            self.blended
                .extend(lo.iter().zip(hi).map(|(&a, &b)| a + w * (b - a)));
        } else {
            self.blended.extend_from_slice(lo);
        }
        self.blended_time_s = t_s;
    }

    fn fill(&mut self, slot: usize, index: usize, len: usize) -> Result<(), ForcingFailure> {
        let s = &mut self.slots[slot];
        s.index = None;
        s.values.clear();
        s.values.resize(len, f64::NAN);
        self.source.read_slice(index, &mut s.values)?;
        s.index = Some(index);
        self.reads += 1;
        Ok(())
    }

    fn mark_usable_cells(&mut self) {
        let (nx, ny, c) = (self.grid.nx, self.grid.ny, self.components);
        let node_ok = |k: usize| {
            self.slots
                .iter()
                .filter(|s| s.index.is_some())
                .all(|s| s.values[k * c..(k + 1) * c].iter().all(|v| v.is_finite()))
        };
        let ok: Vec<bool> = (0..nx * ny).map(node_ok).collect();
        self.usable.clear();
        self.usable.resize(nx * ny, false);
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let k = j * nx + i;
                self.usable[k] = ok[k] && ok[k + 1] && ok[k + nx] && ok[k + nx + 1];
            }
        }
    }

    fn check_floes(&self, floes: &FloeColumns) -> Result<(), ForcingFailure> {
        for i in 0..floes.len() {
            if !floes.is_free(i) {
                continue;
            }
            let p = floes.position[i];
            let why = match self.grid.cell(p) {
                None => "outside the grid",
                Some(c) if !self.usable[c.node] => "over missing values (a fill value or NaN)",
                Some(_) => continue,
            };
            let (a, b) = (self.grid.origin_m, self.grid.end_m());
            return Err(ForcingFailure(format!(
                "{}: floe {} at ({:.1}, {:.1}) m is {why}; the grid spans x {:.1} to {:.1} m, \
                 y {:.1} to {:.1} m",
                self.source.describe(),
                floes.id[i],
                p.x,
                p.y,
                a.x,
                b.x,
                a.y,
                b.y
            )));
        }
        Ok(())
    }

    /// Component `comp` at `p` and `t_s`, with its gradient `(∂/∂x, ∂/∂y)`.
    /// Zero before the first [`GriddedField::prepare`].
    #[inline]
    pub fn value_and_gradient(&self, comp: usize, p: Vec2, t_s: f64) -> (f64, Vec2) {
        match self.lookup(p, t_s) {
            Some(l) => {
                let c = self.corners(&l, comp);
                (
                    l.cell.interpolate(&c),
                    l.cell.gradient(&c, self.inverse_spacing),
                )
            }
            None => (0.0, Vec2::ZERO),
        }
    }

    /// Where `p` and `t_s` fall: cell, fractions, time weight (NaN: the
    /// blended slice of the step's time). A point off the grid takes the
    /// nearest edge (`prepare` refused free floes there).
    #[inline(always)]
    fn lookup(&self, p: Vec2, t_s: f64) -> Option<Lookup> {
        self.interval?;
        let o = self.grid.origin_m;
        let gx = ((p.x - o.x) * self.inverse_spacing.x).clamp(0.0, self.last_index.x);
        let gy = ((p.y - o.y) * self.inverse_spacing.y).clamp(0.0, self.last_index.y);
        // `as` saturates (NaN to 0): never out of bounds.
        let i = (gx as usize).min(self.grid.nx - 2);
        let j = (gy as usize).min(self.grid.ny - 2);
        let w = if t_s == self.blended_time_s {
            f64::NAN
        } else {
            self.weight(t_s)
        };
        Some(Lookup {
            cell: CellPosition {
                node: j * self.grid.nx + i,
                fx: gx - i as f64,
                fy: gy - j as f64,
            },
            w,
        })
    }

    /// The time weight of the upper slice at `t_s` (away from the step's time).
    #[cold]
    fn weight(&self, t_s: f64) -> f64 {
        if self.has_upper {
            ((t_s - self.lower_time_s) * self.inverse_interval_s).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// The four corner values of component `comp`, interpolated in time:
    /// `[v00, v10, v01, v11]` (from the blended slices at the step's time).
    #[inline(always)]
    fn corners(&self, l: &Lookup, comp: usize) -> [f64; 4] {
        let (c, nx) = (self.components, self.grid.nx);
        let k = l.cell.node * c + comp;
        let row = nx * c;
        let at = [k, k + c, k + row, k + row + c];
        if l.w.is_nan() {
            let b = &self.blended;
            return at.map(|i| b[i]);
        }
        self.corners_between_slices(at, l.w)
    }

    #[cold]
    fn corners_between_slices(&self, at: [usize; 4], w: f64) -> [f64; 4] {
        let lo = &self.slots[self.lower].values;
        let mut v = at.map(|i| lo[i]);
        if w != 0.0 {
            let hi = &self.slots[1 - self.lower].values;
            for (x, &i) in v.iter_mut().zip(&at) {
                *x += w * (hi[i] - *x);
            }
        }
        v
    }

    /// The vector at `p` and `t_s` (a two-component field; the first
    /// component alone otherwise).
    #[inline]
    pub fn vector(&self, p: Vec2, t_s: f64) -> Vec2 {
        let Some(l) = self.lookup(p, t_s) else {
            return Vec2::ZERO;
        };
        let u = l.cell.interpolate(&self.corners(&l, 0));
        if self.components < 2 {
            return Vec2::new(u, 0.0);
        }
        Vec2::new(u, l.cell.interpolate(&self.corners(&l, 1)))
    }

    /// The vertical vorticity `∂v/∂x − ∂u/∂y` of a vector field at `p`
    /// and `t_s`, 1/s (of the bilinear interpolant, constant along each
    /// cell's edges).
    #[inline]
    pub fn vorticity(&self, p: Vec2, t_s: f64) -> f64 {
        self.vector_and_vorticity(p, t_s).1
    }

    /// [`GriddedField::vector`] and [`GriddedField::vorticity`] from one
    /// cell lookup.
    #[inline]
    pub fn vector_and_vorticity(&self, p: Vec2, t_s: f64) -> (Vec2, f64) {
        if self.components < 2 {
            return (self.vector(p, t_s), 0.0);
        }
        let Some(l) = self.lookup(p, t_s) else {
            return (Vec2::ZERO, 0.0);
        };
        let (cu, cv) = (self.corners(&l, 0), self.corners(&l, 1));
        let (gu, gv) = (
            l.cell.gradient(&cu, self.inverse_spacing),
            l.cell.gradient(&cv, self.inverse_spacing),
        );
        (
            Vec2::new(l.cell.interpolate(&cu), l.cell.interpolate(&cv)),
            gv.x - gu.y,
        )
    }
}

/// A point's cell and the time weight of the upper slice.
struct Lookup {
    cell: CellPosition,
    w: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU64, Ordering};

    /// Slices of `f(x, y, t)` at the given times, counting reads.
    struct Analytic {
        grid: PlaneGrid,
        times: Vec<f64>,
        f: fn(Vec2, f64) -> [f64; 2],
        reads: AtomicU64,
        hole: Option<usize>,
    }

    impl SliceSource for Analytic {
        fn describe(&self) -> &str {
            "analytic.nc: u, v"
        }
        fn grid(&self) -> &PlaneGrid {
            &self.grid
        }
        fn components(&self) -> usize {
            2
        }
        fn times_s(&self) -> &[f64] {
            &self.times
        }
        fn read_slice(&self, index: usize, out: &mut [f64]) -> Result<(), ForcingFailure> {
            self.reads.fetch_add(1, Ordering::Relaxed);
            let g = self.grid;
            for j in 0..g.ny {
                for i in 0..g.nx {
                    let p =
                        g.origin_m + Vec2::new(i as f64 * g.spacing_m.x, j as f64 * g.spacing_m.y);
                    let v = (self.f)(p, self.times[index]);
                    let k = j * g.nx + i;
                    out[2 * k] = v[0];
                    out[2 * k + 1] = if self.hole == Some(k) { f64::NAN } else { v[1] };
                }
            }
            Ok(())
        }
    }

    fn grid() -> PlaneGrid {
        PlaneGrid {
            origin_m: Vec2::new(-1000.0, 500.0),
            spacing_m: Vec2::new(250.0, 400.0),
            nx: 9,
            ny: 6,
        }
    }

    fn field(
        times: Vec<f64>,
        f: fn(Vec2, f64) -> [f64; 2],
        hole: Option<usize>,
    ) -> (GriddedField, Arc<Analytic>) {
        let src = Arc::new(Analytic {
            grid: grid(),
            times,
            f,
            reads: AtomicU64::new(0),
            hole,
        });
        (GriddedField::new(src.clone()).unwrap(), src)
    }

    fn floes_at(points: &[Vec2]) -> FloeColumns {
        let mut c = FloeColumns::default();
        for (k, &p) in points.iter().enumerate() {
            c.id.push(k as u64);
            c.position.push(p);
            c.motion.push(crate::floes::Motion::Free);
        }
        c
    }

    /// A field bilinear in space and linear in time is reproduced exactly.
    fn bilinear_in_space_linear_in_time(p: Vec2, t: f64) -> [f64; 2] {
        [
            1.0 + 2e-3 * p.x - 3e-4 * p.y + 1e-7 * p.x * p.y + 1e-4 * t,
            -2.0 + 5e-4 * p.y - 2e-3 * p.x * 1e-3 * t / 100.0,
        ]
    }

    #[test]
    fn bilinear_and_linear_fields_are_exact_with_their_gradients() {
        let (mut f, _) = field(
            vec![0.0, 3600.0, 7200.0],
            bilinear_in_space_linear_in_time,
            None,
        );
        let pts = [
            Vec2::new(-1000.0, 500.0),
            Vec2::new(-333.3, 1234.5),
            Vec2::new(999.0, 2500.0),
        ];
        let floes = floes_at(&pts);
        for &t in &[0.0, 100.0, 3600.0, 5000.0, 7200.0] {
            f.prepare(t, &floes).unwrap();
            for &p in &pts {
                let want = bilinear_in_space_linear_in_time(p, t);
                let got = f.vector(p, t);
                assert!((got.x - want[0]).abs() < 1e-12 && (got.y - want[1]).abs() < 1e-12);
                // ∂u/∂x = 2e-3 + 1e-7 y, ∂u/∂y = -3e-4 + 1e-7 x.
                let (_, g) = f.value_and_gradient(0, p, t);
                assert!((g.x - (2e-3 + 1e-7 * p.y)).abs() < 1e-12);
                assert!((g.y - (-3e-4 + 1e-7 * p.x)).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn two_slices_are_held_and_each_is_read_once_going_forward() {
        let times: Vec<f64> = (0..50).map(|k| 600.0 * k as f64).collect();
        let (mut f, src) = field(times, |_, t| [t, 0.0], None);
        let floes = floes_at(&[Vec2::new(0.0, 1000.0)]);
        let mut t = 0.0;
        while t <= 600.0 * 49.0 {
            f.prepare(t, &floes).unwrap();
            assert!((f.vector(Vec2::new(0.0, 1000.0), t).x - t).abs() < 1e-9);
            t += 37.0;
        }
        assert_eq!(src.reads.load(Ordering::Relaxed), 50);
        assert_eq!(f.values_held(), 2 * 2 * grid().nodes());
    }

    #[test]
    fn times_outside_the_record_floes_off_the_grid_and_holes_are_named() {
        let (mut f, _) = field(vec![0.0, 3600.0], |_, _| [1.0, 1.0], Some(9 + 3));
        let on = floes_at(&[Vec2::new(0.0, 1000.0)]);
        let e = f.prepare(3700.0, &on).unwrap_err().0;
        assert!(e.contains("analytic.nc") && e.contains("3700"), "{e}");
        let off = floes_at(&[Vec2::new(0.0, 1000.0), Vec2::new(5000.0, 1000.0)]);
        let e = f.prepare(10.0, &off).unwrap_err().0;
        assert!(
            e.contains("floe 1") && e.contains("outside the grid"),
            "{e}"
        );
        // The hole is node (3, 1): the cells around it are refused.
        let over = floes_at(&[Vec2::new(-1000.0 + 3.5 * 250.0, 500.0 + 1.5 * 400.0)]);
        let e = f.prepare(10.0, &over).unwrap_err().0;
        assert!(e.contains("missing values"), "{e}");
        let beside = floes_at(&[Vec2::new(-1000.0 + 5.5 * 250.0, 500.0 + 1.5 * 400.0)]);
        f.prepare(10.0, &beside).unwrap();
    }

    #[test]
    fn solid_body_rotation_has_twice_its_rate_as_vorticity() {
        let (mut f, _) = field(vec![0.0], |p, _| [-1e-5 * p.y, 1e-5 * p.x], None);
        f.prepare(1e9, &floes_at(&[])).unwrap();
        assert!((f.vorticity(Vec2::new(100.0, 1500.0), 5.0) - 2e-5).abs() < 1e-15);
    }
}

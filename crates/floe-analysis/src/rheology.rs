//! Rheology of a simple-shear cell: a layer of floes between two walls
//! along x (periodic along x), one wall sliding past the other. From one
//! snapshot: the stress on the walls, the same stress from the contacts
//! inside (Love-Weber) plus the floes' velocity fluctuations, the solid
//! fraction and the shear rate; across runs: the inertial number
//! `I = shear rate x floe size x sqrt(areal density / P)` and a fit of
//! `mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1)` (Jop, Forterre & Pouliquen
//! 2006; GDR MiDi 2004).
//!
//! The walls are the prescribed floes (with any floes glued to them): those
//! above the free floes' mean height form the top wall, the rest the
//! bottom. The layer's height `H` is the distance between the mean heights
//! of the two walls' contact points with the free floes, its area `L H`.
//! In equilibrium the Love-Weber sum over the free floes equals the wall
//! traction times `H` exactly (the forces between free floes cancel, the
//! wall contacts remain), so `H` so defined is the height for which the
//! two agree; in a flowing layer they agree on average, once the momentum
//! flux `sum m v' (x) v'` of the fluctuations is added.

use crate::love_weber::{stress_moments, ContactForces};
use crate::polygon::{clip, polygon_area};
use crate::AnalysisError;

/// The error of [`cell_sample`] for a snapshot in which the free floes
/// touch only one wall or none (the layer has no height then).
pub const NOT_TOUCHING: &str = "the free floes do not touch both walls";

/// One snapshot of a shear cell, as arrays over floes and contacts (the
/// layout of a run file's snapshot).
#[derive(Debug, Clone, Copy)]
pub struct CellSnapshot<'a> {
    /// The period along x (the cell's length `L`), m.
    pub period_x_m: f64,
    /// Centroids, m.
    pub position: &'a [[f64; 2]],
    /// Centroid velocities, m/s.
    pub velocity: &'a [[f64; 2]],
    /// Floe areas, m².
    pub area_m2: &'a [f64],
    /// Floe masses, kg.
    pub mass_kg: &'a [f64],
    /// Whether each floe is prescribed (part of a wall).
    pub prescribed: &'a [bool],
    /// Each floe's vertices in world coordinates, m.
    pub vertices: &'a [Vec<[f64; 2]>],
    /// The contacts and their forces.
    pub contacts: ContactForces<'a>,
}

/// What one snapshot says about the layer. Stresses are vertically
/// integrated (N/m) as `[xx, xy, yx, yy]`, tension positive; the wall
/// stresses are compression positive and positive shear resists a top wall
/// moving towards +x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellSample {
    /// Layer height `H` between the walls' mean contact heights, m.
    pub height_m: f64,
    /// Mean normal stress the ice puts on the two walls, N/m.
    pub wall_normal_stress_n_per_m: f64,
    /// Normal stress on the bottom wall and on the top wall, N/m: equal in
    /// the mean in a steady state (the layer's momentum across it is
    /// bounded); apart while the layer still dilates or compacts.
    pub wall_normal_stress_bottom_top_n_per_m: [f64; 2],
    /// Mean shear stress on the two walls, N/m.
    pub wall_shear_stress_n_per_m: f64,
    /// Love-Weber stress of the contacts over the layer (`L H`), N/m.
    pub contact_stress_n_per_m: [f64; 4],
    /// Momentum flux of the free floes' velocity fluctuations about the
    /// fitted profile, `-(1/LH) sum m v' (x) v'`, N/m.
    pub kinetic_stress_n_per_m: [f64; 4],
    /// Ice area over layer area in the middle half of the layer (away from
    /// the walls' rows).
    pub solid_fraction: f64,
    /// Slope of the area-weighted linear fit of the free floes' velocity
    /// along x against their height, 1/s.
    pub shear_rate_per_s: f64,
    /// The walls' speed difference over `H`, 1/s.
    pub wall_shear_rate_per_s: f64,
    /// Free floes' mass over their area, kg/m².
    pub areal_density_kg_per_m2: f64,
    /// Square root of the free floes' mean area, m.
    pub floe_size_m: f64,
}

impl CellSample {
    /// The normal stress across the layer from the contacts and the
    /// fluctuations, `-s_yy`, N/m, compression positive.
    pub fn bulk_normal_stress_n_per_m(&self) -> f64 {
        -(self.contact_stress_n_per_m[3] + self.kinetic_stress_n_per_m[3])
    }

    /// The shear stress from the contacts and the fluctuations,
    /// `(s_xy + s_yx)/2` (the sign convention of the wall shear stress), N/m.
    pub fn bulk_shear_stress_n_per_m(&self) -> f64 {
        let c = self.contact_stress_n_per_m;
        let k = self.kinetic_stress_n_per_m;
        0.5 * (c[1] + c[2] + k[1] + k[2])
    }
}

/// Measures one snapshot of a shear cell.
pub fn cell_sample(s: &CellSnapshot) -> Result<CellSample, AnalysisError> {
    let n = s.position.len();
    for (what, len) in [
        ("positions and velocities", s.velocity.len()),
        ("positions and areas", s.area_m2.len()),
        ("positions and masses", s.mass_kg.len()),
        ("positions and prescribed flags", s.prescribed.len()),
        ("positions and vertices", s.vertices.len()),
    ] {
        if len != n {
            return Err(AnalysisError::LengthMismatch {
                what,
                left: n,
                right: len,
            });
        }
    }
    let c = &s.contacts;
    let m = c.pair.len();
    for (what, len) in [
        ("contact pairs and points", c.point.len()),
        ("contact pairs and normals", c.normal.len()),
        ("contact pairs and normal forces", c.normal_force_n.len()),
        (
            "contact pairs and tangential forces",
            c.tangential_force_n.len(),
        ),
    ] {
        if len != m {
            return Err(AnalysisError::LengthMismatch {
                what,
                left: m,
                right: len,
            });
        }
    }
    let length = s.period_x_m;
    if !(length.is_finite() && length > 0.0) {
        return Err(AnalysisError::InvalidParameter {
            name: "period_x_m",
            value: length,
            reason: "a shear cell needs a positive period along x",
        });
    }
    if c.pair.iter().flatten().any(|&i| i as usize >= n) {
        return Err(AnalysisError::NotEnoughData(
            "a contact names a floe that is not in the snapshot",
        ));
    }
    let free: Vec<usize> = (0..n).filter(|&i| !s.prescribed[i]).collect();
    if free.is_empty() {
        return Err(AnalysisError::NotEnoughData("no free floes in the cell"));
    }
    let free_area: f64 = free.iter().map(|&i| s.area_m2[i]).sum();
    let mid = free
        .iter()
        .map(|&i| s.area_m2[i] * s.position[i][1])
        .sum::<f64>()
        / free_area;
    let top = |i: usize| s.position[i][1] > mid;

    // Wall forces and the heights of the wall contacts.
    let mut force = [[0.0f64; 2]; 2]; // on [bottom, top] wall, by the ice
    let mut height = [(0.0f64, 0usize); 2];
    for k in 0..m {
        let [a, b] = c.pair[k].map(|i| i as usize);
        let on_b = c.force_on_b(k);
        let pt = c.point[k];
        let wall = match (s.prescribed[a], s.prescribed[b]) {
            (true, false) => Some((a, [-on_b[0], -on_b[1]])),
            (false, true) => Some((b, on_b)),
            _ => None,
        };
        if let Some((w, f)) = wall {
            let side = usize::from(top(w));
            force[side][0] += f[0];
            force[side][1] += f[1];
            height[side].0 += pt[1];
            height[side].1 += 1;
        }
    }
    if height[0].1 == 0 || height[1].1 == 0 {
        return Err(AnalysisError::NotEnoughData(NOT_TOUCHING));
    }
    let (y_bottom, y_top) = (
        height[0].0 / height[0].1 as f64,
        height[1].0 / height[1].1 as f64,
    );
    let h = y_top - y_bottom;
    if h <= 0.0 {
        return Err(AnalysisError::NotEnoughData(
            "the top wall's contacts lie below the bottom wall's",
        ));
    }
    let layer = length * h;
    // The free floes' Love-Weber moments over the layer (a wall's side of
    // a contact is not the ice's).
    let moments = stress_moments(s.position, c, [Some(length), None]);
    let mut contact = [0.0f64; 4];
    for &i in &free {
        for (sum, v) in contact.iter_mut().zip(moments[i]) {
            *sum += v / layer;
        }
    }

    // Velocity profile: area-weighted linear fit of v_x against y.
    let (mut sw, mut sy, mut sv, mut syy, mut syv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &i in &free {
        let (w, y, v) = (s.area_m2[i], s.position[i][1], s.velocity[i][0]);
        sw += w;
        sy += w * y;
        sv += w * v;
        syy += w * y * y;
        syv += w * y * v;
    }
    let (ym, vm) = (sy / sw, sv / sw);
    let var = syy / sw - ym * ym;
    let shear_rate = if var > 0.0 {
        (syv / sw - ym * vm) / var
    } else {
        0.0
    };
    let mut kinetic = [0.0f64; 4];
    let mut mass = 0.0;
    for &i in &free {
        let fluct = [
            s.velocity[i][0] - (vm + shear_rate * (s.position[i][1] - ym)),
            s.velocity[i][1],
        ];
        let mi = s.mass_kg[i];
        mass += mi;
        kinetic[0] -= mi * fluct[0] * fluct[0] / layer;
        kinetic[1] -= mi * fluct[0] * fluct[1] / layer;
        kinetic[2] -= mi * fluct[1] * fluct[0] / layer;
        kinetic[3] -= mi * fluct[1] * fluct[1] / layer;
    }

    // Wall speeds: mean x velocity of each wall's floes.
    let mut wall_v = [(0.0f64, 0usize); 2];
    for i in (0..n).filter(|&i| s.prescribed[i]) {
        let side = usize::from(top(i));
        wall_v[side].0 += s.velocity[i][0];
        wall_v[side].1 += 1;
    }
    let wall_speed = |k: usize| wall_v[k].0 / wall_v[k].1.max(1) as f64;

    // Solid fraction in the middle half of the layer.
    let (lo, hi) = (y_bottom + 0.25 * h, y_top - 0.25 * h);
    let ice: f64 = s
        .vertices
        .iter()
        .map(|poly| polygon_area(&clip_to_band(poly, lo, hi)))
        .sum();

    Ok(CellSample {
        height_m: h,
        wall_normal_stress_n_per_m: 0.5 * (force[1][1] - force[0][1]) / length,
        wall_normal_stress_bottom_top_n_per_m: [-force[0][1] / length, force[1][1] / length],
        wall_shear_stress_n_per_m: 0.5 * (force[0][0] - force[1][0]) / length,
        contact_stress_n_per_m: contact,
        kinetic_stress_n_per_m: kinetic,
        solid_fraction: ice / (length * (hi - lo)),
        shear_rate_per_s: shear_rate,
        wall_shear_rate_per_s: (wall_speed(1) - wall_speed(0)) / h,
        areal_density_kg_per_m2: mass / free_area,
        floe_size_m: (free_area / free.len() as f64).sqrt(),
    })
}

/// The inertial number `I = shear rate x floe size x sqrt(areal density / P)`
/// of a layer under the vertically integrated pressure `P` (N/m); with
/// areal density `rho h` (kg/m²) this is the usual `gamma d sqrt(rho / p)`
/// with the 3-D pressure `p = P / h`.
pub fn inertial_number(
    shear_rate_per_s: f64,
    floe_size_m: f64,
    areal_density_kg_per_m2: f64,
    pressure_n_per_m: f64,
) -> f64 {
    shear_rate_per_s.abs() * floe_size_m * (areal_density_kg_per_m2 / pressure_n_per_m).sqrt()
}

/// The part of a polygon between `y = lo` and `y = hi` (Sutherland-Hodgman
/// against the two lines).
fn clip_to_band(poly: &[[f64; 2]], lo: f64, hi: f64) -> Vec<[f64; 2]> {
    let keep_above = |p: &[f64; 2]| p[1] - lo;
    let keep_below = |p: &[f64; 2]| hi - p[1];
    let below = clip(poly, keep_above);
    clip(&below, keep_below)
}

/// A fit of `mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MuOfI {
    /// Friction at vanishing inertial number.
    pub mu_s: f64,
    /// Friction the curve tends to at large inertial number (below `mu_s`
    /// when friction weakens with `I`).
    pub mu_2: f64,
    /// Inertial number of the midpoint between the two.
    pub i_0: f64,
    /// Root-mean-square residual of the fit.
    pub rms_residual: f64,
    /// Whether the best `I_0` lies inside the searched range rather than at
    /// one of its ends: when it does not, the data show no transition and
    /// `mu_s`, `mu_2` and `I_0` mean little on their own.
    pub resolved: bool,
}

impl MuOfI {
    /// The fitted friction at inertial number `i`.
    pub fn mu(&self, i: f64) -> f64 {
        self.mu_s + (self.mu_2 - self.mu_s) / (self.i_0 / i + 1.0)
    }
}

/// Least-squares fit of [`MuOfI`] to points `(I, mu)`, `I > 0`. For a given
/// `I_0` the model is linear in `mu_s` and `mu_2 - mu_s`, solved exactly;
/// `I_0` is searched on a log grid from a tenth of the smallest `I` to ten
/// times the largest and refined by golden section, so no starting guess is
/// needed (farther out the curve is flat over the data and any `I_0` fits).
/// Needs at least three points with distinct `I`.
pub fn fit_mu_of_i(i: &[f64], mu: &[f64]) -> Result<MuOfI, AnalysisError> {
    if i.len() != mu.len() {
        return Err(AnalysisError::LengthMismatch {
            what: "inertial numbers and friction coefficients",
            left: i.len(),
            right: mu.len(),
        });
    }
    if let Some(&bad) = i.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(AnalysisError::InvalidParameter {
            name: "I",
            value: bad,
            reason: "inertial numbers must be positive and finite",
        });
    }
    if let Some(&bad) = mu.iter().find(|v| !v.is_finite()) {
        return Err(AnalysisError::InvalidParameter {
            name: "mu",
            value: bad,
            reason: "friction coefficients must be finite",
        });
    }
    let (lo, hi) = i
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    if i.len() < 3 || hi <= lo {
        return Err(AnalysisError::NotEnoughData(
            "mu(I) needs at least three points with different inertial numbers",
        ));
    }
    // (mu_s, delta, rms) for a given log10 I_0.
    let solve = |log_i0: f64| -> (f64, f64, f64) {
        let i0 = 10f64.powf(log_i0);
        let g: Vec<f64> = i.iter().map(|&v| 1.0 / (i0 / v + 1.0)).collect();
        let n = g.len() as f64;
        let (sg, sm) = (g.iter().sum::<f64>(), mu.iter().sum::<f64>());
        let sgg: f64 = g.iter().map(|x| x * x).sum();
        let sgm: f64 = g.iter().zip(mu).map(|(x, y)| x * y).sum();
        let det = n * sgg - sg * sg;
        let (mu_s, delta) = if det.abs() > 1e-300 {
            let delta = (n * sgm - sg * sm) / det;
            ((sm - delta * sg) / n, delta)
        } else {
            (sm / n, 0.0)
        };
        let ss: f64 = g
            .iter()
            .zip(mu)
            .map(|(x, y)| (mu_s + delta * x - y).powi(2))
            .sum();
        (mu_s, delta, (ss / n).sqrt())
    };
    let (a, b) = (lo.log10() - 1.0, hi.log10() + 1.0);
    let steps = 600;
    let grid = |k: usize| a + (b - a) * k as f64 / steps as f64;
    let best = (0..=steps)
        .min_by(|&p, &q| solve(grid(p)).2.total_cmp(&solve(grid(q)).2))
        .expect("a non-empty grid");
    let (mut x0, mut x1) = (grid(best.saturating_sub(1)), grid((best + 1).min(steps)));
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..100 {
        let (c, d) = (x1 - phi * (x1 - x0), x0 + phi * (x1 - x0));
        if solve(c).2 <= solve(d).2 {
            x1 = d;
        } else {
            x0 = c;
        }
    }
    let log_i0 = 0.5 * (x0 + x1);
    let (mu_s, delta, rms) = solve(log_i0);
    Ok(MuOfI {
        mu_s,
        mu_2: mu_s + delta,
        i_0: 10f64.powf(log_i0),
        rms_residual: rms,
        resolved: best > 0 && best < steps,
    })
}

//! `kind = "diamond"`: a lattice of rhombi given by the side and acute
//! angle or by the diagonals, turned and jittered, periodic where the
//! domain is.

use std::sync::Arc;

use floe_dem::tessellation::{max_jitter_fraction, DiamondLattice, PeriodFit};

use super::{Generate, Generation, Keys, Kind};
use crate::error::ScenarioError;
use crate::numbers::{short, short_list, sig, thousands};
use crate::piece::Piece;
use crate::resolve::limits::{at_most, length, within, MAX_LENGTH_M};

/// Its line of [`super::KINDS`].
pub(super) const KIND: Kind = Kind {
    name: "diamond",
    keys: &[
        "min_area_fraction",
        "side_m",
        "diagonals_m",
        "acute_angle_deg",
        "orientation_deg",
        "jitter_fraction",
    ],
    resolve,
    sea_ice: true,
};

/// A diamond lattice, checked.
#[derive(Debug, Clone)]
struct Diamond {
    side_m: f64,
    acute_angle_deg: f64,
    orientation_deg: f64,
    /// `Some((along, across))` when given by the diagonals.
    diagonals_m: Option<(f64, f64)>,
    jitter_fraction: f64,
}

fn resolve(k: &Keys<'_>) -> Result<Arc<dyn Generate>, ScenarioError> {
    let (f, t) = (k.f, k.t);
    let orientation_deg = match &t.orientation_deg {
        Some(v) => f.finite(v, "tessellation.orientation_deg")?,
        None => 0.0,
    };
    let (side_m, acute_angle_deg, diagonals_m) = match (&t.side_m, &t.diagonals_m) {
        (Some(s), None) => {
            let side = length(f, s, "tessellation.side_m")?;
            let angle = match &t.acute_angle_deg {
                Some(a) => {
                    let a_deg = *a.get_ref();
                    if !(a_deg.is_finite() && a_deg > 0.0 && a_deg < 180.0) {
                        return Err(f.error(
                            a.span(),
                            "tessellation.acute_angle_deg",
                            format!("must lie strictly between 0 and 180, got {}", short(a_deg)),
                        ));
                    }
                    a_deg
                }
                None => 60.0,
            };
            (side, angle, None)
        }
        (None, Some(d)) => {
            if let Some(a) = &t.acute_angle_deg {
                return Err(f.error(
                    a.span(),
                    "tessellation.acute_angle_deg",
                    "does not apply with `diagonals_m` (the diagonals set the angle)",
                ));
            }
            let [along, across] = d.get_ref().0;
            if !(along.is_finite() && across.is_finite() && along > 0.0 && across > 0.0) {
                return Err(f.error(
                    d.span(),
                    "tessellation.diagonals_m",
                    format!(
                        "must be [along, across] > 0, got {}",
                        short_list(&[along, across])
                    ),
                ));
            }
            at_most(
                f,
                d.span(),
                "tessellation.diagonals_m",
                &[along, across],
                MAX_LENGTH_M,
                "m",
            )?;
            let angle = 2.0 * across.atan2(along).to_degrees();
            (0.5 * along.hypot(across), angle, Some((along, across)))
        }
        (Some(s), Some(_)) => {
            return Err(f.error(
                s.span(),
                "tessellation.side_m",
                "give `side_m` (with `acute_angle_deg`) or `diagonals_m`, not both",
            ))
        }
        (None, None) => return Err(k.need("side_m` or `diagonals_m")),
    };
    let jitter_fraction = match &t.jitter_fraction {
        Some(v) => {
            let max = max_jitter_fraction(acute_angle_deg);
            within(f, v, "tessellation.jitter_fraction", 0.0, max, false)?
        }
        None => 0.0,
    };
    Ok(Arc::new(Diamond {
        side_m,
        acute_angle_deg,
        orientation_deg,
        diagonals_m,
        jitter_fraction,
    }))
}

impl Generate for Diamond {
    fn generate(
        &self,
        g: &Generation<'_>,
        report: &mut Vec<String>,
    ) -> Result<Vec<Piece>, ScenarioError> {
        let region = g.region;
        let dem = |e| g.dem(e);
        let lattice = match self.diagonals_m {
            Some((along, across)) => DiamondLattice::from_diagonals(
                region,
                along,
                across,
                self.orientation_deg,
                g.thickness,
                self.jitter_fraction,
                g.seed,
            )
            .map_err(dem)?,
            None => DiamondLattice {
                domain: region,
                side_m: self.side_m,
                acute_angle_deg: self.acute_angle_deg,
                orientation_deg: self.orientation_deg,
                thickness: g.thickness,
                jitter_fraction: self.jitter_fraction,
                seed: g.seed,
            },
        };
        let periodic = g.domain.periodic;
        let (mut t, lr, fit) = if periodic.contains(&true) {
            let (t, lr, fit) = lattice.build_periodic(periodic).map_err(dem)?;
            (t, lr, Some(fit))
        } else {
            let (t, lr) = lattice.build_with_report().map_err(dem)?;
            (t, lr, None)
        };
        let cell = lattice.cell_area_m2();
        let drop = t.drop_floes_smaller_than(g.min_area_fraction * cell);
        let (d_along, d_across) = lattice.diagonals_m();
        report.push(format!(
            "floes: {} diamonds, side {} m, acute angle {} deg, diagonals {} x {} m, orientation {} deg, jitter {}",
            thousands(t.len()),
            sig(lattice.side_m),
            sig(lattice.acute_angle_deg),
            sig(d_along),
            sig(d_across),
            sig(lattice.orientation_deg),
            lattice.jitter_fraction
        ));
        if let Some(fit) = fit {
            report.push(describe_period_fit(&lattice, &fit));
        }
        report.push(format!(
            "  {} clipped at the edges of the ice region; {} slivers dropped by the lattice",
            thousands(lr.clipped_floes),
            lr.dropped_slivers
        ));
        report.push(g.dropped_line("clipped pieces", drop.dropped, drop.dropped_area_m2));
        (g.place)(t, report)
    }
}

/// The report line of a lattice fitted to the domain's periods: how many
/// cells span each period and how much the lattice was changed for it.
fn describe_period_fit(lattice: &DiamondLattice, fit: &PeriodFit) -> String {
    let (e1, e2) = lattice.edge_vectors_m();
    let spans: Vec<String> = fit
        .period_steps
        .iter()
        .zip(["x", "y"])
        .filter_map(|(steps, axis)| {
            steps.map(|[m, n]| format!("{m} e1 + {n} e2 span the period along {axis}"))
        })
        .collect();
    let change = if fit.is_identity() {
        "the lattice is unchanged".to_string()
    } else {
        let (lo, hi) = fit.stretch_range();
        let (d1, d2) = (fit.apply(e1 + e2).length(), fit.apply(e2 - e1).length());
        let stretch = if hi - lo <= 1e-9 * hi {
            format!("scaled by {}", sig(lo))
        } else {
            format!("stretched by {} to {}", sig(lo), sig(hi))
        };
        let turn = fit.rotation_deg();
        let turn = if turn.abs() < 1e-9 {
            String::new()
        } else {
            format!(" and turned by {} deg", sig(turn))
        };
        format!(
            "the lattice is {stretch}{turn} to fit (diagonals now {} x {} m)",
            sig(d1),
            sig(d2)
        )
    };
    format!(
        "  periodic: {}; {change}; floes straddling the seam are whole",
        spans.join(", ")
    )
}

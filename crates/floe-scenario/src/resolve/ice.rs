//! `[ice]`: the thickness distribution, density and initial velocity (the
//! ice grids are read in [`crate::ice_grid_keys`]).

use floe_dem::tessellation::ThicknessDistribution;
use floe_dem::Vec2;
use toml::Spanned;

use super::limits::{at_most, density, thickness, within, MAX_THICKNESS_M, MIN_THICKNESS_M};
use crate::error::ScenarioError;
use crate::numbers::{short, short_list};
use crate::source_file::SourceFile;
use crate::spec::RawIce;

/// Ice density when `[ice] density_kg_per_m3` is absent, kg/m^3.
pub const DEFAULT_ICE_DENSITY_KG_PER_M3: f64 = 917.0;

/// Ice thickness when `[ice]` gives none, m.
pub const DEFAULT_THICKNESS_M: f64 = 1.0;

pub(crate) fn resolve_ice(
    f: &SourceFile,
    raw: Option<&Spanned<RawIce>>,
) -> Result<(ThicknessDistribution, f64, InitialVelocity), ScenarioError> {
    let Some(raw) = raw else {
        return Ok((
            ThicknessDistribution::Uniform {
                thickness_m: DEFAULT_THICKNESS_M,
            },
            DEFAULT_ICE_DENSITY_KG_PER_M3,
            InitialVelocity::default(),
        ));
    };
    let ice = raw.get_ref();
    let ways = [
        ice.thickness_m.is_some(),
        ice.thickness_mean_m.is_some(),
        ice.thickness_range_m.is_some(),
        ice.thickness_grid.is_some(),
    ];
    if ways.iter().filter(|&&w| w).count() > 1 {
        return Err(f.error(
            raw.span(),
            "ice",
            "give one of `thickness_m`, `thickness_mean_m` (with `thickness_std_m`), `thickness_range_m` or `thickness_grid`",
        ));
    }
    if ice.thickness_std_m.is_some() && ice.thickness_mean_m.is_none() {
        let s = ice
            .thickness_std_m
            .as_ref()
            .map(|s| s.span())
            .unwrap_or(0..0);
        return Err(f.error(
            s,
            "ice.thickness_std_m",
            "needs `thickness_mean_m` (log-normal thickness)",
        ));
    }
    let thickness = if let Some(h) = &ice.thickness_m {
        ThicknessDistribution::Uniform {
            thickness_m: thickness(f, h, "ice.thickness_m", false)?,
        }
    } else if let Some(mean) = &ice.thickness_mean_m {
        ThicknessDistribution::LogNormal {
            mean_m: thickness(f, mean, "ice.thickness_mean_m", false)?,
            std_m: match &ice.thickness_std_m {
                Some(s) => thickness(f, s, "ice.thickness_std_m", true)?,
                None => 0.0,
            },
        }
    } else if let Some(r) = &ice.thickness_range_m {
        let [lo, hi] = r.get_ref().0;
        if !(lo.is_finite() && hi.is_finite() && lo >= MIN_THICKNESS_M && hi >= lo) {
            return Err(f.error(
                r.span(),
                "ice.thickness_range_m",
                format!(
                    "must be [min, max] with {MIN_THICKNESS_M} m <= min <= max, got {}",
                    short_list(&[lo, hi])
                ),
            ));
        }
        at_most(
            f,
            r.span(),
            "ice.thickness_range_m",
            &[hi],
            MAX_THICKNESS_M,
            "m",
        )?;
        ThicknessDistribution::UniformRange {
            min_m: lo,
            max_m: hi,
        }
    } else {
        ThicknessDistribution::Uniform {
            thickness_m: DEFAULT_THICKNESS_M,
        }
    };
    let density = match &ice.density_kg_per_m3 {
        Some(v) => match density(f, v, "ice.density_kg_per_m3", false)? {
            // Far lighter than any ice, and the masses underflow.
            rho if rho >= 100.0 => rho,
            rho => {
                return Err(f.error(
                    v.span(),
                    "ice.density_kg_per_m3",
                    format!(
                        "{} kg/m^3 is lighter than any ice (at least 100)",
                        short(rho)
                    ),
                ))
            }
        },
        None => DEFAULT_ICE_DENSITY_KG_PER_M3,
    };
    let uniform = match &ice.initial_velocity_m_per_s {
        Some(v) => f.pair(v, "ice.initial_velocity_m_per_s")?,
        None => Vec2::ZERO,
    };
    let shear_rate_per_s = match &ice.initial_shear_rate_per_s {
        Some(v) => within(
            f,
            v,
            "ice.initial_shear_rate_per_s",
            -MAX_INITIAL_SHEAR_RATE_PER_S,
            MAX_INITIAL_SHEAR_RATE_PER_S,
            false,
        )?,
        None => 0.0,
    };
    Ok((
        thickness,
        density,
        InitialVelocity {
            uniform,
            shear_rate_per_s,
        },
    ))
}

/// Largest `initial_shear_rate_per_s` magnitude: one radian a second is
/// far beyond any ice (and keeps the start's speeds bounded).
const MAX_INITIAL_SHEAR_RATE_PER_S: f64 = 1.0;

/// The free floes' velocity at the start: `uniform + (rate (y - y0), 0)`
/// at a floe's centroid height `y - y0` above the bottom of the ice region
/// (`[ice] initial_velocity_m_per_s`, `initial_shear_rate_per_s`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InitialVelocity {
    /// The same for every floe, m/s.
    pub uniform: Vec2,
    /// `du_x/dy`, 1/s: a simple-shear start (a shear cell's linear profile).
    pub shear_rate_per_s: f64,
}

impl InitialVelocity {
    /// The velocity of a free floe whose centroid is `height_m` above the
    /// bottom of the ice region.
    pub fn at(&self, height_m: f64) -> Vec2 {
        if self.shear_rate_per_s == 0.0 {
            return self.uniform;
        }
        self.uniform + Vec2::new(self.shear_rate_per_s * height_m, 0.0)
    }
}

//! `[wind]`, `[ocean]` and `[coriolis]`: the velocity fields, their drag
//! and the Coriolis parameter.

use std::ops::Range;

use floe_dem::forcing::{Coriolis, DragParameters, Envelope, Forcing, VelocityField};
use floe_dem::Vec2;
use toml::Spanned;

use super::limits::{density, span_of, within};
use crate::error::ScenarioError;
use crate::gridded_inputs::{resolve_gridded_velocity, resolve_sea_surface_height, GridContext};
use crate::numbers::short;
use crate::source_file::SourceFile;
use crate::spec::{Exact, RawCoriolis, RawFluid};

pub(crate) fn resolve_field(
    f: &SourceFile,
    raw: &RawFluid,
    table: &str,
    grids: &mut GridContext<'_>,
) -> Result<VelocityField, ScenarioError> {
    let ways = [
        raw.velocity_m_per_s.is_some(),
        raw.time_series.is_some(),
        raw.shear.is_some(),
        raw.gyre.is_some(),
        raw.file.is_some(),
    ];
    if ways.iter().filter(|&&w| w).count() > 1 {
        let span = [
            span_of(&raw.time_series),
            span_of(&raw.shear),
            span_of(&raw.gyre),
            span_of(&raw.file),
        ]
        .into_iter()
        .flatten()
        .next_back()
        .unwrap_or(0..0);
        return Err(f.error(
            span,
            table,
            "give one of `velocity_m_per_s`, `time_series`, `shear`, `gyre` or `file`",
        ));
    }
    if raw.plane_spacing_m.is_some() && raw.file.is_none() && raw.sea_surface_height.is_none() {
        return Err(f.error(
            span_of(&raw.plane_spacing_m).unwrap_or(0..0),
            format!("{table}.plane_spacing_m"),
            "applies only to a field read from a `file`",
        ));
    }
    let check = |field: VelocityField, span: Range<usize>, key: &str| {
        field
            .validate()
            .map(|()| field)
            .map_err(|e| f.error(span, format!("{table}.{key}"), e.to_string()))
    };
    let field = if let Some(g) = resolve_gridded_velocity(f, raw, table, grids)? {
        g
    } else if let Some(v) = &raw.velocity_m_per_s {
        VelocityField::Uniform(f.pair(v, &format!("{table}.velocity_m_per_s"))?)
    } else if let Some(ts) = &raw.time_series {
        let t = ts.get_ref();
        check(
            VelocityField::TimeSeries {
                times_s: t.times_s.clone(),
                values: t
                    .velocities_m_per_s
                    .iter()
                    .map(|&Exact([x, y])| Vec2::new(x, y))
                    .collect(),
            },
            ts.span(),
            "time_series",
        )?
    } else if let Some(s) = &raw.shear {
        let r = s.get_ref();
        let [a, b] = r.velocity_at_y_min_m_per_s.0;
        let [c, d] = r.velocity_at_y_max_m_per_s.0;
        check(
            VelocityField::LinearShear {
                y_min_m: r.y_min_m,
                y_max_m: r.y_max_m,
                velocity_at_y_min_m_per_s: Vec2::new(a, b),
                velocity_at_y_max_m_per_s: Vec2::new(c, d),
            },
            s.span(),
            "shear",
        )?
    } else if let Some(g) = &raw.gyre {
        let r = g.get_ref();
        check(
            VelocityField::Gyre {
                center_m: Vec2::new(r.center_m.0[0], r.center_m.0[1]),
                core_radius_m: r.core_radius_m,
                max_speed_m_per_s: r.max_speed_m_per_s,
            },
            g.span(),
            "gyre",
        )?
    } else {
        VelocityField::Uniform(Vec2::ZERO)
    };
    match &raw.envelope {
        None => Ok(field),
        Some(e) => {
            let env = Envelope {
                times_s: e.get_ref().times_s.clone(),
                factors: e.get_ref().factors.clone(),
            };
            env.validate()
                .map_err(|err| f.error(e.span(), format!("{table}.envelope"), err.to_string()))?;
            Ok(field.scaled(env))
        }
    }
}

pub(crate) fn resolve_drag(
    f: &SourceFile,
    raw: &RawFluid,
    table: &str,
    mut drag: DragParameters,
) -> Result<DragParameters, ScenarioError> {
    if let Some(v) = &raw.density_kg_per_m3 {
        drag.density_kg_per_m3 = density(f, v, &format!("{table}.density_kg_per_m3"), true)?;
    }
    if let Some(v) = &raw.drag_coefficient {
        drag.drag_coefficient = f.non_negative(v, &format!("{table}.drag_coefficient"))?;
    }
    if let Some(v) = &raw.turning_angle_deg {
        let a = *v.get_ref();
        if !(a.is_finite() && a.abs() < 90.0) {
            return Err(f.error(
                v.span(),
                format!("{table}.turning_angle_deg"),
                format!("must lie strictly between -90 and 90, got {}", short(a)),
            ));
        }
        drag.turning_angle_deg = a;
    }
    if let Some(v) = &raw.relative_to_ice {
        drag.relative_to_ice = *v.get_ref();
    }
    Ok(drag)
}

pub(crate) fn resolve_forcing(
    f: &SourceFile,
    wind: Option<&Spanned<RawFluid>>,
    ocean: Option<&Spanned<RawFluid>>,
    coriolis: Option<&Spanned<RawCoriolis>>,
    grids: &mut GridContext<'_>,
) -> Result<Forcing, ScenarioError> {
    let mut forcing = Forcing::default();
    if let Some(w) = wind {
        let w = w.get_ref();
        if let Some(v) = &w.sea_surface_height {
            return Err(f.error(
                v.span(),
                "wind.sea_surface_height",
                "belongs in [ocean], not [wind]",
            ));
        }
        for (flag, name) in [
            (&w.sea_surface_tilt, "sea_surface_tilt"),
            (&w.rotational_drag, "rotational_drag"),
        ] {
            if let Some(v) = flag {
                return Err(f.error(
                    v.span(),
                    format!("wind.{name}"),
                    "belongs in [ocean], not [wind]",
                ));
            }
        }
        forcing.wind = resolve_field(f, w, "wind", grids)?;
        forcing.air = resolve_drag(f, w, "wind", forcing.air)?;
    }
    if let Some(o) = ocean {
        let o = o.get_ref();
        forcing.current = resolve_field(f, o, "ocean", grids)?;
        forcing.sea_surface_height = resolve_sea_surface_height(f, o, grids)?;
        forcing.ocean = resolve_drag(f, o, "ocean", forcing.ocean)?;
        if let Some(v) = &o.sea_surface_tilt {
            forcing.sea_surface_tilt = *v.get_ref();
        }
        if let Some(v) = &o.rotational_drag {
            forcing.rotational_drag = *v.get_ref();
        }
    }
    if let Some(c) = coriolis {
        let r = c.get_ref();
        forcing.coriolis = match (&r.latitude_deg, &r.f_per_s) {
            (Some(lat), None) => {
                Coriolis::LatitudeDeg(within(f, lat, "coriolis.latitude_deg", -90.0, 90.0, false)?)
            }
            (None, Some(fp)) => Coriolis::ParameterPerS(f.finite(fp, "coriolis.f_per_s")?),
            _ => {
                return Err(f.error(
                    c.span(),
                    "coriolis",
                    "give exactly one of `latitude_deg` or `f_per_s` (omit [coriolis] for none)",
                ))
            }
        };
    }
    Ok(forcing)
}

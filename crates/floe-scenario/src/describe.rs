//! One-line descriptions of a built scenario's parts, for the terminal.

use floe_dem::contact_model::ContactModel;
use floe_dem::forcing::Forcing;
use floe_dem::Vec2;

use crate::numbers::sig;
use crate::resolve::Resolved;

pub(crate) fn describe_thickness(r: &Resolved) -> String {
    use floe_dem::tessellation::ThicknessDistribution as T;
    if let Some(g) = &r.ice_grids.thickness {
        return format!("from {} in `{}`", g.variable, g.written);
    }
    match r.thickness {
        T::Uniform { thickness_m } => format!("{thickness_m} m"),
        T::UniformRange { min_m, max_m } => format!("uniform in [{min_m}, {max_m}] m"),
        T::LogNormal { mean_m, std_m } => format!("log-normal, mean {mean_m} m, std {std_m} m"),
    }
}

pub(crate) fn describe_contact(m: &ContactModel) -> String {
    use floe_friction::{Form, Law, StateLaw};
    let law = match &m.law {
        Law::Amontons(a) => format!("Amontons mu = {}", a.mu),
        Law::RateDependent(r) => format!(
            "rate-dependent mu0 = {}, c1 = {}, V* = {} m/s",
            r.mu0, r.c1, r.v_star_m_per_s
        ),
        Law::Custom(_) => format!("custom law `{}`", m.law.name()),
        Law::RateState(rs) => format!(
            "rate-and-state ({} form, {} law) mu0 = {}, A = {}, B = {}, V* = {} m/s, L = {} m",
            match rs.form {
                Form::Published => "published",
                Form::Regularized => "regularized",
            },
            match rs.state_law {
                StateLaw::Slip => "slip",
                StateLaw::Aging => "aging",
            },
            rs.params.mu0,
            rs.params.a,
            rs.params.b,
            rs.params.v_star_m_per_s,
            rs.params.critical_slip_m
        ),
    };
    format!(
        "contacts: E = {} Pa, nu = {}, restitution {}; friction: {law}",
        m.youngs_modulus_pa, m.poisson_ratio, m.restitution
    )
}

pub(crate) fn describe_forcing(fo: &Forcing) -> String {
    use floe_dem::forcing::VelocityField as V;
    let field = |v: &V| match v {
        V::Uniform(u) if *u == Vec2::ZERO => "at rest".to_string(),
        V::Uniform(u) => format!("uniform [{}, {}] m/s", u.x, u.y),
        V::TimeSeries { times_s, .. } => format!("time series of {} samples", times_s.len()),
        V::LinearShear { .. } => "linear shear".to_string(),
        V::Gyre { .. } => "gyre".to_string(),
        V::Scaled { .. } => "scaled by an envelope".to_string(),
        V::Gridded(g) => format!("gridded ({}, {} times)", g.describe(), g.times_s().len()),
    };
    let f = fo.coriolis.parameter_per_s();
    format!(
        "forcing: wind {} (Cd {}), ocean {} (Cd {}), Coriolis {}",
        field(&fo.wind),
        fo.air.drag_coefficient,
        field(&fo.current),
        fo.ocean.drag_coefficient,
        if f == 0.0 {
            "off".to_string()
        } else {
            format!("f = {} /s", sig(f))
        }
    )
}

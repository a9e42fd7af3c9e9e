//! One-line descriptions of a built scenario's parts, for the terminal.

use floe_dem::contact_model::ContactModel;
use floe_dem::forcing::Forcing;
use floe_dem::fracture::rule::Fracturing;
use floe_dem::Vec2;

use crate::law_variants::LAW_NUMBERS;
use crate::numbers::{parameter as p, sig};
use crate::resolve::Resolved;

pub(crate) fn describe_thickness(r: &Resolved) -> String {
    use floe_dem::tessellation::ThicknessDistribution as T;
    if let Some(g) = &r.ice_grids.thickness {
        return format!("from {} in `{}`", g.variable, g.written);
    }
    match r.thickness {
        T::Uniform { thickness_m } => format!("{} m", p(thickness_m)),
        T::UniformRange { min_m, max_m } => format!("uniform in [{}, {}] m", p(min_m), p(max_m)),
        T::LogNormal { mean_m, std_m } => {
            format!("log-normal, mean {} m, std {} m", p(mean_m), p(std_m))
        }
    }
}

pub(crate) fn describe_contact(m: &ContactModel) -> String {
    let law = m.law.description(&LAW_NUMBERS);
    format!(
        "contacts: E = {} Pa, nu = {}, restitution {}; friction: {law}",
        p(m.youngs_modulus_pa),
        p(m.poisson_ratio),
        p(m.restitution)
    )
}

pub(crate) fn describe_forcing(fo: &Forcing) -> String {
    use floe_dem::forcing::VelocityField as V;
    let field = |v: &V| match v {
        V::Uniform(u) if *u == Vec2::ZERO => "at rest".to_string(),
        V::Uniform(u) => format!("uniform [{}, {}] m/s", p(u.x), p(u.y)),
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
        p(fo.air.drag_coefficient),
        field(&fo.current),
        p(fo.ocean.drag_coefficient),
        if f == 0.0 {
            "off".to_string()
        } else {
            format!("f = {} /s", sig(f))
        }
    )
}

/// The cohesion line of the build report.
pub(crate) fn describe_cohesion(c: &floe_dem::cohesion::Cohesion) -> String {
    let growth = if c.growth_time_s > 0.0 {
        format!(", growing as 1 - exp(-age / {} s)", sig(c.growth_time_s))
    } else {
        ", at full strength at once".into()
    };
    format!(
        "  cohesion: contacts slower than {} m/s for {} s freeze into bonds of up to {} N/m in tension and {} N/m in shear{growth}",
        sig(c.quiet_speed_m_per_s),
        sig(c.bond_after_s),
        sig(c.tensile_strength_n_per_m),
        sig(c.shear_strength_n_per_m),
    )
}

/// The ridging line of the build report.
pub(crate) fn describe_ridging(r: &floe_dem::ridging::Ridging) -> String {
    format!(
        "  ridging: a floe up to {} m thick bears at most {} h^{} N per m of contact ({} N/m at 1 m), the rest of its overlap goes to {} or the coast; kept parts under {} m^2 stay whole",
        sig(r.max_thickness_m),
        sig(r.strength_n_per_m),
        sig(r.thickness_exponent),
        sig(r.strength_at(1.0)),
        match r.rubble {
            floe_dem::ridging::Rubble::Gainer => "the thicker floe",
            floe_dem::ridging::Rubble::Both => "both floes by area",
        },
        sig(r.min_floe_area_m2),
    )
}

/// The welding line of the build report.
pub(crate) fn describe_welding(w: &floe_dem::welding::Welding) -> String {
    format!(
        "  welding: floes bonded for {} s become their convex hull if it adds at most {} % of their area, is at most {} m^2 and moves their centre of mass at most {} % of its radius; checked every {} s",
        sig(w.after_s),
        sig(100.0 * w.max_added_area_fraction),
        sig(w.max_area_m2),
        sig(100.0 * w.max_centre_shift_fraction),
        sig(w.check_every_s),
    )
}

/// The fracture line of the build report.
pub(crate) fn describe_fracture(f: &Fracturing, dt_s: f64) -> String {
    use floe_dem::fracture::criteria::FractureCriterion;
    use floe_dem::fracture::rule::StrengthThickness;
    let r = &f.rule;
    let criterion = match r.criterion {
        FractureCriterion::MohrCoulomb(m) => format!(
            "Mohr-Coulomb cone (q = {}, sigma_c = {} Pa, sigma_11 = {} Pa)",
            sig(m.q),
            sig(m.sigma_c_pa),
            sig(m.sigma_11_pa)
        ),
        FractureCriterion::Hibler(h) => format!(
            "Hibler's ellipse (p* = {} Pa/m, c = {}, {})",
            sig(h.p_star_pa_per_m),
            sig(h.c),
            match r.strength_thickness {
                StrengthThickness::Own => "each floe's thickness",
                StrengthThickness::Pack => "the pack's mean thickness and concentration",
            }
        ),
    };
    format!(
        "fracture: {criterion}, checked every {} steps ({} s); floes of {} m^2 or more break into {} pieces of at least {} m^2",
        r.check_every_steps,
        sig(r.check_every_steps as f64 * dt_s),
        sig(r.min_floe_area_m2),
        r.split.pieces,
        sig(r.split.min_piece_area_m2)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use floe_friction::{Law, RateDependent};

    #[test]
    fn the_build_report_shows_derived_parameters_without_floating_point_noise() {
        // C1 = A - B of Lishman et al.'s lab law, as `floe compare` derives it.
        let c1 = 0.31 - 0.382;
        assert_eq!(c1, -0.07200000000000001);
        let model = ContactModel::default().with_law(Law::RateDependent(RateDependent {
            mu0: 0.872,
            c1,
            v_star_m_per_s: 1e-5,
            v_floor_m_per_s: 1e-5,
        }));
        assert_eq!(
            describe_contact(&model),
            "contacts: E = 6e6 Pa, nu = 0.3, restitution 0.5; \
             friction: rate-dependent mu0 = 0.872, c1 = -0.072, V* = 1e-5 m/s"
        );
    }
}

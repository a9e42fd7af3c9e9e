//! `[floe_stress]`, `[fracture]`, `[cohesion]`, `[ridging]` and
//! `[welding]`: the floe life cycle's settings.

use floe_dem::cohesion::Cohesion;
use floe_dem::fracture::criteria::{FractureCriterion, HiblerEllipse, MohrCoulomb};
use floe_dem::fracture::rule::StrengthThickness;
use floe_dem::pipeline::floe_stress::StressFilter;
use floe_dem::ridging::{Ridging, Rubble};
use floe_dem::welding::Welding;
use toml::Spanned;

use crate::error::ScenarioError;
use crate::resolve::limits::{count, refuse_given, span_of};
use crate::source_file::SourceFile;
use crate::spec::{RawCohesion, RawFloeStress, RawFracture, RawRidging, RawWelding};

/// Smallest floe that breaks unless given, m^2: the anchors' smallest
/// floe (Subzero.jl `FloeSettings.min_floe_area`).
pub const DEFAULT_MIN_FLOE_AREA_M2: f64 = 1e6;
/// Fracture checks unless given, s.
pub const DEFAULT_CHECK_EVERY_S: f64 = 60.0;
/// Most pieces a split may make.
pub const MAX_PIECES: u64 = 16;
/// Most attempts at a split.
pub const MAX_ATTEMPTS: u64 = 1000;

/// Where `[fracture]` and its smallest piece stand in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct FractureSpans {
    /// The table.
    pub table: std::ops::Range<usize>,
    /// `min_piece_area_m2`, if given.
    pub min_piece: Option<std::ops::Range<usize>>,
}

/// `[fracture]` checked, in seconds (the time step turns it into a rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FractureSettings {
    /// The criterion.
    pub criterion: FractureCriterion,
    /// How often it is checked, s.
    pub check_every_s: f64,
    /// Floes smaller than this never break, m^2.
    pub min_floe_area_m2: f64,
    /// No piece is smaller, m^2.
    pub min_piece_area_m2: f64,
    /// Pieces per split.
    pub pieces: usize,
    /// Attempts per split.
    pub attempts: u32,
    /// Hibler's thickness and concentration.
    pub strength_thickness: StrengthThickness,
}

/// The floe stress's time average, if `[floe_stress]` is given
/// (`time_scale_s` defaults to the anchors' averaging).
pub(crate) fn resolve_floe_stress(
    f: &SourceFile,
    raw: Option<&Spanned<RawFloeStress>>,
) -> Result<Option<StressFilter>, ScenarioError> {
    let Some(raw) = raw else {
        return Ok(None);
    };
    Ok(Some(match &raw.get_ref().time_scale_s {
        Some(t) => StressFilter {
            time_scale_s: f.positive(t, "floe_stress.time_scale_s")?,
        },
        None => StressFilter::default(),
    }))
}

/// `[cohesion]`, if given: each value checked (the quiet speed > 0, the
/// others >= 0), the rest [`Cohesion::default`]'s.
pub(crate) fn resolve_cohesion(
    f: &SourceFile,
    raw: Option<&Spanned<RawCohesion>>,
) -> Result<Option<Cohesion>, ScenarioError> {
    let Some(raw) = raw else {
        return Ok(None);
    };
    let r = raw.get_ref();
    let d = Cohesion::default();
    let non_negative = |v: &Option<Spanned<f64>>, key: &str, default: f64| match v {
        Some(x) => f.non_negative(x, &format!("cohesion.{key}")),
        None => Ok(default),
    };
    Ok(Some(Cohesion {
        quiet_speed_m_per_s: match &r.quiet_speed_m_per_s {
            Some(x) => f.positive(x, "cohesion.quiet_speed_m_per_s")?,
            None => d.quiet_speed_m_per_s,
        },
        bond_after_s: non_negative(&r.bond_after_s, "bond_after_s", d.bond_after_s)?,
        tensile_strength_n_per_m: non_negative(
            &r.tensile_strength_n_per_m,
            "tensile_strength_n_per_m",
            d.tensile_strength_n_per_m,
        )?,
        shear_strength_n_per_m: non_negative(
            &r.shear_strength_n_per_m,
            "shear_strength_n_per_m",
            d.shear_strength_n_per_m,
        )?,
        growth_time_s: non_negative(&r.growth_time_s, "growth_time_s", d.growth_time_s)?,
    }))
}

/// `[ridging]`, if given: each value checked (the exponent >= 0, the
/// others > 0), the rest [`Ridging::default`]'s.
pub(crate) fn resolve_ridging(
    f: &SourceFile,
    raw: Option<&Spanned<RawRidging>>,
) -> Result<Option<Ridging>, ScenarioError> {
    let Some(raw) = raw else {
        return Ok(None);
    };
    let r = raw.get_ref();
    let d = Ridging::default();
    let positive = |v: &Option<Spanned<f64>>, key: &str, default: f64| match v {
        Some(x) => f.positive(x, &format!("ridging.{key}")),
        None => Ok(default),
    };
    Ok(Some(Ridging {
        strength_n_per_m: positive(&r.strength_n_per_m, "strength_n_per_m", d.strength_n_per_m)?,
        thickness_exponent: match &r.thickness_exponent {
            Some(x) => f.non_negative(x, "ridging.thickness_exponent")?,
            None => d.thickness_exponent,
        },
        max_thickness_m: positive(&r.max_thickness_m, "max_thickness_m", d.max_thickness_m)?,
        min_floe_area_m2: positive(&r.min_floe_area_m2, "min_floe_area_m2", d.min_floe_area_m2)?,
        rubble: f.keyword(
            &r.rubble,
            "ridging.rubble",
            &[("gainer", Rubble::Gainer), ("both", Rubble::Both)],
            d.rubble,
        )?,
    }))
}

/// `[welding]`, if given: each value checked (the largest area > 0, the
/// others >= 0), the rest [`Welding::default`]'s; refused at the table
/// without `[cohesion]`, whose bonds it welds.
pub(crate) fn resolve_welding(
    f: &SourceFile,
    raw: Option<&Spanned<RawWelding>>,
    cohesion: Option<&Cohesion>,
) -> Result<Option<Welding>, ScenarioError> {
    let Some(raw) = raw else {
        return Ok(None);
    };
    if cohesion.is_none() {
        return Err(f.error(
            raw.span(),
            "welding",
            "welds floes frozen together, and the scenario has no [cohesion] table to freeze them: add one, or drop [welding]",
        ));
    }
    let r = raw.get_ref();
    let d = Welding::default();
    let non_negative = |v: &Option<Spanned<f64>>, key: &str, default: f64| match v {
        Some(x) => f.non_negative(x, &format!("welding.{key}")),
        None => Ok(default),
    };
    Ok(Some(Welding {
        after_s: non_negative(&r.after_s, "after_s", d.after_s)?,
        max_added_area_fraction: non_negative(
            &r.max_added_area_fraction,
            "max_added_area_fraction",
            d.max_added_area_fraction,
        )?,
        max_area_m2: match &r.max_area_m2 {
            Some(x) => f.positive(x, "welding.max_area_m2")?,
            None => d.max_area_m2,
        },
        max_centre_shift_fraction: non_negative(
            &r.max_centre_shift_fraction,
            "max_centre_shift_fraction",
            d.max_centre_shift_fraction,
        )?,
        check_every_s: non_negative(&r.check_every_s, "check_every_s", d.check_every_s)?,
    }))
}

/// `[fracture]`, if given: each value checked, defaults applied, the
/// other criterion's keys refused.
pub(crate) fn resolve_fracture(
    f: &SourceFile,
    raw: Option<&Spanned<RawFracture>>,
) -> Result<Option<(FractureSettings, FractureSpans)>, ScenarioError> {
    let Some(spanned) = raw else {
        return Ok(None);
    };
    let r = spanned.get_ref();
    let Some(criterion) = &r.criterion else {
        return Err(f.error(
            spanned.span(),
            "fracture.criterion",
            "missing: \"mohr_coulomb\" or \"hibler\"",
        ));
    };
    let num = |v: &Option<Spanned<f64>>, key: &str, default: f64| -> Result<f64, ScenarioError> {
        match v {
            Some(x) => f.finite(x, &format!("fracture.{key}")),
            None => Ok(default),
        }
    };
    let given = [
        (span_of(&r.q), "q"),
        (span_of(&r.sigma_c_pa), "sigma_c_pa"),
        (span_of(&r.sigma_11_pa), "sigma_11_pa"),
        (span_of(&r.p_star_pa_per_m), "p_star_pa_per_m"),
        (span_of(&r.c), "c"),
        (span_of(&r.strength_thickness), "strength_thickness"),
    ];
    let (criterion, strength_thickness) = match criterion.get_ref().as_str() {
        "mohr_coulomb" => {
            refuse_given(
                f,
                "fracture",
                "criterion \"mohr_coulomb\"",
                &given,
                &["q", "sigma_c_pa", "sigma_11_pa"],
            )?;
            let d = MohrCoulomb::default();
            let sigma_c_pa = num(&r.sigma_c_pa, "sigma_c_pa", d.sigma_c_pa)?;
            // The cap keeps the anchors' place relative to sigma_c unless given.
            let sigma_11 = d.sigma_11_pa / d.sigma_c_pa * sigma_c_pa;
            let m = MohrCoulomb {
                q: num(&r.q, "q", d.q)?,
                sigma_c_pa,
                sigma_11_pa: num(&r.sigma_11_pa, "sigma_11_pa", sigma_11)?,
            };
            m.check().map_err(|why| located(f, spanned, r, why))?;
            (FractureCriterion::MohrCoulomb(m), StrengthThickness::Own)
        }
        "hibler" => {
            refuse_given(
                f,
                "fracture",
                "criterion \"hibler\"",
                &given,
                &["p_star_pa_per_m", "c", "strength_thickness"],
            )?;
            let d = HiblerEllipse::default();
            let h = HiblerEllipse {
                p_star_pa_per_m: num(&r.p_star_pa_per_m, "p_star_pa_per_m", d.p_star_pa_per_m)?,
                c: num(&r.c, "c", d.c)?,
            };
            h.check().map_err(|why| located(f, spanned, r, why))?;
            let thickness = match &r.strength_thickness {
                None => StrengthThickness::Pack,
                Some(w) => match w.get_ref().as_str() {
                    "own" => StrengthThickness::Own,
                    "pack" => StrengthThickness::Pack,
                    other => {
                        return Err(f.error(
                            w.span(),
                            "fracture.strength_thickness",
                            format!("\"{other}\": \"own\" (the floe's) or \"pack\" (the pack's mean and concentration)"),
                        ))
                    }
                },
            };
            (FractureCriterion::Hibler(h), thickness)
        }
        other => {
            return Err(f.error(
                criterion.span(),
                "fracture.criterion",
                format!("\"{other}\": \"mohr_coulomb\" or \"hibler\""),
            ))
        }
    };
    let check_every_s = match &r.check_every_s {
        Some(t) => f.positive(t, "fracture.check_every_s")?,
        None => DEFAULT_CHECK_EVERY_S,
    };
    let min_floe_area_m2 = match &r.min_floe_area_m2 {
        Some(a) => f.non_negative(a, "fracture.min_floe_area_m2")?,
        None => DEFAULT_MIN_FLOE_AREA_M2,
    };
    let pieces = match &r.pieces {
        Some(n) => count(f, n, "fracture.pieces", 2, MAX_PIECES)?,
        None => 3,
    };
    let attempts = match &r.attempts {
        Some(n) => count(f, n, "fracture.attempts", 1, MAX_ATTEMPTS)? as u32,
        None => 10,
    };
    let min_piece_area_m2 = match &r.min_piece_area_m2 {
        Some(a) => {
            let piece = f.non_negative(a, "fracture.min_piece_area_m2")?;
            if piece * pieces as f64 > min_floe_area_m2 {
                return Err(f.error(
                    a.span(),
                    "fracture.min_piece_area_m2",
                    format!(
                        "{pieces} pieces of at least {piece} m^2 do not fit in a floe of fracture.min_floe_area_m2 = {min_floe_area_m2} m^2: give at most {} m^2",
                        min_floe_area_m2 / pieces as f64
                    ),
                ));
            }
            piece
        }
        None => min_floe_area_m2 / (2 * pieces) as f64,
    };
    let spans = FractureSpans {
        table: spanned.span(),
        min_piece: span_of(&r.min_piece_area_m2),
    };
    Ok(Some((
        FractureSettings {
            criterion,
            check_every_s,
            min_floe_area_m2,
            min_piece_area_m2,
            pieces,
            attempts,
            strength_thickness,
        },
        spans,
    )))
}

/// A criterion's parameter check `why` (which starts with the parameter's
/// name), located at that key if given, else at the table.
fn located(
    f: &SourceFile,
    table: &Spanned<RawFracture>,
    r: &RawFracture,
    why: String,
) -> ScenarioError {
    let keys = [
        ("sigma_c", "sigma_c_pa", span_of(&r.sigma_c_pa)),
        ("sigma_11", "sigma_11_pa", span_of(&r.sigma_11_pa)),
        ("q", "q", span_of(&r.q)),
        ("p*", "p_star_pa_per_m", span_of(&r.p_star_pa_per_m)),
        ("c", "c", span_of(&r.c)),
    ];
    let found = keys
        .into_iter()
        .find(|(name, _, _)| why.starts_with(&format!("{name} ")));
    match found {
        Some((_, key, Some(span))) => f.error(span, format!("fracture.{key}"), why),
        Some((_, key, None)) => f.error(table.span(), format!("fracture.{key}"), why),
        None => f.error(table.span(), "fracture", why),
    }
}

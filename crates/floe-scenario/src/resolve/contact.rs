//! `[contact]` and `[friction]`: the contact model, its friction law read
//! through the law registry ([`crate::law_table`]).

use floe_dem::contact_model::ContactModel;
use floe_friction::experiments::Preset;
use floe_friction::{Form, LawContext, LawRegistry};
use toml::Spanned;

use super::limits::within;
use crate::error::ScenarioError;
use crate::law_table::{law_from_table, preset_applies, RawLawTable};
use crate::source_file::SourceFile;
use crate::spec::RawContact;

/// Accepted contact Young's moduli, Pa: sea ice is about 1e9; below 1e3 Pa
/// floes pass through each other, above 1e13 the stable step vanishes.
pub const YOUNGS_MODULUS_RANGE_PA: (f64, f64) = (1e3, 1e13);

pub(crate) fn resolve_contact(
    f: &SourceFile,
    raw: Option<&RawContact>,
    friction: Option<&Spanned<RawLawTable>>,
    registry: &LawRegistry,
) -> Result<ContactModel, ScenarioError> {
    let mut m = ContactModel::default();
    if let Some(c) = raw {
        if let Some(v) = &c.youngs_modulus_pa {
            m.youngs_modulus_pa = f.in_range(
                v,
                "contact.youngs_modulus_pa",
                YOUNGS_MODULUS_RANGE_PA,
                "Pa",
            )?;
        }
        if let Some(v) = &c.poisson_ratio {
            m.poisson_ratio = within(f, v, "contact.poisson_ratio", 0.0, 0.5, true)?;
        }
        if let Some(v) = &c.restitution {
            m.restitution = within(f, v, "contact.restitution", 0.0, 1.0, false)?;
            if m.restitution < 1e-12 {
                return Err(f.error(
                    v.span(),
                    "contact.restitution",
                    "must lie in [1e-12, 1]; 0 would be an infinitely stiff dashpot, and \
                     below 1e-12 the stable time step vanishes",
                ));
            }
        }
        if let Some(v) = &c.new_contact_slip_rate_m_per_s {
            m.new_contact_slip_rate_m_per_s =
                f.positive(v, "contact.new_contact_slip_rate_m_per_s")?;
        }
        if let Some(v) = &c.sliding_threshold_m_per_s {
            m.sliding_threshold_m_per_s = f.positive(v, "contact.sliding_threshold_m_per_s")?;
        }
        if let Some(v) = &c.memory_s {
            m.memory_s = f.non_negative(v, "contact.memory_s")?;
        }
    }
    let empty = RawLawTable::new();
    let fr = friction.map_or(&empty, |t| t.get_ref());
    // The law's name first: a misspelt law is reported as that, not as a
    // key that does not apply to it.
    if let Some(law) = fr.get("law") {
        let known = law
            .get_ref()
            .as_str()
            .is_some_and(|n| registry.get(n).is_some());
        if !known {
            return Err(f.error(
                law.span(),
                "friction.law",
                format!(
                    "unknown law {}, expected {}",
                    law.get_ref()
                        .as_str()
                        .map_or_else(|| law.get_ref().to_string(), |n| format!("`{n}`")),
                    registry.names_text()
                ),
            ));
        }
    }
    let preset = match fr.get("preset") {
        None => Preset::Tank,
        Some(p) => {
            if !preset_applies(fr, "law", registry) {
                let law = fr
                    .get("law")
                    .and_then(|l| l.get_ref().as_str())
                    .unwrap_or("");
                return Err(f.error(
                    p.span(),
                    "friction.preset",
                    format!("does not apply to law `{law}` (no default depends on it)"),
                ));
            }
            match p.get_ref().as_str() {
                Some("lab") => Preset::Lab,
                Some("tank") => Preset::Tank,
                _ => {
                    return Err(f.error(
                        p.span(),
                        "friction.preset",
                        format!(
                            "unknown value {}, expected one of `lab`, `tank`",
                            p.get_ref()
                        ),
                    ))
                }
            }
        }
    };
    m.law = law_from_table(
        f,
        fr,
        "friction",
        "law",
        &["preset"],
        registry,
        LawContext {
            preset,
            default_form: Form::Regularized,
        },
    )?;
    // The published form (eq. 4b) slips only forward, `V > 0`: in the DEM,
    // "forward" is the contact's tangent `perp(normal)`, a counter-clockwise
    // turn from the pair's normal, so the law favours one sense of relative
    // rotation and mirror-image contacts get different friction (the
    // double shear's two faces: 0.737 against 3.50). Refused here, not
    // in `floe_dem`: the spring-slider protocols use it as the paper does.
    if let floe_friction::Law::RateState(rs) = &m.law {
        if rs.form == Form::Published {
            let span = fr
                .get("form")
                .or_else(|| fr.get("law"))
                .map_or(0..0, |v| v.span());
            return Err(f.error(
                span,
                "friction.form",
                "`published` (eq. 4b) is for the spring-slider (`floe slider`), not DEM \
                 contacts: its slip rate is positive whatever the force, so a contact slips \
                 only counter-clockwise (along perp(normal)), creeps against a reversed force, \
                 and mirror-image contacts get different friction; use `regularized` \
                 (sign-consistent: V = 2 V* exp(-(mu0 + theta)/A) sinh(mu/A), docs/friction.md)",
            ));
        }
    }
    Ok(m)
}

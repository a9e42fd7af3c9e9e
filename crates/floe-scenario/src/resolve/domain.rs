//! `[domain]`: the rectangle the floes live in and its periodic axes.

use toml::Spanned;

use floe_dem::Vec2;

use super::limits::{at_most, MAX_LENGTH_M};
use crate::domain::Domain;
use crate::error::ScenarioError;
use crate::numbers::short_list;
use crate::source_file::SourceFile;
use crate::spec::RawDomain;

pub(crate) fn resolve_domain(
    f: &SourceFile,
    raw: Option<&Spanned<RawDomain>>,
) -> Result<Domain, ScenarioError> {
    let Some(raw) = raw else {
        return Err(f.error_in_file(
            "missing [domain]: give at least `size_m = [width, height]` in metres",
        ));
    };
    let d = raw.get_ref();
    let min_m = match &d.min_m {
        Some(v) => {
            let p = f.pair(v, "domain.min_m")?;
            at_most(f, v.span(), "domain.min_m", &[p.x, p.y], MAX_LENGTH_M, "m")?;
            p
        }
        None => Vec2::ZERO,
    };
    let Some(size) = &d.size_m else {
        return Err(f.error(
            raw.span(),
            "domain.size_m",
            "missing: give the domain's `size_m = [width, height]` in metres",
        ));
    };
    let size_m = f.pair(size, "domain.size_m")?;
    if !(size_m.x > 0.0 && size_m.y > 0.0) {
        return Err(f.error(
            size.span(),
            "domain.size_m",
            format!(
                "width and height must be > 0, got {}",
                short_list(&[size_m.x, size_m.y])
            ),
        ));
    }
    at_most(
        f,
        size.span(),
        "domain.size_m",
        &[size_m.x, size_m.y, min_m.x + size_m.x, min_m.y + size_m.y],
        MAX_LENGTH_M,
        "m",
    )?;
    let periodic = d.periodic.as_ref().map_or([false; 2], |p| p.get_ref().0);
    Ok(Domain {
        min_m,
        size_m,
        periodic,
    })
}

//! `[floe_stress]`: the floe life cycle's settings.

use floe_dem::pipeline::floe_stress::StressFilter;
use toml::Spanned;

use crate::error::ScenarioError;
use crate::source_file::SourceFile;
use crate::spec::RawFloeStress;

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

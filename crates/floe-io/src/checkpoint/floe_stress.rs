//! Floe stress (from version 8): the filter's time scale and each floe's
//! averaged stress. Only a state with floe stress is written as version 8;
//! older versions, and version 7 written for a state without it, read as
//! none.

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::pipeline::floe_stress::{FloeStress, StressFilter};

/// The time scale, then the stresses (a length, then `[xx, xy, yy]` each).
pub(super) fn write(w: &mut Writer, filter: StressFilter, stress: &[FloeStress]) {
    w.f64(filter.time_scale_s);
    w.len(stress.len());
    for s in stress {
        for &x in s {
            w.f64(x);
        }
    }
}

/// [`write`]'s filter and stresses; none before version 8.
pub(super) fn read(r: &mut Reader) -> ReadResult<(Option<StressFilter>, Vec<FloeStress>)> {
    if r.version < 8 {
        return Ok((None, Vec::new()));
    }
    let time_scale_s = r.f64()?;
    let filter = StressFilter::new(time_scale_s)
        .map_err(|_| format!("a floe stress time scale of {time_scale_s} s"))?;
    let stress = r.vec(24, |r| Ok([r.f64()?, r.f64()?, r.f64()?]))?;
    Ok((Some(filter), stress))
}

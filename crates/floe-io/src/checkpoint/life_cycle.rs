//! The floe life cycle (from version 8): floe stress (the filter's time
//! scale and each floe's averaged stress) and the next id fracture gives.
//! Only a state with floe stress or a next id is written as version 8;
//! older versions, and version 7 written for a state without either, read
//! as none.

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::pipeline::floe_stress::{FloeStress, StressFilter};

/// What the life cycle keeps between steps.
pub(super) struct LifeCycle {
    pub(super) stress_filter: Option<StressFilter>,
    pub(super) floe_stress: Vec<FloeStress>,
    pub(super) next_floe_id: u64,
}

/// A flag (1: floe stress, then the time scale and the stresses, a length
/// then `[xx, xy, yy]` each), then the next floe id.
pub(super) fn write(w: &mut Writer, life: &LifeCycle) {
    match life.stress_filter {
        Some(filter) => {
            w.u8(1);
            w.f64(filter.time_scale_s);
            w.len(life.floe_stress.len());
            for s in &life.floe_stress {
                for &x in s {
                    w.f64(x);
                }
            }
        }
        None => w.u8(0),
    }
    w.u64(life.next_floe_id);
}

/// [`write`]'s life cycle; none before version 8.
pub(super) fn read(r: &mut Reader) -> ReadResult<LifeCycle> {
    let mut life = LifeCycle {
        stress_filter: None,
        floe_stress: Vec::new(),
        next_floe_id: 0,
    };
    if r.version < 8 {
        return Ok(life);
    }
    match r.u8()? {
        0 => {}
        1 => {
            let time_scale_s = r.f64()?;
            life.stress_filter = Some(
                StressFilter::new(time_scale_s)
                    .map_err(|_| format!("a floe stress time scale of {time_scale_s} s"))?,
            );
            life.floe_stress = r.vec(24, |r| Ok([r.f64()?, r.f64()?, r.f64()?]))?;
        }
        flag => return Err(format!("a floe stress flag of {flag}")),
    }
    life.next_floe_id = r.u64()?;
    Ok(life)
}

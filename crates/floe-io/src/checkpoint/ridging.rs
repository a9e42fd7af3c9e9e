//! The ridging ledger (from version 10). Only a state that has ridged is
//! written as version 10; older versions read as a zero ledger.

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::ridging::RidgingLedger;
use floe_dem::Vec2;

/// Every field of the ledger, in declaration order.
pub(super) fn write(w: &mut Writer, ledger: &RidgingLedger) {
    let RidgingLedger {
        events,
        volume_to_floes_m3,
        volume_to_coast_m3,
        momentum_to_coast_n_s,
        angular_momentum_to_coast,
        kinetic_energy_lost_j,
        contact_energy_released_j,
    } = *ledger;
    w.u64(events);
    for x in [
        volume_to_floes_m3,
        volume_to_coast_m3,
        momentum_to_coast_n_s.x,
        momentum_to_coast_n_s.y,
        angular_momentum_to_coast,
        kinetic_energy_lost_j,
        contact_energy_released_j,
    ] {
        w.f64(x);
    }
}

/// [`write`]'s ledger; zero before version 10.
pub(super) fn read(r: &mut Reader) -> ReadResult<RidgingLedger> {
    if r.version < 10 {
        return Ok(RidgingLedger::default());
    }
    Ok(RidgingLedger {
        events: r.u64()?,
        volume_to_floes_m3: r.f64()?,
        volume_to_coast_m3: r.f64()?,
        momentum_to_coast_n_s: Vec2::new(r.f64()?, r.f64()?),
        angular_momentum_to_coast: r.f64()?,
        kinetic_energy_lost_j: r.f64()?,
        contact_energy_released_j: r.f64()?,
    })
}

//! The welding ledger (from version 11). Only a state that has welded is
//! written as version 11; older versions read as a zero ledger.

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::welding::WeldingLedger;

/// Every field of the ledger, in declaration order.
pub(super) fn write(w: &mut Writer, ledger: &WeldingLedger) {
    let WeldingLedger {
        events,
        area_added_m2,
        kinetic_energy_lost_j,
        contact_energy_released_j,
    } = *ledger;
    w.u64(events);
    for x in [
        area_added_m2,
        kinetic_energy_lost_j,
        contact_energy_released_j,
    ] {
        w.f64(x);
    }
}

/// [`write`]'s ledger; zero before version 11.
pub(super) fn read(r: &mut Reader) -> ReadResult<WeldingLedger> {
    if r.version < 11 {
        return Ok(WeldingLedger::default());
    }
    Ok(WeldingLedger {
        events: r.u64()?,
        area_added_m2: r.f64()?,
        kinetic_energy_lost_j: r.f64()?,
        contact_energy_released_j: r.f64()?,
    })
}

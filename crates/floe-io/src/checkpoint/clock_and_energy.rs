//! Time, step count, time step and the energy ledger.

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::energy_ledger::EnergyLedger;

/// The clock: time, steps, time step.
pub(super) fn write_clock(w: &mut Writer, time_s: f64, steps: u64, dt_s: f64) {
    w.f64(time_s);
    w.u64(steps);
    w.f64(dt_s);
}

/// [`write_clock`] as `(time_s, steps, dt_s)`; versions 1 and 2 store no
/// time step: `fallback_dt_s` gives it (the scenario's).
pub(super) fn read_clock(
    r: &mut Reader,
    fallback_dt_s: impl FnOnce() -> Option<f64>,
) -> ReadResult<(f64, u64, f64)> {
    let time_s = r.f64()?;
    let steps = r.u64()?;
    let dt_s = if r.version >= 3 {
        r.f64()?
    } else {
        fallback_dt_s().ok_or_else(|| {
            format!(
                "format version {} does not store the time step, and none was given",
                r.version
            )
        })?
    };
    Ok((time_s, steps, dt_s))
}

/// The ledger's five totals in declaration order.
pub(super) fn write_energy(w: &mut Writer, energy: &EnergyLedger) {
    let EnergyLedger {
        forcing_work_j,
        friction_dissipation_j,
        damping_dissipation_j,
        boundary_work_j,
        released_at_break_j,
    } = *energy;
    for v in [
        forcing_work_j,
        friction_dissipation_j,
        damping_dissipation_j,
        boundary_work_j,
        released_at_break_j,
    ] {
        w.f64(v);
    }
}

/// [`write_energy`].
pub(super) fn read_energy(r: &mut Reader) -> ReadResult<EnergyLedger> {
    Ok(EnergyLedger {
        forcing_work_j: r.f64()?,
        friction_dissipation_j: r.f64()?,
        damping_dissipation_j: r.f64()?,
        boundary_work_j: r.f64()?,
        released_at_break_j: r.f64()?,
    })
}

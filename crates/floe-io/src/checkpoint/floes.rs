//! The floe columns: one vector per column, in declaration order.

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::floes::{FloeColumns, Floes, Motion};

/// Every column of `floes` (a free floe's motion as tag 0, a prescribed
/// one's as tag 1 and its velocity).
pub(super) fn write(w: &mut Writer, floes: &Floes) {
    // Exhaustive destructuring: a column added to the floes fails to
    // compile here instead of being silently left out of checkpoints.
    let FloeColumns {
        id,
        position,
        angle,
        velocity,
        angular_velocity,
        thickness_m,
        mass_kg,
        inertia_kg_m2,
        area_m2,
        radius_m,
        r3_moment_m5,
        motion,
        vertex_start,
        vertices,
    } = floes.columns();
    w.len(id.len());
    id.iter().for_each(|&v| w.u64(v));
    w.v2s(position);
    w.f64s(angle);
    w.v2s(velocity);
    w.f64s(angular_velocity);
    w.f64s(thickness_m);
    w.f64s(mass_kg);
    w.f64s(inertia_kg_m2);
    w.f64s(area_m2);
    w.f64s(radius_m);
    w.f64s(r3_moment_m5);
    w.len(motion.len());
    for m in motion {
        match *m {
            Motion::Free => w.u8(0),
            Motion::Prescribed { velocity } => {
                w.u8(1);
                w.v2(velocity);
            }
        }
    }
    w.len(vertex_start.len());
    vertex_start.iter().for_each(|&v| w.u32(v));
    w.v2s(vertices);
}

/// [`write`]; versions 1 and 2 follow the columns with the count of owned
/// floes, which must be all of them (a subdomain's checkpoint is refused).
pub(super) fn read(r: &mut Reader) -> ReadResult<Floes> {
    let columns = FloeColumns {
        id: r.vec(8, Reader::u64)?,
        position: r.v2s()?,
        angle: r.f64s()?,
        velocity: r.v2s()?,
        angular_velocity: r.f64s()?,
        thickness_m: r.f64s()?,
        mass_kg: r.f64s()?,
        inertia_kg_m2: r.f64s()?,
        area_m2: r.f64s()?,
        radius_m: r.f64s()?,
        r3_moment_m5: r.f64s()?,
        motion: r.vec(1, |r| match r.u8()? {
            0 => Ok(Motion::Free),
            1 => Ok(Motion::Prescribed { velocity: r.v2()? }),
            t => Err(format!("unknown motion tag {t}")),
        })?,
        vertex_start: r.vec(4, Reader::u32)?,
        vertices: r.v2s()?,
    };
    if r.version < 3 {
        let owned = r.u64()?;
        if owned != columns.id.len() as u64 {
            return Err(format!(
                "{owned} owned floes of {}: a subdomain's checkpoint",
                columns.id.len()
            ));
        }
    }
    Floes::from_columns(columns).map_err(|e| e.to_string())
}

//! Bonds (from version 9): floes frozen together and the quiet pairs on
//! their way to a bond, each with every field of its record. Only a state
//! holding bonds is written as version 9; older versions read as none.

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::bonds::Bond;

/// The bonds: a length, then per bond its pair, whether it formed (u8),
/// and its times, geometry, stiffness and last evaluation.
pub(super) fn write(w: &mut Writer, bonds: &[Bond]) {
    w.len(bonds.len());
    for bond in bonds {
        let Bond {
            a,
            b,
            quiet_since_s,
            formed,
            formed_at_s,
            anchor_a,
            anchor_b,
            normal_a,
            rest_angle_rad,
            length_m,
            stiffness_n_per_m,
            point_a,
            point_b,
            force_on_b,
            torque_on_a,
            torque_on_b,
            energy_j,
            damping_power_w,
            tension_n_per_m,
            shear_n_per_m,
        } = *bond;
        w.u32(a);
        w.u32(b);
        w.f64(quiet_since_s);
        w.u8(u8::from(formed));
        w.f64(formed_at_s);
        for v in [anchor_a, anchor_b, normal_a] {
            w.v2(v);
        }
        w.f64(rest_angle_rad);
        w.f64(length_m);
        w.f64(stiffness_n_per_m);
        for v in [point_a, point_b, force_on_b] {
            w.v2(v);
        }
        for x in [
            torque_on_a,
            torque_on_b,
            energy_j,
            damping_power_w,
            tension_n_per_m,
            shear_n_per_m,
        ] {
            w.f64(x);
        }
    }
}

/// [`write`]'s bonds; none before version 9.
pub(super) fn read(r: &mut Reader) -> ReadResult<Vec<Bond>> {
    if r.version < 9 {
        return Ok(Vec::new());
    }
    r.vec(8, |r| {
        Ok(Bond {
            a: r.u32()?,
            b: r.u32()?,
            quiet_since_s: r.f64()?,
            formed: match r.u8()? {
                0 => false,
                1 => true,
                flag => return Err(format!("a bond's formed flag of {flag}")),
            },
            formed_at_s: r.f64()?,
            anchor_a: r.v2()?,
            anchor_b: r.v2()?,
            normal_a: r.v2()?,
            rest_angle_rad: r.f64()?,
            length_m: r.f64()?,
            stiffness_n_per_m: r.f64()?,
            point_a: r.v2()?,
            point_b: r.v2()?,
            force_on_b: r.v2()?,
            torque_on_a: r.f64()?,
            torque_on_b: r.f64()?,
            energy_j: r.f64()?,
            damping_power_w: r.f64()?,
            tension_n_per_m: r.f64()?,
            shear_n_per_m: r.f64()?,
        })
    })
}

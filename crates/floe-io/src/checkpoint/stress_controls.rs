//! Stress-controlled walls (from version 6; older versions read as none).

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::stress_control::{ControlLaw, ServoWall, StressControl};

/// A tag (0 proportional: its gain; 1 servo: mass, stress damping, filter
/// time, speed, filtered stress).
fn write_law(w: &mut Writer, law: &ControlLaw) {
    match *law {
        ControlLaw::Proportional {
            gain_m_per_s_per_n_per_m,
        } => {
            w.u8(0);
            w.f64(gain_m_per_s_per_n_per_m);
        }
        ControlLaw::Servo(ServoWall {
            mass_kg,
            stress_damping_s,
            stress_filter_s,
            speed_m_per_s,
            filtered_stress_n_per_m,
        }) => {
            w.u8(1);
            for x in [
                mass_kg,
                stress_damping_s,
                stress_filter_s,
                speed_m_per_s,
                filtered_stress_n_per_m,
            ] {
                w.f64(x);
            }
        }
    }
}

/// [`write_law`]; version 6 stores no tag, only a proportional gain.
fn read_law(r: &mut Reader) -> ReadResult<ControlLaw> {
    let tag = if r.version >= 7 { r.u8()? } else { 0 };
    match tag {
        0 => Ok(ControlLaw::Proportional {
            gain_m_per_s_per_n_per_m: r.f64()?,
        }),
        1 => {
            let mut x = [0.0; 5];
            for v in &mut x {
                *v = r.f64()?;
            }
            let [mass_kg, stress_damping_s, stress_filter_s, speed_m_per_s, filtered_stress_n_per_m] =
                x;
            Ok(ControlLaw::Servo(ServoWall {
                mass_kg,
                stress_damping_s,
                stress_filter_s,
                speed_m_per_s,
                filtered_stress_n_per_m,
            }))
        }
        t => Err(format!("a stress-controlled wall of unknown law {t}")),
    }
}

/// Per wall its pieces' ids, inward normal, length, target stress and
/// control law.
pub(super) fn write(w: &mut Writer, stress_controls: &[StressControl]) {
    w.len(stress_controls.len());
    for c in stress_controls {
        let StressControl {
            floe_ids,
            inward_normal,
            length_m,
            target_stress_n_per_m,
            law,
        } = c;
        w.len(floe_ids.len());
        floe_ids.iter().for_each(|&id| w.u64(id));
        w.v2(*inward_normal);
        w.f64(*length_m);
        w.f64(*target_stress_n_per_m);
        write_law(w, law);
    }
}

/// [`write`]; none before version 6.
pub(super) fn read(r: &mut Reader) -> ReadResult<Vec<StressControl>> {
    if r.version < 6 {
        return Ok(Vec::new());
    }
    r.vec(48, |r| {
        let ids = r.vec(8, |r| r.u64())?;
        let (normal, length) = (r.v2()?, r.f64()?);
        let target = r.f64()?;
        let law = read_law(r)?;
        StressControl::new(ids, normal, length, target, law)
            .map_err(|e| format!("a stress-controlled wall: {e}"))
    })
}

//! Touching and recently broken contacts with their friction states.
//!
//! A friction state is its spring force and the law's state slots; each
//! list of contacts is preceded by the number of slots (u32, the law's
//! `FrictionLaw::state_slots`), so a law with other state needs no new
//! format. Versions 1 and 2 store no slot count: theirs are the
//! rate-and-state law's `theta` and the solver's root, and from version 2
//! its trend (version 1 reads with zero trends).

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::contacts::{BrokenContact, ContactRecord};
use floe_friction::{ContactState, LAW_STATE_SLOTS};

/// The force, then the writer's number of law-state slots.
fn write_friction(w: &mut Writer, s: &ContactState) {
    let ContactState {
        tangential_force_n,
        law_state,
    } = *s;
    w.f64(tangential_force_n);
    law_state[..w.law_state_slots]
        .iter()
        .for_each(|&x| w.f64(x));
}

/// A friction state of `slots` law-state slots (the rest zero).
fn read_friction(r: &mut Reader, slots: usize) -> ReadResult<ContactState> {
    let tangential_force_n = r.f64()?;
    let mut law_state = [0.0; LAW_STATE_SLOTS];
    for x in &mut law_state[..slots] {
        *x = r.f64()?;
    }
    Ok(ContactState {
        tangential_force_n,
        law_state,
    })
}

/// The slot count that precedes a list of friction states.
fn write_slots(w: &mut Writer) {
    w.u32(w.law_state_slots as u32);
}

/// [`write_slots`]: stored from version 3, implied before.
fn read_slots(r: &mut Reader) -> ReadResult<usize> {
    match r.version {
        1 => Ok(2),
        2 => Ok(3),
        _ => {
            let n = r.u32()? as usize;
            if n > LAW_STATE_SLOTS {
                return Err(format!(
                    "{n} law state slots per contact; this floe holds at most {LAW_STATE_SLOTS}"
                ));
            }
            Ok(n)
        }
    }
}

/// The slot count, then per contact its pair, image offset, friction
/// state, age and the geometry and forces of its last evaluation.
pub(super) fn write_touching(w: &mut Writer, contacts: &[ContactRecord]) {
    write_slots(w);
    w.len(contacts.len());
    for c in contacts {
        let ContactRecord {
            a,
            b,
            image_offset,
            friction,
            age_steps,
            overlap_m2,
            point,
            normal,
            length_m,
            normal_force_n,
            slip_rate_m_per_s,
            friction_power_w,
            damping_power_w,
            elastic_force_n,
            normal_energy_j,
            tangential_energy_j,
        } = c;
        w.u32(*a);
        w.u32(*b);
        w.v2(*image_offset);
        write_friction(w, friction);
        w.u64(*age_steps);
        for v in [
            *overlap_m2,
            point.x,
            point.y,
            normal.x,
            normal.y,
            *length_m,
            *normal_force_n,
            *slip_rate_m_per_s,
            *friction_power_w,
            *damping_power_w,
            *elastic_force_n,
            *normal_energy_j,
            *tangential_energy_j,
        ] {
            w.f64(v);
        }
    }
}

/// [`write_touching`]. With `law_state_slots`, contacts of version 3 on
/// that hold another number of slots are refused (written under another
/// law).
pub(super) fn read_touching(
    r: &mut Reader,
    law_state_slots: Option<usize>,
) -> ReadResult<Vec<ContactRecord>> {
    let slots = read_slots(r)?;
    if let Some(expected) = law_state_slots.filter(|_| r.version >= 3) {
        if slots != expected {
            return Err(format!(
                "its contacts hold {slots} law-state slots each, the friction law declares \
                 {expected}: it was written under another law"
            ));
        }
    }
    r.vec(8, |r| {
        Ok(ContactRecord {
            a: r.u32()?,
            b: r.u32()?,
            image_offset: r.v2()?,
            friction: read_friction(r, slots)?,
            age_steps: r.u64()?,
            overlap_m2: r.f64()?,
            point: r.v2()?,
            normal: r.v2()?,
            length_m: r.f64()?,
            normal_force_n: r.f64()?,
            slip_rate_m_per_s: r.f64()?,
            friction_power_w: r.f64()?,
            damping_power_w: r.f64()?,
            elastic_force_n: r.f64()?,
            normal_energy_j: r.f64()?,
            tangential_energy_j: r.f64()?,
        })
    })
}

/// The slot count, then per broken contact its pair, friction state and
/// the time it broke.
pub(super) fn write_broken(w: &mut Writer, broken: &[BrokenContact]) {
    write_slots(w);
    w.len(broken.len());
    for c in broken {
        let BrokenContact {
            a,
            b,
            friction,
            broke_at_s,
        } = c;
        w.u32(*a);
        w.u32(*b);
        write_friction(w, friction);
        w.f64(*broke_at_s);
    }
}

/// [`write_broken`].
pub(super) fn read_broken(r: &mut Reader) -> ReadResult<Vec<BrokenContact>> {
    let slots = read_slots(r)?;
    r.vec(8, |r| {
        Ok(BrokenContact {
            a: r.u32()?,
            b: r.u32()?,
            friction: read_friction(r, slots)?,
            broke_at_s: r.f64()?,
        })
    })
}

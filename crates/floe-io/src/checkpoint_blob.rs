//! A [`WorldState`] as a self-checking byte string.
//!
//! Layout (all integers little-endian, every `f64` as its IEEE bits, so the
//! state round-trips bitwise):
//!
//! | bytes | content |
//! | --- | --- |
//! | 8 | magic `FLOECKPT` |
//! | 4 | format version ([`FORMAT_VERSION`]) |
//! | 4 | zero |
//! | 8 | payload length |
//! | 8 | FNV-1a 64 checksum of the payload |
//! | ... | payload |
//!
//! The payload holds the output counts at the checkpoint (snapshots,
//! contact rows, samples per observable), then every field of the state in
//! declaration order; a vector is its length (u64) then its elements.
//! A contact's friction state is its spring force and the law's state
//! slots: each list of contacts is preceded by the number of slots (u32,
//! the law's `FrictionLaw::state_slots`), so a law with other state needs
//! no new format. Bytes after the payload are ignored (a slot is reused
//! for smaller states without shrinking).
//!
//! Version 7 (written now) stores a stress-controlled wall's law as a tag
//! (0 proportional: its gain; 1 servo: mass, stress damping, filter time,
//! speed, filtered stress) where version 6, which appended the stress-controlled walls
//! (their pieces' ids, inward normal, length, target stress, gain) to
//! version 5, stored the proportional gain alone. Version 5 appended the
//! load points (floe id, stiffness, anchor, segments) to
//! version 4, which appended the motion schedules (per
//! scheduled floe its id, then its segments: duration, start and end
//! velocity, start and end angular velocity). Version 3 added the time step
//! and the slot counts, and dropped the count of owned floes; versions 3
//! and 4 read as states without what they lack. Versions 1 and 2 are still read: their
//! friction state is the force then three slots (`theta`, the solver's
//! root, and from version 2 its trend; version 1 resumes with zero trends),
//! and their time step comes from the caller (the scenario).

use floe_dem::contacts::{BrokenContact, ContactRecord};
use floe_dem::energy_ledger::EnergyLedger;
use floe_dem::floes::{FloeColumns, Floes, Motion};
use floe_dem::load_point::LoadPoint;
use floe_dem::motion_schedule::{MotionSchedule, MotionSegment, ScheduledMotion};
use floe_dem::state::WorldState;
use floe_dem::stress_control::{ControlLaw, ServoWall, StressControl};
use floe_dem::Vec2;
use floe_friction::{ContactState, LAW_STATE_SLOTS};

/// First bytes of every checkpoint.
pub const MAGIC: &[u8; 8] = b"FLOECKPT";
/// Version of the encoding written.
pub const FORMAT_VERSION: u32 = 7;
/// The oldest version read; older and newer ones are refused.
pub const OLDEST_READABLE_VERSION: u32 = 1;
/// Bytes before the payload.
pub const HEADER_LEN: usize = 32;

/// How much output had been written when a checkpoint was taken: what a
/// resume truncates the file back to.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct OutputCounts {
    /// Snapshots written.
    pub snapshots: u64,
    /// Rows of the contact datasets (including the padding to chunk starts).
    pub contact_rows: u64,
    /// Samples written, per observable.
    pub observables: Vec<(String, u64)>,
}

/// FNV-1a, 64 bit.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The payload being written, the format version it follows and the law
/// state slots written per friction state.
struct Enc(Vec<u8>, u32, usize);

impl Enc {
    fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    fn v2(&mut self, v: Vec2) {
        self.f64(v.x);
        self.f64(v.y);
    }
    fn len(&mut self, n: usize) {
        self.u64(n as u64);
    }
    /// Version 6: the proportional gain alone; 7: a tag (0 proportional,
    /// 1 servo) and the law's parameters and state.
    fn control_law(&mut self, law: &ControlLaw, version: u32) {
        match *law {
            ControlLaw::Proportional {
                gain_m_per_s_per_n_per_m,
            } => {
                if version >= 7 {
                    self.u8(0);
                }
                self.f64(gain_m_per_s_per_n_per_m);
            }
            ControlLaw::Servo(ServoWall {
                mass_kg,
                stress_damping_s,
                stress_filter_s,
                speed_m_per_s,
                filtered_stress_n_per_m,
            }) => {
                assert!(version >= 7, "a servo wall needs format 7");
                self.u8(1);
                for x in [
                    mass_kg,
                    stress_damping_s,
                    stress_filter_s,
                    speed_m_per_s,
                    filtered_stress_n_per_m,
                ] {
                    self.f64(x);
                }
            }
        }
    }
    fn f64s(&mut self, v: &[f64]) {
        self.len(v.len());
        v.iter().for_each(|&x| self.f64(x));
    }
    fn v2s(&mut self, v: &[Vec2]) {
        self.len(v.len());
        v.iter().for_each(|&x| self.v2(x));
    }
    fn friction(&mut self, s: &ContactState) {
        let ContactState {
            tangential_force_n,
            law_state,
        } = *s;
        self.f64(tangential_force_n);
        let slots = match self.1 {
            1 => 2,
            2 => 3,
            _ => self.2,
        };
        law_state[..slots].iter().for_each(|&x| self.f64(x));
    }
    /// The slot count that precedes a list of friction states (version 3).
    fn slots(&mut self) {
        if self.1 >= 3 {
            self.u32(self.2 as u32);
        }
    }
    fn segments(&mut self, segments: &[MotionSegment]) {
        self.len(segments.len());
        for g in segments {
            self.f64(g.duration_s);
            self.v2(g.velocity_start);
            self.v2(g.velocity_end);
            self.f64(g.angular_velocity_start);
            self.f64(g.angular_velocity_end);
        }
    }
    fn str(&mut self, s: &str) {
        self.len(s.len());
        self.0.extend_from_slice(s.as_bytes());
    }
}

/// The checkpoint bytes of `state` with the output `counts`, each friction
/// state with `law_state_slots` slots of law state (the law's
/// `FrictionLaw::state_slots`, at most `LAW_STATE_SLOTS`).
pub fn encode(state: &WorldState, counts: &OutputCounts, law_state_slots: usize) -> Vec<u8> {
    encode_version(state, counts, law_state_slots, FORMAT_VERSION)
}

/// [`encode`] in the layout of `version` (older ones for the tests of
/// reading them).
pub fn encode_version(
    state: &WorldState,
    counts: &OutputCounts,
    law_state_slots: usize,
    version: u32,
) -> Vec<u8> {
    assert!(
        law_state_slots <= LAW_STATE_SLOTS,
        "at most {LAW_STATE_SLOTS} slots"
    );
    let mut e = Enc(
        Vec::with_capacity(estimate_len(state)),
        version,
        law_state_slots,
    );
    e.u64(counts.snapshots);
    e.u64(counts.contact_rows);
    e.len(counts.observables.len());
    for (name, n) in &counts.observables {
        e.str(name);
        e.u64(*n);
    }
    // Exhaustive destructuring: a field added to the engine's state fails
    // to compile here instead of being silently left out of checkpoints.
    let WorldState {
        floes,
        contacts,
        broken,
        time_s,
        steps,
        dt_s,
        energy,
        force,
        torque,
        external_force,
        external_torque,
        schedules,
        load_points,
        stress_controls,
    } = state;
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
    e.len(id.len());
    id.iter().for_each(|&v| e.u64(v));
    e.v2s(position);
    e.f64s(angle);
    e.v2s(velocity);
    e.f64s(angular_velocity);
    e.f64s(thickness_m);
    e.f64s(mass_kg);
    e.f64s(inertia_kg_m2);
    e.f64s(area_m2);
    e.f64s(radius_m);
    e.f64s(r3_moment_m5);
    e.len(motion.len());
    for m in motion {
        match *m {
            Motion::Free => e.u8(0),
            Motion::Prescribed { velocity } => {
                e.u8(1);
                e.v2(velocity);
            }
        }
    }
    e.len(vertex_start.len());
    vertex_start.iter().for_each(|&v| e.u32(v));
    e.v2s(vertices);
    if version < 3 {
        e.len(id.len()); // every floe owned
    }
    e.slots();
    e.len(contacts.len());
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
        e.u32(*a);
        e.u32(*b);
        e.v2(*image_offset);
        e.friction(friction);
        e.u64(*age_steps);
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
            e.f64(v);
        }
    }
    e.slots();
    e.len(broken.len());
    for c in broken {
        let BrokenContact {
            a,
            b,
            friction,
            broke_at_s,
        } = c;
        e.u32(*a);
        e.u32(*b);
        e.friction(friction);
        e.f64(*broke_at_s);
    }
    e.f64(*time_s);
    e.u64(*steps);
    if version >= 3 {
        e.f64(*dt_s);
    }
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
        e.f64(v);
    }
    e.v2s(force);
    e.f64s(torque);
    e.v2s(external_force);
    e.f64s(external_torque);
    if version >= 4 {
        e.len(schedules.len());
        for s in schedules {
            e.u64(s.floe_id);
            e.segments(s.schedule.segments());
        }
    }
    if version >= 5 {
        e.len(load_points.len());
        for l in load_points {
            e.u64(l.floe_id);
            e.f64(l.stiffness_n_per_m);
            e.v2(l.anchor);
            e.segments(l.schedule.segments());
        }
    }
    if version >= 6 {
        e.len(stress_controls.len());
        for c in stress_controls {
            let StressControl {
                floe_ids,
                inward_normal,
                length_m,
                target_stress_n_per_m,
                law,
            } = c;
            e.len(floe_ids.len());
            floe_ids.iter().for_each(|&id| e.u64(id));
            e.v2(*inward_normal);
            e.f64(*length_m);
            e.f64(*target_stress_n_per_m);
            e.control_law(law, version);
        }
    }

    let payload = e.0;
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&version.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&fnv1a64(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

/// A generous guess of the encoded size, for reserving slot space.
pub fn estimate_len(state: &WorldState) -> usize {
    HEADER_LEN
        + 1024
        + state.floes.len() * 200
        + state.floes.vertices.len() * 16
        + state.contacts.len() * 176
        + state.broken.len() * 48
}

struct Dec<'a> {
    buf: &'a [u8],
    pos: usize,
    /// Format version of the bytes.
    version: u32,
}

type DecResult<T> = Result<T, String>;

impl<'a> Dec<'a> {
    fn take(&mut self, n: usize) -> DecResult<&'a [u8]> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.buf.len())
            .ok_or_else(|| format!("truncated at byte {} (wanted {n} more)", self.pos))?;
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn u8(&mut self) -> DecResult<u8> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> DecResult<u32> {
        let mut b = [0; 4];
        b.copy_from_slice(self.take(4)?);
        Ok(u32::from_le_bytes(b))
    }
    fn u64(&mut self) -> DecResult<u64> {
        let mut b = [0; 8];
        b.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(b))
    }
    fn f64(&mut self) -> DecResult<f64> {
        Ok(f64::from_bits(self.u64()?))
    }
    /// [`Enc::control_law`].
    fn control_law(&mut self) -> DecResult<ControlLaw> {
        let tag = if self.version >= 7 { self.u8()? } else { 0 };
        match tag {
            0 => Ok(ControlLaw::Proportional {
                gain_m_per_s_per_n_per_m: self.f64()?,
            }),
            1 => {
                let mut x = [0.0; 5];
                for v in &mut x {
                    *v = self.f64()?;
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
    fn v2(&mut self) -> DecResult<Vec2> {
        Ok(Vec2::new(self.f64()?, self.f64()?))
    }
    /// A length prefix, checked against the bytes left (each element is at
    /// least `min_elem` bytes), so a corrupt length cannot allocate wildly.
    fn len(&mut self, min_elem: usize) -> DecResult<usize> {
        let n = self.u64()?;
        let left = (self.buf.len() - self.pos) as u64;
        if n.saturating_mul(min_elem as u64) > left {
            return Err(format!(
                "length {n} at byte {} exceeds the {left} bytes left",
                self.pos - 8
            ));
        }
        Ok(n as usize)
    }
    fn vec<T>(
        &mut self,
        min_elem: usize,
        mut f: impl FnMut(&mut Self) -> DecResult<T>,
    ) -> DecResult<Vec<T>> {
        let n = self.len(min_elem)?;
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            v.push(f(self)?);
        }
        Ok(v)
    }
    fn f64s(&mut self) -> DecResult<Vec<f64>> {
        self.vec(8, Self::f64)
    }
    fn v2s(&mut self) -> DecResult<Vec<Vec2>> {
        self.vec(16, Self::v2)
    }
    /// A friction state of `slots` law-state slots (the rest zero).
    fn friction(&mut self, slots: usize) -> DecResult<ContactState> {
        let tangential_force_n = self.f64()?;
        let mut law_state = [0.0; LAW_STATE_SLOTS];
        for x in &mut law_state[..slots] {
            *x = self.f64()?;
        }
        Ok(ContactState {
            tangential_force_n,
            law_state,
        })
    }
    /// The slot count before a list of friction states: stored from
    /// version 3, implied before.
    fn slots(&mut self) -> DecResult<usize> {
        match self.version {
            1 => Ok(2),
            2 => Ok(3),
            _ => {
                let n = self.u32()? as usize;
                if n > LAW_STATE_SLOTS {
                    return Err(format!(
                        "{n} law state slots per contact; this floe holds at most {LAW_STATE_SLOTS}"
                    ));
                }
                Ok(n)
            }
        }
    }
    fn schedule(&mut self, floe_id: u64) -> DecResult<MotionSchedule> {
        let segments = self.vec(56, |d| {
            Ok(MotionSegment {
                duration_s: d.f64()?,
                velocity_start: d.v2()?,
                velocity_end: d.v2()?,
                angular_velocity_start: d.f64()?,
                angular_velocity_end: d.f64()?,
            })
        })?;
        MotionSchedule::new(segments).map_err(|e| format!("the schedule of floe {floe_id}: {e}"))
    }
    fn str(&mut self) -> DecResult<String> {
        let n = self.len(1)?;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|_| "a series name is not UTF-8".into())
    }
}

/// Checks the header and checksum only; returns the payload.
pub fn verify(bytes: &[u8]) -> DecResult<&[u8]> {
    if bytes.len() < HEADER_LEN {
        return Err(format!("{} bytes, shorter than the header", bytes.len()));
    }
    if &bytes[..8] != MAGIC {
        return Err("bad magic (not a floe checkpoint)".into());
    }
    let word = |at: usize| {
        let mut b = [0; 8];
        b.copy_from_slice(&bytes[at..at + 8]);
        u64::from_le_bytes(b)
    };
    let version = version_of(bytes);
    if !(OLDEST_READABLE_VERSION..=FORMAT_VERSION).contains(&version) {
        return Err(format!(
            "format version {version}; this floe reads versions {OLDEST_READABLE_VERSION} to {FORMAT_VERSION}"
        ));
    }
    let len = word(16);
    let available = (bytes.len() - HEADER_LEN) as u64;
    if len > available {
        return Err(format!(
            "payload of {len} bytes but only {available} stored"
        ));
    }
    let payload = &bytes[HEADER_LEN..HEADER_LEN + len as usize];
    let (stored, actual) = (word(24), fnv1a64(payload));
    if stored != actual {
        return Err(format!(
            "checksum mismatch (stored {stored:016x}, computed {actual:016x})"
        ));
    }
    Ok(payload)
}

/// The format version in a header that [`verify`] accepted.
fn version_of(bytes: &[u8]) -> u32 {
    u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]])
}

/// The state and counts of checkpoint `bytes`, after checking the header,
/// the checksum and the state's consistency. Versions before 3 do not
/// store the time step: `fallback_dt_s` gives it (the scenario's), and is
/// not called for version 3. With `law_state_slots`, a version-3
/// checkpoint whose friction states hold another number of slots is
/// refused (it was written under another law).
pub fn decode(
    bytes: &[u8],
    fallback_dt_s: impl FnOnce() -> Option<f64>,
    law_state_slots: Option<usize>,
) -> DecResult<(WorldState, OutputCounts)> {
    let payload = verify(bytes)?;
    let d = &mut Dec {
        buf: payload,
        pos: 0,
        version: version_of(bytes),
    };
    let snapshots = d.u64()?;
    let contact_rows = d.u64()?;
    let observables = d.vec(16, |d| Ok((d.str()?, d.u64()?)))?;
    let counts = OutputCounts {
        snapshots,
        contact_rows,
        observables,
    };
    let columns = FloeColumns {
        id: d.vec(8, Dec::u64)?,
        position: d.v2s()?,
        angle: d.f64s()?,
        velocity: d.v2s()?,
        angular_velocity: d.f64s()?,
        thickness_m: d.f64s()?,
        mass_kg: d.f64s()?,
        inertia_kg_m2: d.f64s()?,
        area_m2: d.f64s()?,
        radius_m: d.f64s()?,
        r3_moment_m5: d.f64s()?,
        motion: d.vec(1, |d| match d.u8()? {
            0 => Ok(Motion::Free),
            1 => Ok(Motion::Prescribed { velocity: d.v2()? }),
            t => Err(format!("unknown motion tag {t}")),
        })?,
        vertex_start: d.vec(4, Dec::u32)?,
        vertices: d.v2s()?,
    };
    if d.version < 3 {
        let owned = d.u64()?;
        if owned != columns.id.len() as u64 {
            return Err(format!(
                "{owned} owned floes of {}: a subdomain's checkpoint",
                columns.id.len()
            ));
        }
    }
    let floes = Floes::from_columns(columns).map_err(|e| e.to_string())?;
    let slots = d.slots()?;
    if let Some(expected) = law_state_slots.filter(|_| d.version >= 3) {
        if slots != expected {
            return Err(format!(
                "its contacts hold {slots} law-state slots each, the friction law declares \
                 {expected}: it was written under another law"
            ));
        }
    }
    let contacts = d.vec(8, |d| {
        Ok(ContactRecord {
            a: d.u32()?,
            b: d.u32()?,
            image_offset: d.v2()?,
            friction: d.friction(slots)?,
            age_steps: d.u64()?,
            overlap_m2: d.f64()?,
            point: d.v2()?,
            normal: d.v2()?,
            length_m: d.f64()?,
            normal_force_n: d.f64()?,
            slip_rate_m_per_s: d.f64()?,
            friction_power_w: d.f64()?,
            damping_power_w: d.f64()?,
            elastic_force_n: d.f64()?,
            normal_energy_j: d.f64()?,
            tangential_energy_j: d.f64()?,
        })
    })?;
    let slots = d.slots()?;
    let broken = d.vec(8, |d| {
        Ok(BrokenContact {
            a: d.u32()?,
            b: d.u32()?,
            friction: d.friction(slots)?,
            broke_at_s: d.f64()?,
        })
    })?;
    let time_s = d.f64()?;
    let steps = d.u64()?;
    let dt_s = if d.version >= 3 {
        d.f64()?
    } else {
        fallback_dt_s().ok_or_else(|| {
            format!(
                "format version {} does not store the time step, and none was given",
                d.version
            )
        })?
    };
    let energy = EnergyLedger {
        forcing_work_j: d.f64()?,
        friction_dissipation_j: d.f64()?,
        damping_dissipation_j: d.f64()?,
        boundary_work_j: d.f64()?,
        released_at_break_j: d.f64()?,
    };
    let state = WorldState {
        floes,
        contacts,
        broken,
        time_s,
        steps,
        dt_s,
        energy,
        force: d.v2s()?,
        torque: d.f64s()?,
        external_force: d.v2s()?,
        external_torque: d.f64s()?,
        schedules: if d.version >= 4 {
            d.vec(16, |d| {
                let floe_id = d.u64()?;
                let schedule = d.schedule(floe_id)?;
                Ok(ScheduledMotion { floe_id, schedule })
            })?
        } else {
            Vec::new()
        },
        load_points: if d.version >= 5 {
            d.vec(40, |d| {
                let floe_id = d.u64()?;
                let (k, anchor) = (d.f64()?, d.v2()?);
                let schedule = d.schedule(floe_id)?;
                LoadPoint::new(floe_id, k, anchor, schedule)
                    .map_err(|e| format!("the load point of floe {floe_id}: {e}"))
            })?
        } else {
            Vec::new()
        },
        stress_controls: if d.version >= 6 {
            d.vec(48, |d| {
                let ids = d.vec(8, |d| d.u64())?;
                let (normal, length) = (d.v2()?, d.f64()?);
                let target = d.f64()?;
                let law = d.control_law()?;
                StressControl::new(ids, normal, length, target, law)
                    .map_err(|e| format!("a stress-controlled wall: {e}"))
            })?
        } else {
            Vec::new()
        },
    };
    if d.pos != payload.len() {
        return Err(format!(
            "{} unread bytes after the state",
            payload.len() - d.pos
        ));
    }
    state.validate().map_err(|e| e.to_string())?;
    Ok((state, counts))
}

#[cfg(test)]
mod tests {
    use super::*;
    use floe_dem::contact_model::ContactModel;
    use floe_dem::forcing::NoForcing;
    use floe_dem::periodicity::Periodicity;
    use floe_dem::world::{stable_time_step, World};
    use floe_friction::rate_state::SOLVER_TREND;
    use floe_friction::{Amontons, FrictionLaw, Law};

    /// A 4 x 4 grid of squares pressed into each other and let go, a few
    /// steps in: its contacts slip at changing rates, so their friction
    /// states carry non-zero trends.
    fn springing_pack(model: ContactModel) -> WorldState {
        let polys: Vec<Vec<Vec2>> = (0..16)
            .map(|k| {
                let c = Vec2::new(
                    (k % 4) as f64 * 98.0,
                    (k / 4) as f64 * 98.0 + 0.7 * (k % 4) as f64,
                );
                [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(x, y)| c + 50.0 * Vec2::new(x, y))
                    .to_vec()
            })
            .collect();
        let floes = Floes::from_polygons(&polys, &[1.0; 16], 917.0).unwrap();
        let dt = 0.5 * stable_time_step(&floes, &model).0;
        let mut world = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
        for _ in 0..3 {
            world.step();
        }
        world.state().clone()
    }

    /// Checkpoints of versions 1 and 2 (the rate-and-state law's three
    /// slots, no time step) are read with the time step given; version 1
    /// with zero trends. Without a time step they are refused.
    #[test]
    fn checkpoints_of_versions_1_and_2_are_read_with_the_given_time_step() {
        let state = springing_pack(ContactModel::default());
        let trends = state
            .contacts
            .iter()
            .filter(|c| c.friction.law_state[SOLVER_TREND] != 0.0)
            .count();
        assert!(trends > 0, "no contact with a trend to lose");
        let counts = OutputCounts::default();
        let [v1, v2, v3] = [1, 2, 3].map(|v| encode_version(&state, &counts, 3, v));
        // Version 1 is version 2 without the trend's 8 bytes per friction
        // state; version 3 adds the time step and two slot counts, and drops
        // the owned-floe count.
        let frictions = state.contacts.len() + state.broken.len();
        assert_eq!(v2.len() - v1.len(), 8 * frictions);
        let (dt, slot_counts, owned) = (8, 2 * 4, 8);
        assert_eq!(v3.len(), v2.len() + dt + slot_counts - owned);
        let mut expected = state.clone();
        expected
            .contacts
            .iter_mut()
            .for_each(|c| c.friction.law_state[SOLVER_TREND] = 0.0);
        expected
            .broken
            .iter_mut()
            .for_each(|c| c.friction.law_state[SOLVER_TREND] = 0.0);
        let dt = || Some(state.dt_s);
        let (back, _) = decode(&v1, dt, None).unwrap();
        assert_eq!(format!("{back:?}"), format!("{expected:?}"));
        for old in [&v1, &v2] {
            let e = decode(old, || None, None).expect_err("no time step");
            assert!(e.contains("does not store the time step"), "{e}");
        }
        let (back, _) = decode(&v2, dt, None).unwrap();
        assert_eq!(format!("{back:?}"), format!("{state:?}"));
        let (back, _) = decode(&v3, || panic!("version 3 stores dt"), Some(3)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{state:?}"));
        // A version from the future is refused, by name.
        let mut future = v3.clone();
        future[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
        let e = decode(&future, dt, None).expect_err("a future version");
        assert!(
            e.contains(&format!("format version {}", FORMAT_VERSION + 1)),
            "{e}"
        );
    }

    /// Version 7 keeps the motion schedules, load points and stress
    /// controls (a servo wall's state too) bitwise; version 6 reads a
    /// proportional wall; versions 5, 4 and 3 still read, without what they
    /// lack.
    #[test]
    fn boundaries_round_trip_and_older_versions_read_without_them() {
        use floe_dem::motion_schedule::{MotionSchedule, MotionSegment};
        let model = ContactModel::default();
        let state = springing_pack(model.clone());
        let mut world =
            World::resume(state, model.clone(), NoForcing, Periodicity::default()).unwrap();
        let id = world.floes().id[0];
        let v = Vec2::new(0.1, -0.3);
        world
            .set_motion(id, Motion::Prescribed { velocity: v })
            .unwrap();
        let schedule = MotionSchedule::new(vec![
            MotionSegment::ramp(0.7, v, Vec2::ZERO),
            MotionSegment {
                duration_s: 1.3,
                velocity_start: Vec2::new(-0.2, 0.1),
                velocity_end: Vec2::new(1.0 / 3.0, 0.0),
                angular_velocity_start: 1e-3,
                angular_velocity_end: -2e-3,
            },
        ])
        .unwrap();
        world.set_schedule(id, schedule.clone()).unwrap();
        let driven = world.floes().id[5];
        let anchor = world.floes().position[5] + Vec2::new(0.25, -1.0 / 3.0);
        world
            .set_load_point(LoadPoint::new(driven, 2e6, anchor, schedule).unwrap())
            .unwrap();
        let wall = world.floes().id[9];
        world
            .set_motion(
                wall,
                Motion::Prescribed {
                    velocity: Vec2::ZERO,
                },
            )
            .unwrap();
        let normal = Vec2::new(0.6, 0.8);
        let servo = ControlLaw::Servo(ServoWall::new(3e4, 7.0, 2.0).unwrap());
        let control = StressControl::new(vec![wall], normal, 98.0, 1e3 / 3.0, servo).unwrap();
        world.add_stress_control(control).unwrap();
        for _ in 0..3 {
            world.step();
        }
        let state = world.state().clone();
        assert_eq!(
            (
                state.schedules.len(),
                state.load_points.len(),
                state.stress_controls.len()
            ),
            (1, 1, 1)
        );
        let counts = OutputCounts::default();
        let (back, _) = decode(&encode(&state, &counts, 3), || None, Some(3)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{state:?}"));
        let ControlLaw::Servo(moved) = state.stress_controls[0].law else {
            panic!("a servo wall")
        };
        assert!(
            moved.speed_m_per_s != 0.0,
            "the servo's state is not trivial"
        );
        // Version 6: a proportional wall, without the law's tag.
        let mut proportional = state.clone();
        proportional.stress_controls[0].law = ControlLaw::Proportional {
            gain_m_per_s_per_n_per_m: 1e-7,
        };
        let v6 = encode_version(&proportional, &counts, 3, 6);
        let v7 = encode_version(&proportional, &counts, 3, 7);
        assert_eq!(v7.len(), v6.len() + 1);
        let (back, _) = decode(&v6, || None, Some(3)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{proportional:?}"));
        // Version 5: no stress controls; 4: nor load points; 3: nor
        // schedules.
        let mut without = state.clone();
        without.stress_controls.clear();
        let v5 = encode_version(&state, &counts, 3, 5);
        let (back, _) = decode(&v5, || None, Some(3)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{without:?}"));
        without.load_points.clear();
        let v4 = encode_version(&state, &counts, 3, 4);
        let (back, _) = decode(&v4, || None, Some(3)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{without:?}"));
        without.schedules.clear();
        let v3 = encode_version(&state, &counts, 3, 3);
        let (back, _) = decode(&v3, || None, Some(3)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{without:?}"));
    }

    /// Each law's friction states take its own number of slots: Amontons
    /// none, 8 bytes less per slot and contact than the rate-and-state law.
    #[test]
    fn a_law_stores_the_slots_it_declares() {
        let law = Law::Amontons(Amontons { mu: 0.6 });
        let slots = law.state_slots();
        assert_eq!(slots, 0);
        let state = springing_pack(ContactModel::default().with_law(law));
        let counts = OutputCounts::default();
        let (none, three) = (encode(&state, &counts, slots), encode(&state, &counts, 3));
        let frictions = state.contacts.len() + state.broken.len();
        assert!(frictions > 0);
        assert_eq!(three.len() - none.len(), 3 * 8 * frictions);
        let (back, _) = decode(&none, || None, Some(0)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{state:?}"));
        // Read for a law of another slot count: refused.
        let e = decode(&three, || None, Some(0)).expect_err("3 slots for a 0-slot law");
        assert!(e.contains("another law"), "{e}");
        // More slots than a contact state holds is refused.
        let mut bad = encode(&state, &counts, 0);
        let at = bad.len() - payload_tail(&state);
        bad[at..at + 4].copy_from_slice(&((LAW_STATE_SLOTS + 1) as u32).to_le_bytes());
        let payload = bad[HEADER_LEN..].to_vec();
        bad[24..32].copy_from_slice(&fnv1a64(&payload).to_le_bytes());
        let e = decode(&bad, || None, None).expect_err("too many slots");
        assert!(e.contains("law state slots"), "{e}");
    }

    /// Bytes from the slot count before the contacts to the end of the
    /// payload, for a state whose friction states have no slots.
    fn payload_tail(state: &WorldState) -> usize {
        let n = state.floes.len();
        let contact = 4 + 4 + 16 + 8 + 8 + 13 * 8;
        4 + 8
            + state.contacts.len() * contact
            + 4
            + 8
            + state.broken.len() * (4 + 4 + 8 + 8)
            + 8
            + 8
            + 8
            + 5 * 8
            + 4 * 8
            + n * (16 + 8 + 16 + 8)
            + 8 // the schedule count (none here)
            + 8 // the load-point count (none here)
            + 8 // the stress-control count (none here)
    }
}

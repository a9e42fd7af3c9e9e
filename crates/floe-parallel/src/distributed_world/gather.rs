//! The whole world on process 0, for output, a blow-up or a forcing
//! failure: a fixed row per floe (process 0 keeps what never changes) and
//! the contacts each process counts.

use super::*;

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// The whole world's state on process 0 (`None` elsewhere): every
    /// process sends its owned floes' motion and forces (a fixed row each;
    /// process 0 keeps what never changes, the shapes and masses) and the
    /// contacts it counts.
    pub fn gather_whole(&self) -> Result<Option<WorldState>, ParallelError> {
        let world = self.local();
        let state = world.state();
        let f = state.floes.columns();
        let id = |h: u32| f.id[h as usize];
        let mut part = WholePart::default();
        let owned: Vec<usize> = (0..f.len()).filter(|&h| self.owned[h]).collect();
        part.rows.reserve(owned.len() * ROW_BYTES);
        for &h in &owned {
            put_row(&mut part.rows, state, h);
        }
        part.contacts = state
            .contacts
            .iter()
            .filter(|c| self.owned[c.a as usize])
            .map(|c| ([id(c.a), id(c.b)], *c))
            .collect();
        part.broken = state
            .broken
            .iter()
            .filter(|c| self.owned[c.a as usize])
            .map(|c| ([id(c.a), id(c.b)], *c))
            .collect();
        part.bonds = state
            .bonds
            .iter()
            .filter(|b| self.owned[b.a as usize])
            .map(|b| ([id(b.a), id(b.b)], *b))
            .collect();
        // A parked memory is counted by the owner of its lower id, if
        // it is still remembered.
        let memory_s = world.model().memory_s;
        part.broken.extend(self.parked.iter().filter(|([x, _], c)| {
            f.handle_of(*x).is_some_and(|h| self.owned[h])
                && state.time_s - c.broke_at_s <= memory_s
        }));
        let parts = self.comm.gather_to_root(encode(&part));
        let Some(template) = self.whole_floes.as_ref() else {
            return Ok(None);
        };
        let mut columns = template.columns().clone();
        let n = columns.len();
        let (mut force, mut torque) = (vec![Vec2::ZERO; n], vec![0.0; n]);
        let (mut external_force, mut external_torque) = (vec![Vec2::ZERO; n], vec![0.0; n]);
        let stress_filter = state.stress_filter;
        let mut floe_stress = vec![[0.0; 3]; if stress_filter.is_some() { n } else { 0 }];
        let mut seen = vec![false; n];
        let (mut contacts, mut broken, mut bonds) = (Vec::new(), Vec::new(), Vec::new());
        for bytes in parts {
            let p: WholePart = decode(&bytes)?;
            for row in p.rows.chunks_exact(ROW_BYTES) {
                let floe_id = u64::from_le_bytes(row[..8].try_into().expect("8 bytes"));
                let mut rest = &row[8..];
                let v = take_f64s::<18>(&mut rest).expect("a whole row");
                let h = match template.handle_of(floe_id) {
                    Some(h) if !seen[h] => h,
                    _ => {
                        return Err(ParallelError::Wire(format!(
                            "floe {floe_id} gathered twice, or not in the run"
                        )))
                    }
                };
                seen[h] = true;
                columns.position[h] = Vec2::new(v[0], v[1]);
                columns.angle[h] = v[2];
                columns.velocity[h] = Vec2::new(v[3], v[4]);
                columns.angular_velocity[h] = v[5];
                columns.motion[h] = if v[6] == 0.0 {
                    Motion::Free
                } else {
                    Motion::Prescribed {
                        velocity: Vec2::new(v[7], v[8]),
                    }
                };
                force[h] = Vec2::new(v[9], v[10]);
                torque[h] = v[11];
                external_force[h] = Vec2::new(v[12], v[13]);
                external_torque[h] = v[14];
                if let Some(s) = floe_stress.get_mut(h) {
                    *s = [v[15], v[16], v[17]];
                }
            }
            contacts.extend(p.contacts);
            broken.extend(p.broken);
            bonds.extend(p.bonds);
        }
        if let Some(h) = seen.iter().position(|s| !s) {
            return Err(ParallelError::Wire(format!(
                "floe {} was gathered from no process",
                columns.id[h]
            )));
        }
        contacts.sort_unstable_by_key(|(k, _)| *k);
        broken.sort_unstable_by_key(|(k, _)| *k);
        bonds.sort_unstable_by_key(|(k, _)| *k);
        let rehandle = |[x, y]: [u64; 2]| -> Result<(u32, u32), ParallelError> {
            match (template.handle_of(x), template.handle_of(y)) {
                (Some(a), Some(b)) => Ok((a as u32, b as u32)),
                _ => Err(ParallelError::Wire(format!(
                    "a contact names floes {x} and {y}, not both in the run"
                ))),
            }
        };
        let contacts = contacts
            .into_iter()
            .map(|(pair, mut c)| {
                (c.a, c.b) = rehandle(pair)?;
                Ok(c)
            })
            .collect::<Result<Vec<_>, ParallelError>>()?;
        let broken = broken
            .into_iter()
            .map(|(pair, mut c)| {
                (c.a, c.b) = rehandle(pair)?;
                Ok(c)
            })
            .collect::<Result<Vec<_>, ParallelError>>()?;
        let bonds = bonds
            .into_iter()
            .map(|(pair, mut b)| {
                (b.a, b.b) = rehandle(pair)?;
                Ok(b)
            })
            .collect::<Result<Vec<_>, ParallelError>>()?;
        let d = &self.drivers;
        Ok(Some(WorldState {
            floes: Floes::from_columns(columns)?,
            contacts,
            broken,
            bonds,
            time_s: state.time_s,
            steps: state.steps,
            dt_s: state.dt_s,
            energy: state.energy,
            force,
            torque,
            external_force,
            external_torque,
            schedules: d.schedules.clone(),
            load_points: d.load_points.clone(),
            // As the steps have moved them on (the same on every process).
            stress_controls: self.local().stress_controls().to_vec(),
            stress_filter,
            floe_stress,
            next_floe_id: state.next_floe_id,
            ridging: state.ridging,
            welding: state.welding,
        }))
    }

    /// The whole world on process 0, as a world without forcing (what the
    /// writer and the observables read).
    pub(super) fn whole_world(&self) -> Result<Option<World<NoForcing>>, ParallelError> {
        let world = self.local();
        Ok(match self.gather_whole()? {
            Some(state) => Some(World::resume(
                state,
                world.model().clone(),
                NoForcing,
                world.periodicity(),
            )?),
            None => None,
        })
    }

    /// Why the forcing failed, as the single process says it (the whole's
    /// first floe off the grid), on every process.
    pub(super) fn forcing_failure_message(&mut self) -> Result<String, ParallelError> {
        // Process 0's answer, or why it has none, goes to every process.
        let message: Result<String, String> = match self.gather_whole() {
            Ok(Some(state)) => {
                let t = state.time_s;
                let world = self.local_mut();
                Ok(
                    match world.forcing_mut().prepare(t, state.floes.columns()) {
                        Err(failure) => failure.to_string(),
                        Ok(()) => world
                            .forcing_failure()
                            .map_or_else(|| "the forcing failed".into(), ToString::to_string),
                    },
                )
            }
            Ok(None) => Ok(String::new()),
            Err(e) => Err(e.to_string()),
        };
        let bytes = self.comm.broadcast_from_root(encode(&message));
        decode::<Result<String, String>>(&bytes)?.map_err(ParallelError::Wire)
    }

    /// The blow-up as the single process finds it, on every process.
    pub(super) fn blow_up(&self) -> Result<Option<BlowUp>, ParallelError> {
        let found: Result<Option<BlowUp>, String> = self
            .whole_world()
            .map(|w| w.and_then(|w| check_health(&w)))
            .map_err(|e| e.to_string());
        let bytes = self.comm.broadcast_from_root(encode(&found));
        decode::<Result<Option<BlowUp>, String>>(&bytes)?.map_err(ParallelError::Wire)
    }
}

/// Bytes of a floe's row in the gathered whole: its id and eighteen `f64`.
const ROW_BYTES: usize = 152;

/// What a process sends process 0 for the whole world: its floes' rows
/// ([`put_row`]) and the contacts it counts, named by floe ids.
#[derive(Debug, Default, serde::Serialize, serde::Deserialize)]
struct WholePart {
    rows: Vec<u8>,
    contacts: Vec<([u64; 2], ContactRecord)>,
    broken: Vec<([u64; 2], BrokenContact)>,
    bonds: Vec<([u64; 2], Bond)>,
}

/// Floe `h`'s row: id, position, angle, velocity, angular velocity,
/// motion (0 free, 1 prescribed, and the prescribed velocity), force,
/// torque, external force and torque, stress (zero when off).
fn put_row(out: &mut Vec<u8>, state: &WorldState, h: usize) {
    let f = state.floes.columns();
    out.extend_from_slice(&f.id[h].to_le_bytes());
    let (kind, v) = match f.motion[h] {
        Motion::Free => (0.0, Vec2::ZERO),
        Motion::Prescribed { velocity } => (1.0, velocity),
    };
    let stress = state.floe_stress.get(h).copied().unwrap_or_default();
    put_f64s(
        out,
        &[
            f.position[h].x,
            f.position[h].y,
            f.angle[h],
            f.velocity[h].x,
            f.velocity[h].y,
            f.angular_velocity[h],
            kind,
            v.x,
            v.y,
            state.force[h].x,
            state.force[h].y,
            state.torque[h],
            state.external_force[h].x,
            state.external_force[h].y,
            state.external_torque[h],
            stress[0],
            stress[1],
            stress[2],
        ],
    );
}

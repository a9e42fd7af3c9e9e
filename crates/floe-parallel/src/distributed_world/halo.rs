//! Every step's halo: owners send their ghosts' motion and forces to the
//! neighbours that hold them, stress-controlled walls share their forces,
//! and how far floes have moved since the last migration.

use super::*;

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// Sends each ghost its owner's motion and forces.
    pub(super) fn exchange_ghosts(&mut self) {
        let world = self.world.as_ref().expect("present between calls");
        let sends = self
            .send
            .iter()
            .map(|(r, list)| {
                let mut out = Vec::with_capacity(list.len() * KINEMATICS_BYTES);
                for &h in list {
                    let k = world.kinematics(h);
                    put_f64s(
                        &mut out,
                        &[
                            k.position.x,
                            k.position.y,
                            k.angle,
                            k.velocity.x,
                            k.velocity.y,
                            k.angular_velocity,
                            k.force.x,
                            k.force.y,
                            k.torque,
                        ],
                    );
                }
                (*r, out)
            })
            .collect();
        let receives: Vec<(usize, usize)> = self
            .receive
            .iter()
            .map(|(r, list)| (*r, list.len() * KINEMATICS_BYTES))
            .collect();
        let incoming = self.comm.exchange(sends, &receives);
        let world = self.world.as_mut().expect("present between calls");
        for ((_, list), bytes) in self.receive.iter().zip(&incoming) {
            let mut bytes = bytes.as_slice();
            for &h in list {
                let v = take_f64s::<9>(&mut bytes).expect("the owner sends every ghost it listed");
                let k = Kinematics {
                    position: Vec2::new(v[0], v[1]),
                    angle: v[2],
                    velocity: Vec2::new(v[3], v[4]),
                    angular_velocity: v[5],
                    force: Vec2::new(v[6], v[7]),
                    torque: v[8],
                };
                world
                    .set_kinematics(h, &k)
                    .expect("between steps, after the kick");
            }
        }
    }

    /// Hands the force on each stress-controlled wall from its owner to
    /// every process: the next drift moves the walls by their sum.
    pub(super) fn share_wall_forces(&mut self) -> Result<(), ParallelError> {
        if self.controlled.is_empty() {
            return Ok(());
        }
        let world = self.local();
        let ids = &world.floes().id;
        let mut mine = Vec::new();
        for &h in self.controlled.iter().filter(|&&h| self.owned[h]) {
            let k = world.kinematics(h);
            mine.extend_from_slice(&ids[h].to_le_bytes());
            put_f64s(&mut mine, &[k.force.x, k.force.y, k.torque]);
        }
        let all = self.comm.all_gather(mine);
        let world = self.world.as_mut().expect("present between calls");
        for part in &all {
            for row in part.chunks_exact(32) {
                let id = u64::from_le_bytes(row[..8].try_into().expect("8 bytes"));
                let mut rest = &row[8..];
                let v = take_f64s::<3>(&mut rest).expect("24 bytes");
                let h = world.floes().handle_of(id).ok_or_else(|| {
                    ParallelError::Wire(format!("wall {id} is not on every process"))
                })?;
                if !self.owned[h] {
                    let k = Kinematics {
                        force: Vec2::new(v[0], v[1]),
                        torque: v[2],
                        ..world.kinematics(h)
                    };
                    world.set_kinematics(h, &k)?;
                }
            }
        }
        Ok(())
    }

    /// How far any owned floe's outline will have moved since the last
    /// migration by the end of the next drift, m (a free floe's centre:
    /// its reach is a circle), and how far one moves in that drift: the
    /// contacts of the next step are found within the halo only if the
    /// first stays below half the skin.
    pub(super) fn motion_bounds(&self) -> (f64, f64) {
        let world = self.local();
        let state = world.state();
        let f = state.floes.columns();
        let next = state.next_drift_velocities();
        let (dt, periodicity) = (state.dt_s, world.periodicity());
        let (mut moved_max, mut step_max) = (0.0f64, 0.0f64);
        for h in (0..f.len()).filter(|&h| self.owned[h]) {
            let (p0, a0) = self.reference[h];
            let p = f.position[h];
            let (v, w) = next[h];
            let mut step = v.length() * dt;
            let mut moved = (p + periodicity.nearest_image(p0, p) - p0).length() + step;
            if !f.is_free(h) {
                // A wall's outline: its corners turn with it.
                let turn = f.radius_m[h] * w.abs() * dt;
                moved += f.radius_m[h] * (f.angle[h] - a0).abs() + turn;
                step += turn;
            }
            moved_max = moved_max.max(moved);
            step_max = step_max.max(step);
        }
        // A margin for the drift's own rounding.
        (moved_max * (1.0 + 1e-9), step_max)
    }
}

/// Bytes of a ghost's motion and forces ([`Kinematics`]: nine `f64`).
pub(super) const KINEMATICS_BYTES: usize = 72;

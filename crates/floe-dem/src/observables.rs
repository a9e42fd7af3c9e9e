//! Whole-assembly diagnostics: energies, stress, contact statistics.

use crate::contact_kernel::contact_force_on_b;
use crate::energy_ledger::EnergyLedger;
use crate::forcing::ExternalForces;
use crate::world::World;

/// A snapshot of assembly-wide quantities.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Observables {
    /// Simulated time, s.
    pub time_s: f64,
    /// Translational kinetic energy of the free floes, J.
    pub kinetic_translational_j: f64,
    /// Rotational kinetic energy of the free floes, J.
    pub kinetic_rotational_j: f64,
    /// Elastic energy held by the contacts and the bonds, J.
    pub contact_energy_j: f64,
    /// Cumulative work and dissipation since the start, J.
    pub ledger: EnergyLedger,
    /// Mean stress of the assembly, vertically integrated, N/m, as
    /// `[xx, xy, yx, yy]`: `(1/A) sum over free floes p and their contacts c
    /// of f_cp (x) (x_c - x_p)`, the force on the floe times its arm from its
    /// centroid to the contact point (Love-Weber formula; between two free
    /// floes the pair sums to `f_a (x) (x_b - x_a)`, and a wall's side, whose
    /// centroid is not in the ice, adds nothing). Tension positive, so a
    /// compressed pack has negative diagonal stress.
    pub mean_stress_n_per_m: [f64; 4],
    /// Number of contacts.
    pub contacts: usize,
    /// Fraction of contacts slipping faster than the model's sliding threshold.
    pub sliding_fraction: f64,
    /// Mean friction coefficient over contacts, weighted by normal force.
    pub mean_mu: f64,
    /// Sum of the load points' spring forces on their floes, N (`[x, y]`;
    /// zero without load points): the force a spring-driven block is
    /// pushed with.
    pub load_point_force_n: [f64; 2],
    /// Number of bonds (floes frozen together; quiet pairs not yet bonded
    /// not counted).
    pub bonds: usize,
    /// What ridging has moved since the start (zero without it).
    pub ridging: crate::ridging::RidgingLedger,
}

impl<F: ExternalForces> World<F> {
    /// Assembly diagnostics; `domain_area_m2` normalises the stress.
    pub fn observables(&self, domain_area_m2: f64) -> Observables {
        let f = self.floes();
        let contacts = self.contacts();
        let mut o = Observables {
            time_s: self.time_s(),
            ledger: *self.energy(),
            ridging: *self.ridging_ledger(),
            contacts: contacts.len(),
            ..Default::default()
        };
        for i in 0..f.len() {
            if f.is_free(i) {
                o.kinetic_translational_j += 0.5 * f.mass_kg[i] * f.velocity[i].length_squared();
                o.kinetic_rotational_j += 0.5 * f.inertia_kg_m2[i] * f.angular_velocity[i].powi(2);
            }
        }
        let (mut sliding, mut mu_weighted, mut normal_sum) = (0usize, 0.0, 0.0);
        for c in contacts {
            o.contact_energy_j += c.elastic_energy_j();
            let (pa, pb) = (
                f.position[c.a as usize],
                f.position[c.b as usize] + c.image_offset,
            );
            let force_on_b = contact_force_on_b(c);
            // Each free floe's share, force on it (x) its arm to the point;
            // a prescribed floe's arm (a wall's centroid) is not the ice's.
            for (free, force, centroid) in [
                (f.is_free(c.a as usize), -force_on_b, pa),
                (f.is_free(c.b as usize), force_on_b, pb),
            ] {
                if free {
                    let arm = c.point - centroid;
                    o.mean_stress_n_per_m[0] += force.x * arm.x;
                    o.mean_stress_n_per_m[1] += force.x * arm.y;
                    o.mean_stress_n_per_m[2] += force.y * arm.x;
                    o.mean_stress_n_per_m[3] += force.y * arm.y;
                }
            }
            if c.slip_rate_m_per_s.abs() > self.model().sliding_threshold_m_per_s {
                sliding += 1;
            }
            mu_weighted += c.tangential_force_n().abs();
            normal_sum += c.normal_force_n;
        }
        for b in self.bonds().iter().filter(|b| b.formed) {
            o.bonds += 1;
            o.contact_energy_j += b.energy_j;
            // A bond's force acts at its anchors.
            let arm = |h: usize, anchor| {
                let (s, c) = f.angle[h].sin_cos();
                crate::geometry::rotate(anchor, c, s)
            };
            for (h, force, arm) in [
                (b.a as usize, -b.force_on_b, arm(b.a as usize, b.anchor_a)),
                (b.b as usize, b.force_on_b, arm(b.b as usize, b.anchor_b)),
            ] {
                if f.is_free(h) {
                    o.mean_stress_n_per_m[0] += force.x * arm.x;
                    o.mean_stress_n_per_m[1] += force.x * arm.y;
                    o.mean_stress_n_per_m[2] += force.y * arm.x;
                    o.mean_stress_n_per_m[3] += force.y * arm.y;
                }
            }
        }
        for s in &mut o.mean_stress_n_per_m {
            *s /= domain_area_m2;
        }
        if !contacts.is_empty() {
            o.sliding_fraction = sliding as f64 / contacts.len() as f64;
        }
        if normal_sum > 0.0 {
            o.mean_mu = mu_weighted / normal_sum;
        }
        for l in self.load_points() {
            if let Some(h) = f.handle_of(l.floe_id) {
                let force = l.force(self.time_s(), f.position[h], self.periodicity());
                o.load_point_force_n[0] += force.x;
                o.load_point_force_n[1] += force.y;
            }
        }
        o
    }
}

//! The floe life cycle's settings and state on the world: floe stress,
//! fracture after every step of a run.

use super::World;
use crate::error::DemError;
use crate::forcing::ExternalForces;
use crate::fracture::rule::Fracturing;
use crate::pipeline::floe_stress::{self, FloeStress, StressFilter};

impl<F: ExternalForces> World<F> {
    /// Computes each floe's time-averaged stress from now on (`Some`), or
    /// stops (`None`, the stresses dropped). Stresses already held are
    /// kept (a new time scale applies from the next step); otherwise they
    /// start at zero. Part of the state: a resumed world goes on with its
    /// saved filter and stresses.
    pub fn set_stress_filter(&mut self, filter: Option<StressFilter>) {
        let s = &mut self.state;
        match filter {
            Some(_) => s.floe_stress.resize(s.floes.len(), [0.0; 3]),
            None => s.floe_stress.clear(),
        }
        s.stress_filter = filter;
    }

    /// Fracture after every step a run takes (`Stepper::step`; not
    /// `World::step`, which is the four stages alone): `Some` checks the
    /// rule (and turns floe stress on with its default average if off),
    /// `None` stops.
    pub fn set_fracturing(&mut self, fracturing: Option<Fracturing>) -> Result<(), DemError> {
        if let Some(f) = &fracturing {
            f.rule.check()?;
            if self.state.stress_filter.is_none() {
                self.set_stress_filter(Some(StressFilter::default()));
            }
        }
        self.fracturing = fracturing;
        Ok(())
    }

    /// Fracture after every step, if on.
    pub fn fracturing(&self) -> Option<Fracturing> {
        self.fracturing
    }

    /// The floe stress's time average, if the world computes it.
    pub fn stress_filter(&self) -> Option<StressFilter> {
        self.state.stress_filter
    }

    /// Each floe's time-averaged stress (`[xx, xy, yy]`, Pa), in handle
    /// order; empty unless the world computes it.
    pub fn floe_stress(&self) -> &[FloeStress] {
        &self.state.floe_stress
    }

    /// Floe `h`'s stress from its contacts at the end of the last step
    /// and bonds (not averaged; zero for a prescribed floe), Pa: a scan of
    /// the whole contact and bond lists, for diagnostics.
    pub fn instantaneous_stress(&self, h: usize) -> FloeStress {
        let f = self.state.floes.columns();
        if !f.is_free(h) {
            return [0.0; 3];
        }
        let mine = self
            .state
            .contacts
            .iter()
            .filter(|c| c.a as usize == h || c.b as usize == h);
        // Its bonds' moments: the whole list's, for a diagnostic.
        let mut moments = Vec::new();
        if self.state.bonds.iter().any(|b| b.formed) {
            let trig: Vec<(f64, f64)> = f.angle.iter().map(|a| a.sin_cos()).collect();
            moments.resize(f.len(), [0.0; 3]);
            crate::pipeline::cohesion::add_bond_moments(f, &trig, &self.state.bonds, &mut moments);
        }
        floe_stress::from_contacts(f, h, mine, moments.get(h))
    }

    /// The floe stress stage: moves the averages towards the stresses of
    /// the contacts just gathered.
    pub(super) fn update_floe_stress(&mut self) {
        let Some(filter) = self.state.stress_filter else {
            return;
        };
        let s = &mut self.state;
        let p = &mut self.pipeline;
        p.bond_moments.clear();
        if s.bonds.iter().any(|b| b.formed) {
            p.bond_moments.resize(s.floes.len(), [0.0; 3]);
            crate::pipeline::cohesion::add_bond_moments(
                s.floes.columns(),
                &p.trig,
                &s.bonds,
                &mut p.bond_moments,
            );
        }
        floe_stress::update(
            s.floes.columns(),
            &s.contacts,
            &p.gathering,
            &p.bond_moments,
            filter.weight(s.dt_s),
            &mut s.floe_stress,
        );
    }
}

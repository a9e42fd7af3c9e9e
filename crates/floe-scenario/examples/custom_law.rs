//! A friction law defined outside floe-friction, registered and run in a
//! DEM scenario: linear slip weakening (Ida 1972; Palmer & Rice 1973), the
//! friction coefficient falling from `mu_static` to `mu_dynamic` over the
//! slip distance `critical_slip_m`, then constant. Its per-contact state is
//! one slot, the slip accumulated since the contact formed; checkpoints
//! store that slot without a new file format.
//!
//!     cargo run --release -p floe-scenario --example custom_law
//!
//! runs the laboratory double shear (scenarios/lab_double_shear.toml's
//! set-up) with it and prints the friction on the block's faces as the
//! slip grows. tests/scenario/custom_law.rs checks that against the law.

use std::path::Path;

use floe_dem::floes::Motion;
use floe_dem::forcing::Forcing;
use floe_dem::world::World;
use floe_friction::{
    ContactLoad, ContactState, FrictionLaw, Law, LawEntry, LawParams, LawRegistry, ParamDefault,
    ParamKind, ParamSpec, ReferenceMatch, StepOutcome,
};
use floe_scenario::Scenario;

/// Linear slip weakening on a tangential spring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipWeakening {
    /// Friction coefficient before any slip.
    pub mu_static: f64,
    /// Friction coefficient after `critical_slip_m` of slip.
    pub mu_dynamic: f64,
    /// Slip over which friction weakens, m.
    pub critical_slip_m: f64,
}

/// The slot of the contact state holding the accumulated slip, m.
const SLIP: usize = 0;

impl SlipWeakening {
    /// Friction coefficient after `slip_m` of accumulated slip.
    pub fn mu_at(&self, slip_m: f64) -> f64 {
        let weakened = (slip_m / self.critical_slip_m).min(1.0);
        self.mu_static + (self.mu_dynamic - self.mu_static) * weakened
    }
}

impl FrictionLaw for SlipWeakening {
    fn mu_steady(&self, _slip_rate_m_per_s: f64) -> f64 {
        self.mu_dynamic
    }

    /// A new contact has not slipped.
    fn steady_state(&self, _v: f64, _n: f64) -> ContactState {
        ContactState::default()
    }

    /// Coulomb's elastic predictor and plastic corrector, with the
    /// coefficient of the slip accumulated at the start of the step.
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt: f64) -> StepOutcome {
        let n = load.normal_load_n;
        let mu = self.mu_at(state.law_state[SLIP]);
        if n <= 0.0 || n.is_nan() {
            state.tangential_force_n = 0.0;
            let v = load.load_point_velocity_m_per_s;
            state.law_state[SLIP] += v.abs() * dt;
            return StepOutcome {
                slip_rate_m_per_s: v,
                mu,
                iterations: 0,
            };
        }
        let kdt = load.stiffness_n_per_m * dt;
        let trial = state.tangential_force_n + kdt * load.load_point_velocity_m_per_s;
        let cap = mu * n;
        let (force, v) = if trial.abs() <= cap {
            (trial, 0.0)
        } else {
            let f = cap.copysign(trial);
            (f, (trial - f) / kdt)
        };
        state.tangential_force_n = force;
        state.law_state[SLIP] += v.abs() * dt;
        StepOutcome {
            slip_rate_m_per_s: v,
            mu: force / n,
            iterations: 0,
        }
    }

    fn state_slots(&self) -> usize {
        1
    }
}

/// Its parameters, as the registry publishes them.
const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        key: "mu_static",
        unit: "",
        kind: ParamKind::NON_NEGATIVE,
        default: ParamDefault::Required,
        meaning: "friction coefficient before slip",
    },
    ParamSpec {
        key: "mu_dynamic",
        unit: "",
        kind: ParamKind::NON_NEGATIVE,
        default: ParamDefault::Required,
        meaning: "friction coefficient after the critical slip",
    },
    ParamSpec {
        key: "critical_slip_m",
        unit: "m",
        kind: ParamKind::POSITIVE,
        default: ParamDefault::Number(1e-3),
        meaning: "slip over which friction weakens",
    },
];

/// The registry entry: name, parameters, and the law built from them.
pub const ENTRY: LawEntry = LawEntry {
    name: "slip-weakening",
    summary: "linear slip weakening from mu_static to mu_dynamic",
    params: PARAMS,
    build: |p: &LawParams| {
        Ok(Law::custom(
            "slip-weakening",
            SlipWeakening {
                mu_static: p.number("mu_static"),
                mu_dynamic: p.number("mu_dynamic"),
                critical_slip_m: p.number("critical_slip_m"),
            },
        ))
    }, // Not matched to a rate-and-state reference: `floe compare` refuses it.
    reference_match: ReferenceMatch::Unmatched,
};

/// The laboratory double shear of scenarios/lab_double_shear.toml under
/// slip weakening, pushed for 5 mm (25 critical slips of 0.2 mm).
pub const SCENARIO: &str = r#"
title = "lab double shear, slip weakening"
duration_s = 50.0
[domain]
size_m = [1.0, 0.5]
[tessellation]
kind = "double-shear"
block_m = [0.2, 0.1]
side_block_m = [0.3, 0.1]
pusher_m = [0.05, 0.1]
normal_load_per_face_n = 1000.0
push_velocity_m_per_s = 0.0001
[ice]
thickness_m = 0.1
[contact]
youngs_modulus_pa = 4.66e8
[friction]
law = "slip-weakening"
mu_static = 0.8
mu_dynamic = 0.5
critical_slip_m = 2e-4
[ocean]
drag_coefficient = 0.0
"#;

/// The registry with slip weakening added.
pub fn registry() -> LawRegistry {
    let mut r = LawRegistry::builtin();
    r.register(ENTRY).expect("a new name");
    r
}

/// The built scenario's world.
pub fn world() -> World<Forcing> {
    let scenario = Scenario::from_text_with(SCENARIO, Path::new("custom_law"), &registry())
        .unwrap_or_else(|e| panic!("{e}"));
    scenario.build().unwrap_or_else(|e| panic!("{e}")).world
}

/// What the block's faces do: every `every` steps over `steps` steps,
/// `(the block's travel, the slip the law accumulated on its faces, the
/// faces' |F_t / F_n|)`, the last two averaged over the two faces, m, m, 1.
pub fn friction_history(
    world: &mut World<Forcing>,
    steps: usize,
    every: usize,
) -> Vec<(f64, f64, f64)> {
    let block = world
        .floes()
        .motion
        .iter()
        .position(|m| matches!(m, Motion::Free))
        .expect("the free block");
    let x0 = world.floes().position[block].x;
    let mut out = Vec::new();
    for step in 1..=steps {
        world.step();
        if step % every == 0 {
            let faces: Vec<(f64, f64)> = world
                .contacts()
                .iter()
                .filter(|c| c.normal.y.abs() > 0.99)
                .map(|c| (c.friction.law_state[SLIP], c.mu()))
                .collect();
            let n = faces.len().max(1) as f64;
            let slip = faces.iter().map(|f| f.0).sum::<f64>() / n;
            let mu = faces.iter().map(|f| f.1).sum::<f64>() / n;
            out.push((world.floes().position[block].x - x0, slip, mu));
        }
    }
    out
}

#[allow(dead_code)] // also compiled into the run and scenario tests (tests/*/main.rs)
fn main() {
    let mut w = world();
    let steps = (40.0 / w.dt_s()) as usize;
    println!("block travel (mm)  slip on the faces (mm)  mu on the faces");
    for (travel, slip, mu) in friction_history(&mut w, steps, steps / 40) {
        println!("{:17.4}  {:22.4}  {mu:.4}", travel * 1e3, slip * 1e3);
    }
}

//! A `[[wall]]` that holds `normal_stress_n_per_m`: its control keys, the
//! default tuning from the pack it presses on, the stability check and the
//! build report's line (docs/scenarios.md, "Stress control").

use floe_dem::forcing::ExternalForces;
use floe_dem::stress_control::{ControlLaw, ServoWall};
use floe_dem::world::World;

use crate::error::ScenarioError;
use crate::numbers::sig;
use crate::source_file::SourceFile;
use crate::spec::RawWall;

/// The default gain of a proportional wall as a fraction of the stability
/// limit [`stress_gain_limit`].
pub const STRESS_GAIN_FRACTION: f64 = 0.25;

/// The servo wall's default damping ratio on the pack (critical).
pub const SERVO_DAMPING_RATIO: f64 = 1.0;

/// How much stiffer than `kappa L` (and its dashpot) the pack may be
/// against the wall for the step to stay stable (a rough wall's jagged face
/// touches along up to about twice its length): the servo's check.
pub const STIFFNESS_MARGIN: f64 = 2.0;

/// A wall's control as the file gives it (`None`: the default).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ControlKeys {
    /// `stress_control = "proportional"`, `stress_gain_m_per_s_per_n_per_m`.
    Proportional { gain: Option<f64> },
    /// `stress_control = "servo"` (the default), `servo_mass_kg_per_m`,
    /// `servo_damping_ratio`.
    Servo {
        mass_kg_per_m: Option<f64>,
        damping_ratio: Option<f64>,
    },
}

/// The control keys of `wall[index]`; refuses keys of the other law, or
/// any without `normal_stress_n_per_m`.
pub(crate) fn resolve_control_keys(
    f: &SourceFile,
    r: &RawWall,
    index: usize,
) -> Result<Option<ControlKeys>, ScenarioError> {
    let key = |k: &str| format!("wall[{index}].{k}");
    let servo_keys = [
        ("servo_mass_kg_per_m", &r.servo_mass_kg_per_m),
        ("servo_damping_ratio", &r.servo_damping_ratio),
    ];
    let proportional_keys = [(
        "stress_gain_m_per_s_per_n_per_m",
        &r.stress_gain_m_per_s_per_n_per_m,
    )];
    if r.normal_stress_n_per_m.is_none() {
        let given = servo_keys
            .iter()
            .chain(&proportional_keys)
            .find_map(|(k, v)| v.as_ref().map(|v| (*k, v.span())));
        let law = r
            .stress_control
            .as_ref()
            .map(|w| ("stress_control", w.span()));
        if let Some((k, span)) = given.or(law) {
            return Err(f.error(
                span,
                key(k),
                "a wall control without normal_stress_n_per_m: give the stress the wall holds",
            ));
        }
        return Ok(None);
    }
    let servo = f.keyword(
        &r.stress_control,
        &key("stress_control"),
        &[("servo", true), ("proportional", false)],
        true,
    )?;
    let (others, law) = if servo {
        (&proportional_keys[..], "servo")
    } else {
        (&servo_keys[..], "proportional")
    };
    if let Some((k, v)) = others.iter().find_map(|(k, v)| v.as_ref().map(|v| (*k, v))) {
        let wanted = if servo { "proportional" } else { "servo" };
        return Err(f.error(
            v.span(),
            key(k),
            format!(
                "belongs to stress_control = \"{wanted}\", and this wall's control is \"{law}\"{}",
                if servo { " (the default)" } else { "" }
            ),
        ));
    }
    let positive =
        |v: &crate::spec::Num, k: &str| v.as_ref().map(|v| f.positive(v, &key(k))).transpose();
    Ok(Some(if servo {
        ControlKeys::Servo {
            mass_kg_per_m: positive(&r.servo_mass_kg_per_m, "servo_mass_kg_per_m")?,
            damping_ratio: r
                .servo_damping_ratio
                .as_ref()
                .map(|v| f.in_range(v, &key("servo_damping_ratio"), (0.0, 100.0), ""))
                .transpose()?,
        }
    } else {
        ControlKeys::Proportional {
            gain: positive(
                &r.stress_gain_m_per_s_per_n_per_m,
                "stress_gain_m_per_s_per_n_per_m",
            )?,
        }
    }))
}

/// The mean free floe of a world: what the walls' defaults are tuned to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanFloe {
    /// Area, m^2.
    pub area_m2: f64,
    /// Thickness, m.
    pub thickness_m: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// `kappa = E h / sqrt(area)`, the wall contact's stiffness per unit
    /// area, N/m^3 (N/m of force per m of contact per m of overlap).
    pub kappa_n_per_m3: f64,
    /// The contacts' damping ratio.
    pub damping_ratio: f64,
}

impl MeanFloe {
    /// The mean of `world`'s free floes.
    pub fn of<F: ExternalForces>(world: &World<F>) -> Self {
        let f = world.floes();
        let (mut area, mut thickness, mut mass, mut n) = (0.0, 0.0, 0.0, 0usize);
        for i in (0..f.len()).filter(|&i| f.is_free(i)) {
            area += f.area_m2[i];
            thickness += f.thickness_m[i];
            mass += f.mass_kg[i];
            n += 1;
        }
        let n = n.max(1) as f64;
        let (area, h, mass) = (area / n, thickness / n, mass / n);
        let model = world.model();
        MeanFloe {
            area_m2: area,
            thickness_m: h,
            mass_kg: mass,
            kappa_n_per_m3: model.youngs_modulus_pa * h / area.sqrt(),
            damping_ratio: model.damping_ratio(),
        }
    }

    /// The contacts' dashpot per unit contact length, `c' = 2 zeta
    /// sqrt(kappa rho h r)` (`r = sqrt(area)`), N s/m^2.
    pub fn dashpot_n_s_per_m2(&self) -> f64 {
        let rho_h = self.mass_kg / self.area_m2;
        2.0 * self.damping_ratio * (self.kappa_n_per_m3 * rho_h * self.area_m2.sqrt()).sqrt()
    }

    /// The mass per metre of a row of these floes along a wall, `rho h d`
    /// (`d = sqrt(area)`), kg/m: the servo wall's default.
    pub fn row_mass_kg_per_m(&self) -> f64 {
        self.mass_kg / self.area_m2.sqrt()
    }
}

/// The largest stable gain of a proportional wall, (m/s)/(N/m), for the
/// mean free floe at time step `dt_s`. A stress error `e` moves the wall
/// `G e dt` in a step, which raises the elastic stress by `kappa G e dt`:
/// stable for `G dt kappa < 2`. And the wall's new speed `G e` raises the
/// dashpot's stress at once by `G e c'`, with `c' = 2 zeta sqrt(kappa rho h
/// r)` the dashpot per unit contact length (`r = sqrt(area)`): stable for
/// `G c' < 1`. The limit is the smaller.
pub fn stress_gain_limit<F: ExternalForces>(world: &World<F>, dt_s: f64) -> f64 {
    let m = MeanFloe::of(world);
    (2.0 / (dt_s * m.kappa_n_per_m3)).min(1.0 / m.dashpot_n_s_per_m2())
}

/// The control law of a wall of length `length_m` from its keys, tuned to
/// the mean floe `m` at time step `dt_s`, and the report's words for it;
/// refuses a servo that the step cannot integrate stably (naming
/// `servo_mass_kg_per_m` or `servo_damping_ratio`).
pub(crate) fn control_law(
    keys: ControlKeys,
    (m, gain_limit): (MeanFloe, f64),
    length_m: f64,
    dt_s: f64,
) -> Result<(ControlLaw, String), String> {
    match keys {
        ControlKeys::Proportional { gain } => {
            let gain = gain.unwrap_or(STRESS_GAIN_FRACTION * gain_limit);
            Ok((
                ControlLaw::Proportional {
                    gain_m_per_s_per_n_per_m: gain,
                },
                format!(
                    "proportional control, gain {} (m/s)/(N/m), {} of the stability limit",
                    sig(gain),
                    sig(gain / gain_limit)
                ),
            ))
        }
        ControlKeys::Servo {
            mass_kg_per_m,
            damping_ratio,
        } => {
            let per_m = mass_kg_per_m.unwrap_or(m.row_mass_kg_per_m());
            let mass = per_m * length_m;
            let pack = (
                m.kappa_n_per_m3 * length_m,
                m.dashpot_n_s_per_m2() * length_m,
            );
            let zeta = damping_ratio.unwrap_or(SERVO_DAMPING_RATIO);
            // omega = sqrt(K / M) on the nominal pack; D K = 2 zeta sqrt(K M);
            // the filter at 1 / (2 omega).
            let omega = (pack.0 / mass).sqrt();
            let servo =
                ServoWall::new(mass, 2.0 * zeta / omega, 0.5 / omega).map_err(|e| e.to_string())?;
            let margin = servo.stability_margin(pack, dt_s);
            if margin < STIFFNESS_MARGIN {
                return Err(format!(
                    "a servo wall of {} kg/m and damping ratio {} rings at dt = {} s: the step is \
                     stable on a pack up to {} times kappa L = {} N/m only, and a rough wall's \
                     face may be {} times that; give a heavier wall (servo_mass_kg_per_m) or a \
                     smaller dt_s",
                    sig(per_m),
                    sig(zeta),
                    sig(dt_s),
                    sig(margin),
                    sig(pack.0),
                    STIFFNESS_MARGIN
                ));
            }
            Ok((
                ControlLaw::Servo(servo),
                format!(
                    "servo wall of {} kg/m{}, damping ratio {} (D = {} s, stress low-passed over {} s); \
                     period {} s on the pack (kappa L = {} N/m), omega dt = {}, stable on a pack up to {} \
                     times as stiff",
                    sig(per_m),
                    if mass_kg_per_m.is_some() { "" } else { " (a row of the mean floe)" },
                    sig(zeta),
                    sig(servo.stress_damping_s),
                    sig(servo.stress_filter_s),
                    sig(std::f64::consts::TAU / omega),
                    sig(pack.0),
                    sig(omega * dt_s),
                    sig(margin)
                ),
            ))
        }
    }
}

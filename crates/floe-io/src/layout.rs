//! Names of the groups, datasets and attributes of a run file (H5MD 1.1
//! plus floe-specific groups); docs/output.md describes each.

/// The H5MD version written, `[major, minor]`.
pub const H5MD_VERSION: [i32; 2] = [1, 1];
/// The floe layout version written; files with a larger one are refused.
pub const LAYOUT_VERSION: u32 = 1;
/// `creator/name` of every floe file: how a floe file is recognised.
pub const CREATOR: &str = "floe";

/// H5MD metadata group.
pub const H5MD: &str = "h5md";
/// The floes' particle group (the first segment of a run whose floes
/// change).
pub const FLOES: &str = "particles/floes";
/// Attribute of a later segment: the snapshot (over the whole file) of
/// its first row.
pub const FIRST_SNAPSHOT: &str = "first_snapshot";
/// Floe group attribute (only once floes have ridged): the ridging events
/// the run had made when the group's shapes and masses were written.
pub const RIDGING_EVENTS: &str = "ridging_events";

/// The particle group of segment `k`: [`FLOES`] for the first, then
/// `particles/floes_1`, `particles/floes_2`, ...: a run whose floe set
/// changes (fracture) starts a segment at each change.
pub fn floe_segment(k: usize) -> String {
    if k == 0 {
        FLOES.to_string()
    } else {
        format!("{FLOES}_{k}")
    }
}
/// The simulation box, inside [`FLOES`].
pub const BOX: &str = "particles/floes/box";
/// Inside [`FLOES`]: uint8 per floe, 1 for land pieces (optional: files
/// without it have no land).
pub const LAND: &str = "land";
/// Inside a later segment: int64 per floe, the id of the floe it broke
/// from, -1 for a floe of the start.
pub const PARENT_ID: &str = "parent_id";
/// The time-dependent floe elements, inside [`FLOES`], with their units.
pub const FLOE_ELEMENTS: [(&str, &str, usize); 4] = [
    ("position", "m", 2),
    ("velocity", "m s-1", 2),
    ("angle", "rad", 1),
    ("angular_velocity", "rad s-1", 1),
];
/// The floes' time-averaged stress, inside [`FLOES`], `[xx, xy, yy]` per
/// floe (Pa, tension positive, zero for prescribed floes): written only by
/// runs that compute floe stress (`[floe_stress]` in the scenario).
pub const FLOE_STRESS: (&str, &str, usize) = ("stress", "Pa", 3);
/// Attribute of [`FLOE_STRESS`]'s `value`: the order of its components.
pub const STRESS_COMPONENTS: &str = "xx xy yy";
/// The fracture event log (runs whose floes broke).
pub const FRACTURE: &str = "fracture";
/// The ridging event log (runs whose floes ridged).
pub const RIDGING: &str = "ridging";
/// The welding event log (runs whose floes welded).
pub const WELDING: &str = "welding";
/// Contact lists, one per snapshot.
pub const CONTACTS: &str = "contacts";
/// Assembly-wide time series.
pub const OBSERVABLES: &str = "observables";
/// Run parameters (floe-specific).
pub const PARAMETERS: &str = "parameters";
/// The two checkpoint slots and which one is valid.
pub const CHECKPOINT: &str = "checkpoint";
/// Attribute of [`CHECKPOINT`]: the valid slot (0 or 1), -1 for none.
pub const VALID_SLOT: &str = "valid_slot";
/// The checkpoint slots' names inside [`CHECKPOINT`].
pub const SLOTS: [&str; 2] = ["slot0", "slot1"];

/// Per-contact datasets of [`CONTACTS`]: name, unit, values per row.
pub const CONTACT_FIELDS: [(&str, &str, usize); 8] = [
    ("theta", "1", 1),
    ("mu", "1", 1),
    ("normal_force", "N", 1),
    ("tangential_force", "N", 1),
    ("slip_rate", "m s-1", 1),
    ("overlap_area", "m2", 1),
    ("point", "m", 2),
    ("normal", "1", 2),
];

/// Rows of a time series dataset per chunk (uncompressed: see
/// docs/output.md, "Why some datasets are not compressed").
pub const SERIES_CHUNK: usize = 256;
/// Largest number of floes in one chunk of a snapshot array.
pub const MAX_FLOE_CHUNK: usize = 65_536;

/// The observables written for each sample: name, unit, and the values
/// (one, two for the load-point force `[x, y]`, or four for the stress
/// tensor `[xx, xy, yx, yy]`).
pub fn observable_samples(
    o: &floe_dem::observables::Observables,
) -> [(&'static str, &'static str, Vec<f64>); 13] {
    let l = &o.ledger;
    [
        (
            "kinetic_translational",
            "J",
            vec![o.kinetic_translational_j],
        ),
        ("kinetic_rotational", "J", vec![o.kinetic_rotational_j]),
        ("contact_energy", "J", vec![o.contact_energy_j]),
        ("forcing_work", "J", vec![l.forcing_work_j]),
        ("friction_dissipation", "J", vec![l.friction_dissipation_j]),
        ("damping_dissipation", "J", vec![l.damping_dissipation_j]),
        ("boundary_work", "J", vec![l.boundary_work_j]),
        ("released_at_break", "J", vec![l.released_at_break_j]),
        ("mean_stress", "N m-1", o.mean_stress_n_per_m.to_vec()),
        ("contacts", "1", vec![o.contacts as f64]),
        ("sliding_fraction", "1", vec![o.sliding_fraction]),
        ("mean_mu", "1", vec![o.mean_mu]),
        ("load_point_force", "N", o.load_point_force_n.to_vec()),
    ]
}

/// The observable written beside [`observable_samples`]'s when the run
/// has cohesion: the number of bonds.
pub const BONDS_OBSERVABLE: &str = "bonds";

/// The observables written beside [`observable_samples`]'s when the run
/// ridges: name, unit and values of ridging's ledger (the volume moved to
/// floes and lost to the coast; the kinetic energy lost and the contacts'
/// energy released; the events).
pub fn ridging_samples(
    o: &floe_dem::observables::Observables,
) -> [(&'static str, &'static str, Vec<f64>); 3] {
    let r = &o.ridging;
    [
        (
            "ridged_volume",
            "m3",
            vec![r.volume_to_floes_m3, r.volume_to_coast_m3],
        ),
        (
            "ridging_energy_lost",
            "J",
            vec![r.kinetic_energy_lost_j, r.contact_energy_released_j],
        ),
        ("ridging_events", "1", vec![r.events as f64]),
    ]
}

/// The values of optional observable `name` ([`BONDS_OBSERVABLE`] or one
/// of [`ridging_samples`]) in `o`.
pub fn optional_sample(name: &str, o: &floe_dem::observables::Observables) -> Option<Vec<f64>> {
    if name == BONDS_OBSERVABLE {
        return Some(vec![o.bonds as f64]);
    }
    ridging_samples(o)
        .into_iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, _, v)| v)
}

/// `/parameters` attribute: FNV-1a 64 checksum of `scenario_toml` as
/// written at creation, checked on resume.
pub const SCENARIO_CHECKSUM: &str = "scenario_checksum";

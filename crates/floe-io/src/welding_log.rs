//! The welding event log of a run file, `/welding`: one row per pair
//! welded (its step, time, the two floes and the welded floe's ids, areas,
//! mass, thickness, how far the centre of mass moved, the kinetic energy
//! lost and the elastic energy released). Made at the first weld: runs
//! without welding have none.

use hdf5::File;

use floe_dem::world::Weld;

use crate::event_log::{Column, EventLog};
use crate::layout;

/// The log's datasets, in [`COLUMNS`] order.
pub(crate) struct WeldingLog {
    log: EventLog,
}

/// Name, unit and type of each column (`u` unsigned, `f` float).
pub(crate) const COLUMNS: [Column; 13] = [
    ("step", "", 'u'),
    ("time", "s", 'f'),
    ("first", "", 'u'),
    ("second", "", 'u'),
    ("welded", "", 'u'),
    ("area_first", "m2", 'f'),
    ("area_second", "m2", 'f'),
    ("area", "m2", 'f'),
    ("mass", "kg", 'f'),
    ("thickness", "m", 'f'),
    ("centre_shift", "m", 'f'),
    ("kinetic_energy_lost", "J", 'f'),
    ("energy_released", "J", 'f'),
];

/// A row of the log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WeldRow {
    /// The step after which the pair welded.
    pub step: u64,
    /// Simulated time, s.
    pub time_s: f64,
    /// The two floes' ids, the smaller first.
    pub ids: [u64; 2],
    /// The welded floe's id.
    pub welded_id: u64,
    /// The two floes' areas, m^2.
    pub areas_m2: [f64; 2],
    /// The welded floe's area (the pair's convex hull), m^2.
    pub area_m2: f64,
    /// Its mass (the pair's), kg.
    pub mass_kg: f64,
    /// Its thickness (the pair's volume over its area), m.
    pub thickness_m: f64,
    /// How far the centre of mass moved, m.
    pub centre_shift_m: f64,
    /// Kinetic energy lost in the merge, J.
    pub kinetic_energy_lost_j: f64,
    /// Elastic energy of the contacts and bonds the weld ended, J.
    pub released_j: f64,
}

impl WeldingLog {
    /// The log of `file`, made if absent.
    pub(crate) fn open_or_create(file: &File) -> hdf5::Result<Self> {
        EventLog::open_or_create(file, layout::WELDING, &COLUMNS).map(|log| Self { log })
    }

    /// The log of `file`, if it has one.
    pub(crate) fn open(file: &File) -> hdf5::Result<Option<Self>> {
        Ok(EventLog::open(file, layout::WELDING, &COLUMNS)?.map(|log| Self { log }))
    }

    /// Appends `welds`.
    pub(crate) fn append(&mut self, welds: &[Weld]) -> hdf5::Result<()> {
        let u = |f: fn(&Weld) -> u64| welds.iter().map(f).collect::<Vec<u64>>();
        let x = |f: fn(&Weld) -> f64| welds.iter().map(f).collect::<Vec<f64>>();
        let c = &mut self.log.columns;
        c[0].append(&u(|w| w.step))?;
        c[1].append(&x(|w| w.time_s))?;
        c[2].append(&u(|w| w.ids[0]))?;
        c[3].append(&u(|w| w.ids[1]))?;
        c[4].append(&u(|w| w.floe.id))?;
        c[5].append(&x(|w| w.areas_m2[0]))?;
        c[6].append(&x(|w| w.areas_m2[1]))?;
        c[7].append(&x(|w| w.floe.area_m2))?;
        c[8].append(&x(|w| w.floe.mass_kg))?;
        c[9].append(&x(|w| w.floe.thickness_m))?;
        c[10].append(&x(|w| w.centre_shift_m))?;
        c[11].append(&x(|w| w.kinetic_energy_lost_j))?;
        c[12].append(&x(|w| w.released_j))
    }

    /// Drops the rows after step `step` (a resume from a checkpoint there).
    pub(crate) fn truncate_after(&mut self, step: u64) -> hdf5::Result<()> {
        self.log.truncate_after(step)
    }
}

/// Every row of the log of `file` (none without one).
pub(crate) fn read(file: &File) -> hdf5::Result<Vec<WeldRow>> {
    if !file.link_exists(layout::WELDING) {
        return Ok(Vec::new());
    }
    let g = file.group(layout::WELDING)?;
    let u = |name: &str| -> hdf5::Result<Vec<u64>> { g.dataset(name)?.read_raw() };
    let x = |name: &str| -> hdf5::Result<Vec<f64>> { g.dataset(name)?.read_raw() };
    let (step, first, second, welded) = (u("step")?, u("first")?, u("second")?, u("welded")?);
    let floats: Vec<Vec<f64>> = COLUMNS
        .iter()
        .filter(|(_, _, kind)| *kind == 'f')
        .map(|(name, _, _)| x(name))
        .collect::<hdf5::Result<_>>()?;
    let n = floats
        .iter()
        .map(Vec::len)
        .chain([first.len(), second.len(), welded.len()])
        .fold(step.len(), usize::min);
    let f = |k: usize, i: usize| floats[k][i];
    Ok((0..n)
        .map(|i| WeldRow {
            step: step[i],
            time_s: f(0, i),
            ids: [first[i], second[i]],
            welded_id: welded[i],
            areas_m2: [f(1, i), f(2, i)],
            area_m2: f(3, i),
            mass_kg: f(4, i),
            thickness_m: f(5, i),
            centre_shift_m: f(6, i),
            kinetic_energy_lost_j: f(7, i),
            released_j: f(8, i),
        })
        .collect())
}

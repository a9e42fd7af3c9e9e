//! The ridging event log of a run file, `/ridging`: one row per floe that
//! ridging cut (or crushed whole) after a step: its step and time, the
//! loser, the floe or wall it was pressed against, where its ice went in
//! the end (a floe that went whole in the same step passes what it was
//! given on to its own gainer), the areas, volume and mass moved, and the
//! contact's force before and after. Made at the first event: runs without
//! ridging have none.

use hdf5::File;

use floe_dem::world::{final_gainers, PlannedRidge};

use crate::event_log::{Column, EventLog};
use crate::layout;

/// One row of the log.
#[derive(Debug, Clone, PartialEq)]
pub struct RidgeRow {
    /// The step after which the floe ridged.
    pub step: u64,
    /// Simulated time then, s.
    pub time_s: f64,
    /// The floe that lost ice.
    pub loser_id: u64,
    /// The thicker floe, or the wall, it was pressed against.
    pub gainer_id: u64,
    /// Where its ice went: `gainer_id`, or further along when that floe
    /// went whole in the same step.
    pub ice_to_id: u64,
    /// Whether that is a wall or land (the coast's ledger).
    pub to_coast: bool,
    /// Whether the loser went whole (crushed) rather than cut.
    pub whole: bool,
    /// The loser's area before, m^2.
    pub area_before_m2: f64,
    /// The area ridged away, m^2.
    pub area_removed_m2: f64,
    /// The ice volume moved, m^3.
    pub volume_m3: f64,
    /// Its mass, kg.
    pub mass_kg: f64,
    /// The contact's elastic normal force before the cut, N.
    pub force_before_n: f64,
    /// The same after it (the cap; 0 when the loser went whole), N.
    pub force_after_n: f64,
}

/// Name, unit and type of each column (`u` unsigned, `f` float).
pub(crate) const COLUMNS: [Column; 13] = [
    ("step", "", 'u'),
    ("time", "s", 'f'),
    ("loser", "", 'u'),
    ("gainer", "", 'u'),
    ("ice_to", "", 'u'),
    ("to_coast", "", 'u'),
    ("whole", "", 'u'),
    ("area_before", "m2", 'f'),
    ("area_removed", "m2", 'f'),
    ("volume", "m3", 'f'),
    ("mass", "kg", 'f'),
    ("force_before", "N", 'f'),
    ("force_after", "N", 'f'),
];

/// The log's datasets, in [`COLUMNS`] order.
pub(crate) struct RidgingLog {
    log: EventLog,
}

/// The rows of one step's `events` made at `time_s`.
pub fn rows(time_s: f64, events: &[PlannedRidge]) -> Vec<RidgeRow> {
    events
        .iter()
        .zip(final_gainers(events))
        .map(|(e, target)| RidgeRow {
            step: e.step,
            time_s,
            loser_id: e.loser_id,
            gainer_id: e.gainer_id,
            ice_to_id: target.id,
            to_coast: !target.free,
            whole: e.kept.is_empty(),
            area_before_m2: e.loser_area_m2,
            area_removed_m2: e.removed_area_m2,
            volume_m3: e.ice.volume_m3,
            mass_kg: e.ice.mass_kg,
            force_before_n: e.elastic_before_n,
            force_after_n: e.elastic_after_n,
        })
        .collect()
}

impl RidgingLog {
    /// The log of `file`, made if absent.
    pub(crate) fn open_or_create(file: &File) -> hdf5::Result<Self> {
        EventLog::open_or_create(file, layout::RIDGING, &COLUMNS).map(|log| Self { log })
    }

    /// The log of `file`, if it has one.
    pub(crate) fn open(file: &File) -> hdf5::Result<Option<Self>> {
        Ok(EventLog::open(file, layout::RIDGING, &COLUMNS)?.map(|log| Self { log }))
    }

    /// Appends `events`, made at `time_s`.
    pub(crate) fn append(&mut self, time_s: f64, events: &[PlannedRidge]) -> hdf5::Result<()> {
        let rows = rows(time_s, events);
        let u = |f: fn(&RidgeRow) -> u64| rows.iter().map(f).collect::<Vec<u64>>();
        let x = |f: fn(&RidgeRow) -> f64| rows.iter().map(f).collect::<Vec<f64>>();
        let c = &mut self.log.columns;
        c[0].append(&u(|r| r.step))?;
        c[1].append(&x(|r| r.time_s))?;
        c[2].append(&u(|r| r.loser_id))?;
        c[3].append(&u(|r| r.gainer_id))?;
        c[4].append(&u(|r| r.ice_to_id))?;
        c[5].append(&u(|r| u64::from(r.to_coast)))?;
        c[6].append(&u(|r| u64::from(r.whole)))?;
        c[7].append(&x(|r| r.area_before_m2))?;
        c[8].append(&x(|r| r.area_removed_m2))?;
        c[9].append(&x(|r| r.volume_m3))?;
        c[10].append(&x(|r| r.mass_kg))?;
        c[11].append(&x(|r| r.force_before_n))?;
        c[12].append(&x(|r| r.force_after_n))
    }

    /// Drops the rows after step `step` (a resume from a checkpoint there).
    pub(crate) fn truncate_after(&mut self, step: u64) -> hdf5::Result<()> {
        self.log.truncate_after(step)
    }
}

/// Every row of the log of `file` (none without one); a log cut short by a
/// crash is read to its shortest column.
pub(crate) fn read(file: &File) -> hdf5::Result<Vec<RidgeRow>> {
    if !file.link_exists(layout::RIDGING) {
        return Ok(Vec::new());
    }
    let g = file.group(layout::RIDGING)?;
    let u = |name: &str| -> hdf5::Result<Vec<u64>> { g.dataset(name)?.read_raw() };
    let x = |name: &str| -> hdf5::Result<Vec<f64>> { g.dataset(name)?.read_raw() };
    let (step, loser, gainer, ice_to, to_coast, whole) = (
        u("step")?,
        u("loser")?,
        u("gainer")?,
        u("ice_to")?,
        u("to_coast")?,
        u("whole")?,
    );
    let (time, before, removed, volume, mass, f0, f1) = (
        x("time")?,
        x("area_before")?,
        x("area_removed")?,
        x("volume")?,
        x("mass")?,
        x("force_before")?,
        x("force_after")?,
    );
    let n = [
        loser.len(),
        gainer.len(),
        ice_to.len(),
        to_coast.len(),
        whole.len(),
        time.len(),
        before.len(),
        removed.len(),
        volume.len(),
        mass.len(),
        f0.len(),
        f1.len(),
    ]
    .into_iter()
    .fold(step.len(), usize::min);
    Ok((0..n)
        .map(|i| RidgeRow {
            step: step[i],
            time_s: time[i],
            loser_id: loser[i],
            gainer_id: gainer[i],
            ice_to_id: ice_to[i],
            to_coast: to_coast[i] != 0,
            whole: whole[i] != 0,
            area_before_m2: before[i],
            area_removed_m2: removed[i],
            volume_m3: volume[i],
            mass_kg: mass[i],
            force_before_n: f0[i],
            force_after_n: f1[i],
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use floe_dem::world::RidgedIce;
    use floe_dem::Vec2;

    fn plan(loser: u64, gainer: u64, gainer_free: bool, whole: bool, volume: f64) -> PlannedRidge {
        PlannedRidge {
            step: 7,
            loser_id: loser,
            gainer_id: gainer,
            gainer_free,
            kept: if whole {
                Vec::new()
            } else {
                vec![Vec2::ZERO, Vec2::X, Vec2::Y]
            },
            loser_area_m2: 10.0,
            removed_area_m2: if whole { 10.0 } else { 1.0 },
            ice: RidgedIce {
                mass_kg: 900.0 * volume,
                volume_m3: volume,
                arm_m: Vec2::ZERO,
                position_m: Vec2::ZERO,
                velocity_m_per_s: Vec2::ZERO,
                inertia_kg_m2: 1.0,
                angular_velocity: 0.0,
            },
            loser_share: 0.0,
            loser_arm_m: Vec2::ZERO,
            elastic_before_n: 2.0,
            elastic_after_n: if whole { 0.0 } else { 1.0 },
            stored_after_j: 0.0,
        }
    }

    #[test]
    fn ice_given_to_a_floe_crushed_in_the_same_step_is_logged_where_it_ends() {
        // 3 is cut against 5; 5 goes whole against 9, which goes whole
        // against wall 1: the ice of all three ends at the wall. 4 is cut
        // against 6, which stays: its ice stays on 6.
        let events = [
            plan(3, 5, true, false, 1.0),
            plan(4, 6, true, false, 2.0),
            plan(5, 9, true, true, 3.0),
            plan(9, 1, false, true, 4.0),
        ];
        let rows = rows(120.0, &events);
        let to: Vec<(u64, u64, bool, bool)> = rows
            .iter()
            .map(|r| (r.loser_id, r.ice_to_id, r.to_coast, r.whole))
            .collect();
        assert_eq!(
            to,
            [
                (3, 1, true, false),
                (4, 6, false, false),
                (5, 1, true, true),
                (9, 1, true, true)
            ]
        );
        assert!(rows.iter().all(|r| r.time_s == 120.0 && r.step == 7));
        assert_eq!(rows[2].gainer_id, 9, "the gainer as planned is kept too");
    }
}

//! The fracture event log of a run file, `/fracture`: one row per floe a
//! criterion broke (its step, time, id, principal stresses, area, and its
//! pieces: the first id and how many, consecutive; 0 pieces if it stayed
//! whole). Made at the first event: runs without fracture have none.

use hdf5::File;

use floe_dem::world::FractureEvent;

use crate::event_log::{Column, EventLog};
use crate::layout;

/// What a logged floe that did not split says.
pub const STAYED_WHOLE: &str = "stayed whole";

/// The log's datasets, in [`COLUMNS`] order.
pub(crate) struct FractureLog {
    log: EventLog,
}

/// Name, unit and type of each column (`u` unsigned, `f` float).
pub(crate) const COLUMNS: [Column; 8] = [
    ("step", "", 'u'),
    ("time", "s", 'f'),
    ("parent", "", 'u'),
    ("first_piece", "", 'u'),
    ("pieces", "", 'u'),
    ("sigma_1", "Pa", 'f'),
    ("sigma_2", "Pa", 'f'),
    ("area", "m2", 'f'),
];

impl FractureLog {
    /// The log of `file`, made if absent.
    pub(crate) fn open_or_create(file: &File) -> hdf5::Result<Self> {
        EventLog::open_or_create(file, layout::FRACTURE, &COLUMNS).map(|log| Self { log })
    }

    /// The log of `file`, if it has one.
    pub(crate) fn open(file: &File) -> hdf5::Result<Option<Self>> {
        Ok(EventLog::open(file, layout::FRACTURE, &COLUMNS)?.map(|log| Self { log }))
    }

    /// Appends `events`.
    pub(crate) fn append(&mut self, events: &[FractureEvent]) -> hdf5::Result<()> {
        let u = |f: fn(&FractureEvent) -> u64| events.iter().map(f).collect::<Vec<u64>>();
        let x = |f: fn(&FractureEvent) -> f64| events.iter().map(f).collect::<Vec<f64>>();
        let c = &mut self.log.columns;
        c[0].append(&u(|e| e.step))?;
        c[1].append(&x(|e| e.time_s))?;
        c[2].append(&u(|e| e.parent_id))?;
        c[3].append(&u(|e| e.piece_ids.first().copied().unwrap_or(0)))?;
        c[4].append(&u(|e| e.piece_ids.len() as u64))?;
        c[5].append(&x(|e| e.principal_pa.0))?;
        c[6].append(&x(|e| e.principal_pa.1))?;
        c[7].append(&x(|e| e.area_m2))
    }

    /// Drops the rows after step `step` (a resume from a checkpoint there).
    pub(crate) fn truncate_after(&mut self, step: u64) -> hdf5::Result<()> {
        self.log.truncate_after(step)
    }
}

/// Every row of the log of `file` (none without one), as the events it
/// was written from (a floe that stayed whole says only that: the log
/// keeps no reason).
pub(crate) fn read(file: &File) -> hdf5::Result<Vec<FractureEvent>> {
    if !file.link_exists(layout::FRACTURE) {
        return Ok(Vec::new());
    }
    let g = file.group(layout::FRACTURE)?;
    let u = |name: &str| -> hdf5::Result<Vec<u64>> { g.dataset(name)?.read_raw() };
    let x = |name: &str| -> hdf5::Result<Vec<f64>> { g.dataset(name)?.read_raw() };
    let (step, time, parent, first, pieces) = (
        u("step")?,
        x("time")?,
        u("parent")?,
        u("first_piece")?,
        u("pieces")?,
    );
    let (s1, s2, area) = (x("sigma_1")?, x("sigma_2")?, x("area")?);
    let n = [
        time.len(),
        parent.len(),
        first.len(),
        pieces.len(),
        s1.len(),
        s2.len(),
        area.len(),
    ]
    .into_iter()
    .fold(step.len(), usize::min);
    Ok((0..n)
        .map(|i| FractureEvent {
            step: step[i],
            time_s: time[i],
            parent_id: parent[i],
            principal_pa: (s1[i], s2[i]),
            area_m2: area[i],
            piece_ids: (first[i]..first[i] + pieces[i]).collect(),
            whole_because: (pieces[i] == 0).then(|| STAYED_WHOLE.to_string()),
        })
        .collect())
}

//! An event log of a run file: a group of appendable columns, one row per
//! event, the first column the step (rows in step order): the fracture,
//! ridging and welding logs (`fracture_log`, `ridging_log`, `welding_log`).

use hdf5::File;

use crate::appendable::{Appendable, Storage};
use crate::h5;
use crate::layout;

/// A column: name, unit (empty: none) and type (`u` uint64, `f` float64).
pub(crate) type Column = (&'static str, &'static str, char);

/// The columns of a log, in the order its schema gives them.
pub(crate) struct EventLog {
    pub(crate) columns: Vec<Appendable>,
}

impl EventLog {
    /// The log `group` of `file` with `schema`'s columns, made if absent.
    pub(crate) fn open_or_create(
        file: &File,
        group: &str,
        schema: &[Column],
    ) -> hdf5::Result<Self> {
        let g = match file.group(group) {
            Ok(g) => g,
            Err(_) => file.create_group(group)?,
        };
        let storage = Storage::plain(layout::SERIES_CHUNK, &[]);
        let columns = schema
            .iter()
            .map(|&(name, unit, kind)| {
                if g.link_exists(name) {
                    return Appendable::open(&g, name);
                }
                let a = match kind {
                    'u' => Appendable::create::<u64>(&g, name, &[], &storage, None)?,
                    _ => Appendable::create::<f64>(&g, name, &[], &storage, None)?,
                };
                if !unit.is_empty() {
                    h5::write_str(a.dataset(), "unit", unit)?;
                }
                Ok(a)
            })
            .collect::<hdf5::Result<_>>()?;
        Ok(Self { columns })
    }

    /// The log `group` of `file`, if it has one.
    pub(crate) fn open(file: &File, group: &str, schema: &[Column]) -> hdf5::Result<Option<Self>> {
        if !file.link_exists(group) {
            return Ok(None);
        }
        Self::open_or_create(file, group, schema).map(Some)
    }

    /// Drops the rows after step `step` (a resume from a checkpoint there).
    pub(crate) fn truncate_after(&mut self, step: u64) -> hdf5::Result<()> {
        let steps: Vec<u64> = self.columns[0].dataset().read_raw()?;
        let keep = steps.partition_point(|&s| s <= step);
        for c in &mut self.columns {
            c.truncate(keep)?;
        }
        Ok(())
    }
}

//! A time-dependent H5MD element: its `step`, `time` and `value` datasets,
//! grown together.

use hdf5::Group;

use crate::appendable::{Appendable, Storage};
use crate::h5;
use crate::layout;

/// A time-dependent H5MD element: `step`, `time` and `value` grown together.
pub(crate) struct Element {
    pub step: Appendable,
    pub time: Appendable,
    pub value: Appendable,
}

impl Element {
    pub(crate) fn create(
        parent: &Group,
        name: &str,
        unit: &str,
        inner: &[usize],
        value_storage: &Storage,
    ) -> hdf5::Result<Self> {
        let g = parent.create_group(name)?;
        let series = Storage::plain(layout::SERIES_CHUNK, &[]);
        let step = Appendable::create::<i64>(&g, "step", &[], &series, None)?;
        let time = Appendable::create::<f64>(&g, "time", &[], &series, None)?;
        h5::write_str(time.dataset(), "unit", "s")?;
        let value = Appendable::create::<f64>(&g, "value", inner, value_storage, None)?;
        h5::write_str(value.dataset(), "unit", unit)?;
        Ok(Self { step, time, value })
    }

    pub(crate) fn open(parent: &Group, name: &str) -> hdf5::Result<Self> {
        let g = parent.group(name)?;
        Ok(Self {
            step: Appendable::open(&g, "step")?,
            time: Appendable::open(&g, "time")?,
            value: Appendable::open(&g, "value")?,
        })
    }

    pub(crate) fn append(&mut self, step: u64, time_s: f64, value: &[f64]) -> hdf5::Result<()> {
        self.step.append(&[step as i64])?;
        self.time.append(&[time_s])?;
        self.value.append(value)
    }

    pub(crate) fn truncate(&mut self, rows: usize) -> hdf5::Result<()> {
        self.step.truncate(rows)?;
        self.time.truncate(rows)?;
        self.value.truncate(rows)
    }

    /// Complete samples (all three datasets written).
    pub(crate) fn rows(&self) -> usize {
        self.step
            .rows()
            .min(self.time.rows())
            .min(self.value.rows())
    }
}

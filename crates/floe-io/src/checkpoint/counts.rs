//! The output counts at the checkpoint, first in the payload.

use super::bytes::{ReadResult, Reader, Writer};

/// How much output had been written when a checkpoint was taken: what a
/// resume truncates the file back to.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct OutputCounts {
    /// Snapshots written.
    pub snapshots: u64,
    /// Rows of the contact datasets (including the padding to chunk starts).
    pub contact_rows: u64,
    /// Samples written, per observable.
    pub observables: Vec<(String, u64)>,
}

/// Snapshots, contact rows, then per observable its name and samples.
pub(super) fn write(w: &mut Writer, counts: &OutputCounts) {
    let OutputCounts {
        snapshots,
        contact_rows,
        observables,
    } = counts;
    w.u64(*snapshots);
    w.u64(*contact_rows);
    w.len(observables.len());
    for (name, n) in observables {
        w.str(name);
        w.u64(*n);
    }
}

/// [`write`].
pub(super) fn read(r: &mut Reader) -> ReadResult<OutputCounts> {
    Ok(OutputCounts {
        snapshots: r.u64()?,
        contact_rows: r.u64()?,
        observables: r.vec(16, |r| Ok((r.str()?, r.u64()?)))?,
    })
}

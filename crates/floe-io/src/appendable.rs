//! Datasets that grow along their first axis: snapshots, contact rows,
//! time series.

use hdf5::{Dataset, Group, H5Type};
use ndarray::{ArrayView, IxDyn};

/// A chunked dataset with an unlimited first axis and fixed trailing axes.
pub(crate) struct Appendable {
    ds: Dataset,
    /// Values per row (product of the trailing axes).
    width: usize,
    /// Rows written.
    rows: usize,
}

/// How a new appendable dataset is stored.
pub(crate) struct Storage {
    /// Rows per chunk.
    pub chunk_rows: usize,
    /// Trailing axes per chunk (the dataset's own trailing axes, or fewer
    /// floes per chunk for big snapshots).
    pub chunk_inner: Vec<usize>,
    /// Deflate level (0: none) and shuffle.
    pub deflate: u8,
    /// Byte shuffle before deflate.
    pub shuffle: bool,
}

impl Storage {
    /// Uncompressed, `chunk_rows` rows of the full trailing shape per chunk.
    pub fn plain(chunk_rows: usize, inner: &[usize]) -> Self {
        Self {
            chunk_rows,
            chunk_inner: inner.to_vec(),
            deflate: 0,
            shuffle: false,
        }
    }
}

impl Appendable {
    /// A new, empty dataset `name` in `group` with trailing axes `inner`.
    pub fn create<T: H5Type>(
        group: &Group,
        name: &str,
        inner: &[usize],
        storage: &Storage,
        fill: Option<T>,
    ) -> hdf5::Result<Self> {
        let mut shape = vec![hdf5::Extent::resizable(0)];
        shape.extend(inner.iter().map(|&n| hdf5::Extent::fixed(n)));
        let mut chunk = vec![storage.chunk_rows.max(1)];
        chunk.extend(storage.chunk_inner.iter().map(|&n| n.max(1)));
        let mut b = group.new_dataset::<T>().chunk(&chunk[..]);
        if storage.shuffle && storage.deflate > 0 {
            b = b.shuffle();
        }
        if storage.deflate > 0 {
            b = b.deflate(storage.deflate.min(9));
        }
        if let Some(v) = fill {
            b = b.fill_value(v);
        }
        let ds = b.shape(hdf5::SimpleExtents::new(shape)).create(name)?;
        Ok(Self {
            ds,
            width: inner.iter().product(),
            rows: 0,
        })
    }

    /// An existing dataset.
    pub fn open(group: &Group, name: &str) -> hdf5::Result<Self> {
        let ds = group.dataset(name)?;
        let shape = ds.shape();
        if shape.is_empty() {
            return Err(format!("{name} is a scalar, not an appendable dataset").into());
        }
        Ok(Self {
            ds,
            width: shape[1..].iter().product(),
            rows: shape[0],
        })
    }

    /// Rows written.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The dataset.
    pub fn dataset(&self) -> &Dataset {
        &self.ds
    }

    /// Appends `data` (whole rows, row-major) and then `pad` rows left at
    /// the fill value.
    pub fn append_padded<T: H5Type>(&mut self, data: &[T], pad: usize) -> hdf5::Result<()> {
        if self.width == 0 || !data.len().is_multiple_of(self.width) {
            return Err(format!(
                "{} values do not make whole rows of {}",
                data.len(),
                self.width
            )
            .into());
        }
        let new = data.len() / self.width;
        let start = self.rows;
        let mut shape = self.ds.shape();
        shape[0] = start + new + pad;
        self.ds.resize(&shape[..])?;
        if new > 0 {
            shape[0] = new;
            let view = ArrayView::from_shape(IxDyn(&shape), data)
                .map_err(|e| hdf5::Error::from(e.to_string()))?;
            let rows = start..start + new;
            match shape.len() {
                1 => self.ds.write_slice(view, rows)?,
                2 => self.ds.write_slice(view, (rows, ..))?,
                3 => self.ds.write_slice(view, (rows, .., ..))?,
                n => return Err(format!("{n}-d appendable datasets are not supported").into()),
            }
        }
        self.rows = start + new + pad;
        Ok(())
    }

    /// Appends whole rows.
    pub fn append<T: H5Type>(&mut self, data: &[T]) -> hdf5::Result<()> {
        self.append_padded(data, 0)
    }

    /// Drops every row from `rows` on.
    pub fn truncate(&mut self, rows: usize) -> hdf5::Result<()> {
        let mut shape = self.ds.shape();
        if shape[0] != rows {
            shape[0] = rows;
            self.ds.resize(&shape[..])?;
        }
        self.rows = rows;
        Ok(())
    }
}

/// Rows `rows` of `ds`, flattened row-major.
pub(crate) fn read_rows<T: H5Type + Copy>(
    ds: &Dataset,
    rows: std::ops::Range<usize>,
) -> hdf5::Result<Vec<T>> {
    let ndim = ds.ndim();
    if rows.is_empty() {
        return Ok(Vec::new());
    }
    let v: Vec<T> = match ndim {
        1 => ds.read_slice_1d::<T, _>(rows)?.iter().copied().collect(),
        2 => ds
            .read_slice_2d::<T, _>((rows, ..))?
            .iter()
            .copied()
            .collect(),
        3 => ds
            .read_slice::<T, _, ndarray::Ix3>((rows, .., ..))?
            .iter()
            .copied()
            .collect(),
        n => return Err(format!("{n}-d datasets are not read here").into()),
    };
    Ok(v)
}

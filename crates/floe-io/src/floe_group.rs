//! One H5MD particle group of a fixed set of floes: its box, the floes'
//! fixed properties and the snapshot elements. A run whose floes never
//! change has one, `/particles/floes`; each change of the floe set
//! (fracture), or of its shapes and masses (ridging), starts the next,
//! `/particles/floes_1`, ... (a segment), from the snapshot its
//! `first_snapshot` attribute names.

use hdf5::File;

use floe_dem::floes::Floes;

use crate::appendable::Storage;
use crate::element::Element;
use crate::h5;
use crate::layout;
use crate::metadata::{DomainBox, OutputOptions};

/// A segment being written or read.
pub(crate) struct FloeGroup {
    /// Its index: 0 for `/particles/floes`.
    pub index: usize,
    /// The snapshot (over the whole file) its first row is.
    pub first_snapshot: usize,
    /// Its floes' ids, in row order.
    pub ids: Vec<u64>,
    /// The run's ridging events when its shapes and masses were written.
    pub ridging_events: u64,
    /// In [`layout::FLOE_ELEMENTS`] order, then the stress if written.
    pub elements: Vec<Element>,
}

impl FloeGroup {
    /// Creates segment `index` for `floes` (all of them, in handle order),
    /// starting at snapshot `first_snapshot` (`None` for the first
    /// segment, which records none); `land` marks land floes by id in a
    /// later segment (the first gets them from `RunWriter::mark_land`),
    /// `parents` gives each floe's parent id there (-1: none);
    /// `ridging_events`, the run's so far, is recorded when not zero.
    #[allow(clippy::type_complexity)] // the later segment's three records
    pub(crate) fn create(
        file: &File,
        index: usize,
        domain: &DomainBox,
        floes: &Floes,
        opts: &OutputOptions,
        later: Option<(usize, &[u64], &[i64])>,
        ridging_events: u64,
    ) -> hdf5::Result<Self> {
        let n = floes.len();
        let name = layout::floe_segment(index);
        let particles = match file.group("particles") {
            Ok(p) => p,
            Err(_) => file.create_group("particles")?,
        };
        let g = particles.create_group(name.trim_start_matches("particles/"))?;
        let b = g.create_group("box")?;
        h5::write_scalar(&b, "dimension", 2i32)?;
        let boundary = domain.periodic.map(|p| if p { "periodic" } else { "none" });
        h5::write_strs(&b, "boundary", &boundary)?;
        for (name, v) in [("edges", domain.size_m), ("origin", domain.min_m)] {
            let ds = b.new_dataset_builder().with_data(&v[..]).create(name)?;
            h5::write_str(&ds, "unit", "m")?;
        }
        let column = |name: &str, unit: &str, v: &[f64]| -> hdf5::Result<()> {
            let ds = g.new_dataset_builder().with_data(v).create(name)?;
            h5::write_str(&ds, "unit", unit)
        };
        g.new_dataset_builder()
            .with_data(&floes.id[..n])
            .create("id")?;
        let offsets = &floes.vertex_start[..=n];
        g.new_dataset_builder()
            .with_data(offsets)
            .create("vertex_offsets")?;
        let nv = offsets[n] as usize;
        let flat: Vec<f64> = floes.vertices[..nv]
            .iter()
            .flat_map(|v| [v.x, v.y])
            .collect();
        let vertices = ndarray::ArrayView2::from_shape((nv, 2), &flat)
            .map_err(|e| hdf5::Error::from(e.to_string()))?;
        let ds = g
            .new_dataset_builder()
            .with_data(vertices)
            .create("vertices")?;
        h5::write_str(&ds, "unit", "m")?;
        column("thickness", "m", &floes.thickness_m[..n])?;
        column("mass", "kg", &floes.mass_kg[..n])?;
        column("area", "m2", &floes.area_m2[..n])?;
        column("inertia", "kg m2", &floes.inertia_kg_m2[..n])?;
        let prescribed: Vec<u8> = (0..n).map(|i| u8::from(!floes.is_free(i))).collect();
        g.new_dataset_builder()
            .with_data(&prescribed[..])
            .create("prescribed")?;
        if ridging_events > 0 {
            h5::write_scalar(&g, layout::RIDGING_EVENTS, ridging_events)?;
        }
        let first_snapshot = match later {
            Some((first, land, parents)) => {
                h5::write_scalar(&g, layout::FIRST_SNAPSHOT, first as u64)?;
                g.new_dataset_builder()
                    .with_data(parents)
                    .create(layout::PARENT_ID)?;
                if !land.is_empty() {
                    let flags: Vec<u8> = floes.id[..n]
                        .iter()
                        .map(|id| u8::from(land.binary_search(id).is_ok()))
                        .collect();
                    g.new_dataset_builder()
                        .with_data(&flags[..])
                        .create(layout::LAND)?;
                }
                first
            }
            None => 0,
        };
        // Snapshot elements: one chunk per snapshot (up to MAX_FLOE_CHUNK
        // floes), compressed; each chunk is written once.
        let floe_chunk = n.min(layout::MAX_FLOE_CHUNK);
        let mut elements = Vec::new();
        let stress = opts.floe_stress.then_some(layout::FLOE_STRESS);
        for (name, unit, width) in layout::FLOE_ELEMENTS.into_iter().chain(stress) {
            let inner: Vec<usize> = if width == 1 { vec![n] } else { vec![n, width] };
            let chunk_inner: Vec<usize> = if width == 1 {
                vec![floe_chunk]
            } else {
                vec![floe_chunk, width]
            };
            let storage = Storage {
                chunk_rows: 1,
                chunk_inner,
                deflate: opts.deflate_level,
                shuffle: opts.shuffle,
            };
            let element = Element::create(&g, name, unit, &inner, &storage)?;
            if name == layout::FLOE_STRESS.0 {
                h5::write_str(
                    element.value.dataset(),
                    "components",
                    layout::STRESS_COMPONENTS,
                )?;
            }
            elements.push(element);
        }
        Ok(FloeGroup {
            index,
            first_snapshot,
            ids: floes.id[..n].to_vec(),
            ridging_events,
            elements,
        })
    }

    /// Segment `index` of `file`, if it has one.
    pub(crate) fn open(file: &File, index: usize) -> hdf5::Result<Option<Self>> {
        let name = layout::floe_segment(index);
        if !file.link_exists(&name) {
            return Ok(None);
        }
        let g = file.group(&name)?;
        let first_snapshot = if index == 0 {
            0
        } else {
            h5::read_scalar::<u64>(&g, layout::FIRST_SNAPSHOT)? as usize
        };
        let ids: Vec<u64> = g.dataset("id")?.read_raw()?;
        let ridging_events = if g.attr_names()?.iter().any(|a| a == layout::RIDGING_EVENTS) {
            h5::read_scalar::<u64>(&g, layout::RIDGING_EVENTS)?
        } else {
            0
        };
        let mut elements = Vec::new();
        for (name, _, _) in layout::FLOE_ELEMENTS {
            elements.push(Element::open(&g, name)?);
        }
        if g.link_exists(layout::FLOE_STRESS.0) {
            elements.push(Element::open(&g, layout::FLOE_STRESS.0)?);
        }
        Ok(Some(FloeGroup {
            index,
            first_snapshot,
            ids,
            ridging_events,
            elements,
        }))
    }

    /// Complete snapshots in it (every element's three datasets written).
    pub(crate) fn rows(&self) -> usize {
        self.elements.iter().map(Element::rows).min().unwrap_or(0)
    }

    /// Whether it holds floe stress.
    pub(crate) fn has_stress(&self) -> bool {
        self.elements.len() > layout::FLOE_ELEMENTS.len()
    }
}

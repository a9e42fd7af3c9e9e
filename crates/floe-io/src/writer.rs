//! Writing a run: the file's layout at creation, then snapshots,
//! observables and checkpoints as the run goes, and the truncation that
//! makes a resumed file end as the uninterrupted run's would.

use std::path::{Path, PathBuf};

use floe_dem::floes::Floes;
use floe_dem::forcing::ExternalForces;
use floe_dem::observables::Observables;
use floe_dem::state::WorldState;
use floe_dem::world::{FractureEvent, PlannedRidge, Weld, World};
use floe_friction::FrictionLaw;
use hdf5::Group;

use crate::appendable::{Appendable, Storage};
use crate::checkpoint::{self, fnv1a64, OutputCounts};
use crate::element::Element;
use crate::error::{invalid, Context, IoError};
use crate::floe_group::FloeGroup;
use crate::fracture_log::FractureLog;
use crate::h5;
use crate::headroom::Headroom;
use crate::layout;
use crate::metadata::{CheckpointInfo, DomainBox, InputRecord, OutputOptions, RunMetadata};
use crate::reader::{self, RunFile};
use crate::ridging_log::RidgingLog;
use crate::welding_log::WeldingLog;

/// The contact datasets.
struct ContactTables {
    /// Rows per chunk.
    chunk_rows: usize,
    /// Whether each snapshot's rows start on a chunk boundary (for
    /// compressed datasets, so that each chunk is written once).
    pad: bool,
    pair: Appendable,
    /// In [`layout::CONTACT_FIELDS`] order.
    fields: Vec<Appendable>,
    start: Appendable,
    count: Appendable,
    step: Appendable,
    time: Appendable,
}

impl ContactTables {
    fn per_snapshot(&mut self) -> [&mut Appendable; 4] {
        [
            &mut self.start,
            &mut self.count,
            &mut self.step,
            &mut self.time,
        ]
    }

    fn per_row(&mut self) -> impl Iterator<Item = &mut Appendable> {
        std::iter::once(&mut self.pair).chain(self.fields.iter_mut())
    }
}

/// Writes a run file: created once, then appended to as the run goes.
pub struct RunWriter {
    path: PathBuf,
    file: hdf5::File,
    /// The floe group being written: the last segment.
    segment: FloeGroup,
    /// The domain, for the box of a new segment.
    domain: DomainBox,
    /// Compression and stress, for a new segment.
    opts: OutputOptions,
    /// Ids of the land floes, sorted, for a new segment.
    land_ids: Vec<u64>,
    /// The fracture event log, from the first event on.
    fractures: Option<FractureLog>,
    /// The ridging event log, from the first event on.
    ridges: Option<RidgingLog>,
    /// The welding event log, from the first weld on.
    welds: Option<WeldingLog>,
    contacts: ContactTables,
    /// In [`layout::observable_samples`] order, then
    /// [`layout::BONDS_OBSERVABLE`] if the run has cohesion and
    /// [`layout::ridging_samples`]'s if it ridges.
    observables: Vec<(String, Element)>,
    next_slot: usize,
    /// Observable samples not yet written.
    pending: Vec<(u64, Observables)>,
    /// Room claimed past the end of the file before each batch of writes.
    headroom: Headroom,
}

impl Drop for RunWriter {
    fn drop(&mut self) {
        // Best effort: errors here have no one to go to; a caller that
        // cares calls flush() first.
        if self.flush().is_ok() {
            self.headroom.give_back(self.file.size());
        }
    }
}

impl RunWriter {
    /// Creates the run file at `path` with the run's metadata and the
    /// floes' fixed properties (shapes, masses), for the owned floes of
    /// `floes`. Refuses to replace an existing file.
    pub fn create(
        path: &Path,
        meta: &RunMetadata,
        floes: &Floes,
        opts: &OutputOptions,
    ) -> Result<Self, IoError> {
        let cannot = |reason: String| IoError::CannotCreate {
            path: path.to_path_buf(),
            reason,
        };
        if path.symlink_metadata().is_ok() {
            return Err(IoError::AlreadyExists {
                path: path.to_path_buf(),
            });
        }
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        match parent.metadata() {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(cannot(format!(
                    "directory {} does not exist",
                    parent.display()
                )))
            }
            Err(e) => return Err(cannot(format!("{}: {e}", parent.display()))),
            Ok(m) if !m.is_dir() => {
                return Err(cannot(format!("{} is not a directory", parent.display())))
            }
            Ok(m) if m.permissions().readonly() => {
                return Err(cannot(format!(
                    "directory {} is read-only",
                    parent.display()
                )))
            }
            Ok(_) => {}
        }
        if floes.is_empty() {
            return Err(cannot("there are no floes to write".into()));
        }
        let file = h5::create_file(path).map_err(|e| {
            let text = e.to_string();
            cannot(if text.contains("Permission denied") {
                format!("permission denied in {}", parent.display())
            } else {
                text
            })
        })?;
        match Self::lay_out(path, file, meta, floes, opts) {
            Ok(w) => Ok(w),
            Err(e) => {
                // The file is ours and half-made: do not leave it behind.
                let _ = std::fs::remove_file(path);
                Err(match e {
                    IoError::NoSpace { reason, .. } => cannot(reason),
                    e => e,
                })
            }
        }
    }

    fn lay_out(
        path: &Path,
        file: hdf5::File,
        meta: &RunMetadata,
        floes: &Floes,
        opts: &OutputOptions,
    ) -> Result<Self, IoError> {
        let n = floes.len();
        let mut headroom = Headroom::open(path, file.size())?;
        headroom.claim(path, file.size(), n as u64 * 512)?;
        let at = |what: &str| {
            let what = what.to_string();
            move || format!("writing {what}")
        };
        // /h5md
        (|| -> hdf5::Result<()> {
            let g = file.create_group(layout::H5MD)?;
            h5::write_array(&g, "version", &layout::H5MD_VERSION)?;
            let author = g.create_group("author")?;
            h5::write_str(&author, "name", &meta.author)?;
            let creator = g.create_group("creator")?;
            h5::write_str(&creator, "name", layout::CREATOR)?;
            h5::write_str(&creator, "version", &meta.floe_version)?;
            Ok(())
        })()
        .at(path, at("/h5md"))?;
        // /parameters
        (|| -> hdf5::Result<()> {
            let g = file.create_group(layout::PARAMETERS)?;
            h5::write_scalar(&g, "layout_version", layout::LAYOUT_VERSION)?;
            g.new_dataset::<hdf5::types::VarLenUnicode>()
                .create("scenario_toml")?
                .write_scalar(&h5::vlen(&meta.scenario_toml)?)?;
            h5::write_scalar(
                &g,
                layout::SCENARIO_CHECKSUM,
                fnv1a64(meta.scenario_toml.as_bytes()),
            )?;
            h5::write_str(&g, "scenario_path", &meta.scenario_path)?;
            h5::write_str(&g, "floe_version", &meta.floe_version)?;
            h5::write_str(&g, "git_commit", &meta.git_commit)?;
            let args: Vec<&str> = meta.command_line.iter().map(String::as_str).collect();
            h5::write_strs(&g, "command_line", &args)?;
            h5::write_scalar(&g, "threads", meta.threads as u64)?;
            h5::write_scalar(&g, "processes", meta.processes as u64)?;
            h5::write_str(&g, "author", &meta.author)?;
            h5::write_str(&g, "status", "created")?;
            if !meta.inputs.is_empty() {
                let col =
                    |f: fn(&InputRecord) -> &str| meta.inputs.iter().map(f).collect::<Vec<_>>();
                h5::write_strs(&g, "input_roles", &col(|r| &r.role))?;
                h5::write_strs(&g, "input_paths", &col(|r| &r.path))?;
                h5::write_strs(&g, "input_sha256", &col(|r| &r.sha256))?;
            }
            let d = g.create_group("domain")?;
            h5::write_array(&d, "min", &meta.domain.min_m)?;
            h5::write_array(&d, "size", &meta.domain.size_m)?;
            h5::write_array(&d, "periodic", &meta.domain.periodic.map(u8::from))?;
            h5::write_str(&d, "unit", "m")?;
            Ok(())
        })()
        .at(path, at("/parameters"))?;
        // /particles/floes: box, fixed properties, snapshot elements.
        let segment = FloeGroup::create(&file, 0, &meta.domain, floes, opts, None, 0)
            .at(path, at("/particles/floes"))?;
        // Contacts: compressed, each snapshot starts a chunk (padded with
        // fill values) so that each compressed chunk is written once.
        let chunk_rows = n.next_power_of_two().clamp(256, 16_384);
        let contacts = (|| -> hdf5::Result<ContactTables> {
            let g = file.create_group(layout::CONTACTS)?;
            h5::write_scalar(&g, "chunk_rows", chunk_rows as u64)?;
            let rows = |inner: &[usize]| Storage {
                chunk_rows,
                chunk_inner: inner.to_vec(),
                deflate: opts.deflate_level,
                shuffle: opts.shuffle,
            };
            let pair = Appendable::create::<u32>(&g, "pair", &[2], &rows(&[2]), Some(u32::MAX))?;
            let mut fields = Vec::new();
            for (name, unit, width) in layout::CONTACT_FIELDS {
                let inner: &[usize] = if width == 1 { &[] } else { &[2] };
                let a = Appendable::create::<f64>(&g, name, inner, &rows(inner), Some(f64::NAN))?;
                h5::write_str(a.dataset(), "unit", unit)?;
                fields.push(a);
            }
            let series = Storage::plain(layout::SERIES_CHUNK, &[]);
            let time = Appendable::create::<f64>(&g, "time", &[], &series, None)?;
            h5::write_str(time.dataset(), "unit", "s")?;
            Ok(ContactTables {
                chunk_rows,
                pad: opts.deflate_level > 0,
                pair,
                fields,
                start: Appendable::create::<u64>(&g, "start", &[], &series, None)?,
                count: Appendable::create::<u64>(&g, "count", &[], &series, None)?,
                step: Appendable::create::<i64>(&g, "step", &[], &series, None)?,
                time,
            })
        })()
        .at(path, at("/contacts"))?;
        // Observables: small, uncompressed (their chunks are rewritten).
        let observables = (|| -> hdf5::Result<Vec<(String, Element)>> {
            let g = file.create_group(layout::OBSERVABLES)?;
            let mut v = Vec::new();
            for (name, unit, values) in layout::observable_samples(&Observables::default()) {
                v.push((
                    name.to_string(),
                    create_observable(&g, name, unit, values.len())?,
                ));
            }
            if opts.bonds {
                let name = layout::BONDS_OBSERVABLE;
                v.push((name.to_string(), create_observable(&g, name, "1", 1)?));
            }
            if opts.ridging {
                for (name, unit, values) in layout::ridging_samples(&Observables::default()) {
                    v.push((
                        name.to_string(),
                        create_observable(&g, name, unit, values.len())?,
                    ));
                }
            }
            Ok(v)
        })()
        .at(path, at("/observables"))?;
        // Checkpoint slots, sized for the first state; grown when needed.
        let estimate = 4096 + 400 * floes.len() + 16 * floes.vertices.len();
        let slot_chunk = estimate.next_power_of_two().clamp(4096, 1 << 20);
        (|| -> hdf5::Result<()> {
            let g = file.create_group(layout::CHECKPOINT)?;
            h5::write_scalar(&g, layout::VALID_SLOT, -1i64)?;
            h5::write_str(&g, "format", "floe checkpoint, see docs/output.md")?;
            for name in layout::SLOTS {
                let s = Storage::plain(slot_chunk, &[]);
                let a = Appendable::create::<u8>(&g, name, &[], &s, None)?;
                let ds = a.dataset();
                h5::write_scalar(ds, "step", 0u64)?;
                h5::write_scalar(ds, "time", f64::NAN)?;
                h5::write_scalar(ds, "bytes", 0u64)?;
                h5::write_scalar(ds, "snapshot_count", 0u64)?;
                h5::write_scalar(ds, "contact_rows", 0u64)?;
            }
            Ok(())
        })()
        .at(path, at("/checkpoint"))?;
        file.flush().at(path, || "flushing the new file".into())?;
        Ok(Self {
            path: path.to_path_buf(),
            file,
            segment,
            domain: meta.domain,
            opts: *opts,
            land_ids: Vec::new(),
            fractures: None,
            ridges: None,
            welds: None,
            contacts,
            observables,
            next_slot: 0,
            pending: Vec::new(),
            headroom,
        })
    }

    /// Marks the floes with ids in `land_ids` as land (fixed pieces of
    /// coastlines and islands, `[[land]]`) in `/particles/floes/land`
    /// (uint8, one per floe, 1: land), so that pictures tell land from walls. Ids the
    /// file does not hold are ignored. A file without the dataset (older
    /// files, runs without land) has no land. Call once, after
    /// [`RunWriter::create`].
    pub fn mark_land(&mut self, land_ids: &[u64]) -> Result<(), IoError> {
        let mut sorted = land_ids.to_vec();
        sorted.sort_unstable();
        let flags: Vec<u8> = self
            .segment
            .ids
            .iter()
            .map(|id| u8::from(sorted.binary_search(id).is_ok()))
            .collect();
        self.land_ids = sorted;
        (|| -> hdf5::Result<()> {
            self.file
                .group(layout::FLOES)?
                .new_dataset_builder()
                .with_data(&flags[..])
                .create(layout::LAND)?;
            Ok(())
        })()
        .at(&self.path, || {
            format!("writing /{}/{}", layout::FLOES, layout::LAND)
        })?;
        self.file.flush().at(&self.path, || "flushing".to_string())
    }

    /// The file written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends a snapshot of the owned floes (position, velocity, angle,
    /// angular velocity, and stress if the file holds it) and of the
    /// contacts between them, at the world's step and time, and flushes.
    pub fn write_snapshot<F: ExternalForces>(&mut self, world: &World<F>) -> Result<(), IoError> {
        let f = world.floes();
        let n = f.len();
        // A new floe set (fracture) or new shapes and masses (ridging).
        if f.id != self.segment.ids || world.ridging_ledger().events != self.segment.ridging_events
        {
            self.start_segment(world)?;
        }
        let (step, time) = (world.steps(), world.time_s());
        // Floe arrays, contact rows (88 B, padded to a chunk) and indices.
        let rows = (world.contacts().len() + self.contacts.chunk_rows) as u64;
        self.claim(n as u64 * 64 + rows * 96 + (256 << 10))?;
        let xy = |v: &[floe_dem::Vec2]| -> Vec<f64> { v.iter().flat_map(|p| [p.x, p.y]).collect() };
        let mut values = vec![
            xy(&f.position[..n]),
            xy(&f.velocity[..n]),
            f.angle[..n].to_vec(),
            f.angular_velocity[..n].to_vec(),
        ];
        let mut names = layout::FLOE_ELEMENTS.map(|(name, _, _)| name).to_vec();
        if self.segment.has_stress() {
            let stress = world.floe_stress();
            if stress.len() != n {
                return Err(invalid(
                    &self.path,
                    "the file holds floe stress but the world does not compute it",
                ));
            }
            values.push(stress.iter().flatten().copied().collect());
            names.push(layout::FLOE_STRESS.0);
        }
        let group = layout::floe_segment(self.segment.index);
        for (name, (el, v)) in names
            .iter()
            .zip(self.segment.elements.iter_mut().zip(&values))
        {
            el.append(step, time, v)
                .at(&self.path, || format!("appending to /{group}/{name}"))?;
        }
        let cs = world.contacts();
        let law = &world.model().law;
        let m = cs.len();
        let chunk = self.contacts.chunk_rows;
        let pad = if self.contacts.pad {
            (chunk - m % chunk) % chunk
        } else {
            0
        };
        let pairs: Vec<u32> = cs.iter().flat_map(|c| [c.a, c.b]).collect();
        let columns: [Vec<f64>; 8] = [
            cs.iter().map(|c| law.theta(&c.friction)).collect(),
            cs.iter().map(|c| c.mu()).collect(),
            cs.iter().map(|c| c.normal_force_n).collect(),
            cs.iter().map(|c| c.tangential_force_n()).collect(),
            cs.iter().map(|c| c.slip_rate_m_per_s).collect(),
            cs.iter().map(|c| c.overlap_m2).collect(),
            cs.iter().flat_map(|c| [c.point.x, c.point.y]).collect(),
            cs.iter().flat_map(|c| [c.normal.x, c.normal.y]).collect(),
        ];
        let start = self.contacts.pair.rows() as u64;
        let path = self.path.clone();
        let what = || "appending to /contacts".to_string();
        self.contacts
            .pair
            .append_padded(&pairs, pad)
            .at(&path, what)?;
        for (a, v) in self.contacts.fields.iter_mut().zip(&columns) {
            a.append_padded(v, pad).at(&path, what)?;
        }
        let c = &mut self.contacts;
        c.start.append(&[start]).at(&path, what)?;
        c.count.append(&[m as u64]).at(&path, what)?;
        c.step.append(&[step as i64]).at(&path, what)?;
        c.time.append(&[time]).at(&path, what)?;
        self.flush()
    }

    /// Appends `events` to the fracture log (made at the first).
    pub fn write_fractures(&mut self, events: &[FractureEvent]) -> Result<(), IoError> {
        if events.is_empty() {
            return Ok(());
        }
        self.claim(events.len() as u64 * 64 + (64 << 10))?;
        let what = || format!("appending to /{}", layout::FRACTURE);
        if self.fractures.is_none() {
            self.fractures = Some(FractureLog::open_or_create(&self.file).at(&self.path, what)?);
        }
        let log = self.fractures.as_mut().expect("made above");
        log.append(events).at(&self.path, what)
    }

    /// Appends `events`, made at simulated time `time_s`, to the ridging
    /// log (made at the first).
    pub fn write_ridges(&mut self, time_s: f64, events: &[PlannedRidge]) -> Result<(), IoError> {
        if events.is_empty() {
            return Ok(());
        }
        self.claim(events.len() as u64 * 128 + (64 << 10))?;
        let what = || format!("appending to /{}", layout::RIDGING);
        if self.ridges.is_none() {
            self.ridges = Some(RidgingLog::open_or_create(&self.file).at(&self.path, what)?);
        }
        let log = self.ridges.as_mut().expect("made above");
        log.append(time_s, events).at(&self.path, what)
    }

    /// Appends `welds` to the welding log (made at the first).
    pub fn write_welds(&mut self, welds: &[Weld]) -> Result<(), IoError> {
        if welds.is_empty() {
            return Ok(());
        }
        self.claim(welds.len() as u64 * 128 + (64 << 10))?;
        let what = || format!("appending to /{}", layout::WELDING);
        if self.welds.is_none() {
            self.welds = Some(WeldingLog::open_or_create(&self.file).at(&self.path, what)?);
        }
        let log = self.welds.as_mut().expect("made above");
        log.append(welds).at(&self.path, what)
    }

    /// Starts the next segment for the world's floes (their set changed:
    /// fracture; or their shapes and masses: ridging), from the next
    /// snapshot on.
    fn start_segment<F: ExternalForces>(&mut self, world: &World<F>) -> Result<(), IoError> {
        let floes = world.floes();
        self.claim(floes.len() as u64 * 512 + floes.vertices.len() as u64 * 16)?;
        let index = self.segment.index + 1;
        let first = self.segment.first_snapshot + self.segment.rows();
        let opts = OutputOptions {
            floe_stress: world.stress_filter().is_some(),
            ..self.opts
        };
        // Each floe's parent, from the fracture log so far.
        let log = crate::fracture_log::read(&self.file)
            .at(&self.path, || format!("reading /{}", layout::FRACTURE))?;
        let mut parent_of = std::collections::HashMap::new();
        for e in &log {
            for &piece in &e.piece_ids {
                parent_of.insert(piece, e.parent_id as i64);
            }
        }
        // A welded floe's parent is the first of its pair (the welding log
        // names both).
        let welds = crate::welding_log::read(&self.file)
            .at(&self.path, || format!("reading /{}", layout::WELDING))?;
        for w in &welds {
            parent_of.insert(w.welded_id, w.ids[0] as i64);
        }
        let parents: Vec<i64> = (floes.id.iter())
            .map(|id| parent_of.get(id).copied().unwrap_or(-1))
            .collect();
        self.segment = FloeGroup::create(
            &self.file,
            index,
            &self.domain,
            floes,
            &opts,
            Some((first, &self.land_ids, &parents)),
            world.ridging_ledger().events,
        )
        .at(&self.path, || {
            format!("writing /{}", layout::floe_segment(index))
        })?;
        Ok(())
    }

    /// Appends one sample of every observable, at `step` and `o.time_s`.
    ///
    /// Samples are buffered and written in batches (with the next snapshot,
    /// checkpoint or flush, when the writer is dropped, or every
    /// [`layout::SERIES_CHUNK`] samples): one HDF5 append per series and
    /// sample cost about 0.4 ms, more than a step of a 1000-floe run. A
    /// checkpoint writes the buffer first, so what a resume keeps is complete.
    pub fn write_observables(&mut self, step: u64, o: &Observables) -> Result<(), IoError> {
        self.pending.push((step, *o));
        if self.pending.len() >= layout::SERIES_CHUNK {
            self.write_pending()?;
        }
        Ok(())
    }

    /// Writes the buffered observable samples.
    fn write_pending(&mut self) -> Result<(), IoError> {
        if self.pending.is_empty() {
            return Ok(());
        }
        self.claim(self.pending.len() as u64 * 256 + (64 << 10))?;
        let steps: Vec<i64> = self.pending.iter().map(|(s, _)| *s as i64).collect();
        let times: Vec<f64> = self.pending.iter().map(|(_, o)| o.time_s).collect();
        let samples: Vec<_> = self
            .pending
            .iter()
            .map(|(_, o)| layout::observable_samples(o))
            .collect();
        for (k, (name, el)) in self.observables.iter_mut().enumerate() {
            let values: Vec<f64> = match samples.first().and_then(|s| s.get(k)) {
                Some(_) => samples
                    .iter()
                    .flat_map(|s| s[k].2.iter().copied())
                    .collect(),
                None => self
                    .pending
                    .iter()
                    .flat_map(|(_, o)| layout::optional_sample(name, o).unwrap_or_default())
                    .collect(),
            };
            (|| -> hdf5::Result<()> {
                el.step.append(&steps)?;
                el.time.append(&times)?;
                el.value.append(&values)
            })()
            .at(&self.path, || format!("appending to /observables/{name}"))?;
        }
        self.pending.clear();
        Ok(())
    }

    /// Writes `state` as the new checkpoint, with the output written so
    /// far, into the slot not holding the current one; then flushes, marks
    /// it valid and flushes again. A process killed at any point leaves one
    /// valid checkpoint (the old or the new).
    pub fn write_checkpoint(
        &mut self,
        state: &WorldState,
        law_state_slots: usize,
    ) -> Result<(), IoError> {
        self.write_pending()?;
        let counts = OutputCounts {
            snapshots: (self.segment.first_snapshot + self.segment.rows()) as u64,
            contact_rows: self.contacts.pair.rows() as u64,
            observables: self
                .observables
                .iter()
                .map(|(name, el)| (name.clone(), el.rows() as u64))
                .collect(),
        };
        let blob = checkpoint::encode(state, &counts, law_state_slots);
        // A slot that grows is written anew, a quarter larger.
        self.claim(2 * blob.len() as u64 + (256 << 10))?;
        let slot = self.next_slot;
        let name = layout::SLOTS[slot];
        let path = self.path.clone();
        let what = || format!("writing checkpoint /{}/{name}", layout::CHECKPOINT);
        let group = self.file.group(layout::CHECKPOINT).at(&path, what)?;
        (|| -> hdf5::Result<()> {
            let ds = group.dataset(name)?;
            let capacity = ds.shape()[0];
            if blob.len() > capacity {
                let chunk = ds.chunk().map_or(4096, |c| c[0]).max(1);
                let wanted = blob.len() + blob.len() / 4;
                ds.resize(wanted.div_ceil(chunk) * chunk)?;
            }
            ds.write_slice(&blob[..], 0..blob.len())?;
            ds.attr("step")?.write_scalar(&state.steps)?;
            ds.attr("time")?.write_scalar(&state.time_s)?;
            ds.attr("bytes")?.write_scalar(&(blob.len() as u64))?;
            ds.attr("snapshot_count")?.write_scalar(&counts.snapshots)?;
            ds.attr("contact_rows")?
                .write_scalar(&counts.contact_rows)?;
            self.file.flush()?;
            group
                .attr(layout::VALID_SLOT)?
                .write_scalar(&(slot as i64))?;
            self.file.flush()
        })()
        .at(&path, what)?;
        self.next_slot = 1 - slot;
        Ok(())
    }

    /// Sets the run's status (`/parameters` attribute `status`), e.g.
    /// `running`, `completed`, `interrupted at step 12`.
    pub fn set_status(&mut self, status: &str) -> Result<(), IoError> {
        self.claim(64 << 10)?;
        (|| -> hdf5::Result<()> {
            let g = self.file.group(layout::PARAMETERS)?;
            g.attr("status")?.write_scalar(&h5::vlen(status)?)
        })()
        .at(&self.path, || format!("setting the status to {status:?}"))
    }

    /// Claims room for a batch of writes of about `bytes`
    /// ([`crate::headroom`]).
    fn claim(&mut self, bytes: u64) -> Result<(), IoError> {
        self.headroom.claim(&self.path, self.file.size(), bytes)
    }

    /// Writes everything buffered to the file.
    pub fn flush(&mut self) -> Result<(), IoError> {
        self.write_pending()?;
        self.file.flush().at(&self.path, || "flushing".to_string())
    }

    /// Opens the run file at `path` to continue it: reads its valid
    /// checkpoint and truncates every snapshot, contact and observable
    /// dataset to what had been written when the checkpoint was taken, so
    /// the continued file ends as an uninterrupted run's would. Returns the
    /// writer, the state to resume from and where it stands. A checkpoint
    /// of format 1 or 2 takes its time step from `fallback_dt_s`; one of
    /// format 3 or 4 must hold `law_state_slots` per contact (the law's).
    pub fn reopen_for_resume(
        path: &Path,
        fallback_dt_s: impl FnOnce() -> Option<f64>,
        law_state_slots: usize,
    ) -> Result<(Self, WorldState, CheckpointInfo), IoError> {
        let file = h5::open_run(path, true)?;
        check_scenario_unchanged(&file, path)?;
        let (slot, state, counts) =
            reader::read_checkpoint(&file, path, fallback_dt_s, Some(law_state_slots))?
                .ok_or_else(|| IoError::NoCheckpoint {
                    path: path.to_path_buf(),
                })?;
        let slot_name = format!("/{}/{}", layout::CHECKPOINT, layout::SLOTS[slot]);
        let corrupt = |reason: String| IoError::CorruptCheckpoint {
            path: path.to_path_buf(),
            slot: slot_name.clone(),
            reason,
        };
        let what = || "opening the datasets to resume".to_string();
        // The floe groups (segments); the resumed run writes on the last
        // that starts before the checkpoint's snapshot count.
        let mut segments = Vec::new();
        loop {
            match FloeGroup::open(&file, segments.len()) {
                Ok(Some(g)) => segments.push(g),
                Ok(None) => break,
                // A later segment the writer stopped inside: it goes below.
                Err(_) if !segments.is_empty() => break,
                Err(e) => return Err(e).at(path, what),
            }
        }
        let snapshots = counts.snapshots as usize;
        let keep = segments
            .iter()
            .rposition(|g| g.first_snapshot < snapshots)
            .unwrap_or(0);
        let Some(mut segment) = segments.drain(..).nth(keep) else {
            return Err(corrupt(format!("the file has no /{}", layout::FLOES)));
        };
        // A run without fracture keeps its floes: the checkpoint's are the
        // file's (with fracture they may be the next segment's).
        if state.next_floe_id == 0 && state.floes.id != segment.ids {
            return Err(corrupt(format!(
                "its {} floes are not the file's {}",
                state.floes.len(),
                segment.ids.len()
            )));
        }
        let stress = layout::FLOE_STRESS.0;
        let group = layout::floe_segment(segment.index);
        match (state.stress_filter.is_some(), segment.has_stress()) {
            (true, true) | (false, false) => {}
            (on, _) => {
                return Err(corrupt(format!(
                    "it {} floe stress but the file {} /{group}/{stress}",
                    if on { "holds" } else { "holds no" },
                    if on { "has no" } else { "has" },
                )))
            }
        }
        let cg = file.group(layout::CONTACTS).at(path, what)?;
        let mut contacts = (|| -> hdf5::Result<ContactTables> {
            let pair = Appendable::open(&cg, "pair")?;
            let chunk_rows = pair.dataset().chunk().map_or(1, |c| c[0]).max(1);
            Ok(ContactTables {
                chunk_rows,
                pad: !pair.dataset().filters().is_empty(),
                pair,
                fields: layout::CONTACT_FIELDS
                    .iter()
                    .map(|(name, _, _)| Appendable::open(&cg, name))
                    .collect::<hdf5::Result<_>>()?,
                start: Appendable::open(&cg, "start")?,
                count: Appendable::open(&cg, "count")?,
                step: Appendable::open(&cg, "step")?,
                time: Appendable::open(&cg, "time")?,
            })
        })()
        .at(path, what)?;
        let og = file.group(layout::OBSERVABLES).at(path, what)?;
        let og_has_bonds = og.link_exists(layout::BONDS_OBSERVABLE);
        let mut observables = Vec::new();
        for (name, unit, values) in layout::observable_samples(&Observables::default()) {
            // A file from a floe without this observable gets it now: its
            // series starts at the resume.
            let el = if og.link_exists(name) {
                Element::open(&og, name)
            } else {
                create_observable(&og, name, unit, values.len())
            };
            observables.push((name.to_string(), el.at(path, what)?));
        }
        if og_has_bonds {
            let el = Element::open(&og, layout::BONDS_OBSERVABLE).at(path, what)?;
            observables.push((layout::BONDS_OBSERVABLE.to_string(), el));
        }
        let ridging_names = layout::ridging_samples(&Observables::default()).map(|(n, _, _)| n);
        let og_has_ridging = og.link_exists(ridging_names[0]);
        if og_has_ridging {
            for name in ridging_names {
                let el = Element::open(&og, name).at(path, what)?;
                observables.push((name.to_string(), el));
            }
        }
        // Truncate to the checkpoint's counts; refuse counts the file does
        // not reach (the checkpoint would describe output that is not there).
        let snapshots = counts.snapshots as usize;
        let exceeds = |what: &str, want: u64, have: usize| {
            corrupt(format!(
                "it records {want} {what} but the file holds {have}"
            ))
        };
        let local = snapshots - segment.first_snapshot.min(snapshots);
        if segment.rows() < local {
            let have = segment.first_snapshot + segment.rows();
            return Err(exceeds("snapshots", counts.snapshots, have));
        }
        let rows = counts.contact_rows as usize;
        if contacts.per_row().any(|a| a.rows() < rows) {
            return Err(exceeds(
                "contact rows",
                counts.contact_rows,
                contacts.pair.rows(),
            ));
        }
        if contacts.per_snapshot().iter().any(|a| a.rows() < snapshots) {
            return Err(exceeds(
                "contact snapshots",
                counts.snapshots,
                contacts.start.rows(),
            ));
        }
        let mut observable_rows = Vec::new();
        for (name, el) in &observables {
            let want = counts
                .observables
                .iter()
                .find(|(n, _)| n == name)
                .map_or(0, |&(_, c)| c);
            if el.rows() < want as usize {
                return Err(exceeds(&format!("{name} samples"), want, el.rows()));
            }
            observable_rows.push(want as usize);
        }
        // What a new segment needs: the domain's box and the land.
        let reader = RunFile::of_open(path, file.clone());
        let domain = reader.metadata()?.domain;
        let first = reader.static_floes()?;
        let land_ids: Vec<u64> = (0..first.len())
            .filter(|&i| first.land[i])
            .map(|i| first.id[i])
            .collect();
        let mut headroom = Headroom::open(path, file.size())?;
        headroom.claim(path, file.size(), 0)?;
        let what = || "truncating the output to the checkpoint".to_string();
        for el in &mut segment.elements {
            el.truncate(local).at(path, what)?;
        }
        // Segments after the checkpoint go: the resumed run makes them again.
        let mut later = keep + 1;
        while file.link_exists(&layout::floe_segment(later)) {
            file.unlink(&layout::floe_segment(later)).at(path, what)?;
            later += 1;
        }
        for a in contacts.per_row() {
            a.truncate(rows).at(path, what)?;
        }
        for a in contacts.per_snapshot() {
            a.truncate(snapshots).at(path, what)?;
        }
        for ((_, el), &want) in observables.iter_mut().zip(&observable_rows) {
            el.truncate(want).at(path, what)?;
        }
        let mut fractures = FractureLog::open(&file).at(path, what)?;
        if let Some(log) = fractures.as_mut() {
            log.truncate_after(state.steps).at(path, what)?;
        }
        let mut ridges = RidgingLog::open(&file).at(path, what)?;
        if let Some(log) = ridges.as_mut() {
            log.truncate_after(state.steps).at(path, what)?;
        }
        let mut welds = WeldingLog::open(&file).at(path, what)?;
        if let Some(log) = welds.as_mut() {
            log.truncate_after(state.steps).at(path, what)?;
        }
        file.flush().at(path, what)?;
        let info = CheckpointInfo {
            step: state.steps,
            time_s: state.time_s,
        };
        Ok((
            Self {
                path: path.to_path_buf(),
                file,
                segment,
                domain,
                opts: OutputOptions {
                    deflate_level: if contacts.pad { 4 } else { 0 },
                    shuffle: contacts.pad,
                    floe_stress: state.stress_filter.is_some(),
                    bonds: og_has_bonds,
                    ridging: og_has_ridging,
                },
                land_ids,
                fractures,
                ridges,
                welds,
                contacts,
                observables,
                next_slot: 1 - slot,
                pending: Vec::new(),
                headroom,
            },
            state,
            info,
        ))
    }
}

/// Refuses to resume a file whose stored scenario was edited after the run
/// began (files from before the checksum was recorded are not checked).
fn check_scenario_unchanged(file: &hdf5::File, path: &Path) -> Result<(), IoError> {
    let what = || "checking the stored scenario".to_string();
    let g = file.group(layout::PARAMETERS).at(path, what)?;
    if !g
        .attr_names()
        .at(path, what)?
        .iter()
        .any(|n| n == layout::SCENARIO_CHECKSUM)
    {
        return Ok(());
    }
    let recorded: u64 = g
        .attr(layout::SCENARIO_CHECKSUM)
        .and_then(|a| a.read_scalar())
        .at(path, what)?;
    let text = g
        .dataset("scenario_toml")
        .and_then(|d| d.read_scalar::<hdf5::types::VarLenUnicode>())
        .at(path, what)?;
    let now = fnv1a64(text.as_str().as_bytes());
    if now == recorded {
        Ok(())
    } else {
        Err(IoError::Invalid {
            path: path.to_path_buf(),
            reason: format!(
                "the stored scenario (/parameters/scenario_toml) was changed after the run began \
                 (checksum {now:016x}, recorded {recorded:016x}); a run resumes only with the \
                 scenario it started with: start a new run from the edited scenario instead"
            ),
        })
    }
}

/// An observable's element: plain (uncompressed) chunks of
/// [`layout::SERIES_CHUNK`] samples of `values` numbers each.
fn create_observable(g: &Group, name: &str, unit: &str, values: usize) -> hdf5::Result<Element> {
    let inner: Vec<usize> = if values == 1 { vec![] } else { vec![values] };
    let storage = Storage::plain(layout::SERIES_CHUNK, &inner);
    Element::create(g, name, unit, &inner, &storage)
}

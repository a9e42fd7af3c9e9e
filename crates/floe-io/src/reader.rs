//! Reading a run file: metadata, floes, snapshots, contacts, observables,
//! checkpoints.

use std::path::{Path, PathBuf};

use floe_dem::state::WorldState;
use hdf5::Dataset;

use crate::appendable::read_rows;
use crate::checkpoint::{self, OutputCounts};
use crate::error::{invalid, Context, IoError};
use crate::h5;
use crate::layout;
use crate::metadata::{CheckpointInfo, DomainBox, InputRecord, RunMetadata};

/// The floes' fixed properties (owned floes, in file order).
#[derive(Debug, Clone, PartialEq)]
pub struct StaticFloes {
    /// Global identifiers.
    pub id: Vec<u64>,
    /// Start of each floe's vertices in `vertices`, plus the end (length n + 1).
    pub vertex_offsets: Vec<u32>,
    /// Vertices of every floe about its centroid, in the floe's frame, m.
    pub vertices: Vec<[f64; 2]>,
    /// Thickness, m.
    pub thickness_m: Vec<f64>,
    /// Mass, kg.
    pub mass_kg: Vec<f64>,
    /// Area, m^2.
    pub area_m2: Vec<f64>,
    /// Moment of inertia about the centroid, kg m^2.
    pub inertia_kg_m2: Vec<f64>,
    /// Whether the floe moves at a prescribed velocity (a wall).
    pub prescribed: Vec<bool>,
    /// Whether the floe is a piece of land (`[[land]]`; fixed and
    /// prescribed). All false for files written without land, or before
    /// floe marked land.
    pub land: Vec<bool>,
}

impl StaticFloes {
    /// Number of floes.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// Whether there are no floes.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Floe `i`'s vertices in its own frame (about its centroid).
    pub fn local_vertices(&self, i: usize) -> &[[f64; 2]] {
        &self.vertices[self.vertex_offsets[i] as usize..self.vertex_offsets[i + 1] as usize]
    }
}

/// The floes' state at one snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// The run's step count.
    pub step: u64,
    /// Simulated time, s.
    pub time_s: f64,
    /// Centroid positions, m.
    pub position: Vec<[f64; 2]>,
    /// Centroid velocities, m/s.
    pub velocity: Vec<[f64; 2]>,
    /// Orientations, rad.
    pub angle: Vec<f64>,
    /// Angular velocities, rad/s.
    pub angular_velocity: Vec<f64>,
}

impl Snapshot {
    /// Floe `i`'s vertices in world coordinates: its local vertices turned
    /// by its angle and moved to its position (as the engine computes them).
    pub fn world_vertices(&self, floes: &StaticFloes, i: usize) -> Vec<[f64; 2]> {
        let (s, c) = self.angle[i].sin_cos();
        let [px, py] = self.position[i];
        floes
            .local_vertices(i)
            .iter()
            .map(|&[x, y]| [px + (c * x - s * y), py + (s * x + c * y)])
            .collect()
    }
}

/// The contacts at one snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSnapshot {
    /// The run's step count.
    pub step: u64,
    /// Simulated time, s.
    pub time_s: f64,
    /// Floe indices (into the floe arrays) of each contact, `a < b`.
    pub pair: Vec<[u32; 2]>,
    /// Rate-and-state state variable.
    pub theta: Vec<f64>,
    /// Friction coefficient `|F_t| / F_n`.
    pub mu: Vec<f64>,
    /// Normal force on `b`, N.
    pub normal_force_n: Vec<f64>,
    /// Tangential force on `b` along `perp(normal)`, N.
    pub tangential_force_n: Vec<f64>,
    /// Slip rate of `b` relative to `a`, m/s.
    pub slip_rate_m_per_s: Vec<f64>,
    /// Overlap area, m^2.
    pub overlap_m2: Vec<f64>,
    /// Contact point (in the frame where `a` is at its position), m.
    pub point: Vec<[f64; 2]>,
    /// Unit normal from `a` to `b`.
    pub normal: Vec<[f64; 2]>,
}

/// One observable's samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Step of each sample.
    pub step: Vec<u64>,
    /// Time of each sample, s.
    pub time_s: Vec<f64>,
    /// Values, flattened `[sample, ...sample_shape]`.
    pub value: Vec<f64>,
    /// Shape of one sample: `[]` for a number, `[4]` for the stress tensor.
    pub sample_shape: Vec<usize>,
    /// Unit of the values.
    pub unit: String,
}

/// A run file opened for reading.
pub struct RunFile {
    path: PathBuf,
    file: hdf5::File,
    /// The floe groups before the last, read once per handle: a writer
    /// appends to the last group only, so the earlier ones never change
    /// (reading every group for every snapshot made a render of a file
    /// with S groups cost S^2 group reads).
    sealed: std::sync::Mutex<SealedSegments>,
}

/// Floe groups that a later group follows: their snapshot ranges
/// (index, first snapshot, rows) and, once read, their floes.
#[derive(Debug, Default)]
struct SealedSegments {
    segments: Vec<(usize, usize, usize)>,
    floes: Vec<Option<StaticFloes>>,
}

fn pairs<T: Copy>(flat: &[T]) -> Vec<[T; 2]> {
    flat.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

/// Length of a dataset's first axis.
fn rows(ds: &Dataset) -> usize {
    ds.shape().first().copied().unwrap_or(0)
}

impl RunFile {
    /// A reader of `file`, already open (the writer's, on resume).
    pub(crate) fn of_open(path: &Path, file: hdf5::File) -> Self {
        Self {
            path: path.to_path_buf(),
            file,
            sealed: Default::default(),
        }
    }

    /// Opens the run file at `path` read-only, after checking that it is a
    /// floe run file.
    pub fn open(path: &Path) -> Result<Self, IoError> {
        Ok(Self {
            path: path.to_path_buf(),
            file: h5::open_run(path, false)?,
            sealed: Default::default(),
        })
    }

    /// Opens `path` and applies `read` to it, again on a fresh open if
    /// that fails with an HDF5 error or inconsistent content: a run being
    /// written flushes its metadata while a reader opens and reads, and a
    /// reader can catch an index that points past the end it saw at open
    /// ("addr overflow", about 1.7 % of `floe info` calls on a file written
    /// every 20 ms). The next try sees a consistent file; only a damaged
    /// one fails every try (2.5 s in all).
    pub fn read_retrying<T>(
        path: &Path,
        read: impl Fn(&RunFile) -> Result<T, IoError>,
    ) -> Result<T, IoError> {
        const TRIES: u32 = 8;
        let mut wait = std::time::Duration::from_millis(20);
        // Only a file can be half-written; a directory or a missing path
        // fails at once.
        let tries = if path.is_file() { TRIES } else { 1 };
        for _ in 1..tries {
            match RunFile::open(path).and_then(|run| read(&run)) {
                Err(IoError::Hdf5 { .. } | IoError::Invalid { .. }) => {
                    std::thread::sleep(wait);
                    wait *= 2;
                }
                done => return done,
            }
        }
        RunFile::open(path).and_then(|run| read(&run))
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    pub(crate) fn ds(&self, name: &str) -> Result<Dataset, IoError> {
        self.file
            .dataset(name)
            .at(&self.path, || format!("opening /{name}"))
    }

    fn read_all<T: hdf5::H5Type + Copy>(&self, name: &str) -> Result<Vec<T>, IoError> {
        self.ds(name)?
            .read_raw::<T>()
            .at(&self.path, || format!("reading /{name}"))
    }

    fn read_range<T: hdf5::H5Type + Copy>(
        &self,
        name: &str,
        range: std::ops::Range<usize>,
    ) -> Result<Vec<T>, IoError> {
        let ds = self.ds(name)?;
        if range.end > rows(&ds) {
            return Err(invalid(
                &self.path,
                format!(
                    "/{name} has {} rows, fewer than the {} expected (file damaged or being written)",
                    rows(&ds),
                    range.end
                ),
            ));
        }
        read_rows(&ds, range).at(&self.path, || format!("reading /{name}"))
    }

    fn read_one<T: hdf5::H5Type + Copy>(&self, name: &str, k: usize) -> Result<T, IoError> {
        self.read_range::<T>(name, k..k + 1)?
            .first()
            .copied()
            .ok_or_else(|| invalid(&self.path, format!("/{name} has no row {k}")))
    }

    /// The run's provenance and domain.
    pub fn metadata(&self) -> Result<RunMetadata, IoError> {
        let path = &self.path;
        (|| -> hdf5::Result<RunMetadata> {
            let g = self.file.group(layout::PARAMETERS)?;
            let d = g.group("domain")?;
            let two = |name: &str| -> hdf5::Result<[f64; 2]> {
                let v = d.attr(name)?.read_raw::<f64>()?;
                v.get(..2)
                    .map(|s| [s[0], s[1]])
                    .ok_or_else(|| format!("domain {name} has {} values", v.len()).into())
            };
            let periodic = d.attr("periodic")?.read_raw::<u8>()?;
            if periodic.len() != 2 {
                return Err("domain periodic does not have 2 values".into());
            }
            Ok(RunMetadata {
                scenario_toml: g
                    .dataset("scenario_toml")?
                    .read_scalar::<hdf5::types::VarLenUnicode>()?
                    .as_str()
                    .to_string(),
                scenario_path: h5::read_str(&g, "scenario_path")?,
                floe_version: h5::read_str(&g, "floe_version")?,
                git_commit: h5::read_str(&g, "git_commit")?,
                command_line: h5::read_strs(&g, "command_line")?,
                threads: g.attr("threads")?.read_scalar::<u64>()? as usize,
                processes: match g.attr("processes") {
                    Ok(a) => a.read_scalar::<u64>()? as usize,
                    Err(_) => 1,
                },
                author: h5::read_str(&g, "author")?,
                domain: DomainBox {
                    min_m: two("min")?,
                    size_m: two("size")?,
                    periodic: [periodic[0] != 0, periodic[1] != 0],
                },
                inputs: read_inputs(&g)?,
            })
        })()
        .at(path, || "reading /parameters".into())
    }

    /// The run's status: `created`, `running`, `completed`, `interrupted at step N`, ...
    pub fn status(&self) -> Result<String, IoError> {
        (|| -> hdf5::Result<String> {
            let g = self.file.group(layout::PARAMETERS)?;
            h5::read_str(&g, "status")
        })()
        .at(&self.path, || "reading /parameters status".into())
    }

    /// Snapshot `k`'s rows of the contact datasets: the first and how many.
    pub(crate) fn contact_rows(&self, k: usize) -> Result<(usize, usize), IoError> {
        let start: u64 = self.read_one(&format!("{}/start", layout::CONTACTS), k)?;
        let count: u64 = self.read_one(&format!("{}/count", layout::CONTACTS), k)?;
        Ok((start as usize, count as usize))
    }

    /// Whether segment `index` marks its pieces of land (files written
    /// without land, or before floe marked it, do not).
    pub(crate) fn has_land_marks(&self, index: usize) -> bool {
        self.file
            .link_exists(&format!("{}/{}", layout::floe_segment(index), layout::LAND))
    }

    /// The fixed properties of the floes the run began with (those of
    /// every snapshot unless floes broke: then [`RunFile::floes_at`]).
    pub fn static_floes(&self) -> Result<StaticFloes, IoError> {
        self.segment_floes(0)
    }

    /// The fixed properties of the floes of snapshot `k`, in the order of
    /// its arrays (a run whose floes break writes a segment per floe set,
    /// docs/output.md).
    pub fn floes_at(&self, k: usize) -> Result<StaticFloes, IoError> {
        let (segment, _) = self.locate(k)?;
        self.segment_floes(segment)
    }

    /// The floe groups (segments) of the file: each one's index, first
    /// snapshot and complete snapshots.
    fn segments(&self) -> Result<Vec<(usize, usize, usize)>, IoError> {
        let mut sealed = self.sealed.lock().unwrap_or_else(|e| e.into_inner());
        let out = self.segments_after(sealed.segments.clone())?;
        // All but the last are followed by another: sealed.
        let keep = out.len().saturating_sub(1);
        if keep > sealed.segments.len() {
            sealed.segments = out[..keep].to_vec();
            sealed.floes.resize(keep, None);
        }
        Ok(out)
    }

    /// `known` (the sealed segments) and the segments after them.
    fn segments_after(
        &self,
        known: Vec<(usize, usize, usize)>,
    ) -> Result<Vec<(usize, usize, usize)>, IoError> {
        let mut out = known;
        loop {
            let index = out.len();
            let name = layout::floe_segment(index);
            if !self.file.link_exists(&name) {
                return Ok(out);
            }
            // A later segment still being made (a writer stopped inside
            // it) counts as absent: it holds no snapshot yet.
            let made = |path: &str| self.file.link_exists(&format!("{name}/{path}"));
            let first = if index == 0 {
                0
            } else {
                let read = || -> hdf5::Result<u64> {
                    let g = self.file.group(&name)?;
                    h5::read_scalar(&g, layout::FIRST_SNAPSHOT)
                };
                match read() {
                    Ok(first) if made("angular_velocity/value") => first as usize,
                    _ => return Ok(out),
                }
            };
            let mut rows = usize::MAX;
            let stress = made(layout::FLOE_STRESS.0).then_some(layout::FLOE_STRESS);
            for (element, _, _) in layout::FLOE_ELEMENTS.into_iter().chain(stress) {
                for part in ["step", "time", "value"] {
                    rows = rows.min(self::rows(&self.ds(&format!("{name}/{element}/{part}"))?));
                }
            }
            out.push((index, first, rows));
        }
    }

    /// The segment holding snapshot `k` and the snapshot's row in it.
    pub(crate) fn locate(&self, k: usize) -> Result<(usize, usize), IoError> {
        let segments = self.segments()?;
        let n = self.count_of(&segments)?;
        if k >= n {
            return Err(invalid(
                &self.path,
                format!("no snapshot {k}: the file has {n} snapshots"),
            ));
        }
        let (index, first, _) = segments
            .iter()
            .rev()
            .find(|&&(_, first, _)| first <= k)
            .copied()
            .unwrap_or((0, 0, 0));
        Ok((index, k - first))
    }

    /// Segment `index`'s floes' fixed properties (read once if sealed).
    fn segment_floes(&self, index: usize) -> Result<StaticFloes, IoError> {
        let cached = {
            let sealed = self.sealed.lock().unwrap_or_else(|e| e.into_inner());
            sealed.floes.get(index).cloned()
        };
        match cached {
            Some(Some(floes)) => Ok(floes),
            Some(None) => {
                let floes = self.read_segment_floes(index)?;
                let mut sealed = self.sealed.lock().unwrap_or_else(|e| e.into_inner());
                sealed.floes[index] = Some(floes.clone());
                Ok(floes)
            }
            None => self.read_segment_floes(index),
        }
    }

    /// Segment `index`'s floes' fixed properties, from the file.
    fn read_segment_floes(&self, index: usize) -> Result<StaticFloes, IoError> {
        let group = layout::floe_segment(index);
        let p = |name: &str| format!("{group}/{name}");
        let id: Vec<u64> = self.read_all(&p("id"))?;
        let n = id.len();
        let vertex_offsets: Vec<u32> = self.read_all(&p("vertex_offsets"))?;
        let vertices = pairs(&self.read_all::<f64>(&p("vertices"))?);
        let land_path = p(layout::LAND);
        let land = if self.file.link_exists(&land_path) {
            self.read_all::<u8>(&land_path)?
                .into_iter()
                .map(|b| b != 0)
                .collect()
        } else {
            vec![false; n]
        };
        let floes = StaticFloes {
            land,
            id,
            vertex_offsets,
            vertices,
            thickness_m: self.read_all(&p("thickness"))?,
            mass_kg: self.read_all(&p("mass"))?,
            area_m2: self.read_all(&p("area"))?,
            inertia_kg_m2: self.read_all(&p("inertia"))?,
            prescribed: self
                .read_all::<u8>(&p("prescribed"))?
                .into_iter()
                .map(|b| b != 0)
                .collect(),
        };
        let o = &floes.vertex_offsets;
        let consistent = [
            floes.thickness_m.len(),
            floes.mass_kg.len(),
            floes.area_m2.len(),
            floes.inertia_kg_m2.len(),
            floes.prescribed.len(),
            floes.land.len(),
        ]
        .iter()
        .all(|&l| l == n)
            && o.len() == n + 1
            && o.windows(2).all(|w| w[0] <= w[1])
            && o.last().map(|&v| v as usize) == Some(floes.vertices.len());
        if !consistent {
            return Err(invalid(
                &self.path,
                format!("the floe arrays under /{group} do not agree in length"),
            ));
        }
        Ok(floes)
    }

    /// Complete snapshots in the file.
    pub fn snapshot_count(&self) -> Result<usize, IoError> {
        self.count_of(&self.segments()?)
    }

    /// Complete snapshots of a file with these `segments`.
    fn count_of(&self, segments: &[(usize, usize, usize)]) -> Result<usize, IoError> {
        // Segments are written one after the other: the last one's rows
        // follow all the others'.
        let mut n = segments.last().map_or(0, |&(_, first, rows)| first + rows);
        for part in ["start", "count", "step", "time"] {
            n = n.min(rows(&self.ds(&format!("{}/{part}", layout::CONTACTS))?));
        }
        Ok(n)
    }

    /// The times of the complete snapshots, s, without reading them (a run
    /// with `[[output.window]]` writes them unevenly spaced).
    pub fn snapshot_times(&self) -> Result<Vec<f64>, IoError> {
        let n = self.snapshot_count()?;
        let mut times = Vec::with_capacity(n);
        for (index, first, _) in self.segments()? {
            if first >= n {
                break;
            }
            let name = format!("{}/position/time", layout::floe_segment(index));
            let end = rows(&self.ds(&name)?).min(n - first);
            times.truncate(first);
            times.extend(self.read_range::<f64>(&name, 0..end)?);
        }
        Ok(times)
    }

    fn check_snapshot(&self, k: usize) -> Result<(), IoError> {
        let n = self.snapshot_count()?;
        if k >= n {
            return Err(invalid(
                &self.path,
                format!("no snapshot {k}: the file has {n} snapshots"),
            ));
        }
        Ok(())
    }

    /// Snapshot `k` (0 is the first).
    pub fn snapshot(&self, k: usize) -> Result<Snapshot, IoError> {
        let (segment, row) = self.locate(k)?;
        let group = layout::floe_segment(segment);
        let el = |name: &str, part: &str| format!("{group}/{name}/{part}");
        let value = |name: &str| self.read_range::<f64>(&el(name, "value"), row..row + 1);
        let step: i64 = self.read_one(&el("position", "step"), row)?;
        Ok(Snapshot {
            step: step as u64,
            time_s: self.read_one(&el("position", "time"), row)?,
            position: pairs(&value("position")?),
            velocity: pairs(&value("velocity")?),
            angle: value("angle")?,
            angular_velocity: value("angular_velocity")?,
        })
    }

    /// Whether the run wrote each floe's stress with its snapshots (a run
    /// with `[floe_stress]`).
    pub fn has_floe_stress(&self) -> bool {
        self.file
            .link_exists(&format!("{}/{}", layout::FLOES, layout::FLOE_STRESS.0))
    }

    /// Each floe's time-averaged stress at snapshot `k` (`[xx, xy, yy]`,
    /// Pa, tension positive), in the snapshot's floe order; `None` if the
    /// run did not compute floe stress.
    pub fn floe_stress(&self, k: usize) -> Result<Option<Vec<[f64; 3]>>, IoError> {
        let (segment, row) = self.locate(k)?;
        let name = format!(
            "{}/{}/value",
            layout::floe_segment(segment),
            layout::FLOE_STRESS.0
        );
        if !self.file.link_exists(&name) {
            return Ok(None);
        }
        let flat = self.read_range::<f64>(&name, row..row + 1)?;
        Ok(Some(
            flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        ))
    }

    /// The fracture event log: every floe a criterion broke, in order
    /// (empty for a run without fracture).
    pub fn fractures(&self) -> Result<Vec<floe_dem::world::FractureEvent>, IoError> {
        crate::fracture_log::read(&self.file)
            .at(&self.path, || format!("reading /{}", layout::FRACTURE))
    }

    /// The ridging event log: every floe ridging cut, in order (empty for
    /// a run without ridging).
    pub fn ridges(&self) -> Result<Vec<crate::ridging_log::RidgeRow>, IoError> {
        crate::ridging_log::read(&self.file)
            .at(&self.path, || format!("reading /{}", layout::RIDGING))
    }

    /// The welding event log: every pair welded, in order (empty for a
    /// run without welding).
    pub fn welds(&self) -> Result<Vec<crate::welding_log::WeldRow>, IoError> {
        crate::welding_log::read(&self.file)
            .at(&self.path, || format!("reading /{}", layout::WELDING))
    }

    /// Each floe of snapshot `k`'s parent: the id of the floe it broke
    /// from, `None` for a floe of the start (and for every floe of the
    /// first segment, or of a file written before parents were recorded).
    pub fn parent_ids_at(&self, k: usize) -> Result<Vec<Option<u64>>, IoError> {
        let (segment, _) = self.locate(k)?;
        let name = format!("{}/{}", layout::floe_segment(segment), layout::PARENT_ID);
        if !self.file.link_exists(&name) {
            return Ok(vec![None; self.floes_at(k)?.id.len()]);
        }
        let parents: Vec<i64> = self.read_all(&name)?;
        Ok(parents.into_iter().map(|p| u64::try_from(p).ok()).collect())
    }

    /// The contacts of snapshot `k`.
    pub fn contacts(&self, k: usize) -> Result<ContactSnapshot, IoError> {
        self.check_snapshot(k)?;
        let c = |name: &str| format!("{}/{name}", layout::CONTACTS);
        let start: u64 = self.read_one(&c("start"), k)?;
        let count: u64 = self.read_one(&c("count"), k)?;
        let end = start
            .checked_add(count)
            .ok_or_else(|| invalid(&self.path, format!("contact rows of snapshot {k} overflow")))?;
        let range = start as usize..end as usize;
        let f = |name: &str| self.read_range::<f64>(&c(name), range.clone());
        let step: i64 = self.read_one(&c("step"), k)?;
        Ok(ContactSnapshot {
            step: step as u64,
            time_s: self.read_one(&c("time"), k)?,
            pair: pairs(&self.read_range::<u32>(&c("pair"), range.clone())?),
            theta: f("theta")?,
            mu: f("mu")?,
            normal_force_n: f("normal_force")?,
            tangential_force_n: f("tangential_force")?,
            slip_rate_m_per_s: f("slip_rate")?,
            overlap_m2: f("overlap_area")?,
            point: pairs(&f("point")?),
            normal: pairs(&f("normal")?),
        })
    }

    /// Names of the observables, sorted.
    pub fn observable_names(&self) -> Result<Vec<String>, IoError> {
        let mut names = self
            .file
            .group(layout::OBSERVABLES)
            .and_then(|g| g.member_names())
            .at(&self.path, || format!("listing /{}", layout::OBSERVABLES))?;
        names.sort();
        Ok(names)
    }

    /// The samples of observable `name`.
    pub fn observable(&self, name: &str) -> Result<Series, IoError> {
        let names = self.observable_names()?;
        if !names.iter().any(|n| n == name) {
            return Err(invalid(
                &self.path,
                format!("no observable {name:?}; the file has {}", names.join(", ")),
            ));
        }
        let p = |part: &str| format!("{}/{name}/{part}", layout::OBSERVABLES);
        let value_ds = self.ds(&p("value"))?;
        let n = rows(&self.ds(&p("step"))?)
            .min(rows(&self.ds(&p("time"))?))
            .min(rows(&value_ds));
        let unit = h5::read_str(&value_ds, "unit").at(&self.path, || {
            format!("reading the unit of /{}", p("value"))
        })?;
        Ok(Series {
            step: self
                .read_range::<i64>(&p("step"), 0..n)?
                .into_iter()
                .map(|s| s as u64)
                .collect(),
            time_s: self.read_range(&p("time"), 0..n)?,
            value: self.read_range(&p("value"), 0..n)?,
            sample_shape: value_ds.shape()[1..].to_vec(),
            unit,
        })
    }

    /// Step and time of the valid checkpoint, if any (without reading it).
    pub fn checkpoint(&self) -> Result<Option<CheckpointInfo>, IoError> {
        let Some(slot) = valid_slot(&self.file, &self.path)? else {
            return Ok(None);
        };
        let name = format!("{}/{}", layout::CHECKPOINT, layout::SLOTS[slot]);
        let ds = self.ds(&name)?;
        (|| -> hdf5::Result<Option<CheckpointInfo>> {
            Ok(Some(CheckpointInfo {
                step: ds.attr("step")?.read_scalar()?,
                time_s: ds.attr("time")?.read_scalar()?,
            }))
        })()
        .at(&self.path, || format!("reading /{name} attributes"))
    }

    /// The state stored in the valid checkpoint, if any, after checking it.
    /// A checkpoint of format 1 or 2 does not store the time step:
    /// `fallback_dt_s` gives it (the scenario's; see `Scenario::engine_parts`).
    pub fn checkpoint_state(
        &self,
        fallback_dt_s: impl FnOnce() -> Option<f64>,
    ) -> Result<Option<WorldState>, IoError> {
        Ok(
            read_checkpoint(&self.file, &self.path, fallback_dt_s, None)?
                .map(|(_, state, _)| state),
        )
    }
}

/// The valid checkpoint slot, if any.
fn valid_slot(file: &hdf5::File, path: &Path) -> Result<Option<usize>, IoError> {
    let slot: i64 = file
        .group(layout::CHECKPOINT)
        .and_then(|g| g.attr(layout::VALID_SLOT))
        .and_then(|a| a.read_scalar())
        .at(path, || {
            format!("reading /{} {}", layout::CHECKPOINT, layout::VALID_SLOT)
        })?;
    match slot {
        -1 => Ok(None),
        0 | 1 => Ok(Some(slot as usize)),
        s => Err(IoError::CorruptCheckpoint {
            path: path.to_path_buf(),
            slot: format!("/{}", layout::CHECKPOINT),
            reason: format!("{} is {s}, not -1, 0 or 1", layout::VALID_SLOT),
        }),
    }
}

/// The valid checkpoint's slot, state and output counts, checked.
pub(crate) fn read_checkpoint(
    file: &hdf5::File,
    path: &Path,
    fallback_dt_s: impl FnOnce() -> Option<f64>,
    law_state_slots: Option<usize>,
) -> Result<Option<(usize, WorldState, OutputCounts)>, IoError> {
    let Some(slot) = valid_slot(file, path)? else {
        return Ok(None);
    };
    let name = format!("/{}/{}", layout::CHECKPOINT, layout::SLOTS[slot]);
    let corrupt = |reason: String| IoError::CorruptCheckpoint {
        path: path.to_path_buf(),
        slot: name.clone(),
        reason,
    };
    let (bytes, step) = (|| -> hdf5::Result<(Vec<u8>, u64)> {
        let ds = file.dataset(&name)?;
        let len = ds.attr("bytes")?.read_scalar::<u64>()? as usize;
        let step = ds.attr("step")?.read_scalar::<u64>()?;
        if len > rows(&ds) {
            return Err(format!("{len} bytes recorded but the slot holds {}", rows(&ds)).into());
        }
        Ok((read_rows::<u8>(&ds, 0..len)?, step))
    })()
    .map_err(|e| corrupt(e.to_string()))?;
    let (state, counts) =
        checkpoint::decode(&bytes, fallback_dt_s, law_state_slots).map_err(corrupt)?;
    if state.steps != step {
        return Err(corrupt(format!(
            "the state is at step {} but the slot says {step}",
            state.steps
        )));
    }
    Ok(Some((slot, state, counts)))
}

/// `/parameters` `input_roles`, `input_paths`, `input_sha256` (absent in
/// runs without input files).
fn read_inputs(g: &hdf5::Group) -> hdf5::Result<Vec<InputRecord>> {
    if !g.attr_names()?.iter().any(|n| n == "input_paths") {
        return Ok(Vec::new());
    }
    let (roles, paths, sums) = (
        h5::read_strs(g, "input_roles")?,
        h5::read_strs(g, "input_paths")?,
        h5::read_strs(g, "input_sha256")?,
    );
    if roles.len() != paths.len() || sums.len() != paths.len() {
        return Err("input_roles, input_paths and input_sha256 differ in length".into());
    }
    Ok(roles
        .into_iter()
        .zip(paths)
        .zip(sums)
        .map(|((role, path), sha256)| InputRecord { role, path, sha256 })
        .collect())
}

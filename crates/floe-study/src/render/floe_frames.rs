//! The frames of a run's floe maps: the selected snapshots, one colour
//! scale for all of them (read once through every frame), then each frame
//! read again when it is drawn, so that a movie of thousands of snapshots
//! holds one snapshot at a time.

use std::path::{Path, PathBuf};

use floe_io::{IoError, RunFile, Snapshot, StaticFloes};

use super::colour::ColourScale;
use super::floe_map::FloeMap;
use super::per_floe::{self, ContactView};
use super::{select, ColourBy, Snapshots};
use floe_dem::run::format_sim_time;
use floe_run::Error;

/// Most values the colour scale is fitted to: past this, an even sample
/// of each frame's floes (the scale is a pair of percentiles).
const SCALE_SAMPLE: usize = 4_000_000;

/// The frames to draw of one run.
pub(crate) struct FloeFrames {
    file: PathBuf,
    colour: ColourBy,
    period: [Option<f64>; 2],
    frames: Vec<usize>,
    steps: Vec<u64>,
    scale: ColourScale,
    view: ((f64, f64), (f64, f64)),
    name: String,
}

impl FloeFrames {
    /// The snapshots of `file` that `which` selects, coloured by `colour`.
    pub(crate) fn read(file: &Path, which: Snapshots, colour: ColourBy) -> Result<Self, Error> {
        // Read with retries: the file may be one a run is writing.
        let count = RunFile::read_retrying(file, RunFile::snapshot_count)?;
        let frames = select(which, count)?;
        let (meta, steps, sample) = RunFile::read_retrying(file, |run| {
            let meta = run.metadata()?;
            let period = period(&meta.domain);
            let first = run.static_floes()?;
            let free = first.prescribed.iter().filter(|p| !**p).count();
            let stride = (free * frames.len()).div_ceil(SCALE_SAMPLE).max(1);
            let (mut steps, mut sample) = (Vec::with_capacity(frames.len()), Vec::new());
            for &k in &frames {
                let (snap, floes, values) = frame_values(run, k, colour, period)?;
                steps.push(snap.step);
                let free_values =
                    values
                        .iter()
                        .zip(&floes.prescribed)
                        .filter_map(|(v, &p)| if p { None } else { *v });
                sample.extend(free_values.step_by(stride));
            }
            Ok((meta, steps, sample))
        })?;
        let domain = meta.domain;
        let margin = 0.04 * domain.size_m[0].max(domain.size_m[1]);
        let view = (
            (
                domain.min_m[0] - margin,
                domain.min_m[0] + domain.size_m[0] + margin,
            ),
            (
                domain.min_m[1] - margin,
                domain.min_m[1] + domain.size_m[1] + margin,
            ),
        );
        Ok(Self {
            file: file.to_path_buf(),
            colour,
            period: period(&domain),
            scale: ColourScale::fit(sample.into_iter(), colour == ColourBy::Theta),
            frames,
            steps,
            view,
            name: file
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        })
    }

    /// How many frames.
    pub(crate) fn len(&self) -> usize {
        self.frames.len()
    }

    /// The run's step at each frame.
    pub(crate) fn steps(&self) -> &[u64] {
        &self.steps
    }

    /// The region every frame shows, m.
    pub(crate) fn view(&self) -> ((f64, f64), (f64, f64)) {
        self.view
    }

    /// Reads frame `i` and hands its map to `draw`.
    pub(crate) fn draw(
        &self,
        i: usize,
        draw: impl FnOnce(&FloeMap) -> Result<(), Error>,
    ) -> Result<(), Error> {
        let k = self.frames[i];
        let (snap, floes, values) = RunFile::read_retrying(&self.file, |run| {
            frame_values(run, k, self.colour, self.period)
        })?;
        let floes = &floes;
        let polygons: Vec<Vec<(f64, f64)>> = (0..floes.len())
            .map(|i| {
                let (s, c) = snap.angle[i].sin_cos();
                let p = snap.position[i];
                floes
                    .local_vertices(i)
                    .iter()
                    .map(|q| (p[0] + c * q[0] - s * q[1], p[1] + s * q[0] + c * q[1]))
                    .collect()
            })
            .collect();
        let title = format!(
            "{}: step {}, t = {}",
            self.name,
            snap.step,
            format_sim_time(snap.time_s)
        );
        draw(&FloeMap {
            title: &title,
            polygons: &polygons,
            values: &values,
            prescribed: &floes.prescribed,
            land: &floes.land,
            scale: self.scale,
            label: self.colour.label(),
            view: self.view,
        })
    }
}

/// Each piece's generation (its parent's plus one; floes of the start,
/// absent, are 0), from the fracture log in the order it was written.
pub(crate) fn generations(
    log: &[floe_dem::world::FractureEvent],
) -> std::collections::HashMap<u64, u32> {
    let mut generation = std::collections::HashMap::new();
    for e in log {
        let g = generation.get(&e.parent_id).copied().unwrap_or(0) + 1;
        for &piece in &e.piece_ids {
            generation.insert(piece, g);
        }
    }
    generation
}

/// The periods of the domain's periodic axes.
fn period(domain: &floe_io::DomainBox) -> [Option<f64>; 2] {
    [0, 1].map(|d| domain.periodic[d].then_some(domain.size_m[d]))
}

/// Snapshot `k`, its floes and the value each floe is coloured by.
fn frame_values(
    run: &RunFile,
    k: usize,
    colour: ColourBy,
    period: [Option<f64>; 2],
) -> Result<(Snapshot, StaticFloes, Vec<Option<f64>>), IoError> {
    let snap = run.snapshot(k)?;
    let floes = run.floes_at(k)?;
    let values = match colour {
        ColourBy::Generation => {
            let generation = generations(&run.fractures()?);
            floes
                .id
                .iter()
                .map(|id| Some(generation.get(id).copied().unwrap_or(0) as f64))
                .collect()
        }
        ColourBy::Speed => snap
            .velocity
            .iter()
            .map(|v| Some(v[0].hypot(v[1])))
            .collect(),
        ColourBy::Theta | ColourBy::Stress => {
            let c = run.contacts(k)?;
            let view = ContactView {
                pair: &c.pair,
                normal: &c.normal,
                normal_force_n: &c.normal_force_n,
                tangential_force_n: &c.tangential_force_n,
                point: &c.point,
                theta: &c.theta,
            };
            if colour == ColourBy::Theta {
                per_floe::mean_theta(floes.len(), &view)
            } else {
                per_floe::pressure(&snap.position, &floes.area_m2, &view, period)
                    .into_iter()
                    .map(|p| p.map(|p| p * 1e-3))
                    .collect()
            }
        }
    };
    Ok((snap, floes, values))
}

#[cfg(test)]
mod tests {
    use super::*;
    use floe_dem::world::FractureEvent;

    fn event(parent_id: u64, piece_ids: Vec<u64>) -> FractureEvent {
        FractureEvent {
            step: 10,
            time_s: 1.0,
            parent_id,
            principal_pa: (0.0, -1e5),
            area_m2: 1e6,
            piece_ids,
            whole_because: None,
        }
    }

    #[test]
    fn a_piece_is_one_generation_past_its_parent() {
        let log = [
            event(1, vec![10, 11, 12]),
            // A floe that stayed whole makes no generation.
            event(2, vec![]),
            event(11, vec![13, 14]),
            event(14, vec![15, 16]),
        ];
        let g = generations(&log);
        let of = |id: u64| g.get(&id).copied().unwrap_or(0);
        assert_eq!(
            [1, 2, 10, 11, 12, 13, 14, 15, 16].map(of),
            [0, 0, 1, 1, 1, 2, 2, 3, 3]
        );
    }
}

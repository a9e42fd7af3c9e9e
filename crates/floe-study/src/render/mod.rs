//! `floe render`: PNG maps of the floes of a run (coloured by speed, theta
//! or pressure; walls dark grey, land grey-brown) and PNG plots of its
//! observables, or a movie of the maps ([`movie`]); maps and movies of the
//! gridded fields of `floe grid` ([`grid_map`]).

pub mod colour;
mod colour_bar;
mod floe_frames;
pub mod floe_map;
mod grid_file;
pub mod grid_map;
pub mod movie;
mod movie_ffmpeg;
mod movie_gif;
mod observables;
mod palette;
pub mod per_floe;

use std::path::{Path, PathBuf};

use floe_frames::FloeFrames;
use floe_run::Error;
use movie::{Movie, MovieArgs, MovieWritten};

/// Which snapshots to draw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Snapshots {
    /// One snapshot; negative counts from the end (-1 is the last).
    One(i64),
    /// Every K-th snapshot, starting with the first.
    Every(usize),
}

/// What colours the floes of a map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourBy {
    /// Floe speed, m/s.
    Speed,
    /// Mean rate-and-state theta over the floe's contacts.
    Theta,
    /// Floe pressure from its contact forces, N/m (compression positive).
    Stress,
    /// How many times the floe's ancestry broke (0: a floe of the start),
    /// from the run's fracture log.
    Generation,
}

impl ColourBy {
    fn name(self) -> &'static str {
        match self {
            ColourBy::Speed => "speed",
            ColourBy::Theta => "theta",
            ColourBy::Stress => "stress",
            ColourBy::Generation => "generation",
        }
    }

    fn label(self) -> &'static str {
        match self {
            ColourBy::Speed => "speed (m/s)",
            ColourBy::Theta => "theta (mean over contacts)",
            ColourBy::Stress => "pressure (kN/m)",
            ColourBy::Generation => "generation (breaks since the start)",
        }
    }
}

/// The snapshot indices `which` selects among `count`.
pub fn select(which: Snapshots, count: usize) -> Result<Vec<usize>, Error> {
    match which {
        Snapshots::One(k) => {
            let index = if k < 0 { count as i64 + k } else { k };
            if index < 0 || index >= count as i64 {
                return Err(Error::Usage(format!(
                    "--snapshot {k}: the file has {count} snapshots (0..{})",
                    count.saturating_sub(1)
                )));
            }
            Ok(vec![index as usize])
        }
        Snapshots::Every(0) => Err(Error::Usage("--every must be at least 1".into())),
        Snapshots::Every(k) => Ok((0..count).step_by(k).collect()),
    }
}

/// Draws the selected snapshots and the observables into `out_dir`;
/// returns the files written. Refuses to replace pictures unless `force`.
pub fn render(
    file: &Path,
    which: Snapshots,
    colour: ColourBy,
    out_dir: &Path,
    force: bool,
) -> Result<Vec<PathBuf>, Error> {
    render_with_progress(file, which, colour, out_dir, force, &mut |_, _| {})
}

/// [`render`], with `progress` told (frames drawn, frames in all) after
/// each map.
pub fn render_with_progress(
    file: &Path,
    which: Snapshots,
    colour: ColourBy,
    out_dir: &Path,
    force: bool,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<PathBuf>, Error> {
    let frames = FloeFrames::read(file, which, colour)?;
    let mut targets: Vec<PathBuf> = frames
        .steps()
        .iter()
        .map(|step| out_dir.join(format!("floes_{}_{step:09}.png", colour.name())))
        .collect();
    targets.push(out_dir.join("observables.png"));
    if !force {
        if let Some(existing) = targets.iter().find(|p| p.exists()) {
            return Err(Error::WouldOverwrite(existing.clone()));
        }
    }
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    for (i, target) in targets.iter().take(frames.len()).enumerate() {
        frames.draw(i, |map| floe_map::draw(target, map))?;
        progress(i + 1, frames.len());
    }
    observables::observables_figure(file, targets.last().expect("observables target"))?;
    Ok(targets)
}

/// Draws the selected snapshots as the frames of a movie (see
/// [`movie::plan`] for its name and encoding).
pub fn render_movie(
    file: &Path,
    which: Snapshots,
    colour: ColourBy,
    args: &MovieArgs,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<MovieWritten, Error> {
    let (target, encoding) = movie::plan(args, file)?;
    let frames = FloeFrames::read(file, which, colour)?;
    let size = encoding.frame_size(floe_map::frame_size(frames.view()));
    let mut out = Movie::create(&target, encoding, size, args.fps)?;
    let mut rgb = vec![0u8; size.0 as usize * size.1 as usize * 3];
    for i in 0..frames.len() {
        frames.draw(i, |map| floe_map::draw_rgb(map, size, &mut rgb, &target))?;
        out.push(&rgb)?;
        progress(i + 1, frames.len());
    }
    out.finish()
}

//! `floe render`: maps, plots and movies of a run or of gridded fields.

use std::path::PathBuf;

use clap::ValueEnum;
use floe_study::render::movie::{Encoding, MovieArgs};
use floe_study::render::{self, ColourBy, Snapshots};

use super::values::frame_rate;
use crate::progress_bar::CountProgress;
use crate::CliError;

/// Frames per second of a movie unless `--fps` says otherwise.
const DEFAULT_FPS: f64 = 10.0;

/// Draw PNG maps of the floes and plots of the observables, or a movie
/// of the maps; of a gridded-fields file of `floe grid`, maps or a
/// movie of its fields.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run's HDF5 file, or gridded fields (NetCDF) of `floe grid`.
    pub file: PathBuf,
    /// Draw only this snapshot (0-based; negative counts from the end).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "every")]
    pub snapshot: Option<i64>,
    /// Draw every K-th snapshot (default: the last snapshot only; every
    /// snapshot for a movie).
    #[arg(long, value_name = "K")]
    pub every: Option<usize>,
    /// What colours the floes.
    #[arg(long, value_enum, default_value_t = Colour::Speed)]
    pub color: Colour,
    /// Output directory for the pictures.
    #[arg(long, short, required_unless_present = "movie")]
    pub output: Option<PathBuf>,
    /// Write a movie of the maps instead: OUT.mp4 (needs ffmpeg),
    /// OUT.gif, or OUT (MP4 if ffmpeg is on PATH, else GIF).
    #[arg(long, value_name = "OUT")]
    pub movie: Option<PathBuf>,
    /// Frames per second of the movie (default 10).
    #[arg(long, requires = "movie", value_parser = frame_rate)]
    pub fps: Option<f64>,
    /// The field of a gridded-fields file a movie shows (default
    /// concentration).
    #[arg(long, requires = "movie")]
    pub field: Option<String>,
    /// Replace existing pictures or movie.
    #[arg(long)]
    pub force: bool,
}

/// `floe render --color`
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Colour {
    /// Floe speed, m/s.
    Speed,
    /// Mean rate-and-state theta over the floe's contacts.
    Theta,
    /// Floe pressure from its contact forces, N/m (compression positive).
    Stress,
    /// How many times the floe's ancestry broke (0: a floe of the start).
    Generation,
}

impl From<Colour> for ColourBy {
    fn from(c: Colour) -> Self {
        match c {
            Colour::Speed => ColourBy::Speed,
            Colour::Theta => ColourBy::Theta,
            Colour::Stress => ColourBy::Stress,
            Colour::Generation => ColourBy::Generation,
        }
    }
}

impl Args {
    /// Draws the pictures or the movie; returns what was written.
    pub fn run(self) -> Result<String, CliError> {
        let Args {
            file,
            snapshot,
            every,
            color,
            output,
            movie,
            fps,
            field,
            force,
        } = self;
        let which = match (snapshot, every) {
            (Some(k), _) => Snapshots::One(k),
            (None, Some(k)) => Snapshots::Every(k),
            (None, None) if movie.is_some() => Snapshots::Every(1),
            (None, None) => Snapshots::One(-1),
        };
        let grid = render::grid_map::is_grid_file(&file);
        let mut bar = CountProgress::new(if grid && movie.is_none() {
            "maps"
        } else {
            "frames"
        });
        let mut progress = |done, total| bar.update(done, total);
        if movie.is_some() && output.is_some() {
            return Err(CliError::Usage(
                "render: give -o DIR (pictures) or --movie OUT, not both".into(),
            ));
        }
        if let Some(path) = movie {
            let args = MovieArgs {
                path,
                fps: fps.unwrap_or(DEFAULT_FPS),
                force,
            };
            let written = if grid {
                let field = field.as_deref().unwrap_or("concentration");
                render::grid_map::render_grid_movie(&file, which, field, &args, &mut progress)?
            } else {
                render::render_movie(&file, which, color.into(), &args, &mut progress)?
            };
            return Ok(format!(
                "movie: {} ({} frames of {} x {} pixels, {})",
                written.path.display(),
                written.frames,
                written.size.0,
                written.size.1,
                match written.encoding {
                    Encoding::Mp4 => "H.264 MP4",
                    Encoding::Gif => "GIF",
                }
            ));
        }
        let Some(output) = output else {
            return Err(CliError::Usage(
                "render: give -o DIR (pictures) or --movie OUT".into(),
            ));
        };
        let written = if grid {
            render::grid_map::render_grid(&file, which, &output, force, &mut progress)?
        } else {
            render::render_with_progress(&file, which, color.into(), &output, force, &mut progress)?
        };
        Ok(format!(
            "{} pictures in {}",
            written.len(),
            output.display()
        ))
    }
}

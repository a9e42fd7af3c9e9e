//! `floe render --movie`: frames (RGB images of one size) written as an
//! animation, an MP4 through `ffmpeg` where it is on `PATH`, a GIF
//! otherwise; under a temporary name beside the target, renamed when
//! complete.

use std::path::{Path, PathBuf};

use super::movie_ffmpeg::FfmpegSink;
use super::movie_gif::GifSink;
use crate::partial_file::PartialFile;
use floe_run::same_file::refuse_overwriting_input;
use floe_run::Error;

/// What `--movie` asks for.
#[derive(Debug, Clone)]
pub struct MovieArgs {
    /// The movie: `.mp4` (needs ffmpeg), `.gif`, or no extension (MP4 when
    /// ffmpeg is on `PATH`, GIF otherwise; the extension is added).
    pub path: PathBuf,
    /// Frames per second.
    pub fps: f64,
    /// Replace an existing movie.
    pub force: bool,
}

/// How a movie is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// H.264 in MP4 (yuv420p, what browsers and players play), by ffmpeg.
    Mp4,
    /// Animated GIF (256 colours per frame), by the `gif` crate.
    Gif,
}

/// A movie written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MovieWritten {
    /// Where.
    pub path: PathBuf,
    /// How.
    pub encoding: Encoding,
    /// Frames in it.
    pub frames: usize,
    /// Width and height, pixels.
    pub size: (u32, u32),
}

/// Frame rates accepted, frames per second.
pub const FPS_RANGE: (f64, f64) = (0.1, 60.0);

/// Whether `ffmpeg` runs (`ffmpeg -version` succeeds).
pub fn ffmpeg_available() -> bool {
    std::process::Command::new("ffmpeg")
        .arg("-version")
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// The movie file and its encoding for `args` (the extension decides;
/// none: MP4 if ffmpeg runs, GIF otherwise), after checking the frame
/// rate, that it overwrites neither `input` nor, without `force`,
/// anything else.
pub fn plan(args: &MovieArgs, input: &Path) -> Result<(PathBuf, Encoding), Error> {
    let (lo, hi) = FPS_RANGE;
    if !(args.fps >= lo && args.fps <= hi) {
        return Err(Error::Usage(format!(
            "--fps {}: frames per second, from {lo} to {hi}",
            args.fps
        )));
    }
    let path = &args.path;
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let (target, encoding) = match extension.as_deref() {
        Some("mp4") if ffmpeg_available() => (path.clone(), Encoding::Mp4),
        Some("mp4") => {
            return Err(Error::Usage(format!(
                "--movie {}: an MP4 is written by ffmpeg, which is not on PATH; install ffmpeg \
                 (Debian: apt-get install ffmpeg) or write a GIF: --movie {}",
                path.display(),
                path.with_extension("gif").display()
            )))
        }
        Some("gif") => (path.clone(), Encoding::Gif),
        None if ffmpeg_available() => (path.with_extension("mp4"), Encoding::Mp4),
        None => (path.with_extension("gif"), Encoding::Gif),
        Some(other) => {
            return Err(Error::Usage(format!(
                "--movie {}: floe writes .mp4 (through ffmpeg) or .gif movies, not .{other}",
                path.display()
            )))
        }
    };
    if target.is_dir() {
        return Err(Error::Usage(format!(
            "--movie {}: a directory; name the movie file",
            target.display()
        )));
    }
    refuse_overwriting_input(input, "input", [target.as_path()])?;
    if target.exists() && !args.force {
        return Err(Error::WouldOverwrite(target));
    }
    Ok((target, encoding))
}

/// A movie being written: frames go to its encoder as they come.
pub struct Movie {
    partial: PartialFile,
    sink: Sink,
    encoding: Encoding,
    size: (u32, u32),
    frames: usize,
}

enum Sink {
    Mp4(FfmpegSink),
    Gif(GifSink),
}

impl Encoding {
    /// The size of the frames of a movie of pictures of `size` pixels:
    /// the same for a GIF; each side rounded up to even for H.264 in
    /// yuv420p, which needs even sides.
    pub fn frame_size(self, size: (u32, u32)) -> (u32, u32) {
        match self {
            Encoding::Gif => size,
            Encoding::Mp4 => (size.0 + size.0 % 2, size.1 + size.1 % 2),
        }
    }
}

impl Movie {
    /// Starts a movie at `target` of frames of `size` pixels (from
    /// [`Encoding::frame_size`]).
    pub fn create(
        target: &Path,
        encoding: Encoding,
        size: (u32, u32),
        fps: f64,
    ) -> Result<Self, Error> {
        let partial = PartialFile::new(target);
        let file = partial.create()?;
        let sink = match encoding {
            // ffmpeg opens the file again and writes over it.
            Encoding::Mp4 => Sink::Mp4(FfmpegSink::start(partial.path(), target, size, fps)?),
            Encoding::Gif => Sink::Gif(GifSink::create(file, target, size, fps)?),
        };
        Ok(Self {
            partial,
            sink,
            encoding,
            size,
            frames: 0,
        })
    }

    /// Appends a frame: `size` pixels, RGB, rows from the top.
    pub fn push(&mut self, rgb: &[u8]) -> Result<(), Error> {
        let (w, h) = self.size;
        if rgb.len() != w as usize * h as usize * 3 {
            return Err(Error::Encode {
                path: self.partial.target().to_path_buf(),
                message: format!("a frame of {} bytes for {w} x {h} pixels", rgb.len()),
            });
        }
        match &mut self.sink {
            Sink::Mp4(s) => s.push(rgb)?,
            Sink::Gif(s) => s.push(rgb)?,
        }
        self.frames += 1;
        Ok(())
    }

    /// Finishes the encoding and renames the movie onto its target.
    pub fn finish(self) -> Result<MovieWritten, Error> {
        match self.sink {
            Sink::Mp4(s) => s.finish()?,
            Sink::Gif(s) => s.finish()?,
        }
        Ok(MovieWritten {
            path: self.partial.commit()?,
            encoding: self.encoding,
            frames: self.frames,
            size: self.size,
        })
    }
}

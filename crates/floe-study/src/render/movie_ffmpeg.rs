//! The MP4 encoder of `floe render --movie`: raw RGB frames piped to
//! `ffmpeg`, which encodes H.264 in yuv420p (what browsers and players
//! play) with the index at the front of the file (`+faststart`).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::thread::JoinHandle;

use floe_run::Error;

/// x264's constant quality (lower: better; 23 is its default): maps have
/// sharp edges and small text.
const CRF: &str = "20";

/// An ffmpeg process encoding the frames it is given.
pub(crate) struct FfmpegSink {
    child: Child,
    stdin: Option<ChildStdin>,
    stderr: Option<JoinHandle<String>>,
    target: PathBuf,
}

impl FfmpegSink {
    /// Starts ffmpeg writing an MP4 to `path` (the partial file of
    /// `target`) from frames of `size` pixels (even sides) at `fps`.
    pub(crate) fn start(
        path: &Path,
        target: &Path,
        size: (u32, u32),
        fps: f64,
    ) -> Result<Self, Error> {
        let mut child = Command::new("ffmpeg")
            .args(["-hide_banner", "-nostats", "-loglevel", "error"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgb24"])
            .args(["-video_size", &format!("{}x{}", size.0, size.1)])
            .args(["-framerate", &fps.to_string(), "-i", "pipe:0", "-an"])
            .args(["-c:v", "libx264", "-crf", CRF, "-pix_fmt", "yuv420p"])
            .args(["-movflags", "+faststart", "-f", "mp4", "-y"])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| Error::Encode {
                path: target.to_path_buf(),
                message: format!("cannot start ffmpeg: {e}"),
            })?;
        let stdin = child.stdin.take();
        // Read ffmpeg's messages as they come, so that it never waits on a
        // full pipe while floe waits on it.
        let stderr = child.stderr.take().map(|mut pipe| {
            std::thread::spawn(move || {
                let mut text = String::new();
                let _ = pipe.read_to_string(&mut text);
                text
            })
        });
        Ok(Self {
            child,
            stdin,
            stderr,
            target: target.to_path_buf(),
        })
    }

    /// Hands ffmpeg a frame of RGB pixels.
    pub(crate) fn push(&mut self, rgb: &[u8]) -> Result<(), Error> {
        let written = match self.stdin.as_mut() {
            Some(stdin) => stdin.write_all(rgb),
            None => Err(std::io::Error::from(std::io::ErrorKind::BrokenPipe)),
        };
        match written {
            Ok(()) => Ok(()),
            // ffmpeg quit: its exit status and messages say why.
            Err(e) => Err(self
                .close()
                .err()
                .unwrap_or_else(|| self.failure(format!("ffmpeg stopped reading frames: {e}")))),
        }
    }

    /// Ends the input and waits for ffmpeg to finish the file.
    pub(crate) fn finish(mut self) -> Result<(), Error> {
        self.close()
    }

    fn close(&mut self) -> Result<(), Error> {
        drop(self.stdin.take());
        let status = self
            .child
            .wait()
            .map_err(|e| self.failure(format!("waiting for ffmpeg: {e}")))?;
        let messages = self
            .stderr
            .take()
            .and_then(|t| t.join().ok())
            .unwrap_or_default();
        if status.success() {
            return Ok(());
        }
        let said = messages.trim();
        Err(self.failure(format!(
            "ffmpeg failed ({status}){}{said}",
            if said.is_empty() { "" } else { ": " }
        )))
    }

    fn failure(&self, message: String) -> Error {
        Error::Encode {
            path: self.target.clone(),
            message,
        }
    }
}

impl Drop for FfmpegSink {
    fn drop(&mut self) {
        // Abandoned before `finish` (an error while drawing): stop ffmpeg.
        if self.stdin.take().is_some() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

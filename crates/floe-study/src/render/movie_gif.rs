//! The GIF encoder of `floe render --movie`: every frame with a palette
//! of its own ([`quantise`]), looping forever.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use super::palette::quantise;
use floe_run::Error;

/// An animated GIF being written.
pub(crate) struct GifSink {
    encoder: gif::Encoder<BufWriter<File>>,
    size: (u16, u16),
    delay_cs: u16,
    target: PathBuf,
}

impl GifSink {
    /// Starts the GIF in `file` (the partial file of `target`) for frames
    /// of `size` pixels shown at `fps` (GIF delays are whole hundredths of
    /// a second, at least 2: at most 50 frames per second).
    pub(crate) fn create(
        file: File,
        target: &Path,
        size: (u32, u32),
        fps: f64,
    ) -> Result<Self, Error> {
        let encode = |message: String| Error::Encode {
            path: target.to_path_buf(),
            message,
        };
        let side = |n: u32| {
            u16::try_from(n)
                .map_err(|_| encode(format!("{n} pixels: a GIF is at most 65535 a side")))
        };
        let size = (side(size.0)?, side(size.1)?);
        let mut encoder = gif::Encoder::new(BufWriter::new(file), size.0, size.1, &[])
            .map_err(|e| encode(e.to_string()))?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| encode(e.to_string()))?;
        Ok(Self {
            encoder,
            size,
            delay_cs: (100.0 / fps).round().clamp(2.0, f64::from(u16::MAX)) as u16,
            target: target.to_path_buf(),
        })
    }

    /// Appends a frame of RGB pixels (the size given at creation).
    pub(crate) fn push(&mut self, rgb: &[u8]) -> Result<(), Error> {
        let (palette, indices) = quantise(rgb);
        let mut frame =
            gif::Frame::from_palette_pixels(self.size.0, self.size.1, indices, palette, None);
        frame.delay = self.delay_cs;
        self.encoder.write_frame(&frame).map_err(|e| self.error(e))
    }

    /// Writes the trailer and flushes the file.
    pub(crate) fn finish(self) -> Result<(), Error> {
        let target = self.target.clone();
        let writer = self.encoder.into_inner().map_err(|e| Error::Encode {
            path: target.clone(),
            message: e.to_string(),
        })?;
        writer
            .into_inner()
            .map_err(|e| Error::io(&target, e.into_error()))?;
        Ok(())
    }

    fn error(&self, e: gif::EncodingError) -> Error {
        Error::Encode {
            path: self.target.clone(),
            message: e.to_string(),
        }
    }
}

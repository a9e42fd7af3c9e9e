//! `floe export`: a run file for other tools. `--xdmf` writes an XDMF file
//! ParaView opens (floe_io::xdmf): fields read from the run file itself,
//! only the floes' world-coordinate polygons in a sidecar.

use std::path::PathBuf;

use crate::CliError;

/// Describe a run file for ParaView: `--xdmf` writes RUN.xdmf (fields
/// pointing into RUN.h5) and RUN.xdmf.h5 (the floes' polygons in world
/// coordinates); open RUN.xdmf in ParaView (docs/output.md, "ParaView").
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run file.
    pub file: PathBuf,
    /// Write the XDMF description (the only format so far; required).
    #[arg(long, required = true)]
    pub xdmf: bool,
    /// The XDMF file (default: the run file with .xdmf for .h5); its
    /// sidecar is this name with .h5 added.
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// Replace existing outputs.
    #[arg(long)]
    pub force: bool,
}

impl Args {
    /// Writes the description; returns the line to print.
    pub fn run(self) -> Result<String, CliError> {
        let output = self
            .output
            .unwrap_or_else(|| self.file.with_extension("xdmf"));
        let done = floe_io::xdmf::write_xdmf(&self.file, &output, self.force)?;
        Ok(format!(
            "{}: {} snapshots for ParaView (polygons in {})",
            done.xdmf.display(),
            done.snapshots,
            done.sidecar.display()
        ))
    }
}

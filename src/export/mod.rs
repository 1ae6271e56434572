//! Files the user asked for, written so that nothing is ever half-written: the simulated
//! fields ([`fields`]: `vr-ocean export`), PNG frames and JSON reports. Every file goes
//! through a temporary name and a rename; every output directory is checked before work starts.

pub mod fields;

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

pub use fields::{write_cascade, write_interaction, write_whitecaps};

/// A file or directory that could not be written.
#[derive(Debug)]
pub struct ExportError {
    /// What was being written.
    pub path: PathBuf,
    /// Why it failed.
    pub source: io::Error,
}

impl std::fmt::Display for ExportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "cannot write {}: {}", self.path.display(), self.source)
    }
}

impl std::error::Error for ExportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.source)
    }
}

fn at(path: &Path) -> impl FnOnce(io::Error) -> ExportError + '_ {
    move |source| ExportError {
        path: path.to_owned(),
        source,
    }
}

/// Creates `dir` (and parents) and checks that a file can be created in it, so a bad `--out`
/// fails before any work.
pub fn prepare_dir(dir: &Path) -> Result<(), ExportError> {
    fs::create_dir_all(dir).map_err(at(dir))?;
    // Per process: runs writing into the same directory at once must not race on it.
    let probe = dir.join(format!(".vr-ocean-write-test-{}", std::process::id()));
    fs::write(&probe, b"").map_err(at(&probe))?;
    fs::remove_file(&probe).map_err(at(&probe))
}

/// Writes `path` through a temporary file (`.partial`) and a rename, so an interrupted write
/// never leaves a truncated file under the final name.
pub fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<fs::File>) -> io::Result<()>,
) -> Result<(), ExportError> {
    let tmp = path.with_extension("partial");
    let file = fs::File::create(&tmp).map_err(at(&tmp))?;
    let mut w = BufWriter::new(file);
    fill(&mut w).map_err(at(&tmp))?;
    w.flush().map_err(at(&tmp))?;
    w.into_inner()
        .map_err(|e| e.into_error())
        .and_then(|f| f.sync_all())
        .map_err(at(&tmp))?;
    fs::rename(&tmp, path).map_err(at(path))
}

/// Writes `bytes` to `path` atomically.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    write_atomically(path, |w| w.write_all(bytes))
}

/// JPEG quality of [`save_jpeg`]: small files (a 1024² sea in ~150 kB) without visible blocks.
pub const JPEG_QUALITY: u8 = 90;

/// Saves tightly packed sRGB RGBA8 rows of `width`×`height` as a JPEG (alpha dropped),
/// atomically: for images committed to the repository (the gallery).
pub fn save_jpeg(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), ExportError> {
    let rgb: Vec<u8> = rgba
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    write_atomically(path, |w| {
        image::codecs::jpeg::JpegEncoder::new_with_quality(w, JPEG_QUALITY)
            .encode(&rgb, width, height, image::ExtendedColorType::Rgb8)
            .map_err(io::Error::other)
    })
}

/// Saves tightly packed sRGB RGBA8 rows of `width`×`height` as a PNG, atomically.
pub fn save_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), ExportError> {
    write_atomically(path, |w| {
        image::write_buffer_with_format(
            w,
            rgba,
            width,
            height,
            image::ExtendedColorType::Rgba8,
            image::ImageFormat::Png,
        )
        .map_err(io::Error::other)
    })
}

//! `vr-ocean export`: the simulated fields as float32 OpenEXR and NumPy `.npy` files, so they
//! can be inspected and checked in other tools.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::sim::surface::{self, CascadeSurface};

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
/// fails before any simulation work.
pub fn prepare_dir(dir: &Path) -> Result<(), ExportError> {
    fs::create_dir_all(dir).map_err(at(dir))?;
    let probe = dir.join(".vr-ocean-write-test");
    fs::write(&probe, b"").map_err(at(&probe))?;
    fs::remove_file(&probe).map_err(at(&probe))
}

/// The fields of one cascade as planes: name, components per texel, values.
fn planes(s: &CascadeSurface, base: &[[f32; 4]]) -> Vec<(&'static str, usize, Vec<f32>)> {
    let comp = |k: usize| s.displacement.iter().map(|d| d[k]).collect::<Vec<f32>>();
    let normals: Vec<f32> = base.iter().flat_map(|&b| surface::unit(b)).collect();
    vec![
        ("height", 1, comp(1)),
        ("dx", 1, comp(0)),
        ("dz", 1, comp(2)),
        ("jacobian", 1, comp(3)),
        ("normals", 3, normals),
        ("foam", 1, base.iter().map(|b| b[3]).collect()),
    ]
}

/// Writes `bytes` to `path` through a temporary file and a rename, so an interrupted export
/// never leaves a truncated file under the final name.
fn write_atomically(
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

/// Writes one cascade's fields as `{stem}_{field}.npy` (shape [N, N] or [N, N, 3], row index =
/// z texel, column = x texel) and one multi-channel `{stem}.exr` (channels height, dx, dz,
/// jacobian, foam, normal.x/y/z). The surface must keep its level-0 normals
/// ([`crate::sim::Surfaces::with_float_copies`]). Returns the files written.
pub fn write_cascade(
    s: &CascadeSurface,
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, ExportError> {
    let n = s.grid.n() as u64;
    let mut written = Vec::new();
    let base = s.base_normals().ok_or_else(|| ExportError {
        path: dir.join(stem),
        source: io::Error::other("the surface was simulated without level-0 normals"),
    })?;
    let planes = planes(s, base);
    for (name, comps, data) in &planes {
        let path = dir.join(format!("{stem}_{name}.npy"));
        let shape: Vec<u64> = if *comps == 1 {
            vec![n, n]
        } else {
            vec![n, n, *comps as u64]
        };
        write_atomically(&path, |w| {
            use npyz::WriterBuilder;
            let mut npy = npyz::WriteOptions::new()
                .default_dtype()
                .shape(&shape)
                .writer(w)
                .begin_nd()?;
            npy.extend(data.iter().copied())?;
            npy.finish()
        })?;
        written.push(path);
    }
    let path = dir.join(format!("{stem}.exr"));
    write_atomically(&path, |w| write_exr(w, s.grid.n(), &planes))?;
    written.push(path);
    Ok(written)
}

fn write_exr(
    w: &mut BufWriter<fs::File>,
    n: usize,
    planes: &[(&'static str, usize, Vec<f32>)],
) -> io::Result<()> {
    use exr::prelude::*;
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    for (name, comps, data) in planes {
        if *comps == 1 {
            channels.push(AnyChannel::new(*name, FlatSamples::F32(data.clone())));
        } else {
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                let plane: Vec<f32> = data.iter().skip(k).step_by(*comps).copied().collect();
                let name = format!("normal.{axis}");
                channels.push(AnyChannel::new(name.as_str(), FlatSamples::F32(plane)));
            }
        }
    }
    let layer = Layer::new(
        (n, n),
        LayerAttributes::named("ocean"),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let mut cursor = io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut cursor)
        .map_err(|e| io::Error::other(e.to_string()))?;
    w.write_all(cursor.get_ref())
}

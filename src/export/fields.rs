//! `vr-ocean export`: the simulated fields as float32 OpenEXR and NumPy `.npy` files, so they
//! can be inspected and checked in other tools.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use super::{write_atomically, ExportError};
use crate::sim::surface::{self, CascadeSurface};

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
        write_npy(&path, &shape, data)?;
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

/// Writes the whitecap coverage the renderer draws ([`crate::sim::whitecaps`]): per level l,
/// `{stem}_whitecaps_l{l}.npy` (shape [T, T] float32 in [0, 1], row index = z, column = x, the
/// window unwrapped from its toroidal storage so that [0, 0] is its first lattice point), and
/// `{stem}_whitecaps.json` with each level's `origin_x`, `origin_z` (world position of [0, 0],
/// m), `spacing` (m), `texels` and `mean` coverage. Returns the files written.
pub fn write_whitecaps(
    w: &crate::sim::whitecaps::Whitecaps,
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, ExportError> {
    use crate::sim::whitecaps::WHITECAP_TEXELS;
    let t = WHITECAP_TEXELS;
    let mut written = Vec::new();
    let mut levels = Vec::new();
    for (l, level) in w.levels.iter().enumerate() {
        let slot = |i: i32| i.rem_euclid(t as i32) as usize;
        let data: Vec<f32> = (0..t as i32)
            .flat_map(|j| (0..t as i32).map(move |i| (i, j)))
            .map(|(i, j)| {
                let idx = slot(level.origin[1] + j) * t + slot(level.origin[0] + i);
                f32::from(level.coverage[idx]) / 255.0
            })
            .collect();
        let path = dir.join(format!("{stem}_whitecaps_l{l}.npy"));
        write_npy(&path, &[t as u64, t as u64], &data)?;
        written.push(path);
        levels.push(serde_json::json!({
            "level": l,
            "origin_x": level.origin[0] as f64 * level.spacing as f64,
            "origin_z": level.origin[1] as f64 * level.spacing as f64,
            "spacing": level.spacing,
            "texels": t,
            "mean": level.mean,
        }));
    }
    let path = dir.join(format!("{stem}_whitecaps.json"));
    write_json(&path, &serde_json::json!({ "levels": levels }))?;
    written.push(path);
    Ok(written)
}

/// Writes the interaction layer's drawn height as `{stem}_interaction_height.npy` ([N, N]
/// float32, row = z, column = x) and `{stem}_interaction.json` with `origin_x`, `origin_z`
/// (world position of cell [0, 0], m), `cell_m`, `cells`, `source_x`, `source_z` (the drop
/// point or the towed body at this time, m), `time` (s) and `energy_j`. Returns the files
/// written.
pub fn write_interaction(
    layer: &crate::sim::interaction::InteractionLayer,
    source: [f32; 2],
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, ExportError> {
    let n = layer.config().cells.n() as u64;
    let path = dir.join(format!("{stem}_interaction_height.npy"));
    write_npy(&path, &[n, n], layer.heights())?;
    let mut written = vec![path];
    let [ox, oz] = layer.origin_m();
    let path = dir.join(format!("{stem}_interaction.json"));
    let json = serde_json::json!({
        "origin_x": ox,
        "origin_z": oz,
        "cell_m": layer.config().cell_m,
        "cells": n,
        "source_x": source[0],
        "source_z": source[1],
        "time": layer.time(),
        "energy_j": layer.stats().energy_j,
    });
    write_json(&path, &json)?;
    written.push(path);
    Ok(written)
}

/// Writes `data` as a float32 `.npy` of `shape` at `path`, atomically.
fn write_npy(path: &Path, shape: &[u64], data: &[f32]) -> Result<(), ExportError> {
    write_atomically(path, |w| {
        use npyz::WriterBuilder;
        let mut npy = npyz::WriteOptions::new()
            .default_dtype()
            .shape(shape)
            .writer(w)
            .begin_nd()?;
        npy.extend(data.iter().copied())?;
        npy.finish()
    })
}

/// Writes `value` as pretty JSON at `path`, atomically.
fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), ExportError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| ExportError {
        path: path.to_owned(),
        source: io::Error::other(e),
    })?;
    super::write_bytes(path, text.as_bytes())
}

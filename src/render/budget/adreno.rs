//! What the Adreno's own compiler makes of the water's shaders: ir3 (Mesa's compiler of the
//! Adreno ISA), run through turnip on its no-op kernel shim as an Adreno 650 (Quest 2) or 740
//! (Quest 3), reports per pipeline executable the statistics read here ([`ShaderStats::of`],
//! the names of `src/freedreno/vulkan/tu_pipeline.cc`). Qualcomm's own compiler on the headset
//! differs; ir3 is the closest open measurement of the same instruction set, registers and
//! wave limits.
//!
//! ir3's categories: cat0 flow and `nop`, cat1 moves and conversions, cat2 and cat3 the ALU (cat3:
//! three sources, `mad`), cat4 the special-function unit (`rcp`, `rsq`, `sqrt`, `log2`, `exp2`,
//! `sin`, `cos`), cat5 texture, cat6 memory, cat7 barriers.

use crate::render::budget::paths::WATER_PATHS;
use crate::render::statistics::{Executable, PipelineStatistics};

/// What ir3 made of one shader (one pipeline executable).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShaderStats {
    /// Instruction slots of one wave's pass through the shader, every branch's included:
    /// instructions, their repeats and the `nop`s between them (ir3's "Instruction Count").
    pub instructions: u32,
    /// Of those, latency slots: `nop`s and `(nopN)` on other instructions.
    pub nops: u32,
    /// Full-precision (32-bit) vec4 registers per lane.
    pub full_registers: u32,
    /// Half-precision (16-bit) vec4 registers per lane: where `mediump` became 16-bit.
    pub half_registers: u32,
    /// Waves a core can hold at once with these registers (the latency they hide).
    pub max_waves: u32,
    /// ALU instructions (cat2 and cat3).
    pub alu: u32,
    /// Special-function instructions (cat4).
    pub special: u32,
    /// Texture instructions (cat5).
    pub texture: u32,
    /// Moves and conversions (cat1).
    pub moves: u32,
    /// Cycles ir3 estimates a wave waits on the special-function unit (`(ss)`).
    pub ss_stall_cycles: u32,
    /// Cycles ir3 estimates a wave waits on texture and memory (`(sy)`).
    pub sy_stall_cycles: u32,
}

impl ShaderStats {
    /// The statistics turnip reported for `exe`; `None` when it is not turnip's (a statistic
    /// missing).
    pub fn of(exe: &Executable) -> Option<Self> {
        let get = |name: &str| exe.get(name).map(|v| v as u32);
        let cat = |n: u32| get(&format!("cat{n} instructions"));
        Some(Self {
            instructions: get("Instruction Count")?,
            nops: get("NOPs Count")?,
            full_registers: get("Registers used")?,
            half_registers: get("Half-registers used")?,
            max_waves: get("Max Waves Per Core")?,
            alu: cat(2)? + cat(3)?,
            special: cat(4)?,
            texture: cat(5)?,
            moves: cat(1)?,
            ss_stall_cycles: get("Estimated cycles stalled on SS")?,
            sy_stall_cycles: get("Estimated cycles stalled on SY")?,
        })
    }
}

/// One water path (or the whole pipeline) as ir3 compiled it for a GPU.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AdrenoPath {
    /// The path (`render::budget::paths::WATER_PATHS`' name), or `pipeline` and `vertex` for
    /// the ocean's drawn pipeline's fragment and vertex shaders.
    pub path: String,
    /// What ir3 made of it.
    #[serde(flatten)]
    pub stats: ShaderStats,
}

/// Why the Adreno statistics could not be read.
#[derive(Clone, Debug, PartialEq)]
pub struct AdrenoError(pub String);

impl std::fmt::Display for AdrenoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl std::error::Error for AdrenoError {}

/// What turnip's name for the binning pass's variant of a vertex shader contains ("Binning VS").
const BINNING: &str = "Binning";

/// The water paths of a headset's pipelines (`render::budget::paths::headset_pipelines`, built on
/// turnip): each path's fragment shader, then the drawn ocean pipeline's fragment (`pipeline`)
/// and vertex (`vertex`) shaders, and its binning pass's vertex shader (`binning`) where the
/// driver reports one.
pub fn water_paths(pipelines: &[PipelineStatistics]) -> Result<Vec<AdrenoPath>, AdrenoError> {
    // `label`'s executable of `stage`: the binning pass's variant (turnip's "Binning VS") or
    // the drawn one, whichever the driver lists first.
    let find = |label: &str, stage: &str, binning: bool| -> Result<&Executable, AdrenoError> {
        let p = pipelines
            .iter()
            .find(|p| p.label == label)
            .ok_or_else(|| AdrenoError(format!("no pipeline {label:?} in the statistics")))?;
        p.executables
            .iter()
            .find(|e| e.stage == stage && e.name.contains(BINNING) == binning)
            .ok_or_else(|| AdrenoError(format!("{label:?} has no {stage} shader")))
    };
    let stage = |label: &str, stage: &str| -> Result<ShaderStats, AdrenoError> {
        ShaderStats::of(find(label, stage, false)?).ok_or_else(|| {
            AdrenoError(format!(
                "{label:?}'s {stage} shader has no ir3 statistics (not turnip's driver?)"
            ))
        })
    };
    let mut out = Vec::new();
    for path in WATER_PATHS {
        out.push(AdrenoPath {
            path: path.name.to_string(),
            stats: stage(path.label, "fragment")?,
        });
    }
    // The pipeline the headset draws: foveated where its pass has a density map.
    let drawn = ["ocean (foveated)", "ocean"]
        .into_iter()
        .find(|l| pipelines.iter().any(|p| p.label == *l))
        .ok_or_else(|| AdrenoError("no ocean pipeline in the statistics".into()))?;
    out.push(AdrenoPath {
        path: "pipeline".into(),
        stats: stage(drawn, "fragment")?,
    });
    out.push(AdrenoPath {
        path: "vertex".into(),
        stats: stage(drawn, "vertex")?,
    });
    // The tiler's binning pass runs a vertex shader of its own (the position alone): where the
    // driver reports it, its own statistics.
    if let Some(stats) = find(drawn, "vertex", true).ok().and_then(ShaderStats::of) {
        out.push(AdrenoPath {
            path: "binning".into(),
            stats,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::statistics::{StatValue, Statistic};

    fn turnip_exe(stage: &str, instructions: u64) -> Executable {
        let names = [
            ("Max Waves Per Core", 12),
            ("Instruction Count", instructions),
            ("NOPs Count", instructions / 3),
            ("Registers used", 16),
            ("Half-registers used", 2),
            ("Estimated cycles stalled on SS", 40),
            ("Estimated cycles stalled on SY", 90),
            ("cat0 instructions", 10),
            ("cat1 instructions", 20),
            ("cat2 instructions", 300),
            ("cat3 instructions", 100),
            ("cat4 instructions", 30),
            ("cat5 instructions", 9),
        ];
        Executable {
            stage: stage.into(),
            name: "MESA".into(),
            statistics: names
                .iter()
                .map(|&(n, v)| Statistic {
                    name: n.into(),
                    value: StatValue::Uint(v),
                })
                .collect(),
        }
    }

    #[test]
    fn turnips_statistics_are_read_by_name_and_every_path_is_found() {
        let s = ShaderStats::of(&turnip_exe("fragment", 900)).unwrap();
        assert_eq!(
            (s.instructions, s.nops, s.alu, s.special, s.texture),
            (900, 300, 400, 30, 9)
        );
        assert_eq!(
            (s.full_registers, s.half_registers, s.max_waves),
            (16, 2, 12)
        );
        let mut pipelines: Vec<PipelineStatistics> = WATER_PATHS
            .iter()
            .map(|path| PipelineStatistics {
                label: path.label.to_string(),
                executables: vec![turnip_exe("vertex", 500), turnip_exe("fragment", 1000)],
            })
            .collect();
        // Without the drawn pipeline: refused, naming it.
        let e = water_paths(&pipelines).unwrap_err();
        assert!(e.0.contains("ocean"), "{e}");
        pipelines.push(PipelineStatistics {
            label: "ocean (foveated)".into(),
            executables: vec![turnip_exe("vertex", 576), turnip_exe("fragment", 2372)],
        });
        let paths = water_paths(&pipelines).unwrap();
        assert_eq!(paths.len(), WATER_PATHS.len() + 2);
        assert_eq!(paths.last().unwrap().stats.instructions, 576);
        // The binning pass's vertex shader where the driver lists it, before the drawn one or
        // after: each is read as itself.
        let mut binning = turnip_exe("vertex", 498);
        binning.name = "Binning VS".into();
        pipelines.last_mut().unwrap().executables.insert(0, binning);
        let paths = water_paths(&pipelines).unwrap();
        assert_eq!(paths.len(), WATER_PATHS.len() + 3);
        let last = paths.last().unwrap();
        assert_eq!(
            (last.path.as_str(), last.stats.instructions),
            ("binning", 498)
        );
        assert_eq!(paths[paths.len() - 2].stats.instructions, 576);
        // Another driver's statistics are not ir3's.
        let mut other = turnip_exe("fragment", 10);
        other.statistics.retain(|s| s.name != "Max Waves Per Core");
        assert_eq!(ShaderStats::of(&other), None);
    }
}

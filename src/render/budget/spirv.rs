//! Instruction counts of an optimized SPIR-V module: what one invocation of its entry point
//! costs a GPU's shader core, in scalar ALU operations, special-function operations
//! (reciprocal, square root, exponentials: the slower units) and texture samples.
//!
//! The cost variants (`shaders/shader_table.rs` `COST_SHADERS`) are inlined and unrolled by
//! `spirv-opt -O`, so a module is one function of straight-line code with a few selections;
//! every instruction is counted once (both sides of a data-dependent branch: an upper bound, as
//! a GPU's lanes run both sides when they diverge). Each arithmetic instruction counts once per
//! component of its result; moves, loads, composites and phis count nothing (registers);
//! `abs` and negation count nothing (source modifiers on mobile GPUs). A module that still has
//! a loop or a call is refused: its count would not be per invocation.
//!
//! Operations in relaxed precision (GLSL `mediump`) are counted apart ([`InstructionCounts::
//! relaxed`]): those decorated `RelaxedPrecision`, and those all of whose non-constant operands
//! are relaxed (GLSL's rule: an operation takes the highest precision of its operands). The
//! second rule restores what `spirv-opt`'s loop unroller drops: it decorates only the first
//! copy of an unrolled body (SPIRV-Tools issue 5902, fixed after the Debian packages we use);
//! the pipeline's own shader is not unrolled by spirv-opt, so its driver sees every decoration.

use std::collections::{HashMap, HashSet};

/// What one invocation costs.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InstructionCounts {
    /// Scalar FP32/integer operations (one per component; an FMA is one).
    pub alu: u32,
    /// Of `alu`, those in relaxed precision (GLSL `mediump`: decorated `RelaxedPrecision`, or
    /// every operand that carries a precision relaxed, see the module doc): a GPU with native
    /// FP16 (Adreno) may run them at half precision, at twice the FP32 rate.
    pub relaxed: u32,
    /// Special-function operations: reciprocal (of a division), square root, inverse square
    /// root, exp2, log2, sin, cos (one per component).
    pub special: u32,
    /// Texture samples (filtered lookups; a level-of-detail query counts as one), of every
    /// kind; those of the three kinds below are also counted apart (the rest take implicit
    /// derivatives: the quad's own, one level of detail per quad).
    pub samples: u32,
    /// Of `samples`, those at an explicit level of detail (`textureLod`): a level per lane.
    #[serde(default)]
    pub lod_samples: u32,
    /// Of `samples`, those with explicit gradients (`textureGrad`): a footprint per lane.
    #[serde(default)]
    pub grad_samples: u32,
    /// Of `samples`, level-of-detail queries (`textureQueryLod`).
    #[serde(default)]
    pub lod_queries: u32,
    /// Conditional branches left after optimization.
    pub branches: u32,
}

impl InstructionCounts {
    /// `self - base`, floored at zero per field: the work a path adds to another.
    pub fn minus(self, base: InstructionCounts) -> InstructionCounts {
        InstructionCounts {
            alu: self.alu.saturating_sub(base.alu),
            relaxed: self.relaxed.saturating_sub(base.relaxed),
            special: self.special.saturating_sub(base.special),
            samples: self.samples.saturating_sub(base.samples),
            lod_samples: self.lod_samples.saturating_sub(base.lod_samples),
            grad_samples: self.grad_samples.saturating_sub(base.grad_samples),
            lod_queries: self.lod_queries.saturating_sub(base.lod_queries),
            branches: self.branches.saturating_sub(base.branches),
        }
    }
}

/// Why a module could not be counted.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CountError {
    /// Not SPIR-V (bad magic, truncated instruction).
    Malformed(String),
    /// Still has a loop or a function call: not optimized into straight-line code.
    NotStraightLine(&'static str),
}

impl std::fmt::Display for CountError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CountError::Malformed(why) => write!(f, "not a SPIR-V module: {why}"),
            CountError::NotStraightLine(what) => write!(
                f,
                "the module still has {what}: build it through spirv-opt -O (`cargo xtask shaders`)"
            ),
        }
    }
}

impl std::error::Error for CountError {}

const MAGIC: u32 = 0x0723_0203;
/// Image operands: an explicit level of detail.
const IMAGE_OPERANDS_LOD: u32 = 0x2;
/// Image operands: explicit gradients.
const IMAGE_OPERANDS_GRAD: u32 = 0x4;

/// Whether sample opcode `code` takes a depth reference before its image operands
/// (OpImageSampleDrefImplicitLod 89 .. OpImageSampleProjDrefExplicitLod 92, OpImageDrefGather
/// 97).
fn sample_has_dref(code: u16) -> bool {
    matches!(code, 89..=92 | 97)
}
/// The `RelaxedPrecision` decoration.
const RELAXED_PRECISION: u32 = 0;

mod op {
    pub const UNDEF: u16 = 1;
    pub const EXT_INST_IMPORT: u16 = 11;
    pub const DECORATE: u16 = 71;
    pub const EXT_INST: u16 = 12;
    pub const TYPE_BOOL: u16 = 20;
    pub const TYPE_INT: u16 = 21;
    pub const TYPE_FLOAT: u16 = 22;
    pub const TYPE_VECTOR: u16 = 23;
    pub const TYPE_MATRIX: u16 = 24;
    pub const CONSTANT_FIRST: u16 = 41; // OpConstantTrue
    pub const CONSTANT_LAST: u16 = 52; // OpSpecConstantOp
    pub const LOAD: u16 = 61;
    pub const VECTOR_SHUFFLE: u16 = 79;
    pub const COMPOSITE_EXTRACT: u16 = 81;
    pub const COMPOSITE_INSERT: u16 = 82;
    pub const SELECT: u16 = 169;
    pub const PHI: u16 = 245;
    pub const FUNCTION_CALL: u16 = 57;
    pub const IMAGE_SAMPLE_FIRST: u16 = 87; // OpImageSampleImplicitLod
    pub const IMAGE_SAMPLE_LAST: u16 = 97; // OpImageDrefGather
    pub const IMAGE_QUERY_LOD: u16 = 105;
    pub const CONVERT_FIRST: u16 = 109; // OpConvertFToU
    pub const CONVERT_LAST: u16 = 115; // OpFConvert
    pub const S_NEGATE: u16 = 126;
    pub const F_NEGATE: u16 = 127;
    pub const ARITH_FIRST: u16 = 128; // OpIAdd
    pub const F_DIV: u16 = 136;
    pub const F_REM: u16 = 140;
    pub const F_MOD: u16 = 141;
    pub const VECTOR_TIMES_SCALAR: u16 = 142;
    pub const MATRIX_TIMES_SCALAR: u16 = 143;
    pub const VECTOR_TIMES_MATRIX: u16 = 144;
    pub const MATRIX_TIMES_VECTOR: u16 = 145;
    pub const MATRIX_TIMES_MATRIX: u16 = 146;
    pub const DOT: u16 = 148;
    pub const RELATIONAL_FIRST: u16 = 154; // OpAny
    pub const RELATIONAL_LAST: u16 = 205; // OpBitCount (logical, select, compares, bits)
    pub const DERIVATIVE_FIRST: u16 = 207; // OpDPdx
    pub const DERIVATIVE_LAST: u16 = 215; // OpFwidthCoarse
    pub const LOOP_MERGE: u16 = 246;
    pub const BRANCH_CONDITIONAL: u16 = 250;
    pub const SWITCH: u16 = 251;
}

/// GLSL.std.450 extended instructions (the numbers of its specification).
mod glsl {
    pub const F_ABS: u32 = 4;
    pub const S_ABS: u32 = 5;
    pub const SIN: u32 = 13;
    pub const TAN: u32 = 15;
    pub const ASIN: u32 = 16;
    pub const ATANH: u32 = 24;
    pub const ATAN2: u32 = 25;
    pub const POW: u32 = 26;
    pub const EXP: u32 = 27;
    pub const INVERSE_SQRT: u32 = 32;
    pub const F_CLAMP: u32 = 43;
    pub const S_CLAMP: u32 = 45;
    pub const F_MIX: u32 = 46;
    pub const I_MIX: u32 = 47;
    pub const SMOOTH_STEP: u32 = 49;
    pub const LENGTH: u32 = 66;
    pub const DISTANCE: u32 = 67;
    pub const CROSS: u32 = 68;
    pub const NORMALIZE: u32 = 69;
    pub const FACE_FORWARD: u32 = 70;
    pub const REFLECT: u32 = 71;
    pub const REFRACT: u32 = 72;
    pub const N_CLAMP: u32 = 81;
}

/// Counts the module `words` (see the module doc).
pub fn count(words: &[u32]) -> Result<InstructionCounts, CountError> {
    if words.len() < 5 || words[0] != MAGIC {
        return Err(CountError::Malformed("no SPIR-V header".into()));
    }
    // Components of each type id, and which ids are results of which type.
    let mut components: HashMap<u32, u32> = HashMap::new();
    let mut result_type: HashMap<u32, u32> = HashMap::new();
    let mut glsl_set = None;
    // Ids decorated or derived RelaxedPrecision (decorations precede the functions in a
    // module), and ids that carry no precision (constants, undefined values).
    let mut relaxed: HashSet<u32> = HashSet::new();
    let mut constants: HashSet<u32> = HashSet::new();
    let mut counts = InstructionCounts::default();
    let mut at = 5;
    while at < words.len() {
        let word = words[at];
        let (len, code) = ((word >> 16) as usize, (word & 0xffff) as u16);
        if len == 0 || at + len > words.len() {
            return Err(CountError::Malformed(format!(
                "instruction at word {at} runs past the end"
            )));
        }
        let ins = &words[at..at + len];
        at += len;
        match code {
            op::EXT_INST_IMPORT => {
                let name: Vec<u8> = ins[2..].iter().flat_map(|w| w.to_le_bytes()).collect();
                if name.starts_with(b"GLSL.std.450") {
                    glsl_set = Some(ins[1]);
                }
                continue;
            }
            op::TYPE_BOOL | op::TYPE_INT | op::TYPE_FLOAT => {
                components.insert(ins[1], 1);
                continue;
            }
            op::TYPE_VECTOR | op::TYPE_MATRIX if len >= 4 => {
                let inner = components.get(&ins[2]).copied().unwrap_or(1);
                components.insert(ins[1], inner * ins[3]);
                continue;
            }
            op::DECORATE if len >= 3 => {
                if ins[2] == RELAXED_PRECISION {
                    relaxed.insert(ins[1]);
                }
                continue;
            }
            op::UNDEF | op::CONSTANT_FIRST..=op::CONSTANT_LAST if len >= 3 => {
                constants.insert(ins[2]);
                continue;
            }
            op::LOOP_MERGE => return Err(CountError::NotStraightLine("a loop")),
            op::FUNCTION_CALL => return Err(CountError::NotStraightLine("a function call")),
            op::BRANCH_CONDITIONAL | op::SWITCH => {
                counts.branches += 1;
                continue;
            }
            _ => {}
        }
        // Instructions with a result type: (type, id, operands...).
        if len < 3 {
            continue;
        }
        let n = |id: u32| components.get(&id).copied().unwrap_or(1);
        let (ty, id) = (ins[1], ins[2]);
        let width = n(ty);
        let alu_before = counts.alu;
        match code {
            op::IMAGE_SAMPLE_FIRST..=op::IMAGE_SAMPLE_LAST => {
                counts.samples += 1;
                // The image operands' mask follows the coordinates (a Dref sample has one more
                // operand before it).
                let mask_at = if sample_has_dref(code) { 6 } else { 5 };
                let mask = ins.get(mask_at).copied().unwrap_or(0);
                if mask & IMAGE_OPERANDS_GRAD != 0 {
                    counts.grad_samples += 1;
                } else if mask & IMAGE_OPERANDS_LOD != 0 {
                    counts.lod_samples += 1;
                }
            }
            op::IMAGE_QUERY_LOD => {
                counts.samples += 1;
                counts.lod_queries += 1;
            }
            op::S_NEGATE | op::F_NEGATE => {}
            op::F_DIV => {
                counts.alu += width;
                counts.special += width;
            }
            op::F_REM | op::F_MOD => {
                counts.alu += 3 * width;
                counts.special += width;
            }
            op::VECTOR_TIMES_SCALAR | op::MATRIX_TIMES_SCALAR => counts.alu += width,
            op::VECTOR_TIMES_MATRIX | op::MATRIX_TIMES_VECTOR => {
                // One multiply-add per matrix element.
                let vector = result_type.get(&ins[4]).map_or(4, |&t| n(t));
                counts.alu += width * vector;
            }
            op::MATRIX_TIMES_MATRIX => counts.alu += width * 4,
            op::DOT => {
                let operand = result_type.get(&ins[3]).map_or(3, |&t| n(t));
                counts.alu += 2 * operand - 1;
            }
            op::ARITH_FIRST..=op::F_MOD => counts.alu += width,
            op::CONVERT_FIRST..=op::CONVERT_LAST
            | op::RELATIONAL_FIRST..=op::RELATIONAL_LAST
            | op::DERIVATIVE_FIRST..=op::DERIVATIVE_LAST => counts.alu += width,
            op::EXT_INST if Some(ins[3]) == glsl_set && len >= 5 => {
                let operand = result_type
                    .get(&ins[5.min(len - 1)])
                    .map_or(width, |&t| n(t));
                let (alu, special) = glsl_cost(ins[4], width, operand);
                counts.alu += alu;
                counts.special += special;
            }
            _ => {}
        }
        if !relaxed.contains(&id) && derives_relaxed(code, ins, &relaxed, &constants) {
            relaxed.insert(id);
        }
        if relaxed.contains(&id) {
            counts.relaxed += counts.alu - alu_before;
        }
        if has_result_type(code) {
            result_type.insert(id, ty);
        }
    }
    Ok(counts)
}

/// Whether the value of instruction `ins` (opcode `code`) is in relaxed precision by GLSL's rule:
/// it has operands that carry a precision, and all of them are relaxed.
fn derives_relaxed(
    code: u16,
    ins: &[u32],
    relaxed: &HashSet<u32>,
    constants: &HashSet<u32>,
) -> bool {
    if !has_result_type(code) {
        return false;
    }
    // The words that are value operands (not literals: an extended instruction's set and
    // number, an extract's indices, a shuffle's components; a sample's coordinates do not set
    // its precision, its sampler does).
    let operands = match code {
        op::EXT_INST => &ins[5.min(ins.len())..],
        op::VECTOR_SHUFFLE => &ins[3..5.min(ins.len())],
        op::COMPOSITE_EXTRACT
        | op::LOAD
        | op::IMAGE_SAMPLE_FIRST..=op::IMAGE_SAMPLE_LAST
        | op::IMAGE_QUERY_LOD => &ins[3..4.min(ins.len())],
        op::COMPOSITE_INSERT => &ins[3..5.min(ins.len())],
        // A selection's precision is its values', not its condition's.
        op::SELECT => &ins[4.min(ins.len())..],
        // A phi's operands alternate value and block.
        op::PHI => {
            let values: Vec<u32> = ins[3..].iter().step_by(2).copied().collect();
            return all_relaxed(&values, relaxed, constants);
        }
        _ => &ins[3..],
    };
    all_relaxed(operands, relaxed, constants)
}

/// Some of `ids` carry a precision, and every one of those is relaxed.
fn all_relaxed(ids: &[u32], relaxed: &HashSet<u32>, constants: &HashSet<u32>) -> bool {
    let mut any = false;
    for id in ids.iter().filter(|id| !constants.contains(id)) {
        if !relaxed.contains(id) {
            return false;
        }
        any = true;
    }
    any
}

/// Whether instructions of opcode `code` start with (result type, result id): the values the
/// counted instructions read (not stores, decorations or names, whose words mean other things).
fn has_result_type(code: u16) -> bool {
    matches!(
        code,
        op::EXT_INST
            | op::LOAD
            | 79..=83 // OpVectorShuffle, OpCompositeConstruct/Extract/Insert, OpCopyObject
            | op::IMAGE_SAMPLE_FIRST..=op::IMAGE_SAMPLE_LAST
            | op::IMAGE_QUERY_LOD
            | op::CONVERT_FIRST..=op::CONVERT_LAST
            | op::S_NEGATE..=op::DOT
            | op::RELATIONAL_FIRST..=op::RELATIONAL_LAST
            | op::DERIVATIVE_FIRST..=op::DERIVATIVE_LAST
            | op::PHI
    )
}

/// (ALU, special) operations of GLSL.std.450 instruction `inst` with a result of `n`
/// components and a first operand of `m`.
fn glsl_cost(inst: u32, n: u32, m: u32) -> (u32, u32) {
    match inst {
        glsl::F_ABS | glsl::S_ABS => (0, 0),
        // sin, cos: the special unit after a range reduction.
        glsl::SIN..=14 => (n, n),
        glsl::TAN => (2 * n, 3 * n),
        // Inverse and hyperbolic trigonometry: a polynomial and a reciprocal or root each.
        glsl::ASIN..=glsl::ATANH | glsl::ATAN2 => (12 * n, 2 * n),
        // pow = exp2(y · log2(x)).
        glsl::POW => (n, 2 * n),
        // exp, log, exp2, log2 (a scale for the natural ones), sqrt, inversesqrt.
        glsl::EXP..=glsl::INVERSE_SQRT => (n, n),
        glsl::F_CLAMP..=glsl::S_CLAMP | glsl::N_CLAMP => (2 * n, 0),
        glsl::F_MIX | glsl::I_MIX => (2 * n, 0),
        // (x − e0) / (e1 − e0), clamped, t²(3 − 2t).
        glsl::SMOOTH_STEP => (6 * n, n),
        glsl::LENGTH => (2 * m - 1, 1),
        glsl::DISTANCE => (3 * m - 1, 1),
        glsl::CROSS => (6, 0),
        glsl::NORMALIZE => (3 * n - 1, 1),
        glsl::FACE_FORWARD => (2 * m, 0),
        glsl::REFLECT => (4 * n - 1, 0),
        glsl::REFRACT => (5 * n + 4, 1),
        // Rounding, sign, min, max, step, fma, radians and the rest: one each.
        _ => (n, 0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shaders::cost;

    #[test]
    fn the_cost_variants_are_straight_line_and_ordered() {
        let c = |w: &[u32]| count(w).expect("a cost variant counts");
        let sky = c(cost::SKY);
        let single = c(cost::SINGLE);
        let super0 = c(cost::SUPERSAMPLED);
        let super1 = c(cost::SUPERSAMPLED_RESAMPLE);
        let foam = c(cost::FOAM);
        let plain = c(cost::PLAIN);
        let vertex = c(cost::VERTEX);
        println!("sky {sky:?}\nsingle {single:?}\nsuper0 {super0:?}\nsuper1 {super1:?}");
        println!("foam {foam:?}\nplain {plain:?}\nvertex {vertex:?}");
        // The sky reads one map; the water its three cascades, the whitecaps and the sky.
        assert!(sky.samples >= 1 && sky.alu < single.alu);
        assert!(single.samples >= 6, "{single:?}");
        // Supersampling the surface adds work; each cascade sampled again adds 3 samples (one at
        // each sub-pixel position besides the pixel's own).
        assert!(super0.alu > single.alu);
        assert_eq!(super1.samples, super0.samples + 3);
        // Foam adds the pattern's samples (two scales at two taps: `filtered_foam`) and the
        // bubbles'.
        assert_eq!(foam.samples, single.samples + 5);
        assert!(plain.alu < single.alu);
        assert!(vertex.samples >= 3 && vertex.alu > 20);
        // 39-44 % of the water's arithmetic is in relaxed precision (mediump: the body, foam,
        // the Fresnel weight, the tone map), 0.3 of the supersampled path's (its highlight,
        // evaluated four times, is in full: 0.31 since the glint follows Cox & Munk);
        // positions and the vertex shader stay in full. The tone curve's knee,
        // a variant of its own, is relaxed throughout.
        for path in [single, foam, plain] {
            assert!(path.relaxed * 20 >= path.alu * 7, "{path:?}");
        }
        let knee = c(cost::KNEE).minus(single);
        assert!(
            knee.alu > 10 && knee.relaxed * 4 >= knee.alu * 3,
            "{knee:?}"
        );
        assert!(super0.relaxed * 10 >= super0.alu * 3, "{super0:?}");
        assert_eq!(vertex.relaxed, 0);
    }

    #[test]
    fn loops_calls_and_garbage_are_refused() {
        assert!(matches!(count(&[1, 2, 3]), Err(CountError::Malformed(_))));
        // The pipeline's own shader still has its loops.
        assert!(matches!(
            count(crate::render::shaders::OCEAN_FRAG),
            Err(CountError::NotStraightLine(_))
        ));
        // A truncated instruction.
        let mut words = cost::SKY.to_vec();
        words.truncate(words.len() - 1);
        words.push(0x00ff_0001);
        assert!(matches!(count(&words), Err(CountError::Malformed(_))));
    }

    #[test]
    fn components_multiply_the_count() {
        // vec3 = vec3 * vec3 counts 3; a dot of two vec3s 5; a divide one special each.
        let header = [MAGIC, 0x0001_0300, 0, 100, 0];
        let float = [(3 << 16) | op::TYPE_FLOAT as u32, 1, 32];
        let vec3 = [(4 << 16) | op::TYPE_VECTOR as u32, 2, 1, 3];
        let mul = [(5 << 16) | 133, 2, 10, 11, 12];
        let dot = [(5 << 16) | op::DOT as u32, 1, 13, 10, 10];
        let div = [(5 << 16) | op::F_DIV as u32, 2, 14, 10, 10];
        let words: Vec<u32> = [&header[..], &float, &vec3, &mul, &dot, &div].concat();
        let c = count(&words).unwrap();
        assert_eq!(c.alu, 3 + 5 + 3);
        assert_eq!(c.special, 3);
        assert_eq!(c.relaxed, 0);
        // The multiply's result (id 10) and the divide's (14) decorated relaxed: their ALU
        // operations (not the divide's reciprocals) count as relaxed, and so does the dot of
        // two relaxed values (GLSL's rule), but not a dot with an operand in full precision.
        let relax = |id| [(3 << 16) | op::DECORATE as u32, id, RELAXED_PRECISION];
        let with_dot = |dot: &[u32]| {
            let parts: [&[u32]; 8] = [
                &header,
                &relax(10),
                &relax(14),
                &float,
                &vec3,
                &mul,
                dot,
                &div,
            ];
            count(&parts.concat()).unwrap()
        };
        let c = with_dot(&dot);
        assert_eq!((c.alu, c.special, c.relaxed), (11, 3, 3 + 5 + 3));
        let mixed = [(5 << 16) | op::DOT as u32, 1, 13, 10, 11];
        assert_eq!(with_dot(&mixed).relaxed, 3 + 3);
        // A constant operand carries no precision: relaxed × constant stays relaxed.
        let constant = [(4 << 16) | 43, 1, 20, 0x3f80_0000];
        let scale = [(5 << 16) | op::VECTOR_TIMES_SCALAR as u32, 2, 21, 10, 20];
        let words: Vec<u32> = [
            &header[..],
            &relax(10),
            &float,
            &vec3,
            &constant,
            &mul,
            &scale,
        ]
        .concat();
        assert_eq!(count(&words).unwrap().relaxed, 3 + 3);
    }
}

//! Sound placed round the head: interaural time differences (Woodworth's spherical head),
//! level differences by the head's shadow (Brown & Duda's one-pole, one-zero filter per ear)
//! and distance attenuation (1/r beyond a metre). A source is rendered mono by its voice and
//! placed here, with its delays and gains eased across each block so a moving head never
//! clicks.

use std::f32::consts::PI;

use glam::Vec3;

use super::dsp::HeadShadow;
use super::scene::Listener;

/// Head radius (m): the mean adult's, the value Brown & Duda and Woodworth's formula use.
pub const HEAD_RADIUS: f32 = 0.0875;

/// Speed of sound in air at 20 °C (m/s).
pub const SPEED_OF_SOUND: f32 = 343.0;

/// Distance (m) inside which a source is not made louder.
pub const REFERENCE_DISTANCE: f32 = 1.0;

/// Longest delay a source's lines hold (samples): the widest ITD plus the common offset, with
/// room for 96 kHz.
const DELAY_LEN: usize = 128;

/// The least α of the shadow filter (at [`THETA_MIN`] from the ear) and where (Brown & Duda).
const ALPHA_MIN: f32 = 0.1;
const THETA_MIN: f32 = 5.0 * PI / 6.0;

/// Where a source sits for the two ears: what the head model makes of a position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Delay at each ear (samples, left then right).
    pub delay: [f32; 2],
    /// Distance gain, the same at both ears.
    pub gain: f32,
    /// The shadow filter's α at each ear.
    pub alpha: [f32; 2],
}

/// Woodworth's interaural time difference (s) for a source at lateral angle φ (radians,
/// + right of the median plane): (a/c)·(φ + sin φ). Positive: the right ear hears first.
pub fn woodworth_itd(lateral: f32) -> f32 {
    HEAD_RADIUS / SPEED_OF_SOUND * (lateral + lateral.sin())
}

/// Brown & Duda's α for a source `theta` radians from an ear's axis.
pub fn shadow_alpha(theta: f32) -> f32 {
    (1.0 + 0.5 * ALPHA_MIN) + (1.0 - 0.5 * ALPHA_MIN) * (theta / THETA_MIN * PI).cos()
}

/// Where a source at `source` (world, m) sits for `listener`, at `rate` samples/s.
pub fn place(listener: &Listener, source: Vec3, rate: f32) -> Placement {
    let rel = listener.orientation.inverse() * (source - listener.position);
    let r = rel.length();
    let dir = if r > 1e-4 && r.is_finite() {
        rel / r
    } else {
        Vec3::NEG_Z
    };
    let lateral = dir.x.clamp(-1.0, 1.0).asin();
    let itd = woodworth_itd(lateral) * rate;
    // A common offset keeps both delays positive; only their difference is heard.
    let offset = woodworth_itd(0.5 * PI) * rate * 0.5 + 1.0;
    let theta = |ear: Vec3| dir.dot(ear).clamp(-1.0, 1.0).acos();
    Placement {
        delay: [offset + 0.5 * itd, offset - 0.5 * itd],
        // A source at no finite distance is silent.
        gain: if r.is_finite() {
            REFERENCE_DISTANCE / r.max(REFERENCE_DISTANCE)
        } else {
            0.0
        },
        alpha: [
            shadow_alpha(theta(Vec3::NEG_X)),
            shadow_alpha(theta(Vec3::X)),
        ],
    }
}

/// One source's ears: a delay line and a shadow filter each.
#[derive(Clone, Debug)]
pub struct Spatializer {
    line: [f32; DELAY_LEN],
    at: usize,
    current: Option<Placement>,
    shadow: [HeadShadow; 2],
    /// Blocks rendered silent in a row (a silent, drained source is skipped).
    quiet: u32,
}

impl Spatializer {
    /// Silent lines for `rate` samples/s.
    pub fn new(rate: f32) -> Self {
        Self {
            line: [0.0; DELAY_LEN],
            at: 0,
            current: None,
            shadow: [HeadShadow::new(HEAD_RADIUS, SPEED_OF_SOUND, rate); 2],
            quiet: 0,
        }
    }

    /// Adds `mono`, placed at `target` (eased from the last block's placement), into `out`
    /// (interleaved stereo, `mono.len()` frames). `silent`: the voice made nothing this block;
    /// once the lines have drained the block costs nothing.
    pub fn render(&mut self, mono: &[f32], target: Placement, silent: bool, out: &mut [f32]) {
        self.quiet = if silent { self.quiet + 1 } else { 0 };
        let from = self.current.unwrap_or(target);
        self.current = Some(target);
        if self.quiet > 1 {
            return;
        }
        for (ear, s) in self.shadow.iter_mut().enumerate() {
            s.set_alpha(target.alpha[ear]);
        }
        let n = mono.len();
        let step = 1.0 / n.max(1) as f32;
        for (i, (&x, frame)) in mono.iter().zip(out.chunks_exact_mut(2)).enumerate() {
            self.line[self.at] = x;
            let t = (i + 1) as f32 * step;
            let gain = from.gain + (target.gain - from.gain) * t;
            for (ear, o) in frame.iter_mut().enumerate() {
                let d = from.delay[ear] + (target.delay[ear] - from.delay[ear]) * t;
                let y = self.shadow[ear].next(self.tap(d));
                *o += gain * y;
            }
            self.at = (self.at + 1) % DELAY_LEN;
        }
    }

    /// The line `delay` samples back (linear interpolation).
    #[inline]
    fn tap(&self, delay: f32) -> f32 {
        let d = delay.clamp(0.0, (DELAY_LEN - 2) as f32);
        let whole = d as usize;
        let frac = d - whole as f32;
        let i0 = (self.at + DELAY_LEN - whole) % DELAY_LEN;
        let i1 = (i0 + DELAY_LEN - 1) % DELAY_LEN;
        self.line[i0] + (self.line[i1] - self.line[i0]) * frac
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn a_source_on_the_left_reaches_the_left_ear_first_and_louder() {
        let head = Listener::default();
        let p = place(&head, head.position + Vec3::new(-3.0, 0.0, 0.0), 48_000.0);
        let itd = (p.delay[1] - p.delay[0]) / 48_000.0;
        assert!((itd - HEAD_RADIUS / SPEED_OF_SOUND * (PI / 2.0 + 1.0)).abs() < 1e-6);
        assert!(p.alpha[0] > 1.9 && p.alpha[1] < 0.3, "{p:?}");
        assert!((p.gain - 1.0 / 3.0).abs() < 1e-6);
        // Ahead: no difference at all.
        let ahead = place(&head, head.position + Vec3::new(0.0, 0.0, -5.0), 48_000.0);
        assert!((ahead.delay[0] - ahead.delay[1]).abs() < 1e-4);
        assert!((ahead.alpha[0] - ahead.alpha[1]).abs() < 1e-5);
    }

    #[test]
    fn turning_the_head_moves_the_source() {
        let mut head = Listener::default();
        let src = head.position + Vec3::new(-3.0, 0.0, 0.0);
        // Turned 90° left, the source on the world's −x is straight ahead.
        head.orientation = Quat::from_rotation_y(0.5 * PI);
        let p = place(&head, src, 48_000.0);
        assert!((p.delay[0] - p.delay[1]).abs() < 1e-3, "{p:?}");
    }

    #[test]
    fn the_lines_delay_by_the_placement() {
        let mut s = Spatializer::new(48_000.0);
        let p = Placement {
            delay: [3.0, 10.0],
            gain: 1.0,
            alpha: [1.0, 1.0],
        };
        let mut mono = [0.0f32; 32];
        mono[0] = 1.0;
        let mut out = [0.0f32; 64];
        s.render(&mono, p, false, &mut out);
        let peak = |ear: usize| {
            (0..32)
                .max_by(|&a, &b| out[2 * a + ear].abs().total_cmp(&out[2 * b + ear].abs()))
                .unwrap()
        };
        assert_eq!((peak(0), peak(1)), (3, 10));
    }
}

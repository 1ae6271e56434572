//! The ears under the water (issue 45, item 5): what a diver hears. The surface reflects
//! almost all of the air's sound (the wind is all but gone), the water round the head carries
//! the nearby wash, the breaking and the bubbles by bone conduction, low and close: the mix
//! loses its high frequencies and most of its width. A stage on the mixed sound, eased over
//! [`CROSSING_S`] as the head crosses the surface, so crossing it never clicks.

use super::dsp::OnePole;

/// Time constant (s) of the crossing: long enough that no gain or filter change clicks, short
/// enough that going under is heard as it happens.
pub const CROSSING_S: f32 = 0.06;
/// The low-pass cutoff (Hz) fully under the water (bone conduction passes little above a
/// few hundred hertz) and above it (out of hearing: the stage passes everything).
pub const UNDER_CUTOFF_HZ: f32 = 600.0;
const OPEN_CUTOFF_HZ: f32 = 18_000.0;
/// What is left of the air's sound (the wind) fully under the water.
pub const AIR_UNDER: f32 = 0.08;
/// What is left of the difference between the ears fully under (sound is 4.4 times as fast in
/// water: the time and level cues that place it in the air are mostly gone).
const WIDTH_UNDER: f32 = 0.35;
/// The water's own sound, closer under the water (the gain on the filtered mix).
const CLOSE_UNDER: f32 = 1.6;

/// The underwater stage's state: how far under the ears are (0 in the air, 1 in the water,
/// eased), and its two-pole low-pass per ear.
pub struct Submerged {
    rate: f32,
    immersion: f32,
    ease: f32,
    low: [[OnePole; 2]; 2],
}

impl Submerged {
    /// A stage in the air, at `rate` samples per second.
    pub fn new(rate: f32) -> Self {
        Self {
            rate,
            immersion: 0.0,
            ease: 1.0 - (-1.0 / (CROSSING_S * rate)).exp(),
            low: [[OnePole::new(OPEN_CUTOFF_HZ, rate); 2]; 2],
        }
    }

    /// What is left of the air's sound now: the wind's gain for the coming block.
    pub fn air_gain(&self) -> f32 {
        1.0 - (1.0 - AIR_UNDER) * self.immersion
    }

    /// Filters interleaved stereo `stereo` in place, easing toward under the water when `under`.
    pub fn process(&mut self, under: bool, stereo: &mut [f32]) {
        let target = if under { 1.0 } else { 0.0 };
        // The cutoff for this block, from how far under the ears are at its start (log-spaced:
        // the ear hears octaves).
        let cutoff = OPEN_CUTOFF_HZ * (UNDER_CUTOFF_HZ / OPEN_CUTOFF_HZ).powf(self.immersion);
        for ear in &mut self.low {
            for pole in ear {
                pole.set_cutoff(cutoff, self.rate);
            }
        }
        if self.immersion == 0.0 && !under {
            // In the air and settled: the filters keep up with the sound, which passes as is.
            for s in stereo.chunks_exact_mut(2) {
                for ([first, second], x) in self.low.iter_mut().zip(s.iter()) {
                    second.next(first.next(*x));
                }
            }
            return;
        }
        for s in stereo.chunks_exact_mut(2) {
            self.immersion += (target - self.immersion) * self.ease;
            if !under && self.immersion < 1e-4 {
                self.immersion = 0.0;
            }
            let m = self.immersion;
            let mut wet = [0.0; 2];
            for (([first, second], x), w) in self.low.iter_mut().zip(s.iter()).zip(&mut wet) {
                *w = second.next(first.next(*x));
            }
            // Mid and side: the side narrowed, the filtered mix closer.
            let (mid, side) = (0.5 * (wet[0] + wet[1]), 0.5 * (wet[0] - wet[1]));
            let side = side * (1.0 - (1.0 - WIDTH_UNDER) * m);
            let gain = 1.0 + (CLOSE_UNDER - 1.0) * m;
            let under_mix = [(mid + side) * gain, (mid - side) * gain];
            for (x, u) in s.iter_mut().zip(under_mix) {
                *x += (u - *x) * m;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RATE: f32 = 48_000.0;

    /// Runs `samples` stereo frames of `signal(n)` through `stage`, `under` or not.
    fn run(
        stage: &mut Submerged,
        under: bool,
        from: usize,
        samples: usize,
        signal: impl Fn(usize) -> f32,
    ) -> Vec<f32> {
        let mut out = Vec::with_capacity(samples);
        for block in (from..from + samples).collect::<Vec<_>>().chunks(64) {
            let mut buf: Vec<f32> = block.iter().flat_map(|&n| [signal(n), signal(n)]).collect();
            stage.process(under, &mut buf);
            out.extend(buf.chunks_exact(2).map(|s| s[0]));
        }
        out
    }

    #[test]
    fn going_under_eases_the_level_and_cuts_the_highs() {
        // A steady level: above the water it passes unchanged; going under it rises to the
        // closer gain over tens of milliseconds, never by a step.
        let mut s = Submerged::new(RATE);
        let dc = run(&mut s, false, 0, 4800, |_| 0.5);
        assert!(
            dc.iter().all(|&x| (x - 0.5).abs() < 1e-6),
            "the air's sound is changed"
        );
        let down = run(&mut s, true, 4800, 24_000, |_| 0.5);
        let step = down
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0f32, f32::max);
        let settled = *down.last().unwrap();
        // No faster than a glide of the whole change (0.3) over 20 ms: inaudible as a click.
        assert!(step < 0.3 / (0.02 * RATE), "a step of {step} going under");
        assert!(
            (settled - 0.5 * CLOSE_UNDER).abs() < 0.01,
            "settled at {settled}"
        );
        // A 5 kHz tone under the water: over 20 dB down.
        let tone = |n: usize| (n as f32 * 5000.0 / RATE * std::f32::consts::TAU).sin();
        let under = run(&mut s, true, 0, 4800, tone);
        let rms = (under[2400..].iter().map(|x| x * x).sum::<f32>() / 2400.0).sqrt();
        let db = 20.0 * (rms / std::f32::consts::FRAC_1_SQRT_2).log10();
        assert!(db < -20.0, "5 kHz under the water: {db:.1} dB");
    }
}

//! The soundscape's voices, one sound each, rendered mono (or, for the diffuse wind, stereo)
//! into a block. Each takes plain parameters per block and eases them itself; none allocates.
//!
//! | voice | what makes it | what drives it |
//! |---|---|---|
//! | [`wind::Wind`] | pink noise through a band that rises with the speed, spray hiss above 8 m/s | wind speed, gusting |
//! | [`water::Rumble`] | low-passed noise under 100 Hz | Hs, the water's heave round the deck |
//! | [`water::Wash`] | band-passed noise, slaps on the deck | rise speed and clearance at a wash point |
//! | [`bubbles::Bubbles`] | damped sinusoids at Minnaert's frequency | (used by the two below) |
//! | [`breaking::Crackle`] | bubble grains and fizz | whitecaps made and lying in a sector |
//! | [`splash::SplashVoice`] | a slap, the cavity's thump, a spray of bubbles | an impact's energy and size |

pub mod breaking;
pub mod bubbles;
pub mod splash;
pub mod water;
pub mod wind;

/// A parameter eased linearly from `from` (the last block's) to `to` at sample `i` of `n`.
#[inline]
pub(crate) fn ramp(from: f32, to: f32, i: usize, n: usize) -> f32 {
    from + (to - from) * ((i + 1) as f32 / n as f32)
}

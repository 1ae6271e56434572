//! The window's size as the user gives it (`--size WIDTHxHEIGHT`), checked.

use ash::vk;

use crate::xr::desktop::EyeSize;

/// A validated window size: at least 2×1 pixels (one per eye), at most 8192 a side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowSize {
    width: u32,
    height: u32,
}

impl WindowSize {
    /// The largest side accepted.
    pub const MAX: u32 = 8192;

    /// Checks the width is in [2, 8192] and the height in [1, 8192].
    pub fn new(width: u32, height: u32) -> Result<Self, String> {
        if (2..=Self::MAX).contains(&width) && (1..=Self::MAX).contains(&height) {
            Ok(Self { width, height })
        } else {
            Err(format!(
                "window size {width}x{height}: the width must be in [2, {max}] pixels (one half \
                 per eye) and the height in [1, {max}]",
                max = Self::MAX
            ))
        }
    }

    /// Parses `WxH`.
    pub fn parse(s: &str) -> Result<Self, String> {
        let (w, h) = s
            .split_once(['x', 'X'])
            .ok_or_else(|| format!("window size `{s}`: expected WIDTHxHEIGHT, e.g. 1600x800"))?;
        let p = |v: &str| {
            v.trim()
                .parse::<u32>()
                .map_err(|_| format!("window size `{s}`: `{v}` is not a whole number of pixels"))
        };
        Self::new(p(w)?, p(h)?)
    }

    /// The per-eye image size: half the width, the full height (capped at [`EyeSize::MAX`]).
    pub fn eye(self) -> EyeSize {
        // Both sides are in [1, EyeSize::MAX] because `new` keeps the width at least 2.
        EyeSize {
            width: (self.width / 2).min(EyeSize::MAX),
            height: self.height.min(EyeSize::MAX),
        }
    }

    /// As a Vulkan extent.
    pub fn extent(self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.width,
            height: self.height,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn window_sizes_are_checked() {
        assert!(WindowSize::parse("0x800")
            .unwrap_err()
            .contains("[2, 8192]"));
        assert!(WindowSize::parse("1600x0").is_err());
        assert!(WindowSize::parse("1x10").is_err());
        assert!(WindowSize::parse("1600").is_err());
        assert!(WindowSize::parse("axb").is_err());
        let s = WindowSize::parse("1600x800").unwrap();
        assert_eq!(
            s.eye().extent(),
            vk::Extent2D {
                width: 800,
                height: 800
            }
        );
        assert_eq!(
            WindowSize::parse("8192x8192")
                .unwrap()
                .eye()
                .extent()
                .height,
            EyeSize::MAX
        );
    }
}

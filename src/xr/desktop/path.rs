//! Scripted camera paths: reproducible head motion for headless runs, tests and benchmarks.
//!
//! # Format
//! A UTF-8 text file, one key per line: `t x y z yaw pitch`, separated by spaces or tabs.
//! - `t`: time in seconds, strictly increasing, the first ≥ 0;
//! - `x y z`: head position in metres (y up; the sea level is y = 0);
//! - `yaw`: degrees, 0 looks along −z, positive turns left (towards −x);
//! - `pitch`: degrees in (−90, 90), positive looks up.
//!
//! A line `throw t` throws a crate from the head along the view at time `t` s (as the window's
//! throw key does), and `boat t speed` launches a boat ahead along the view whose motor holds
//! `speed` m/s, so runs with splashes and wakes are reproducible.
//!
//! `#` starts a comment; blank lines are ignored. Between keys the pose is linear in position,
//! yaw and pitch; before the first key it holds the first, after the last the last. At least
//! one key is required.
//!
//! ```text
//! # standing at the shore, turning to look along the waves
//! 0   0 1.7 0    0  -5
//! 10  0 1.7 -20  90 -10
//! throw 2.5
//! ```

use std::path::Path;

use glam::{Quat, Vec3};

/// One key of a path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathKey {
    /// Time (s).
    pub t: f64,
    /// Head position (m).
    pub position: Vec3,
    /// Yaw (degrees, positive turns left).
    pub yaw: f32,
    /// Pitch (degrees, positive looks up).
    pub pitch: f32,
}

/// A parsed camera path.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPath {
    keys: Vec<PathKey>,
    /// Times of the scripted throws (s), increasing.
    throws: Vec<f64>,
    /// Times (s) and speeds (m/s) of the scripted boat launches, by time.
    boats: Vec<(f64, f32)>,
}

/// A path file that could not be read, with the line at fault.
#[derive(Debug, Clone, PartialEq)]
pub struct PathError(pub String);

impl std::fmt::Display for PathError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PathError {}

/// Largest yaw a key may have (degrees): a hundred turns.
pub const MAX_YAW_DEG: f32 = 36_000.0;

impl CameraPath {
    /// Reads and parses a path file.
    pub fn load(path: &Path) -> Result<Self, PathError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| PathError(format!("cannot read camera path {}: {e}", path.display())))?;
        Self::parse(&text).map_err(|e| PathError(format!("{}: {}", path.display(), e.0)))
    }

    /// Parses the text of a path file.
    pub fn parse(text: &str) -> Result<Self, PathError> {
        let mut keys: Vec<PathKey> = Vec::new();
        let mut throws: Vec<f64> = Vec::new();
        let mut boats: Vec<(f64, f32)> = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line_no = i + 1;
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split_whitespace().collect();
            if fields[0] == "throw" {
                let t = match fields[..] {
                    [_, t] => t.parse::<f64>().ok().filter(|t| t.is_finite() && *t >= 0.0),
                    _ => None,
                }
                .ok_or_else(|| {
                    PathError(format!(
                        "line {line_no}: expected `throw t` with a time t >= 0 (s)"
                    ))
                })?;
                throws.push(t);
                continue;
            }
            if fields[0] == "boat" {
                let launch = match fields[..] {
                    [_, t, v] => t
                        .parse::<f64>()
                        .ok()
                        .filter(|t| t.is_finite() && *t >= 0.0)
                        .zip(v.parse::<f32>().ok().filter(|v| (0.0..=10.0).contains(v))),
                    _ => None,
                }
                .ok_or_else(|| {
                    PathError(format!(
                        "line {line_no}: expected `boat t speed` with a time t >= 0 (s) and a \
                         speed from 0 to 10 (m/s)"
                    ))
                })?;
                boats.push(launch);
                continue;
            }
            if fields.len() != 6 {
                return Err(PathError(format!(
                    "line {line_no}: expected 6 numbers `t x y z yaw pitch`, found {}",
                    fields.len()
                )));
            }
            let mut v = [0f64; 6];
            for (k, f) in fields.iter().enumerate() {
                v[k] = f
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        PathError(format!("line {line_no}: `{f}` is not a finite number"))
                    })?;
            }
            let key = PathKey {
                t: v[0],
                position: Vec3::new(v[1] as f32, v[2] as f32, v[3] as f32),
                yaw: v[4] as f32,
                pitch: v[5] as f32,
            };
            if key.t < 0.0 {
                return Err(PathError(format!(
                    "line {line_no}: time {} is negative",
                    key.t
                )));
            }
            if let Some(prev) = keys.last() {
                if key.t <= prev.t {
                    return Err(PathError(format!(
                        "line {line_no}: time {} does not increase (previous {})",
                        key.t, prev.t
                    )));
                }
            }
            if !(key.pitch > -90.0 && key.pitch < 90.0) {
                return Err(PathError(format!(
                    "line {line_no}: pitch {} is outside (-90, 90) degrees",
                    key.pitch
                )));
            }
            // A yaw that f32 cannot hold (1e40 reads as a finite f64) would turn the view
            // into NaN; a hundred turns either way is plenty for any path.
            if !key.yaw.is_finite() || key.yaw.abs() > MAX_YAW_DEG {
                return Err(PathError(format!(
                    "line {line_no}: yaw {} is beyond ±{MAX_YAW_DEG} degrees",
                    fields[4]
                )));
            }
            if key.position.abs().max_element() > crate::lod::frustum::MAX_COORDINATE {
                return Err(PathError(format!(
                    "line {line_no}: position {} is beyond ±{} m",
                    key.position,
                    crate::lod::frustum::MAX_COORDINATE
                )));
            }
            keys.push(key);
        }
        if keys.is_empty() {
            return Err(PathError("the path has no keys".into()));
        }
        throws.sort_by(f64::total_cmp);
        boats.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(Self {
            keys,
            throws,
            boats,
        })
    }

    /// A path standing still at `position`, looking along `yaw`/`pitch`.
    pub fn still(position: Vec3, yaw: f32, pitch: f32) -> Self {
        Self {
            keys: vec![PathKey {
                t: 0.0,
                position,
                yaw,
                pitch,
            }],
            throws: Vec::new(),
            boats: Vec::new(),
        }
    }

    /// The speeds (m/s) of the scripted boats launched in [`from`, `to`) (s).
    pub fn boats_in(&self, from: f64, to: f64) -> impl Iterator<Item = f32> + '_ {
        self.boats
            .iter()
            .filter(move |(t, _)| *t >= from && *t < to)
            .map(|&(_, v)| v)
    }

    /// How many scripted throws fall in [`from`, `to`) (s).
    pub fn throws_in(&self, from: f64, to: f64) -> usize {
        self.throws.iter().filter(|&&t| t >= from && t < to).count()
    }

    /// The keys.
    pub fn keys(&self) -> &[PathKey] {
        &self.keys
    }

    /// Time of the last key (s).
    pub fn duration(&self) -> f64 {
        self.keys.last().map_or(0.0, |k| k.t)
    }

    /// Head position and orientation at time `t` (s).
    pub fn pose(&self, t: f64) -> (Vec3, Quat) {
        let k = &self.keys;
        let i = k.partition_point(|key| key.t <= t);
        let (a, b, s) = if i == 0 {
            (k[0], k[0], 0.0)
        } else if i == k.len() {
            (k[i - 1], k[i - 1], 0.0)
        } else {
            let (a, b) = (k[i - 1], k[i]);
            (a, b, ((t - a.t) / (b.t - a.t)) as f32)
        };
        let lerp = |x: f32, y: f32| x + (y - x) * s;
        let position = a.position.lerp(b.position, s);
        (
            position,
            head_orientation(lerp(a.yaw, b.yaw), lerp(a.pitch, b.pitch)),
        )
    }
}

/// Orientation for `yaw` (degrees, about +y, positive left) then `pitch` (about the local x,
/// positive up).
pub fn head_orientation(yaw: f32, pitch: f32) -> Quat {
    Quat::from_rotation_y(yaw.to_radians()) * Quat::from_rotation_x(pitch.to_radians())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_interpolates() {
        let p = CameraPath::parse("# c\n0 0 1 0 0 0\n\n10 10 1 0 90 -10 # end\n").unwrap();
        assert_eq!(p.keys().len(), 2);
        let (pos, q) = p.pose(5.0);
        assert!((pos - Vec3::new(5.0, 1.0, 0.0)).length() < 1e-6);
        let fwd = q * Vec3::NEG_Z;
        let expect = head_orientation(45.0, -5.0) * Vec3::NEG_Z;
        assert!((fwd - expect).length() < 1e-6);
        assert_eq!(p.pose(-1.0).0, Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(p.pose(99.0).0, Vec3::new(10.0, 1.0, 0.0));
        // Yaw 90 looks along −x.
        let left = head_orientation(90.0, 0.0) * Vec3::NEG_Z;
        assert!((left - Vec3::NEG_X).length() < 1e-6);
    }

    #[test]
    fn rejects_malformed_files_naming_the_line() {
        let bad = [
            ("", "no keys"),
            ("0 0 1 0 0", "line 1: expected 6"),
            ("0 0 1 0 0 x", "`x` is not"),
            ("0 0 1 0 0 NaN", "`NaN` is not"),
            (
                "1 0 1 0 0 0\n1 0 1 0 0 0",
                "line 2: time 1 does not increase",
            ),
            ("-1 0 1 0 0 0", "negative"),
            ("0 0 1 0 0 95", "pitch 95"),
            ("0 1e9 1 0 0 0", "beyond"),
            // Found by the fuzzer (fuzz/corpus/camera_path/regression-yaw-beyond-f32).
            ("0 0 6 0 1e43 -12", "yaw 1e43 is beyond"),
            ("0 0 6 0 40000 0", "beyond ±36000 degrees"),
            ("0 0 1 0 0 0\nthrow", "line 2: expected `throw t`"),
            ("0 0 1 0 0 0\nthrow -1", "line 2: expected `throw t`"),
            ("0 0 1 0 0 0\nboat 1", "line 2: expected `boat t speed`"),
            ("0 0 1 0 0 0\nboat 1 40", "speed from 0 to 10"),
        ];
        for (text, msg) in bad {
            let e = CameraPath::parse(text).unwrap_err();
            assert!(e.0.contains(msg), "{text:?}: {e}");
        }
    }

    /// Scripted throws and boats fall in the frame spans that hold their times.
    #[test]
    fn scripts_throws_and_boats() {
        let p = CameraPath::parse("0 0 1 0 0 0\nthrow 2\nboat 0.5 1.5\nthrow 1\n").unwrap();
        assert_eq!(p.throws_in(0.0, 1.0), 0);
        assert_eq!(p.throws_in(1.0, 2.5), 2);
        assert_eq!(p.boats_in(0.4, 0.6).collect::<Vec<_>>(), vec![1.5]);
        assert_eq!(p.boats_in(0.6, 9.0).count(), 0);
    }
}

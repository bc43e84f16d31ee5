//! Coordinate axes, for shapes with an axis, scene files' `axis = "z"` and the CLI's
//! `--axis x|y|z`.

use glam::DVec3;

/// One of the three coordinate axes. In scene files `"x"`, `"y"` or `"z"`, in either
/// case as by [`str::parse`]; any other value is a deserialization error (an unknown
/// variant) at its place in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The x axis.
    X,
    /// The y axis.
    Y,
    /// The z axis.
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }

    /// The unit vector along the axis.
    #[must_use]
    pub fn unit(self) -> DVec3 {
        DVec3::AXES[self.index()]
    }

    /// Splits `p` into (along the axis, the two other coordinates in cyclic order).
    #[must_use]
    pub(crate) fn split(self, p: DVec3) -> (f64, [f64; 2]) {
        let i = self.index();
        (p[i], [p[(i + 1) % 3], p[(i + 2) % 3]])
    }

    /// The inverse of [`Axis::split`]: the vector with coordinate `w` along the axis
    /// and `[u, v]` across it.
    #[must_use]
    pub(crate) fn join(self, w: f64, [u, v]: [f64; 2]) -> DVec3 {
        let i = self.index();
        let mut p = DVec3::ZERO;
        p[i] = w;
        p[(i + 1) % 3] = u;
        p[(i + 2) % 3] = v;
        p
    }
}

impl std::str::FromStr for Axis {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "x" => Ok(Axis::X),
            "y" => Ok(Axis::Y),
            "z" => Ok(Axis::Z),
            _ => Err(format!("'{s}' is not an axis (use x, y or z)")),
        }
    }
}

/// A string read by [`str::parse`], so scene files take what `--axis` takes; a derived
/// enum would list the upper-case spellings as variants of their own in its errors.
impl<'de> serde::Deserialize<'de> for Axis {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let s = String::deserialize(deserializer)?;
        s.parse().map_err(|_| serde::de::Error::unknown_variant(&s, &["x", "y", "z"]))
    }
}

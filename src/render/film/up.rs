//! The world's up direction a camera request names: a coordinate axis, or any vector.
//! An axis also names the frame the views and orbit angles are given in
//! ([`NamedView`](super::NamedView), [`orbit_direction`](super::orbit_direction)); a
//! vector's frame is its nearest axis's (ties go to x, then y).

use glam::DVec3;

use crate::shape::Axis;

/// An up direction: an axis, or a vector whose views are named in the frame of the
/// axis nearest to it. The default is z, octsolid's own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Up {
    /// A coordinate axis: also names the frame of the named views and orbit angles.
    Axis(Axis),
    /// Any non-zero vector: views are named in the frame of the axis nearest to it.
    Vector(DVec3),
}

impl Default for Up {
    fn default() -> Self {
        Up::Axis(Axis::Z)
    }
}

impl Up {
    /// The nearest coordinate axis (the frame views are named in).
    #[must_use]
    pub fn axis(self) -> Axis {
        match self {
            Up::Axis(a) => a,
            Up::Vector(v) => {
                let a = v.abs();
                if a.x >= a.y && a.x >= a.z {
                    Axis::X
                } else if a.y >= a.z {
                    Axis::Y
                } else {
                    Axis::Z
                }
            }
        }
    }

    /// The unit up vector.
    #[must_use]
    pub fn vector(self) -> DVec3 {
        match self {
            Up::Axis(a) => a.unit(),
            Up::Vector(v) => v.normalize(),
        }
    }
}

impl std::str::FromStr for Up {
    type Err = String;

    /// Parses an axis (`x`, `y`, `z`, any case) or a vector `X,Y,Z` of finite, not all
    /// zero, numbers.
    fn from_str(s: &str) -> Result<Self, String> {
        if let Ok(axis) = s.trim().parse::<Axis>() {
            return Ok(Up::Axis(axis));
        }
        let parts: Vec<&str> = s.split(',').collect();
        let numbers: Option<Vec<f64>> = parts.iter().map(|t| t.trim().parse::<f64>().ok()).collect();
        let v = match numbers.as_deref() {
            Some(&[x, y, z]) if [x, y, z].iter().all(|c| c.is_finite()) => DVec3::new(x, y, z),
            _ => return Err(format!("'{s}' is neither x, y, z nor X,Y,Z")),
        };
        if v.length() < 1e-12 {
            return Err(format!("'{s}': the up vector is zero"));
        }
        Ok(Up::Vector(v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_up_is_an_axis_or_a_vector_framed_by_its_nearest_axis() {
        assert_eq!("Y".parse::<Up>(), Ok(Up::Axis(Axis::Y)));
        let tilted: Up = "0.1, 2, -0.5".parse().unwrap();
        assert_eq!(tilted.axis(), Axis::Y);
        assert!((tilted.vector().length() - 1.0).abs() < 1e-12);
        assert!("0,0,0".parse::<Up>().unwrap_err().contains("zero"));
        assert!("1,2".parse::<Up>().is_err());
        assert!("1,nan,2".parse::<Up>().is_err());
        assert_eq!(Up::default().vector(), DVec3::Z);
    }
}

//! Profile specifications: a [`Profile`] written as data, what a scene's `extrude` and
//! `revolve` take after `profile =` (docs/SCENES.md).
//!
//! One key naming the kind: `{ polygon = [[x, y], ...] }`, `{ polygon_with_holes = {
//! outline = [[x, y], ...], holes = [[[x, y], ...], ...] } }`, `{ circle = { center =
//! [x, y], radius = r } }`, `{ rectangle = { center = [x, y], size = [w, h] } }` (both
//! centres default to the origin), `{ union = [profile, ...] }` and `{ difference =
//! [profile, ...] }` (the first minus the rest). Unknown kinds and fields are
//! deserialization errors; [`ProfileSpec::build`] makes the profile with its
//! constructors' checks (which the shape spec holding it runs as it is read, so a
//! crossing polygon is refused at its place in the file). A profile nests at most
//! [`MAX_PROFILE_NESTING`] deep.

use glam::DVec2;
use serde::Deserialize;

use super::Profile;
use crate::error::{Error, Result};

/// The most nodes on a path from a profile's root to a leaf.
pub const MAX_PROFILE_NESTING: usize = 64;

/// A profile as data (see the module doc).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ProfileSpec {
    /// A simple polygon: its corners in order.
    Polygon(Vec<[f64; 2]>),
    /// A polygon with holes, filled by the even-odd rule.
    PolygonWithHoles {
        /// The outer ring's corners.
        outline: Vec<[f64; 2]>,
        /// Each hole's corners (inside the outline; an island is a ring in a hole).
        holes: Vec<Vec<[f64; 2]>>,
    },
    /// A disc.
    Circle {
        /// Centre (default the origin).
        center: Option<[f64; 2]>,
        /// Radius.
        radius: f64,
    },
    /// An axis-aligned rectangle.
    Rectangle {
        /// Centre (default the origin).
        center: Option<[f64; 2]>,
        /// Width and height.
        size: [f64; 2],
    },
    /// Points in any of the profiles.
    Union(Vec<ProfileSpec>),
    /// Points in the first profile and none of the others.
    Difference(Vec<ProfileSpec>),
}

fn points(ring: &[[f64; 2]]) -> Vec<DVec2> {
    ring.iter().map(|&p| DVec2::from_array(p)).collect()
}

impl ProfileSpec {
    /// The profile this spec describes; errors name the refused value.
    pub fn build(&self) -> Result<Profile> {
        self.build_nested(1)
    }

    fn build_nested(&self, depth: usize) -> Result<Profile> {
        if depth > MAX_PROFILE_NESTING {
            return Err(Error::invalid("profile", format!("profiles nested deeper than {MAX_PROFILE_NESTING}")));
        }
        let centre = |c: Option<[f64; 2]>| c.map_or(DVec2::ZERO, DVec2::from_array);
        match self {
            ProfileSpec::Polygon(ring) => Profile::polygon(points(ring)),
            ProfileSpec::PolygonWithHoles { outline, holes } => {
                Profile::polygon_with_holes(points(outline), holes.iter().map(|h| points(h)).collect())
            }
            ProfileSpec::Circle { center, radius } => Profile::circle(centre(*center), *radius),
            ProfileSpec::Rectangle { center, size } => Profile::rectangle(centre(*center), DVec2::from_array(*size)),
            ProfileSpec::Union(parts) => {
                Profile::union(parts.iter().map(|p| p.build_nested(depth + 1)).collect::<Result<_>>()?)
            }
            ProfileSpec::Difference(parts) => {
                Profile::difference(parts.iter().map(|p| p.build_nested(depth + 1)).collect::<Result<_>>()?)
            }
        }
    }

    /// Whether the profile's [`Profile::area`] is exact (no set operation).
    #[must_use]
    pub fn has_exact_area(&self) -> bool {
        !matches!(self, ProfileSpec::Union(_) | ProfileSpec::Difference(_))
    }
}

//! The distance an offset measures: Euclidean (the ball, the default), Manhattan (the
//! octahedron, L1) or Chebyshev (the cube, L-infinity), each from a voxel's centre to
//! the nearest voxel of the other phase taken as a cube, so an offset of `o` voxels
//! along an axis is a gap of `max(|o| - 1/2, 0)` on that axis.
//!
//! The separable transform of [`super::tiles`] sums a cost an axis, in integers:
//! - Euclidean: `(2|o| - 1)^2` (four times the squared gap), summed: four times the
//!   squared distance, under `4 D^2`;
//! - Manhattan: `2|o| - 1` (twice the gap), summed: twice the distance, under `2 D`;
//! - Chebyshev: the distance is the largest gap, under `D` exactly when every `|o|` is
//!   at most the reach `R = ceil(D + 1/2) - 1`, which bounds every offset the
//!   transform looks at; so the cost is 1 an axis the offset moves along (0 on none),
//!   and a voxel has a site in its cube of reach when its sum is at most 3.
//!
//! In each, a site's own value is 0 and every other voxel's at least 1, as the
//! transform needs. Along a surface (the sub-voxel rule) the distance is Euclidean only.

/// The distance an offset, shell or round measures (see the module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Metric {
    /// The straight-line distance: growing by a ball.
    #[default]
    Euclidean,
    /// The sum of the distances along the axes (L1): growing by an octahedron.
    Manhattan,
    /// The largest distance along an axis (L-infinity): growing by a cube.
    Chebyshev,
}

impl Metric {
    /// Every metric, in the order help lists them.
    pub const ALL: [Metric; 3] = [Metric::Euclidean, Metric::Manhattan, Metric::Chebyshev];

    /// The metric's one spelling (`euclidean`, `manhattan`, `chebyshev`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Metric::Euclidean => "euclidean",
            Metric::Manhattan => "manhattan",
            Metric::Chebyshev => "chebyshev",
        }
    }

    /// The transform's cost of an offset of `o` voxels along one axis (module doc).
    pub(super) fn axis_cost(self, o: i64) -> i64 {
        match (self, o) {
            (_, 0) => 0,
            (Metric::Euclidean, o) => super::edt::axis_cost(o),
            (Metric::Manhattan, o) => 2 * o.abs() - 1,
            (Metric::Chebyshev, _) => 1,
        }
    }

    /// The largest sum of costs of a voxel within `radius` voxels (strictly under it).
    pub(super) fn limit(self, radius: f64) -> i64 {
        match self {
            Metric::Euclidean => ((4.0 * radius * radius).ceil() - 1.0).min(1e18) as i64,
            Metric::Manhattan => ((2.0 * radius).ceil() - 1.0).min(1e18) as i64,
            Metric::Chebyshev => 3,
        }
    }
}

crate::spelling::spelled!(Metric);

#[cfg(test)]
mod tests {
    use super::*;

    /// The metric's distance from a centre to the cube `o` away, by its definition.
    fn distance(metric: Metric, o: [i64; 3]) -> f64 {
        let gaps = o.map(|c| (c.abs() as f64 - 0.5).max(0.0));
        match metric {
            Metric::Euclidean => gaps.iter().map(|g| g * g).sum::<f64>().sqrt(),
            Metric::Manhattan => gaps.iter().sum(),
            Metric::Chebyshev => gaps.iter().copied().fold(0.0, f64::max),
        }
    }

    #[test]
    fn the_summed_costs_within_the_reach_say_what_the_distance_says() {
        for metric in [Metric::Euclidean, Metric::Manhattan, Metric::Chebyshev] {
            for radius in [0.6, 1.0, 1.5, 2.0, 2.49, 3.7, 5.0] {
                // The reach (`Step::reach`): the offsets the transform looks at.
                let reach = ((radius + 0.5_f64).ceil() - 1.0) as i64;
                for z in -reach..=reach {
                    for y in -reach..=reach {
                        for x in -reach..=reach {
                            let sum: i64 = [x, y, z].iter().map(|&c| metric.axis_cost(c)).sum();
                            let under = distance(metric, [x, y, z]) < radius;
                            assert_eq!(sum <= metric.limit(radius), under, "{metric} {radius} {x},{y},{z}");
                            assert_eq!(sum == 0, [x, y, z] == [0; 3]);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn names_read_back() {
        for metric in [Metric::Euclidean, Metric::Manhattan, Metric::Chebyshev] {
            assert_eq!(metric.to_string().parse::<Metric>(), Ok(metric));
        }
        assert!("l2".parse::<Metric>().unwrap_err().contains("euclidean"));
    }
}

//! The Menger sponge, level 4, as a user-defined [`Shape`]: a script can voxelize
//! anything that classifies boxes and points.
//!
//! Run: `cargo run --release --example menger [LEVEL] [DEPTH]` (defaults 4 and 9;
//! writes menger.oct and menger.png).

use octsolid::prelude::*;

/// The level-`level` Menger sponge filling the cube `[-1, 1]^3`.
struct Menger {
    level: u32,
}

impl Menger {
    /// Base-3 digit of `t` in `[0, 1)` at `depth` (1 = the first third), clamped.
    fn digit(t: f64, depth: u32) -> i64 {
        ((t * 3f64.powi(depth as i32)).floor() as i64).rem_euclid(3)
    }

    /// Whether the cell holding unit-cube point `t` at `depth` is removed: two or more
    /// of its three base-3 digits are the middle one.
    fn removed_at(t: DVec3, depth: u32) -> bool {
        [t.x, t.y, t.z].iter().filter(|&&c| Self::digit(c, depth) == 1).count() >= 2
    }
}

impl Shape for Menger {
    fn contains(&self, p: DVec3) -> bool {
        let t = (p + DVec3::ONE) / 2.0;
        t.cmpge(DVec3::ZERO).all() && t.cmplt(DVec3::ONE).all() && (1..=self.level).all(|d| !Self::removed_at(t, d))
    }

    fn classify(&self, b: &Aabb) -> Class {
        let (lo, hi) = ((b.min + DVec3::ONE) / 2.0, (b.max + DVec3::ONE) / 2.0);
        if hi.cmplt(DVec3::ZERO).any() || lo.cmpge(DVec3::ONE).any() {
            return Class::Outside;
        }
        if lo.cmplt(DVec3::ZERO).any() || hi.cmpge(DVec3::ONE).any() {
            return Class::Boundary;
        }
        // Walk down the levels while the box stays inside one cell of that level.
        for d in 1..=self.level {
            let cells = 3f64.powi(d as i32);
            let (a, z) = ((lo * cells).floor(), (hi * cells).floor());
            if a != z {
                return Class::Boundary;
            }
            if Self::removed_at(lo, d) {
                return Class::Outside;
            }
        }
        Class::Inside
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(Aabb::new(-DVec3::ONE, DVec3::ONE))
    }
}

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1).map(|a| a.parse::<u32>());
    let level = args.next().transpose().map_err(|e| Error::InvalidArgument { what: "level", reason: e.to_string() })?;
    let depth = args.next().transpose().map_err(|e| Error::InvalidArgument { what: "depth", reason: e.to_string() })?;
    let (level, depth) = (level.unwrap_or(4), depth.unwrap_or(9).min(21) as u8);

    let sponge = Menger { level };
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, depth)?;
    let solid = voxelize(&sponge, domain, &VoxelizeOptions::default())?;
    oct::save(&solid, "menger.oct".as_ref())?;
    png::save(&slice_image(&solid, 2, -0.99, 810)?, "menger.png".as_ref())?;

    // Each level keeps 20 of 27 sub-cubes.
    let exact = 8.0 * (20.0f64 / 27.0).powi(level as i32);
    println!(
        "Menger sponge level {level} at depth {depth}: {} nodes, {} voxels",
        solid.node_count(),
        solid.voxel_count()
    );
    println!(
        "volume {:.5}, analytic {:.5} ({:+.2}%; a 2^{depth} grid cannot align with thirds)",
        solid.volume(),
        exact,
        100.0 * (solid.volume() / exact - 1.0)
    );
    println!("wrote menger.oct and menger.png (slice at z = -0.99: a Sierpinski carpet)");
    Ok(())
}

//! Cross-section images: the solid cut by an axis-aligned plane, drawn with the
//! octree's node structure (fill by node level, outlines on node borders).

use image::{Rgb, RgbImage};
use rayon::prelude::*;

use crate::error::{Error, Number, Result};
use crate::octree::LinearOctree;
use crate::shape::Axis;

/// Largest slice image edge in pixels.
pub const MAX_SLICE_SIZE: u32 = 16_384;

/// Colour of empty space.
const EMPTY: Rgb<u8> = Rgb([246, 246, 242]);

/// Peak bytes of a `size x size` slice written as a PNG: the 3-byte pixels, and as
/// much again for the encoder's filtered rows and compressed stream.
#[must_use]
pub fn estimate_bytes(size: u32) -> u64 {
    2 * 3 * u64::from(size) * u64::from(size)
}

/// Draws the cross-section of `tree` at world coordinate `at` along `axis` as a
/// `size` x `size` image.
///
/// The image shows the domain's face: for axis z the image's right is +x and its up
/// is +y (for x: +y right, +z up; for y: +x right, +z up). Each pixel shows the node
/// holding the voxel under its centre, coloured by level (large nodes deep blue,
/// voxels light amber), with node borders drawn darker where nodes span 6 pixels or more.
pub fn slice_image(tree: &LinearOctree, axis: Axis, at: f64, size: u32) -> Result<RgbImage> {
    let axis = axis.index();
    if !(1..=MAX_SLICE_SIZE).contains(&size) {
        return Err(Error::invalid("size", format!("{size} pixels is outside 1..={MAX_SLICE_SIZE}")));
    }
    let d = tree.domain();
    let lo = d.min()[axis];
    if !(at >= lo && at < lo + d.edge()) {
        return Err(Error::invalid(
            "slice position",
            format!("{} is outside [{}, {})", Number(at), Number(lo), Number(lo + d.edge())),
        ));
    }
    let n = d.resolution();
    let layer = (((at - lo) / d.voxel_size()) as u32).min(n - 1);
    let (u_axis, v_axis) = [(1, 2), (0, 2), (0, 1)][axis];
    let to_voxel = |p: u32| ((u64::from(p) * 2 + 1) * u64::from(n) / (2 * u64::from(size))) as u32;

    // Step 1: which node (index in Morton order) each pixel sees, usize::MAX for empty.
    let ids: Vec<usize> = (0..size)
        .into_par_iter()
        .flat_map_iter(|row| {
            let v = to_voxel(size - 1 - row);
            (0..size).map(move |col| {
                let mut voxel = [0; 3];
                voxel[axis] = layer;
                voxel[u_axis] = to_voxel(col);
                voxel[v_axis] = v;
                tree.find_code(crate::morton::encode(voxel[0], voxel[1], voxel[2])).unwrap_or(usize::MAX)
            })
        })
        .collect();

    // Step 2: fill by level, outline where the node changes between neighbours.
    let depth = f64::from(tree.depth().max(1));
    let pixels_per_voxel = f64::from(size) / f64::from(n);
    let mut img = RgbImage::new(size, size);
    for (i, px) in img.pixels_mut().enumerate() {
        let id = ids[i];
        let (row, col) = (i / size as usize, i % size as usize);
        *px = if id == usize::MAX {
            EMPTY
        } else {
            let key = tree.keys()[id];
            let node_pixels = f64::from(1u32 << key.k()) * pixels_per_voxel;
            let border = (col > 0 && ids[i - 1] != id) || (row > 0 && ids[i - size as usize] != id);
            let fill = level_colour(f64::from(key.level(tree.depth())) / depth);
            if border && node_pixels >= 6.0 { Rgb(fill.0.map(|c| (f64::from(c) * 0.55) as u8)) } else { fill }
        };
    }
    Ok(img)
}

/// Colour ramp for a node level `t` in `[0, 1]` (0 = root): deep blue through teal
/// to light amber, piecewise linear through three stops.
fn level_colour(t: f64) -> Rgb<u8> {
    const STOPS: [[f64; 3]; 3] = [[38.0, 60.0, 130.0], [40.0, 150.0, 150.0], [250.0, 200.0, 90.0]];
    let t = t.clamp(0.0, 1.0) * 2.0;
    let (i, f) = if t >= 1.0 { (1, t - 1.0) } else { (0, t) };
    Rgb(std::array::from_fn(|c| (STOPS[i][c] + (STOPS[i + 1][c] - STOPS[i][c]) * f) as u8))
}

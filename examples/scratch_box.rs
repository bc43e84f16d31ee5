use octsolid::prelude::*;
use octsolid::surface::{ExtractOptions, HermiteData, extract};
fn main() {
    let size = DVec3::new(1.1, 0.7, 0.9);
    let turned = Cuboid::new(DVec3::ZERO, size).unwrap().rotate(DVec3::new(1.0, 2.0, 0.5), 0.6);
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let tree = voxelize(&turned, domain, &Default::default()).unwrap();
    let h = HermiteData::from_shape(&turned, &tree);
    let s =
        extract(&tree, &h, &ExtractOptions { tolerance: 0.0, ..Default::default() }, &octsolid::NoProgress).unwrap();
    let voxel = domain.voxel_size();
    let mut worst = (0.0, 0);
    for (i, v) in s.mesh.vertices.iter().enumerate() {
        let d = turned.surface(*v).unwrap().distance.abs() / voxel;
        if d > worst.0 {
            worst = (d, i);
        }
    }
    let v = s.mesh.vertices[worst.1];
    let lat = (v - domain.min()) / voxel;
    println!("worst {:?} at {:?} lattice {:?}", worst, v, lat);
    let c = lat.round();
    for (k, cr) in h.faces() {
        let p = cr.point(*k);
        if (p - c).abs().max_element() <= 0.6 {
            let w = domain.min() + p * voxel;
            println!(
                "face {:?} t {} n {:?} sdf {:.3e}",
                k.voxel(),
                cr.t,
                cr.normal,
                turned.surface(w).unwrap().distance / voxel
            );
        }
    }
}

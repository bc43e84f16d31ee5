//! A pipe flange: a disc with a raised hub, a bore through both and a ring of six
//! bolt holes.
//!
//! Run: `cargo run --release --example flange` (writes example-output/flange/flange.oct,
//! flange.png and flange-render.png).

use std::f64::consts::PI;

use octsolid::prelude::*;

mod common;

fn main() -> std::process::ExitCode {
    common::run("flange", flange)
}

fn flange(out: &std::path::Path) -> Result<()> {
    // Dimensions (metres): disc 0.2 thick, hub 0.6 tall, the part standing on z = 0.
    let (disc_r, disc_t) = (1.0, 0.2);
    let (hub_r, hub_h) = (0.4, 0.6);
    let bore_r = 0.2;
    let (bolt_r, pitch_r, bolts) = (0.08, 0.7, 6);

    // Model: disc | hub, minus bore, minus bolt holes on the pitch circle.
    let z_up = |r, h: f64| Cylinder::new(DVec3::new(0.0, 0.0, h / 2.0), Axis::Z, r, h);
    let mut flange = (z_up(disc_r, disc_t)? | z_up(hub_r, hub_h)?) - z_up(bore_r, hub_h)?;
    for i in 0..bolts {
        let a = 2.0 * PI * f64::from(i) / f64::from(bolts);
        let centre = DVec3::new(pitch_r * a.cos(), pitch_r * a.sin(), disc_t / 2.0);
        flange = flange - Cylinder::new(centre, Axis::Z, bolt_r, disc_t)?;
    }

    // Voxelize: the domain is the cube around the disc, 512 voxels a side.
    let domain = Domain::new(DVec3::new(-1.05, -1.05, -0.1), 2.1, 9)?;
    let solid = voxelize(&flange, domain, &VoxelizeOptions::default())?;
    oct::write(&solid, out.join("flange.oct"))?;
    png::write(&slice_image(&solid, Axis::Z, 0.1, 768)?, out.join("flange.png"))?;
    // A picture of the part in one call: default camera, lights and material.
    octsolid::quick(&solid, out.join("flange-render.png"))?;

    let exact = PI * (disc_r * disc_r * disc_t + hub_r * hub_r * (hub_h - disc_t))
        - PI * bore_r * bore_r * hub_h
        - f64::from(bolts) * PI * bolt_r * bolt_r * disc_t;
    println!("flange at depth 9: {} nodes, {} voxels", solid.node_count(), solid.voxel_count());
    println!("volume {:.5}, analytic {:.5} ({:+.3}%)", solid.volume(), exact, 100.0 * (solid.volume() / exact - 1.0));
    println!("flange.oct, flange.png (slice through the disc at z = 0.1) and flange-render.png");
    Ok(())
}

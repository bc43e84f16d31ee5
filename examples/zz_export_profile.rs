use octsolid::budget::MemoryBudget;
use octsolid::mesh::{BoundaryOptions, InsideRule, MeshVoxelizeOptions, boundary_mesh, load_mesh, voxelize_mesh};
use octsolid::octree::Domain;
use octsolid::progress::NoProgress;
fn main() {
    let bunny = load_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/models/stanford-bunny.obj").as_ref()).unwrap();
    let options =
        MeshVoxelizeOptions { inside: InsideRule::Auto, budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let domain = Domain::around(&bunny.bounds(), 0.02, std::env::var("D").map_or(10, |d| d.parse().unwrap())).unwrap();
    let (tree, _) = voxelize_mesh(&bunny, domain, &options).unwrap();
    let unit = std::env::args().nth(1).is_some_and(|a| a == "u");
    if std::env::var("SKIP").is_ok() {
        return;
    }
    let t = std::time::Instant::now();
    let mesh = boundary_mesh(&tree, &BoundaryOptions { unit_faces: unit });
    eprintln!("{} tris in {:?}", mesh.triangles.len(), t.elapsed());
}

//! Gathering (the chapter's `[F][B] = [E]` by Gauss-Seidel) against independent
//! oracles: the analytic furnace (a closed box of uniform reflectance rho emitting E
//! everywhere shows `B = E / (1 - rho)`), progressive refinement run to a much smaller
//! unshot fraction (the same system's fixed point, reached another way) within 1% on
//! every element of lit rooms, and refusals (a matrix over the budget, subdivision).

mod common;

use common::radiosity_room::{cuboid, diffuse, tree};
use glam::DVec3;
use octsolid::octree::LinearOctree;
use octsolid::render::radiosity::{Radiosity, RadiosityOptions, Solver, form_factor_matrix_bytes};
use octsolid::render::{Light, Material, Scene};
use octsolid::{MemoryBudget, NoProgress};

/// A closed room: the hollow between [-0.5, 0.5]^3 and [-0.75, 0.75]^3.
fn room() -> LinearOctree {
    tree(&(cuboid([-0.75; 3], [0.75; 3]) - cuboid([-0.5; 3], [0.5; 3])))
}

fn gathering(patch_size: f64, elements: u32) -> RadiosityOptions {
    RadiosityOptions {
        patch_size: Some(patch_size),
        elements,
        solver: Solver::Gathering,
        ..RadiosityOptions::default()
    }
}

#[test]
fn the_gathered_furnace_shows_e_over_one_minus_rho() {
    let emission = 0.8;
    for rho in [0.0, 0.3, 0.7] {
        let mut scene = Scene::new();
        scene.lights.clear();
        scene.add("room", room(), diffuse(rho, emission));
        let r = Radiosity::solve(&scene, &gathering(0.25, 2), &NoProgress).unwrap();
        let s = r.stats();
        assert!(s.residual <= 1e-6 && s.iterations >= 1, "{} sweeps, residual {}", s.iterations, s.residual);
        let want = emission / (1.0 - rho);
        let mut seen = 0;
        for (center, _, _, shown) in r.elements().filter(|e| e.0.abs().max_element() <= 0.5 + 1e-9) {
            seen += 1;
            for c in shown.to_array() {
                assert!((c - want).abs() <= 0.005 * want, "rho {rho}: {c} at {center}, want {want}");
            }
        }
        assert_eq!(seen, 6 * 8 * 8, "the inner walls' elements");
    }
}

/// A closed room of coloured walls lit by an emissive lamp and a point light, with a
/// block casting shadows.
fn lit_room() -> Scene {
    let mut scene = Scene::new();
    scene.lights = vec![Light::Point { position: DVec3::new(0.3, 0.3, 0.3), color: DVec3::new(0.05, 0.04, 0.03) }];
    scene.add("room", room(), Material { color: DVec3::new(0.7, 0.5, 0.3), ..diffuse(0.0, 0.0) });
    scene.add("lamp", tree(&cuboid([-0.125, -0.125, 0.375], [0.125, 0.125, 0.4375])), diffuse(0.6, 2.0));
    scene.add("block", tree(&cuboid([-0.3125, -0.3125, -0.5], [0.0, 0.0, -0.125])), diffuse(0.6, 0.0));
    scene
}

#[test]
fn gathering_agrees_with_shooting_within_one_percent_on_every_element() {
    let scene = lit_room();
    let gathered = Radiosity::solve(&scene, &gathering(0.25, 2), &NoProgress).unwrap();
    let shooting =
        RadiosityOptions { until: 1e-5, ..RadiosityOptions { solver: Solver::Shooting, ..gathering(0.25, 2) } };
    let shot = Radiosity::solve(&scene, &shooting, &NoProgress).unwrap();
    let (g, s) = (gathered.radiosities(), shot.radiosities());
    assert_eq!(g.len(), s.len());
    let largest = s.iter().map(|v| v.max_element()).fold(0.0, f64::max);
    let mut lit = 0;
    for (k, (a, b)) in g.iter().zip(s).enumerate() {
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() <= 0.01 * b[c] + 1e-9 * largest, "element {k}: gathered {a}, shot {b}");
        }
        lit += usize::from(b.max_element() > 0.0);
    }
    assert!(lit > g.len() / 3, "{lit} of {} elements lit", g.len());
    // The energy book balances: what the lights and the lamp emit is absorbed or
    // escapes, and a closed room lets next to nothing escape (the near field's far
    // receivers take what the near ones leave, module near_field, so no shot delivers
    // more than it sends).
    let st = gathered.stats();
    assert!((st.absorbed + st.escaped - st.emitted).abs() < 1e-9 * st.emitted);
    assert!(st.escaped.abs() < 0.02 * st.emitted, "escaped {} of {}", st.escaped, st.emitted);
    let sh = shot.stats();
    assert!(
        (sh.escaped - st.escaped).abs() < 0.002 * st.emitted,
        "shooting escaped {}, gathering {}",
        sh.escaped,
        st.escaped
    );
}

#[test]
fn gathering_refuses_a_matrix_over_the_budget_with_its_size_and_subdivision() {
    let scene = lit_room();
    let small = RadiosityOptions { budget: MemoryBudget(1 << 20), ..gathering(0.25, 2) };
    let e = Radiosity::solve(&scene, &small, &NoProgress).unwrap_err().to_string();
    assert!(e.contains("form-factor matrix"), "{e}");
    let ok = Radiosity::solve(&scene, &gathering(0.25, 2), &NoProgress).unwrap();
    let bytes = form_factor_matrix_bytes(ok.radiosities().len(), ok.stats().patches);
    assert!(bytes > 1 << 20, "the matrix takes {bytes} bytes");
    let subdivided = RadiosityOptions { subdivide: Some(0.5), ..gathering(0.25, 2) };
    let e = Radiosity::solve(&scene, &subdivided, &NoProgress).unwrap_err().to_string();
    assert!(e.contains("subdivision"), "{e}");
}

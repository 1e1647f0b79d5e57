//! Meshing a triangle mesh's signed distance field (frep_from_mesh's):
//! a wavy sphere of 320k triangles at depth 8 and of 1.3M at depth 9, end
//! to end (the field's hierarchy built, then meshed).
//! Run: cargo bench -p geode-mesher --bench mesh_field

use geode_frep::{Field, MeshDistance};
use geode_mesher::{polygonise, MeshOptions};

#[path = "../../frep/benches/support/wavy_sphere.rs"]
mod wavy_sphere;
use wavy_sphere::wavy_sphere;

fn main() {
    divan::main();
}

fn mesh(rings: u32, depth: u32) -> usize {
    let (p, t) = wavy_sphere(rings);
    let field = Field::mesh(MeshDistance::new(p, t, &|| false).unwrap());
    let (g, _) = polygonise(
        &field,
        &MeshOptions::new([-1.1; 3], [1.1; 3], depth),
        &|| false,
        &|_| {},
    )
    .unwrap();
    g.num_prims()
}

#[divan::bench(sample_count = 3)]
fn triangles_320k_at_depth_8() -> usize {
    mesh(280, 8)
}

#[divan::bench(sample_count = 1)]
fn triangles_1_3m_at_depth_9() -> usize {
    mesh(570, 9)
}

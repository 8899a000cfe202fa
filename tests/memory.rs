//! What `exact` allocates of its own, against `linked_list`, the exact method engines ship:
//! on the scenes the project's bench compares them on, at 1280x720, exact takes at most half
//! of linked_list's GPU memory. A method's own memory is its peak over blend's, which holds
//! the same scene and frame targets, as `translucid bench` reports it
//! (`peak_over_blend_bytes`).
//!
//! Exact's memory follows the frame's triangles (records for coverage and shading, bin
//! lists), linked_list's its fragments (a node each, at least one a pixel), so the scene with
//! the most triangles and the fewest fragments is the tight one: the Stanford dragon, from the
//! shared scene collection beside the project when it is there.

use std::path::{Path, PathBuf};
use translucid::methods::MethodKind;
use translucid::renderer::Renderer;
use translucid::scene::{self, Scene};
use translucid_tests::{asset, gpu};

const SIZE: (u32, u32) = (1280, 720);

/// Peak GPU bytes of a renderer of `kind` on its own device over the frame after its first
/// (so that buffers grown for the first frame are counted as a frame loop keeps them).
fn peak(scene: &Scene, kind: MethodKind) -> i64 {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, scene, kind, SIZE.0, SIZE.1).expect("renderer");
    renderer.render(false).expect("first frame");
    let frame = renderer.render(false).expect("second frame");
    frame.peak_gpu_bytes as i64
}

fn check(name: &str, scene: &Scene) {
    let blend = peak(scene, MethodKind::Blend);
    let exact = peak(scene, MethodKind::Exact) - blend;
    let linked_list = peak(scene, MethodKind::LinkedList) - blend;
    let mb = |bytes: i64| bytes as f64 / f64::from(1 << 20);
    eprintln!(
        "{name}: exact {:.1} MB, linked_list {:.1} MB over blend",
        mb(exact),
        mb(linked_list)
    );
    assert!(
        2 * exact <= linked_list,
        "{name}: exact takes {:.1} MB over blend, more than half of linked_list's {:.1} MB",
        mb(exact),
        mb(linked_list)
    );
}

fn shared(relative: &str) -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/scenes")
        .join(relative);
    if path.is_file() {
        Some(path)
    } else {
        eprintln!(
            "skipped {relative}: no shared scene collection beside the project (a clone alone \
             has only assets/scenes)"
        );
        None
    }
}

#[test]
fn exact_takes_at_most_half_of_linked_lists_memory() {
    for name in ["spheres", "particles", "hairball"] {
        check(name, &scene::load(name).expect("generated scene"));
    }
    let vase = asset("GlassVaseFlowers/GlassVaseFlowers.glb");
    let mut files = vec![vase];
    files.extend(shared(
        "meshes/stanford_dragon_100k/stanford_dragon_100k_blend.gltf",
    ));
    files.extend(shared(
        "khronos/StainedGlassLamp/glTF-JPG-PNG/StainedGlassLamp.gltf",
    ));
    for path in files {
        let name = path
            .file_name()
            .expect("file")
            .to_string_lossy()
            .into_owned();
        let scene = scene::load(path.to_str().expect("utf-8 path")).expect("scene");
        check(&name, &scene);
    }
}

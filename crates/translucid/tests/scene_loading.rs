//! glTF import of the vendored scenes, scene specs, and clear errors (never panics) on bad
//! input. Bad files are written to the system temp directory under unique names.

use std::path::{Path, PathBuf};
use translucid::scene::{self, Scene};
use translucid::Error;

fn asset(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/scenes")
        .join(relative)
}

fn load_asset(relative: &str) -> Scene {
    scene::gltf::load(&asset(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

#[test]
fn glass_vase_flowers_has_blend_transmission_and_a_texture() {
    let s = load_asset("GlassVaseFlowers/GlassVaseFlowers.glb");
    assert!(!s.transparent.is_empty() && s.transparent_quads() > 0);
    assert!(!s.opaque.is_empty(), "the flowers are MASK, so opaque");
    let transparent_materials: Vec<_> = s
        .transparent
        .iter()
        .map(|d| &s.materials[d.material])
        .collect();
    assert!(
        transparent_materials.iter().any(|m| m.transmission > 0.0),
        "transmission glass"
    );
    assert!(
        transparent_materials
            .iter()
            .any(|m| m.transmission == 0.0 && m.base_colour.w < 1.0),
        "BLEND glass"
    );
    assert!(s
        .opaque
        .iter()
        .any(|d| s.materials[d.material].alpha_cutoff.is_some()));
    assert!(!s.textures.is_empty(), "flower texture");
    assert!(s.textures.iter().all(|t| t.srgb && t.width() > 1));
}

#[test]
fn attenuation_test_has_polychrome_transmittance() {
    let s = load_asset("AttenuationTest/AttenuationTest.glb");
    assert!(s.transparent_quads() > 0);
    let tinted = s.transparent.iter().any(|d| {
        let m = &s.materials[d.material];
        let tint = m.transmission_tint;
        m.transmission > 0.0 && tint.max_element() - tint.min_element() > 0.3
    });
    assert!(tinted, "no coloured transmission tint");
    assert!(!s.textures.is_empty(), "labels and backdrop are textured");
}

#[test]
fn utah_teapot_blend_loads_with_external_buffer() {
    let s = load_asset("utah_teapot/utah_teapot_blend.gltf");
    assert_eq!(s.transparent.len(), 1);
    assert_eq!(s.meshes[0].triangle_count(), 6320);
    let m = &s.materials[s.transparent[0].material];
    assert!((m.base_colour.w - 0.4).abs() < 1e-6 && m.double_sided && m.lit);
    assert_eq!(m.reflectance, 0.0, "plain BLEND has no reflectance");
    assert!(s.meshes[0].normals.is_some());
}

#[test]
fn spec_picks_generated_scene_or_file() {
    assert_eq!(scene::load("layers").expect("generated").name, "layers");
    let path = asset("utah_teapot/utah_teapot_blend.gltf");
    let s = scene::load(path.to_str().expect("utf-8 path")).expect("file");
    assert_eq!(s.name, "utah_teapot_blend");
    match scene::load("no-such-scene") {
        Err(Error::UnknownScene(name, known)) => {
            assert_eq!(name, "no-such-scene");
            assert!(known.contains("particles") && known.contains("polychrome"));
            assert!(known.contains("draws<N>"), "{known}");
        }
        other => panic!("expected UnknownScene, got {other:?}"),
    }
}

#[test]
fn missing_file_is_a_scene_io_error() {
    let path = temp_path("does-not-exist.glb");
    let err = scene::gltf::load(&path).expect_err("missing file");
    assert!(matches!(err, Error::SceneIo { .. }), "{err:?}");
    assert!(err.to_string().contains("does-not-exist.glb"), "{err}");
    // Through a spec too: a .glb path is a file, not an unknown name.
    let spec = scene::load(path.to_str().expect("utf-8 path"));
    assert!(matches!(spec, Err(Error::SceneIo { .. })), "{spec:?}");
}

#[test]
fn malformed_json_and_binary_are_invalid_gltf() {
    for (name, bytes) in [
        ("broken.gltf", b"{ \"asset\": { \"version\": " as &[u8]),
        ("truncated.glb", b"glTF\x02\x00\x00\x00\xff\x00\x00\x00JSON"),
        ("empty.gltf", b""),
        ("no-asset.gltf", b"{}"),
    ] {
        let err = load_bytes(name, bytes).expect_err(name);
        assert!(matches!(err, Error::InvalidGltf { .. }), "{name}: {err:?}");
        assert!(err.to_string().contains(name), "{name}: {err}");
    }
}

/// GLB container errors name the value that is wrong, and the file.
#[test]
fn glb_container_errors_name_the_value() {
    let json = br#"{"asset":{"version":"2.0"}}  "#; // padded to a multiple of 4
    let glb = |version: u32, kind: &[u8; 4], length_delta: i64| {
        let mut bytes = b"glTF".to_vec();
        bytes.extend(version.to_le_bytes());
        let total = 12 + 8 + json.len() as i64 + length_delta;
        bytes.extend((total as u32).to_le_bytes());
        bytes.extend((json.len() as u32).to_le_bytes());
        bytes.extend(kind);
        bytes.extend(json);
        bytes
    };
    for (name, bytes, wanted) in [
        ("version.glb", glb(3, b"JSON", 0), "version 3"),
        ("chunk.glb", glb(2, b"XSON", 0), "type 0x4e4f5358"),
        ("length.glb", glb(2, b"JSON", 8), "says the file has"),
    ] {
        let err = load_bytes(name, &bytes).expect_err(name);
        let msg = err.to_string();
        assert!(msg.contains(wanted) && msg.contains(name), "{name}: {msg}");
    }
}

/// A JSON value of the wrong type is named by its field, not only a line and column.
#[test]
fn json_type_errors_name_the_field() {
    let json = Tiny::triangle().json().replace(
        r#""componentType": 5125, "count": 3"#,
        r#""componentType": 5125, "count": "three""#,
    );
    assert!(json.contains(r#""three""#));
    let err = load_bytes("type.gltf", json.as_bytes()).expect_err("count is a string");
    let msg = err.to_string();
    assert!(msg.contains("accessors[1].count"), "{msg}");
}

#[test]
fn required_unsupported_extension_is_refused_by_name() {
    let json = Tiny::triangle()
        .top(r#""extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"]"#)
        .json();
    let err = load_bytes("draco.gltf", json.as_bytes()).expect_err("draco required");
    match &err {
        Error::UnsupportedExtension { extension, .. } => {
            assert_eq!(extension, "KHR_draco_mesh_compression")
        }
        other => panic!("expected UnsupportedExtension, got {other:?}"),
    }
    assert!(err.to_string().contains("KHR_draco_mesh_compression"));
}

#[test]
fn required_implemented_extensions_load() {
    let material = r#"{"extensions": {
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_volume": {"thicknessFactor": 2.0, "attenuationDistance": 1.0, "attenuationColor": [0.5, 1.0, 0.25]},
        "KHR_materials_ior": {"ior": 1.0}}}"#;
    let json = Tiny::triangle()
        .material(material)
        .top(r#""extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"],
                "extensionsRequired": ["KHR_materials_transmission", "KHR_materials_volume"]"#)
        .json();
    let s = load_bytes("volume.gltf", json.as_bytes()).expect("volume loads");
    assert_eq!(
        s.transparent.len(),
        1,
        "transmission goes to the transparent layer"
    );
    let m = &s.materials[0];
    assert_eq!(m.transmission, 1.0);
    assert_eq!(m.reflectance, 0.0, "ior 1 reflects nothing");
    let expected = glam::Vec3::new(0.25, 1.0, 0.0625);
    assert!(
        (m.transmission_tint - expected).abs().max_element() < 1e-6,
        "{:?}",
        m.transmission_tint
    );
}

#[test]
fn used_but_unsupported_extension_loads() {
    let material = r#"{"alphaMode": "BLEND",
        "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.5, 0.25, 0.5]},
        "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0},
                       "KHR_materials_sheen": {"sheenColorFactor": [1.0, 1.0, 1.0]}}}"#;
    let json = Tiny::triangle()
        .material(material)
        .top(r#""extensionsUsed": ["KHR_materials_clearcoat", "KHR_materials_sheen"]"#)
        .json();
    let s = load_bytes("clearcoat.gltf", json.as_bytes()).expect("clearcoat is optional");
    assert_eq!(s.transparent.len(), 1);
    assert_eq!(
        s.materials[0].base_colour,
        glam::Vec4::new(1.0, 0.5, 0.25, 0.5)
    );
    assert_eq!(s.materials[0].transmission, 0.0);
}

#[test]
fn nan_position_is_refused_naming_the_primitive() {
    let mut tiny = Tiny::triangle();
    tiny.positions[1][2] = f32::NAN;
    let err = load_bytes("nan.gltf", tiny.json().as_bytes()).expect_err("NaN");
    assert!(matches!(err, Error::InvalidScene(_)), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("not finite") && msg.contains("primitive 0") && msg.contains("tri"),
        "{msg}"
    );
}

#[test]
fn out_of_range_index_is_refused() {
    let mut tiny = Tiny::triangle();
    tiny.indices[2] = 7;
    let err = load_bytes("index.gltf", tiny.json().as_bytes()).expect_err("index 7 of 3");
    assert!(matches!(err, Error::InvalidScene(_)), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("out of range") && msg.contains("mesh 0"),
        "{msg}"
    );
}

#[test]
fn missing_buffer_file_names_the_buffer_and_primitive() {
    let json = Tiny::triangle().buffer_uri("\"gone-missing.bin\"").json();
    let err = load_bytes("nobuffer.gltf", json.as_bytes()).expect_err("missing buffer");
    let msg = err.to_string();
    assert!(
        msg.contains("gone-missing.bin") && msg.contains("primitive 0"),
        "{msg}"
    );
}

#[test]
fn accessor_overrunning_its_buffer_is_refused() {
    let json = Tiny::triangle().position_count(1000).json();
    let err = load_bytes("overrun.gltf", json.as_bytes()).expect_err("overrun");
    assert!(matches!(err, Error::InvalidScene(_)), "{err:?}");
    assert!(err.to_string().contains("POSITION"), "{err}");
}

#[test]
fn strips_are_converted_and_points_skipped() {
    let mut tiny = Tiny::triangle();
    tiny.positions.push([1.0, 1.0, 0.0]);
    tiny.indices = vec![0, 1, 2, 3];
    let strip = Tiny {
        mode: 5,
        ..tiny.clone()
    };
    let s = load_bytes("strip.gltf", strip.json().as_bytes()).expect("strip");
    assert_eq!(s.meshes[0].triangle_count(), 2);
    assert_eq!(
        s.meshes[0].quads.len(),
        1,
        "the strip's two triangles pair into a quad"
    );

    // A file of points only draws nothing: an error, not an empty scene.
    let points = Tiny { mode: 0, ..tiny };
    let err = load_bytes("points.gltf", points.json().as_bytes()).expect_err("points only");
    assert!(err.to_string().contains("no triangles"), "{err}");
}

#[test]
fn camera_node_gives_the_view() {
    let json = Tiny::triangle()
        .top(r#""cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}]"#)
        .nodes(
            r#"{"mesh": 0}, {"camera": 0, "translation": [0.0, 0.0, 4.0]}"#,
            "[0, 1]",
        )
        .json();
    let s = load_bytes("camera_node.gltf", json.as_bytes()).expect("camera");
    let translucid::scene::Projection::Perspective { fov_y, near, far } = s.camera.projection
    else {
        panic!("a glTF perspective camera: {:?}", s.camera.projection);
    };
    assert_eq!(fov_y, 0.7);
    assert_eq!(near, 0.1);
    assert!(far > 4.0 && far.is_finite(), "far from bounds: {far}");
    let eye = s.camera.view.inverse().transform_point3(glam::Vec3::ZERO);
    assert!(
        (eye - glam::Vec3::new(0.0, 0.0, 4.0)).length() < 1e-5,
        "{eye}"
    );
}

/// An orthographic camera is the scene's camera: ymag is its half height, the aspect follows
/// the render size, and fragments are ordered by device depth.
#[test]
fn orthographic_camera_is_taken() {
    let json = Tiny::triangle()
        .top(
            r#""cameras": [{"type": "orthographic",
                "orthographic": {"xmag": 3, "ymag": 2, "znear": 0.5, "zfar": 9}}]"#,
        )
        .nodes(
            r#"{"mesh": 0}, {"camera": 0, "translation": [0.0, 0.0, 4.0]}"#,
            "[0, 1]",
        )
        .json();
    let s = load_bytes("ortho.gltf", json.as_bytes()).expect("camera");
    assert_eq!(
        s.camera.projection,
        translucid::scene::Projection::Orthographic {
            half_height: 2.0,
            near: 0.5,
            far: 9.0
        }
    );
    assert_eq!(
        s.camera.depth_order(),
        translucid::raster::DepthOrder::DeviceZ
    );
    // The point 1 unit left of the axis, 4 in front: a quarter of the way across a frame
    // 2 * 2 * 2 units wide (aspect 2).
    let clip = s.camera.view_projection(200, 100) * glam::Vec4::new(-1.0, 0.0, 0.0, 1.0);
    assert!((clip.x / clip.w + 0.25).abs() < 1e-6, "{clip}");
}

#[test]
fn node_cycle_is_refused() {
    let json = Tiny::triangle()
        .nodes(r#"{"mesh": 0, "children": [1]}, {"children": [0]}"#, "[0]")
        .json();
    let err = load_bytes("cycle.gltf", json.as_bytes()).expect_err("cycle");
    assert!(matches!(err, Error::InvalidGltf { .. }), "{err:?}");
    assert!(err.to_string().contains("own ancestor"), "{err}");
}

/// A camera whose `type` names the projection object it lacks: the gltf crate unwraps it.
#[test]
fn camera_without_its_projection_object_is_refused() {
    for (kind, object) in [
        (
            "perspective",
            r#""orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}"#,
        ),
        (
            "orthographic",
            r#""perspective": {"yfov": 0.8, "znear": 0.1}"#,
        ),
    ] {
        let json = Tiny::triangle()
            .nodes(r#"{"mesh": 0}, {"camera": 0}"#, "[0, 1]")
            .top(&format!(r#""cameras": [{{"type": "{kind}", {object}}}]"#))
            .json();
        let err = load_bytes("camera.gltf", json.as_bytes()).expect_err(kind);
        assert!(matches!(err, Error::InvalidGltf { .. }), "{err:?}");
        let msg = err.to_string();
        assert!(msg.contains("camera 0") && msg.contains(kind), "{msg}");
    }
}

/// An attribute naming an accessor past the end of `accessors`: gltf-json's own validation
/// indexes with it.
#[test]
fn attribute_accessor_out_of_range_is_refused() {
    let json = Tiny::triangle()
        .json()
        .replace(r#""POSITION": 0"#, r#""POSITION": 9"#);
    let err = load_bytes("accessor.gltf", json.as_bytes()).expect_err("accessor 9 of 2");
    assert!(matches!(err, Error::InvalidGltf { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("POSITION") && msg.contains("accessor 9") && msg.contains("mesh 0"),
        "{msg}"
    );
}

/// An image in a buffer view must say its MIME type; the gltf crate unwraps it.
#[test]
fn image_in_a_buffer_view_without_mime_type_is_refused() {
    let json = Tiny::triangle()
        .material(r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}"#)
        .top(r#""textures": [{"source": 0}], "images": [{"bufferView": 1}]"#)
        .json();
    let err = load_bytes("mime.gltf", json.as_bytes()).expect_err("no mimeType");
    assert!(matches!(err, Error::InvalidGltf { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(msg.contains("image 0") && msg.contains("mimeType"), "{msg}");
}

/// An image with neither a uri nor a bufferView (found by the fuzzer): the gltf crate
/// unwraps the uri.
#[test]
fn image_without_a_source_is_refused() {
    let json = Tiny::triangle()
        .material(r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}"#)
        .top(r#""textures": [{"source": 0}], "images": [{"name": "nothing"}]"#)
        .json();
    let err = load_bytes("sourceless.gltf", json.as_bytes()).expect_err("no source");
    assert!(matches!(err, Error::InvalidGltf { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("image 0 (nothing)") && msg.contains("neither"),
        "{msg}"
    );
}

/// A mesh listed 100 000 times by the scene: framing a camera once transformed every vertex
/// of every instance (billions for a scanned mesh), which took minutes.
#[test]
fn framing_many_instances_of_a_mesh_is_bounded() {
    let roots: Vec<String> = std::iter::repeat_n("0".to_string(), 100_000).collect();
    let mut tiny = Tiny::triangle();
    // A big mesh: 600 000 vertices, 60 billion transforms over the instances.
    tiny.positions = (0..600_000)
        .map(|i| [(i % 1000) as f32, (i / 1000) as f32, 0.0])
        .collect();
    tiny.indices = vec![0, 1, 1000];
    let json = tiny
        .nodes(r#"{"mesh": 0}"#, &format!("[{}]", roots.join(",")))
        .json();
    let started = std::time::Instant::now();
    let scene = load_bytes("instances.gltf", json.as_bytes()).expect("loads");
    assert_eq!(scene.opaque.len() + scene.transparent.len(), 100_000);
    assert!(
        started.elapsed().as_secs() < 20,
        "framing took {:?}",
        started.elapsed()
    );
}

/// A buffer URI naming something that is not a regular file (a pipe that never ends, a
/// device, even in an allowed folder) is refused before it is read; reading one blocked
/// forever or until memory ran out.
#[cfg(unix)]
#[test]
fn buffer_uri_of_a_pipe_or_device_is_refused() {
    let dir = fresh_dir("pipe");
    let fifo = dir.join("stream.bin");
    make_fifo(&fifo);
    std::os::unix::fs::symlink("/dev/zero", dir.join("zeros.bin")).expect("symlink");
    let path = dir.join("pipe.gltf");
    std::fs::write(&path, Tiny::triangle().buffer_uri("\"/dev/zero\"").json()).expect("write");
    let allow_dev = scene::gltf::ImportOptions::allowing([PathBuf::from("/dev")]);
    let err = scene::gltf::load_with(&path, &allow_dev).expect_err("/dev/zero");
    assert!(err.to_string().contains("not a regular file"), "{err}");
    // A link in the file's folder is followed before the folder is checked.
    for (uri, why) in [
        ("\"stream.bin\"", "not a regular file"),
        ("\"zeros.bin\"", "outside"),
    ] {
        std::fs::write(&path, Tiny::triangle().buffer_uri(uri).json()).expect("write");
        let err = scene::gltf::load(&path).expect_err(uri);
        let msg = err.to_string();
        assert!(msg.contains(why), "{uri}: {msg}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A node whose matrix is projective (its last row not 0 0 0 1) is refused, naming the node:
/// glTF requires affine nodes, and a fuzzed w of 1.8e19 put exact 48/255 off the reference.
/// Draws given straight to the core are held to the same.
#[test]
fn projective_transforms_are_refused() {
    let json = Tiny::triangle()
        .nodes(
            r#"{"mesh": 0, "matrix": [1,0,0,0, 0,1,0,18446744073709551615, 0,0,1,0, 0,0,0,1]}"#,
            "[0]",
        )
        .json();
    let err = load_bytes("projective.gltf", json.as_bytes()).expect_err("projective node");
    assert!(
        err.to_string().contains("node 0's transform is not affine"),
        "{err}"
    );

    let mut scene = load_bytes("affine.gltf", Tiny::triangle().json().as_bytes()).expect("loads");
    let draws = if scene.transparent.is_empty() {
        &mut scene.opaque
    } else {
        &mut scene.transparent
    };
    draws[0].transform.x_axis.w = 0.5;
    let err = scene.validate().expect_err("projective draw");
    assert!(err.to_string().contains("must be affine"), "{err}");
}

/// A node's rotation is made a unit quaternion, as glTF requires: a fuzzed rotation of
/// (4294967297, 0, 0, 1) scaled the node by 1.8e19 and put exact off the reference. A zero
/// rotation is refused.
#[test]
fn node_rotations_are_unit_quaternions() {
    let with_rotation = |rotation: &str| {
        let node = format!(r#"{{"mesh": 0, "rotation": {rotation}}}"#);
        let json = Tiny::triangle().nodes(&node, "[0]").json();
        load_bytes("rotation.gltf", json.as_bytes())
    };
    let scene = with_rotation("[4294967297, 0, 0, 1]").expect("loads");
    let draw = scene
        .opaque
        .first()
        .or(scene.transparent.first())
        .expect("a draw");
    let x_turn = glam::Mat4::from_quat(glam::Quat::from_rotation_x(std::f32::consts::PI));
    assert!(
        draw.transform.abs_diff_eq(x_turn, 1e-4),
        "{:?}",
        draw.transform
    );
    let err = with_rotation("[0, 0, 0, 0]").expect_err("no direction");
    assert!(err.to_string().contains("rotation"), "{err}");
}

/// A buffer URI reaches only files inside the glTF file's folder: absolute paths, `..`,
/// `file://` URIs and links out of it are refused (each read `/etc/passwd` into the pixels
/// before), unless the caller allows the folder they lead to.
#[cfg(unix)]
#[test]
fn buffer_uris_reach_only_the_files_folder_unless_allowed() {
    let dir = fresh_dir("confined");
    let folder = dir.join("assets");
    std::fs::create_dir_all(&folder).expect("temp dir");
    // The same bytes inside the folder and outside it, so only the path decides.
    let tiny = Tiny::triangle();
    let bytes = tiny.buffer_bytes();
    std::fs::write(folder.join("inside.bin"), &bytes).expect("write");
    let outside = dir.join("outside.bin");
    std::fs::write(&outside, &bytes).expect("write");
    std::os::unix::fs::symlink(&outside, folder.join("link.bin")).expect("symlink");
    let outside = outside.canonicalize().expect("canonical");
    let path = folder.join("scene.gltf");
    let load = |uri: &str, options: &scene::gltf::ImportOptions| {
        std::fs::write(&path, tiny.clone().buffer_uri(&format!("{uri:?}")).json()).expect("write");
        scene::gltf::load_with(&path, options)
    };
    let defaults = scene::gltf::ImportOptions::default();
    load("inside.bin", &defaults).expect("a file in the folder");
    load("./inside.bin", &defaults).expect("a path that stays in the folder");
    let absolute = outside.display().to_string();
    let escapes = [
        absolute.clone(),
        format!("file://{absolute}"),
        "../outside.bin".into(),
        "../../../../../../../../etc/passwd".into(),
        "/etc/passwd".into(),
        "file:///etc/passwd".into(),
        "/proc/self/environ".into(),
        "link.bin".into(),
        "%2E%2E/outside.bin".into(),
    ];
    for uri in &escapes {
        let err = load(uri, &defaults).expect_err(uri);
        assert!(err.to_string().contains("outside"), "{uri}: {err}");
    }
    let allowed = scene::gltf::ImportOptions::allowing([dir.clone()]);
    for uri in &escapes[..3] {
        load(uri, &allowed).unwrap_or_else(|e| panic!("{uri} in an allowed folder: {e}"));
    }
    load("link.bin", &allowed).expect("a link into an allowed folder");
    let err = load("/etc/passwd", &allowed).expect_err("outside every allowed folder");
    assert!(err.to_string().contains("outside"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The glTF file itself is checked like a URI: a pipe named `.gltf` (which hung a
/// `conformance` run) and a link to `/dev/zero` named `.glb` (read until memory ran out)
/// are refused at once.
#[cfg(unix)]
#[test]
fn the_file_itself_must_be_a_regular_file() {
    let dir = fresh_dir("main-file");
    let fifo = dir.join("b.gltf");
    make_fifo(&fifo);
    let zeros = dir.join("zeros.glb");
    std::os::unix::fs::symlink("/dev/zero", &zeros).expect("symlink");
    for path in [fifo, zeros] {
        // On a thread, so that a regression fails here instead of hanging the suite.
        let (send, receive) = std::sync::mpsc::channel();
        let loading = path.clone();
        std::thread::spawn(move || send.send(scene::gltf::load(&loading).map(|_| ())));
        let result = receive
            .recv_timeout(std::time::Duration::from_secs(20))
            .unwrap_or_else(|_| panic!("{} still loading after 20 s", path.display()));
        let err = result.expect_err("not a file");
        assert!(err.to_string().contains("not a regular file"), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Forty meshes of three indices each whose POSITION, NORMAL and COLOR_0 are one 16 M
/// element accessor without a bufferView (a 7 KB file): every primitive reads it again,
/// which once asked for ~30 GB and aborted the process. The elements read are budgeted over
/// the whole file, and the file is refused by that limit's name.
#[test]
fn a_small_file_reading_one_huge_accessor_many_times_is_refused() {
    let huge = r#"{"componentType": 5126, "count": 16777216, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0], "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5125}, "values": {"bufferView": 0}}}"#;
    let primitive = r#"{"attributes": {"POSITION": 2, "NORMAL": 2, "COLOR_0": 2}, "indices": 1, "material": 0, "mode": 4}"#;
    let meshes: Vec<String> = (0..40)
        .map(|_| format!(r#"{{"primitives": [{primitive}]}}"#))
        .collect();
    let nodes: Vec<String> = (0..40).map(|m| format!(r#"{{"mesh": {m}}}"#)).collect();
    let roots: Vec<String> = (0..40).map(|m| m.to_string()).collect();
    let tiny = Tiny::triangle().nodes(&nodes.join(", "), &format!("[{}]", roots.join(", ")));
    let json = tiny.json();
    let meshes_start = json.find(r#""meshes": ["#).expect("meshes");
    let meshes_end = json.find(r#""materials""#).expect("materials");
    let json = format!(
        "{}\"meshes\": [{}],\n  {}",
        &json[..meshes_start],
        meshes.join(", "),
        &json[meshes_end..]
    )
    .replace(
        r#""type": "SCALAR"}"#,
        &format!(r#""type": "SCALAR"}}, {huge}"#),
    );
    assert!(json.len() < 16 << 10, "{} bytes", json.len());
    let err = load_bytes("shared-accessor.gltf", json.as_bytes()).expect_err("refused");
    assert!(matches!(err, Error::ImportLimit { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(msg.contains("ImportLimits::elements"), "{msg}");

    // A limit the caller lowers holds the same way, before anything is read.
    let path = temp_path("shared-accessor-2.gltf");
    std::fs::write(&path, Tiny::triangle().json()).expect("write");
    let mut options = scene::gltf::ImportOptions::default();
    options.limits.elements = 5;
    let err = scene::gltf::load_with(&path, &options).expect_err("6 elements");
    assert!(err.to_string().contains("ImportLimits::elements"), "{err}");
    options.limits.elements = 6;
    scene::gltf::load_with(&path, &options).expect("3 positions and 3 indices fit 6");
    let _ = std::fs::remove_file(&path);
}

/// An external buffer file is read up to its declared byteLength, not whole: here the
/// declared bytes, then 64 GiB the file does not declare (sparse, so they take no disk).
#[test]
fn buffer_file_is_read_up_to_its_byte_length() {
    let dir = fresh_dir("long-buffer");
    let tiny = Tiny::triangle();
    let buffer = dir.join("long.bin");
    std::fs::write(&buffer, tiny.buffer_bytes()).expect("write buffer");
    std::fs::File::options()
        .write(true)
        .open(&buffer)
        .and_then(|f| f.set_len(64 << 30))
        .expect("extend the buffer file");
    let path = dir.join("long.gltf");
    std::fs::write(&path, tiny.buffer_uri("\"long.bin\"").json()).expect("write");
    let scene = scene::gltf::load(&path).expect("a longer file is fine");
    assert_eq!(scene.meshes[0].positions.len(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}

/// An image wider than any device allows is refused from its header, before it is decoded
/// or reaches the GPU (a 100000×1 PNG crashed the driver).
#[test]
fn image_over_the_largest_texture_is_refused_before_decoding() {
    let mut png = Vec::new();
    image::RgbaImage::new(100_000, 1)
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("encode");
    let uri = format!("data:image/png;base64,{}", base64(&png));
    let json = Tiny::triangle()
        .material(r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}"#)
        .top(&format!(
            r#""textures": [{{"source": 0}}], "images": [{{"uri": "{uri}"}}]"#
        ))
        .json();
    let err = load_bytes("wide.gltf", json.as_bytes()).expect_err("100000 wide");
    assert!(matches!(err, Error::InvalidGltf { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("100000x1") && msg.contains(&scene::MAX_TEXTURE_SIZE.to_string()),
        "{msg}"
    );
}

/// Textures are bounded in all, not only one by one: six textures sharing one large image
/// once ran the process out of memory. Every base colour image's header is read before any
/// image is decoded (these have their pixel data cut short, so decoding one would fail).
#[test]
fn textures_past_the_scene_texel_limit_are_refused_before_decoding() {
    let side = scene::MAX_TEXTURE_SIZE;
    let large = base64(&png_header_only(side, side));
    let per_texture = u64::from(side) * u64::from(side);
    let fitting = scene::MAX_SCENE_TEXELS / per_texture;
    let count = fitting + 1;
    let materials: Vec<String> = (0..count)
        .map(|i| format!(r#"{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": {i}}}}}}}"#))
        .collect();
    let textures: Vec<String> = (0..count)
        .map(|i| format!(r#"{{"source": {i}}}"#))
        .collect();
    let images: Vec<String> = (0..count)
        .map(|_| format!(r#"{{"uri": "data:image/png;base64,{large}"}}"#))
        .collect();
    let json = Tiny::triangle()
        .material(&materials.join(", "))
        .top(&format!(
            r#""textures": [{}], "images": [{}]"#,
            textures.join(", "),
            images.join(", ")
        ))
        .json();
    let err = load_bytes("texels.gltf", json.as_bytes()).expect_err("over the limit");
    let msg = err.to_string();
    assert!(
        msg.contains(&format!("texture {fitting}"))
            && msg.contains(&format!("{side}x{side}"))
            && msg.contains(&scene::MAX_SCENE_TEXELS.to_string()),
        "{msg}"
    );
}

/// A PNG of `width` x `height` with a valid header and a pixel stream cut after two bytes.
fn png_header_only(width: u32, height: u32) -> Vec<u8> {
    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &b in bytes {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
            }
        }
        !crc
    }
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8; 4], data: &[u8]| {
        png.extend((data.len() as u32).to_be_bytes());
        let body: Vec<u8> = kind.iter().chain(data).copied().collect();
        png.extend(&body);
        png.extend(crc32(&body).to_be_bytes());
    };
    let mut header = Vec::new();
    header.extend(width.to_be_bytes());
    header.extend(height.to_be_bytes());
    header.extend([8, 6, 0, 0, 0]); // 8-bit RGBA, deflate, no interlace
    chunk(b"IHDR", &header);
    // Readers take the header as read once they reach pixel data: a zlib stream's start.
    chunk(b"IDAT", &[0x78, 0x01]);
    chunk(b"IEND", &[]);
    png
}

/// A sparse accessor with no bufferView is zeros but for its entries, so its count is not
/// bounded by the file's bytes: a billion positions once ran the process out of memory.
#[test]
fn huge_zero_filled_accessors_are_refused_before_reading() {
    let sparse = r#""sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5125}, "values": {"bufferView": 0}}"#;
    let huge_positions = Tiny::triangle().json().replace(
        r#"{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3""#,
        &format!(r#"{{{sparse}, "componentType": 5126, "count": 1000000000, "type": "VEC3""#),
    );
    assert!(huge_positions.contains("1000000000"));
    let err = load_bytes("sparse.gltf", huge_positions.as_bytes()).expect_err("1e9 positions");
    let msg = err.to_string();
    assert!(
        msg.contains("POSITION") && msg.contains("1000000000"),
        "{msg}"
    );

    // A TEXCOORD of a billion elements on three positions.
    let accessor =
        format!(r#"{{{sparse}, "componentType": 5126, "count": 1000000000, "type": "VEC2"}}"#);
    let huge_uvs = Tiny::triangle()
        .json()
        .replace(r#""POSITION": 0"#, r#""POSITION": 0, "TEXCOORD_0": 2"#)
        .replace(
            r#""type": "SCALAR"}"#,
            &format!(r#""type": "SCALAR"}}, {accessor}"#),
        );
    assert!(huge_uvs.contains(r#""TEXCOORD_0": 2"#));
    let mut texel = Vec::new();
    image::RgbaImage::new(1, 1)
        .write_to(
            &mut std::io::Cursor::new(&mut texel),
            image::ImageFormat::Png,
        )
        .expect("encode");
    let huge_uvs = huge_uvs.replace(
        r#""materials": [{}]"#,
        &format!(
            r#""materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}}}}], "textures": [{{"source": 0}}], "images": [{{"uri": "data:image/png;base64,{}"}}]"#,
            base64(&texel)
        ),
    );
    let err = load_bytes("sparse-uv.gltf", huge_uvs.as_bytes()).expect_err("1e9 uvs");
    let msg = err.to_string();
    assert!(
        msg.contains("TEXCOORD") && msg.contains("1000000000"),
        "{msg}"
    );
}

/// Vertices at 1e30 are finite, but no camera can frame them: the message says so, not
/// "camera: view matrix is not finite" about a camera the file does not have.
#[test]
fn vertices_too_far_apart_to_frame_are_refused_saying_why() {
    let mut tiny = Tiny::triangle();
    tiny.positions = vec![[-1e30, 0.0, 0.0], [1e30, 0.0, 0.0], [0.0, 1e30, 0.0]];
    let err = load_bytes("far.gltf", tiny.json().as_bytes()).expect_err("1e30");
    assert!(matches!(err, Error::InvalidGltf { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(msg.contains("no camera") && msg.contains("frame"), "{msg}");
}

/// A 5000-character URI is cut in messages, not printed whole (twice).
#[test]
fn long_uris_are_cut_in_messages() {
    let long = "x".repeat(5000);
    let json = Tiny::triangle()
        .buffer_uri(&format!("\"{long}.bin\""))
        .json();
    let err = load_bytes("long-uri.gltf", json.as_bytes()).expect_err("missing file");
    let msg = err.to_string();
    assert!(
        msg.len() < 600 && msg.contains("characters"),
        "{} characters: {msg}",
        msg.len()
    );
}

/// A buffer listed 100 000 times (found by the fuzzer) would be read 100 000 times; a
/// primitive repeated as often, converted as often. Both are refused from what the file
/// declares, before anything is read.
#[test]
fn files_declaring_too_much_are_refused_before_reading() {
    let json = Tiny::triangle().json();
    let start = json.find(r#""buffers": ["#).expect("buffers") + r#""buffers": ["#.len();
    let end = start + json[start..].find("}]").expect("end") + 1;
    let one = &json[start..end];
    let large = one.replace(r#""byteLength": 48"#, r#""byteLength": 60000"#);
    let many = vec![large.as_str(); 100_000].join(", ");
    let buffers = format!("{}{many}{}", &json[..start], &json[end..]);
    let err = load_bytes("buffers.gltf", buffers.as_bytes()).expect_err("6 GB declared");
    assert!(matches!(err, Error::ImportLimit { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("byteLengths") && msg.contains("ImportLimits::bytes"),
        "{msg}"
    );

    // Seven primitives of 5 M triangles each: indices without a bufferView (zeros), so
    // that the file is small; refused from the counts alone.
    let sparse = r#"{"componentType": 5125, "count": 15000000, "type": "SCALAR", "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5125}, "values": {"bufferView": 1}}}"#;
    let primitive = r#"{"attributes": {"POSITION": 0}, "indices": 1, "material": 0, "mode": 4}"#;
    let json = Tiny::triangle()
        .json()
        .replace(
            r#"{"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}"#,
            sparse,
        )
        .replace(primitive, &[primitive; 7].join(", "));
    assert!(json.contains("15000000"));
    let err = load_bytes("primitives.gltf", json.as_bytes()).expect_err("35 M triangles");
    assert!(matches!(err, Error::ImportLimit { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("35000000") && msg.contains("ImportLimits::triangles"),
        "{msg}"
    );
}

#[test]
fn reused_mesh_is_converted_once_and_drawn_per_node() {
    let json = Tiny::triangle()
        .nodes(
            r#"{"mesh": 0}, {"mesh": 0, "translation": [2.0, 0.0, 0.0]}"#,
            "[0, 1]",
        )
        .json();
    let s = load_bytes("reuse.gltf", json.as_bytes()).expect("reuse");
    assert_eq!((s.meshes.len(), s.opaque.len()), (1, 2));
    assert_eq!(s.opaque[1].transform.w_axis.x, 2.0);
}

// --- helpers ------------------------------------------------------------------------------

/// A named pipe at `path` (a file that never ends when read).
#[cfg(unix)]
fn make_fifo(path: &Path) {
    let made = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo");
    assert!(made.success(), "mkfifo {}", path.display());
}

fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("translucid-{}-{name}", std::process::id()))
}

/// An empty folder of its own for one test.
fn fresh_dir(name: &str) -> PathBuf {
    let dir = temp_path(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Writes `bytes` to a fresh temp file and loads it.
fn load_bytes(name: &str, bytes: &[u8]) -> translucid::Result<Scene> {
    let path = temp_path(name);
    std::fs::write(&path, bytes).expect("write temp file");
    let result = scene::gltf::load(&path);
    let _ = std::fs::remove_file(&path);
    result
}

/// A one-primitive glTF JSON with an embedded base64 buffer, and knobs to break it.
#[derive(Clone)]
struct Tiny {
    positions: Vec<[f32; 3]>,
    indices: Vec<u32>,
    mode: u32,
    material: String,
    top: String,
    buffer_uri: Option<String>,
    position_count: Option<usize>,
    nodes: String,
    scene_nodes: String,
}

impl Tiny {
    fn triangle() -> Self {
        Self {
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            indices: vec![0, 1, 2],
            mode: 4,
            material: "{}".into(),
            top: String::new(),
            buffer_uri: None,
            position_count: None,
            nodes: r#"{"mesh": 0}"#.into(),
            scene_nodes: "[0]".into(),
        }
    }

    fn material(mut self, json: &str) -> Self {
        self.material = json.into();
        self
    }

    fn top(mut self, json: &str) -> Self {
        self.top = format!("{json},");
        self
    }

    fn buffer_uri(mut self, json: &str) -> Self {
        self.buffer_uri = Some(json.into());
        self
    }

    fn position_count(mut self, count: usize) -> Self {
        self.position_count = Some(count);
        self
    }

    /// Replaces the node array and the scene's root nodes.
    fn nodes(mut self, nodes: &str, scene_nodes: &str) -> Self {
        self.nodes = nodes.into();
        self.scene_nodes = scene_nodes.into();
        self
    }

    /// The bytes of the embedded buffer, to write as an external `.bin`.
    fn buffer_bytes(&self) -> Vec<u8> {
        let json = Self {
            buffer_uri: None,
            ..self.clone()
        }
        .json();
        let start = json.find("base64,").expect("data URI") + "base64,".len();
        let end = start + json[start..].find('"').expect("end of URI");
        decode_base64(&json[start..end])
    }

    fn json(&self) -> String {
        let mut bytes: Vec<u8> = self
            .positions
            .iter()
            .flatten()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        let positions_len = bytes.len();
        bytes.extend(self.indices.iter().flat_map(|i| i.to_le_bytes()));
        // min/max must be finite JSON numbers even when a test plants a NaN.
        let finite = |f: f32| if f.is_finite() { f } else { 0.0 };
        let min: Vec<f32> = (0..3)
            .map(|c| {
                self.positions
                    .iter()
                    .map(|p| finite(p[c]))
                    .fold(f32::MAX, f32::min)
            })
            .collect();
        let max: Vec<f32> = (0..3)
            .map(|c| {
                self.positions
                    .iter()
                    .map(|p| finite(p[c]))
                    .fold(f32::MIN, f32::max)
            })
            .collect();
        let uri = self.buffer_uri.clone().unwrap_or_else(|| {
            format!(
                "\"data:application/octet-stream;base64,{}\"",
                base64(&bytes)
            )
        });
        format!(
            r#"{{
  "asset": {{"version": "2.0"}},
  {top}
  "scene": 0,
  "scenes": [{{"nodes": {scene_nodes}}}],
  "nodes": [{nodes}],
  "meshes": [{{"name": "tri", "primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 0, "mode": {mode}}}]}}],
  "materials": [{material}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": {pcount}, "type": "VEC3", "min": {min:?}, "max": {max:?}}},
    {{"bufferView": 1, "componentType": 5125, "count": {icount}, "type": "SCALAR"}}
  ],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": {positions_len}}},
    {{"buffer": 0, "byteOffset": {positions_len}, "byteLength": {indices_len}}}
  ],
  "buffers": [{{"uri": {uri}, "byteLength": {total}}}]
}}"#,
            top = self.top,
            nodes = self.nodes,
            scene_nodes = self.scene_nodes,
            mode = self.mode,
            material = self.material,
            pcount = self.position_count.unwrap_or(self.positions.len()),
            icount = self.indices.len(),
            indices_len = bytes.len() - positions_len,
            total = bytes.len(),
        )
    }
}

/// Standard base64 with padding (RFC 4648), enough for embedded test buffers.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

fn decode_base64(text: &str) -> Vec<u8> {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let values: Vec<u32> = text
        .bytes()
        .filter(|&b| b != b'=')
        .map(|b| ALPHABET.iter().position(|&a| a == b).expect("base64") as u32)
        .collect();
    let mut out = Vec::new();
    for chunk in values.chunks(4) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, v)| n | v << (18 - 6 * i));
        for i in 0..chunk.len() - 1 {
            out.push((n >> (16 - 8 * i)) as u8);
        }
    }
    out
}

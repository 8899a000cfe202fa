//! What a scene needs of the raster shader, decided on the host so that code it cannot reach
//! is compiled away (specialization constants of `shaders/exact/raster.comp`).

#![deny(unsafe_code)]

use super::layout::BIN_SIZE;
use crate::raster::{clip_position, viewport_transform, GUARD_BAND};
use crate::scene::Scene;
use glam::{Mat4, Vec3};

/// How many constants the raster takes: other programs on the same stages (the wavelet bin
/// raster) number theirs from here.
pub const RASTER_CONSTANTS: usize = 12;

/// Specialization constants of the raster stage, in `constant_id` order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RasterFeatures {
    /// Some triangle may need the homogeneous path (near plane, behind the eye, guard band).
    pub homogeneous: bool,
    pub textures: bool,
    /// Some lit draw has vertex normals, and some lit draw has none. Normals are only for
    /// lighting, so with neither the shader drops lighting altogether.
    pub vertex_normals: bool,
    pub face_normals: bool,
    /// Fragments each pixel selects per pass over its bin.
    pub select_size: u32,
    /// Each bin's list holds 2^slab_bits depth slabs (constant 6 of the binning stages too).
    pub slab_bits: u32,
    /// Rows of a block per workgroup of the first raster dispatch: a subgroup must see one
    /// row, so BIN_SIZE only where subgroups are exactly a row wide, else 1.
    pub rows: u32,
    /// Some draw's material transmits light (transmission above 0).
    pub transmission: bool,
    /// Some draw's mesh has vertex colours (the others' are white).
    pub vertex_colours: bool,
    /// Every quad's corners have one colour (particles, billboards), so that shading reads
    /// one colour per triangle instead of three.
    pub flat_colours: bool,
    /// Binning invocations per triangle once bins hold slabs (constant 11 of setup and
    /// binning; exact_bins.glsl): a row's width of them, unless the dispatch would pass the
    /// workgroups every device allows.
    pub deep_binning_lanes: u32,
}

/// The selection size to start with, and the ones frames with deep pixels move to, a step at
/// a time while some pixel still needs more than two sweeps. (On lavapipe at 1280x720, with
/// the raster compositing after each slab: particles, 60 deep, take three sweeps of 16 and
/// are 5-10 % slower with 24, and 1.4x slower with 8; hairball is faster with 16 than 8.)
pub const SELECT_SIZE: u32 = 8;
pub const SELECT_STEPS: [u32; 2] = [SELECT_SIZE, DEEP_SELECT_SIZE];
pub const DEEP_SELECT_SIZE: u32 = 16;
// A suspended row saves its pixels' selections (ExactPixelState).
const _: () = assert!(DEEP_SELECT_SIZE <= super::layout::MAX_SELECT_SIZE);
/// Frames averaging more fragments per pixel than this order their bins by depth slab:
/// there pixels need several sweeps, and compositing after each slab repays the longer scan of
/// 2^DEEP_SLAB_BITS slabs per bin. (On lavapipe at 1280x720, slabs take particles, about 18
/// per pixel, from 1.5 to 0.9 s of raster, and cost hairball, about 1, a fifth of its time.
/// Sixteen slabs took particles 4 % under eight, 2.5 % with `--threshold 0.05`; 32 were no
/// faster, their longer scan eating what the raster saved.)
pub const SLAB_FRAGMENTS_PER_PIXEL: u64 = 8;
pub const DEEP_SLAB_BITS: u32 = 4;
// A bin entry has the bits above ENTRY_SLAB_SHIFT for its slab, and the counters keep the
// farthest depth of MAX_SLABS.
const _: () = assert!(DEEP_SLAB_BITS <= 32 - super::layout::ENTRY_SLAB_SHIFT);
const _: () = assert!(1 << DEEP_SLAB_BITS <= super::layout::MAX_SLABS);

impl RasterFeatures {
    pub fn of(scene: &Scene, width: u32, height: u32, subgroup_size: u32) -> Self {
        let draws = || scene.transparent.iter();
        let lit = |d: &crate::scene::Draw| scene.materials[d.material].lit;
        let view_projection = scene.camera.view_projection(width as f32 / height as f32);
        Self {
            homogeneous: draws().any(|d| {
                let mvp = view_projection * d.transform;
                !bounds_on_fixed_path(&mvp, &scene.meshes[d.mesh].positions, width, height)
            }),
            textures: draws().any(|d| scene.materials[d.material].texture.is_some()),
            vertex_normals: draws().any(|d| lit(d) && scene.meshes[d.mesh].normals.is_some()),
            face_normals: draws().any(|d| lit(d) && scene.meshes[d.mesh].normals.is_none()),
            select_size: SELECT_SIZE,
            slab_bits: 0,
            rows: if subgroup_size == BIN_SIZE {
                BIN_SIZE
            } else {
                1
            },
            transmission: draws().any(|d| scene.materials[d.material].transmission > 0.0),
            vertex_colours: draws().any(|d| scene.meshes[d.mesh].colours.is_some()),
            flat_colours: draws().all(|d| flat_colours(&scene.meshes[d.mesh])),
            deep_binning_lanes: deep_binning_lanes(
                draws()
                    .map(|d| scene.meshes[d.mesh].quads.len() as u64)
                    .sum(),
            ),
        }
    }

    /// What the next frame should use after one with `fragments` fragments in front of the
    /// opaque layer over `pixels` pixels, some pixel needing `sweeps` sweeps. (Fragments
    /// found, not composited: with a threshold, pixels composite fewer than they have, and
    /// counting those kept the deep particles of `--threshold 0.2` from their slabs.) Only
    /// ever moves up, so that a scene does not rebuild its pipelines back and forth.
    pub fn after_frame(self, sweeps: u32, fragments: u64, pixels: u64) -> Self {
        let mut next = self;
        if sweeps > 2 {
            next.select_size = SELECT_STEPS
                .into_iter()
                .find(|&size| size > self.select_size)
                .unwrap_or(self.select_size);
        }
        if fragments > SLAB_FRAGMENTS_PER_PIXEL * pixels {
            next.slab_bits = DEEP_SLAB_BITS;
        }
        next
    }

    /// Everything deep frames move to.
    pub fn deep(self) -> Self {
        Self {
            select_size: DEEP_SELECT_SIZE,
            slab_bits: DEEP_SLAB_BITS,
            ..self
        }
    }

    /// Depth slabs per bin.
    pub fn slabs(&self) -> u32 {
        1 << self.slab_bits
    }

    /// The constants of the binning stages: the slabs (constant 6) and the lanes per
    /// triangle (11).
    pub fn binning_constants(&self) -> [u32; RASTER_CONSTANTS] {
        let mut constants = [0; RASTER_CONSTANTS];
        constants[6] = self.slab_bits;
        constants[11] = self.deep_binning_lanes;
        constants
    }

    /// The constants for the first raster dispatch or for continuations (`continuation`).
    pub fn constants(&self, continuation: bool) -> [u32; RASTER_CONSTANTS] {
        [
            u32::from(self.homogeneous),
            u32::from(self.textures),
            u32::from(self.vertex_normals),
            u32::from(self.face_normals),
            u32::from(continuation),
            self.select_size,
            self.slab_bits,
            if continuation { 1 } else { self.rows },
            u32::from(self.transmission),
            u32::from(self.vertex_colours),
            u32::from(self.flat_colours),
            self.deep_binning_lanes,
        ]
    }
}

/// Binning lanes per triangle for a frame of `quads` transparent quads: BIN_SIZE, unless two
/// triangles a quad would then need more than the 65 535 binning workgroups (of 64) every
/// Vulkan device must allow in one dimension.
fn deep_binning_lanes(quads: u64) -> u32 {
    const MAX_GROUPS: u64 = 65_535;
    if quads * 2 * u64::from(BIN_SIZE) <= MAX_GROUPS * u64::from(super::layout::BINNING_GROUP_SIZE)
    {
        BIN_SIZE
    } else {
        1
    }
}

/// Whether each quad of `mesh` has one colour at all its corners (true without colours).
fn flat_colours(mesh: &crate::scene::Mesh) -> bool {
    let Some(colours) = &mesh.colours else {
        return true;
    };
    mesh.quads.iter().all(|q| {
        let first = colours[q[0] as usize];
        q.iter().all(|&v| colours[v as usize] == first)
    })
}

/// Whether every vertex inside the positions' bounding box lands on the fixed-point path:
/// in front of the near plane and well inside the guard band. The conditions are linear in
/// clip space, so checking the box's corners (with a margin for rounding) covers its inside.
fn bounds_on_fixed_path(mvp: &Mat4, positions: &[Vec3], width: u32, height: u32) -> bool {
    let Some(first) = positions.first() else {
        return true;
    };
    let (lo, hi) = positions
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    (0..8).all(|corner| {
        let pick = |bit: u32, a: f32, b: f32| if corner & bit == 0 { a } else { b };
        let p = Vec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        );
        let clip = clip_position(mvp, p);
        let fb = viewport_transform(clip, width, height);
        clip.w > 0.0
            && clip.z > 1e-6 * clip.w
            && fb.x.abs() < GUARD_BAND * 0.5
            && fb.y.abs() < GUARD_BAND * 0.5
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_scenes_need_only_the_fixed_path_and_no_textures() {
        for name in ["layers", "spheres", "planes"] {
            let scene = crate::scene::generated::generate(name).expect("scene");
            let f = RasterFeatures::of(&scene, 640, 360, 8);
            assert!(!f.homogeneous && !f.textures, "{name}: {f:?}");
        }
    }

    #[test]
    fn deep_frames_step_the_selection_up_and_never_down() {
        let scene = crate::scene::generated::generate("spheres").expect("scene");
        let start = RasterFeatures::of(&scene, 640, 360, 8);
        assert_eq!(start.select_size, SELECT_SIZE);
        let pixels = 640 * 360;
        let sizes: Vec<u32> =
            std::iter::successors(Some(start), |f| Some(f.after_frame(3, 0, pixels)))
                .map(|f| f.select_size)
                .take(5)
                .collect();
        assert_eq!(sizes, [8, 16, 16, 16, 16]);
        let shallow = start.after_frame(2, 0, pixels);
        assert_eq!(shallow.select_size, 8, "two sweeps keep the size");
        assert_eq!(shallow.slab_bits, 0);
        assert_eq!(
            start.after_frame(1, 9 * pixels, pixels).slab_bits,
            DEEP_SLAB_BITS
        );
    }

    #[test]
    fn deep_binning_takes_a_row_of_lanes_per_triangle_while_the_dispatch_allows() {
        assert_eq!(deep_binning_lanes(4096), BIN_SIZE);
        assert_eq!(deep_binning_lanes(262_140), BIN_SIZE);
        assert_eq!(deep_binning_lanes(262_141), 1);
    }

    #[test]
    fn colours_are_flat_only_when_every_quad_has_one() {
        let particles = crate::scene::generated::generate("particles").expect("scene");
        assert!(RasterFeatures::of(&particles, 640, 360, 8).flat_colours);
        let mut mesh = crate::scene::Mesh::from_quads("q", vec![Vec3::ZERO; 4], vec![[0, 1, 2, 3]]);
        assert!(flat_colours(&mesh), "no colours");
        mesh.colours = Some(vec![glam::Vec4::ONE; 4]);
        assert!(flat_colours(&mesh));
        mesh.colours.as_mut().expect("colours")[3].x = 0.5;
        assert!(
            !flat_colours(&mesh),
            "the second triangle's last corner differs"
        );
    }

    #[test]
    fn a_mesh_around_the_camera_needs_the_homogeneous_path() {
        let mvp = crate::scene::Camera::default().view_projection(1.0);
        let around = [Vec3::new(-1.0, -1.0, 4.0), Vec3::new(1.0, 1.0, 6.0)];
        assert!(!bounds_on_fixed_path(&mvp, &around, 64, 64));
        let ahead = [Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 1.0, 1.0)];
        assert!(bounds_on_fixed_path(&mvp, &ahead, 64, 64));
    }
}

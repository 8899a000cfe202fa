//! Meshes from C arrays. Exports `translucid_mesh_*`.

use crate::cast::{check_header, translucid_context, try_out, try_ref, try_slice, try_str};
use crate::panic;
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use glam::{Vec2, Vec3, Vec4};
use std::ffi::{c_char, c_void};
use translucid::scene::Mesh;

/// Most vertices in one mesh.
pub const TRANSLUCID_MAX_VERTICES: u32 = 1 << 24;
/// Most indices in one mesh.
pub const TRANSLUCID_MAX_INDICES: u32 = 1 << 26;

/// How `indices` group vertices.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_primitive {
    /// Three indices per triangle; translucid pairs triangles that share an edge into quads.
    Triangles = 0,
    /// Four indices per quad `a b c d`: triangles `a b c` and `a c d`.
    Quads = 1,
}

/// A mesh. Zero-initialise, then set `s_type` and the arrays. Every array is copied: the
/// caller may free it once the call returns.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_mesh_create_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO`.
    pub s_type: u32,
    /// NULL.
    pub next: *const c_void,
    /// A `translucid_primitive`.
    pub primitive: u32,
    /// 1 to `TRANSLUCID_MAX_VERTICES`.
    pub vertex_count: u32,
    /// Required: `vertex_count` x 3 floats (x y z), finite.
    pub positions: *const f32,
    /// Optional: `vertex_count` x 3 floats, used by lit materials.
    pub normals: *const f32,
    /// Optional: `vertex_count` x 4 floats, linear RGBA multiplied into the base colour, each
    /// in [0, 65504].
    pub colours: *const f32,
    /// Optional: `vertex_count` x 2 floats, texture coordinates, each within ±16777216 (2^24).
    pub uvs: *const f32,
    /// 1 to `TRANSLUCID_MAX_INDICES`, a multiple of 3 (triangles) or 4 (quads).
    pub index_count: u32,
    /// Required: `index_count` vertex indices, each below `vertex_count`.
    pub indices: *const u32,
    /// Optional name for messages (copied).
    pub name: *const c_char,
}

/// A mesh handle. `{0}` is the NULL handle.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct translucid_mesh {
    pub id: u64,
}

fn mesh_from_info(info: &translucid_mesh_create_info) -> FfiResult<Mesh> {
    check_header(
        info.s_type,
        info.next,
        translucid_structure_type::MeshCreateInfo,
        "translucid_mesh_create_info",
    )?;
    let corners = match info.primitive {
        p if p == translucid_primitive::Triangles as u32 => 3,
        p if p == translucid_primitive::Quads as u32 => 4,
        p => return Err(Failure::enumeration("primitive", p)),
    };
    let n = info.vertex_count;
    if n == 0 || n > TRANSLUCID_MAX_VERTICES {
        return Err(Failure::size(format!(
            "vertex_count is {n}; it must be 1 to {TRANSLUCID_MAX_VERTICES}"
        )));
    }
    let count = info.index_count;
    if count == 0 || count > TRANSLUCID_MAX_INDICES || count % corners != 0 {
        return Err(Failure::size(format!(
            "index_count is {count}; it must be a multiple of {corners} from {corners} to \
             {TRANSLUCID_MAX_INDICES}"
        )));
    }
    let n = usize::try_from(n).map_err(|_| Failure::size("vertex_count too large"))?;
    let count = usize::try_from(count).map_err(|_| Failure::size("index_count too large"))?;
    let name = try_str(info.name, "name")?.unwrap_or("").to_string();
    let positions = try_slice(info.positions, n * 3, "positions")?;
    let indices = try_slice(info.indices, count, "indices")?;
    let optional = |ptr: *const f32, width: usize, what: &str| -> FfiResult<Option<&[f32]>> {
        (!ptr.is_null())
            .then(|| try_slice(ptr, n * width, what))
            .transpose()
    };
    let normals = optional(info.normals, 3, "normals")?;
    let colours = optional(info.colours, 4, "colours")?;
    let uvs = optional(info.uvs, 2, "uvs")?;

    let positions: Vec<Vec3> = positions.chunks_exact(3).map(Vec3::from_slice).collect();
    let mut mesh = if corners == 3 {
        let triangles: Vec<[u32; 3]> = indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        Mesh::from_triangles(name, positions, &triangles)
    } else {
        let quads = indices
            .chunks_exact(4)
            .map(|q| [q[0], q[1], q[2], q[3]])
            .collect();
        Mesh::from_quads(name, positions, quads)
    };
    mesh.normals = normals.map(|v| v.chunks_exact(3).map(Vec3::from_slice).collect());
    mesh.colours = colours.map(|v| v.chunks_exact(4).map(Vec4::from_slice).collect());
    mesh.uvs = uvs.map(|v| v.chunks_exact(2).map(Vec2::from_slice).collect());
    mesh.validate()
        .map_err(|e| Failure::argument(format!("mesh \"{}\": {e}", mesh.name)))?;
    Ok(mesh)
}

impl translucid_mesh {
    /// Creates a mesh from `info` (copying every array) and writes its handle to `*out_mesh`.
    /// It is uploaded once, with the context's other assets, when the next frame is recorded
    /// or rendered: create assets while loading, not every frame (each creation or
    /// destruction of a mesh, texture or material makes the next frame upload the context's
    /// assets again). Frames draw it by handle.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_mesh_create(
        context: *mut translucid_context,
        info: *const translucid_mesh_create_info,
        out_mesh: *mut translucid_mesh,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let info = try_ref(info, "info")?;
            let out = try_out(out_mesh, "out_mesh")?;
            let id = objects.core.create_mesh(mesh_from_info(info)?)?;
            out.write(translucid_mesh { id });
            Ok(translucid_result::Success)
        })
    }

    /// Moves `vertex_count` vertices of a mesh, from `first_vertex` on, to `positions`
    /// (`vertex_count` x 3 floats, finite), as particle systems and skinned meshes do every
    /// frame; its indices, normals, colours and texture coordinates stay. Frames recorded
    /// after the call draw the new positions; frames in flight keep the old ones. Nothing is
    /// uploaded again but the mesh's vertices.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_mesh_update(
        context: *mut translucid_context,
        mesh: translucid_mesh,
        first_vertex: u32,
        vertex_count: u32,
        positions: *const f32,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let total = objects.core.mesh(mesh.id)?.positions.len();
            let first = first_vertex as usize;
            let count = vertex_count as usize;
            if count == 0 || first.checked_add(count).is_none_or(|end| end > total) {
                // Before the positions are read: a count past the mesh names no memory of
                // the caller's to trust. (The core checks the range too, and the values.)
                return Err(Failure::size(format!(
                    "vertices {first_vertex} to {} of a mesh of {total}: vertex_count must be \
                     at least 1 and first_vertex + vertex_count at most the mesh's vertex_count",
                    u64::from(first_vertex) + u64::from(vertex_count)
                )));
            }
            let given = try_slice(positions, count * 3, "positions")?;
            // x, y, z floats are glam's Vec3 (12 bytes, 4-aligned): no copy on a call that
            // particle systems make every frame.
            let positions: &[Vec3] = bytemuck::cast_slice(given);
            objects.core.update_mesh(mesh.id, first, positions)?;
            Ok(translucid_result::Success)
        })
    }

    /// Destroys a mesh; its handle becomes stale. Frames already rendered are unaffected, and
    /// host-device frames in flight that draw it keep their copy until they are completed or
    /// abandoned: destroying it never waits and never breaks a frame in flight.
    #[no_mangle]
    pub extern "C" fn translucid_mesh_destroy(
        context: *mut translucid_context,
        mesh: translucid_mesh,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            objects.core.destroy_mesh(mesh.id)?;
            Ok(translucid_result::Success)
        })
    }
}

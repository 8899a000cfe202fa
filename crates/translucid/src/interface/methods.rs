//! The descriptor sets of the graphics methods' passes and of the engine's depth import, each
//! with its include (`interface_<set>.glsl`). Sets bound at different places by different
//! pipelines take their number from a name the including shader defines.

use super::{Binding, Include, SetDecl, StructDecl};

shader_constants! {
    /// Words of one VkDrawIndexedIndirectCommand in depth_peeling's gate, and the word of its
    /// instanceCount (1 for a pass that runs, 0 for one skipped).
    pub const GATE_DRAW_WORDS: u32 = 5;
    pub const GATE_INSTANCE_COUNT: u32 = 1;
}

/// The most coefficient images a wavelet pixel has (rank 3: 48 coefficients, 4 a texel).
pub const WAVELET_MAX_TEXELS: u32 = 12;

/// Set 1 of the mesh pipelines: the draw's base-colour texture, bound per draw (lavapipe, like
/// many Vulkan 1.2 devices, cannot index sampler arrays dynamically).
pub const BASE_TEXTURE_SET: SetDecl =
    SetDecl::new("1", &[Binding::sampled("u_baseTexture", "sampler2D", 1)]);

/// wboit's composite: what the accumulation left.
pub const WBOIT_COMPOSITE_SET: SetDecl = SetDecl::new(
    "0",
    &[
        Binding::sampled("u_radiance", "sampler2D", 1),
        Binding::sampled("u_opacity", "sampler2D", 1),
        Binding::sampled("u_absorbance", "sampler2D", 1),
    ],
);

/// The engine's depth image, sampled into translucid's depth target.
pub const DEPTH_IMPORT_SET: SetDecl =
    SetDecl::new("0", &[Binding::sampled("u_engineDepth", "sampler2D", 1)]);

/// depth_peeling's peeling passes: the range the previous pass left.
pub const DEPTH_PEELING_PEEL_SET: SetDecl =
    SetDecl::new("2", &[Binding::sampled("u_previous", "sampler2D", 1)]);

/// depth_peeling's compute passes (composite after each peel, resolve at the end).
pub const DEPTH_PEELING_COMPOSITE_SET: SetDecl = SetDecl::new(
    "0",
    &[
        Binding::sampled("u_range", "sampler2D", 1),
        Binding::sampled("u_frontLayer", "sampler2D", 3).doc(&[
            "The pass's front and back layer, one image per colour channel: (radiance, 0, 0,",
            "transmittance).",
        ]),
        Binding::sampled("u_backLayer", "sampler2D", 3),
        Binding::image("u_front", ["rgba32f", "", "image2D"]).doc(&[
            "Front to back: radiance and transmittance of the front layers so far; back to",
            "front: the same of the back layers.",
        ]),
        Binding::image("u_frontT", ["rgba32f", "", "image2D"]),
        Binding::image("u_back", ["rgba32f", "", "image2D"]),
        Binding::image("u_backT", ["rgba32f", "", "image2D"]),
        Binding::buffer_instance(
            "Peeling",
            "",
            &[
                "uint unpeeledPixels",
                "uint mostFragments",
                "uint fragmentsLeft[]",
            ],
            "g_peeling",
        )
        .doc(&[
            "Pixels left with fragments after the last pass, the most fragments a pixel has,",
            "then per pass whether any pixel has fragments left (word 2 + pass: its next",
            "pass's condition).",
        ]),
        Binding::image("u_colour", ["rgba16f", "", "image2D"]),
        Binding::sampled("u_fragments", "sampler2D", 1)
            .doc(&["The first pass's count of each pixel's fragments."]),
    ],
);

/// depth_peeling's gate after each composite: once a pass leaves no pixel anything to peel,
/// the passes after it are skipped by the indirect commands it zeroes.
pub const DEPTH_PEELING_GATE_SET: SetDecl = SetDecl::new(
    "0",
    &[
        Binding::buffer_instance(
            "PeelingFlags",
            "readonly",
            &[
                "uint unpeeledPixels",
                "uint mostFragments",
                "uint fragmentsLeft[]",
            ],
            "g_flags",
        )
        .doc(&["The composites' Peeling buffer."]),
        Binding::buffer_instance(
            "PeelingGate",
            "",
            &[
                "uint composite[4]",
                "uint clearDraw[4]",
                "uint gate[4]",
                "uint draws[]",
            ],
            "g_gate",
        )
        .doc(&[
            "The frame's indirect commands: the composite's dispatch, the clear's draw, the",
            "gate's own dispatch, then the transparent draws' VkDrawIndexedIndirectCommands",
            "(GATE_DRAW_WORDS words each, instanceCount at GATE_INSTANCE_COUNT).",
        ]),
    ],
);

/// linked_list's lists, at set LIST_SET: 2 in the append pass (after the scene's sets), 0 in
/// the resolve.
pub const LINKED_LIST_SET: SetDecl = SetDecl::new(
    "LIST_SET",
    &[
        Binding::buffer("HeadBlock", "", &["uint g_heads[]"]),
        Binding::buffer("NodeBlock", "", &["uint g_nodes[]"]),
        Binding::buffer_instance(
            "ListCounters",
            "",
            &[
                "uint fragments",
                "uint capacity",
                "uint width",
                "uint height",
            ],
            "g_list",
        )
        .doc(&[
            "Fragments that asked for a node (all of them: past `capacity`, the rest found",
            "none), the nodes the pool holds, and the frame's size in pixels (heads are rows",
            "of its width).",
        ]),
        Binding::storage_texels("u_nodeTexels", ["r32ui", "", "uimageBuffer"]),
    ],
);

/// The resolve's set: the lists, and the colour it composites onto.
pub const LINKED_LIST_RESOLVE_SET: SetDecl = SetDecl {
    set: "LIST_SET",
    extends: Some(&LINKED_LIST_SET),
    bindings: &[Binding::image("u_colour", ["rgba16f", "", "image2D"])],
};

/// wavelet's accumulation passes: each pixel's depth bounds.
pub const WAVELET_BOUNDS_SET: SetDecl =
    SetDecl::new("2", &[Binding::sampled("u_waveletBounds", "sampler2D", 1)]);

/// What reads a pixel's wavelet data (resolve and shade), at set WAVELET_READ_SET: its bounds
/// and coefficient images (slots past the rank's texel count hold any valid image and are
/// never read).
pub const WAVELET_READ_SET: SetDecl = SetDecl::new(
    "WAVELET_READ_SET",
    &[
        Binding::sampled("u_waveletBounds", "sampler2D", 1),
        Binding::sampled("u_waveletCoefficients", "sampler2D", WAVELET_MAX_TEXELS),
    ],
);

/// The resolve's: the same, and the opaque depth.
pub const WAVELET_RESOLVE_SET: SetDecl = SetDecl {
    set: "WAVELET_READ_SET",
    extends: Some(&WAVELET_READ_SET),
    bindings: &[Binding::sampled("u_opaqueDepth", "sampler2D", 1)],
};

/// The include of `set`, in `file`, after the includes `needs`.
fn set_include(
    file: &'static str,
    set: &'static SetDecl,
    needs: &'static [&'static str],
) -> Include {
    const STRUCTS: &[&StructDecl] = &[];
    Include {
        file,
        source: "methods.rs",
        constants: &[],
        structs: STRUCTS,
        sets: vec![set],
        more: None,
        needs,
    }
}

shader_struct! {
    /// The push constants of the depth import (host/depth_import.frag).
    pub struct DepthImportPush as DepthImportPush {
        /// The frame's top-left corner in the engine's depth image.
        pub origin_x: uint,
        pub origin_y: uint,
    }
}

fn depth_import_include() -> Include {
    const STRUCTS: &[&StructDecl] = &[&DepthImportPush::GLSL];
    Include {
        structs: STRUCTS,
        ..set_include("interface_depth_import.glsl", &DEPTH_IMPORT_SET, &[])
    }
}

pub fn includes() -> Vec<Include> {
    vec![
        set_include("interface_base_texture.glsl", &BASE_TEXTURE_SET, &[]),
        set_include("interface_wboit.glsl", &WBOIT_COMPOSITE_SET, &[]),
        depth_import_include(),
        set_include(
            "interface_depth_peeling_peel.glsl",
            &DEPTH_PEELING_PEEL_SET,
            &[],
        ),
        set_include(
            "interface_depth_peeling.glsl",
            &DEPTH_PEELING_COMPOSITE_SET,
            &[],
        ),
        Include {
            constants: CONSTANTS,
            ..set_include(
                "interface_depth_peeling_gate.glsl",
                &DEPTH_PEELING_GATE_SET,
                &[],
            )
        },
        set_include("interface_linked_list.glsl", &LINKED_LIST_SET, &[]),
        set_include(
            "interface_linked_list_resolve.glsl",
            &LINKED_LIST_RESOLVE_SET,
            &["interface_linked_list.glsl"],
        ),
        set_include("interface_wavelet_bounds.glsl", &WAVELET_BOUNDS_SET, &[]),
        set_include("interface_wavelet_read.glsl", &WAVELET_READ_SET, &[]),
        set_include(
            "interface_wavelet_resolve.glsl",
            &WAVELET_RESOLVE_SET,
            &["interface_wavelet_read.glsl"],
        ),
    ]
}

// The bins' shader interface (generated from crates/translucid/src/interface/bins.rs), and
// the unpacked triangle the stages work with, which lives in registers only.
#ifndef TRANSLUCID_BIN_TRIANGLE_GLSL
#define TRANSLUCID_BIN_TRIANGLE_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "interface_bins.glsl"
// A visible triangle after setup, as the stages use it. Fixed-point edges
// E = a*px + b*py + c are positive inside; on the homogeneous path the lines live in
// BinHomogeneous. Stored packed as a BinTriangleRecord
// (interface_bins.glsl); the loaders are in bins_bindings.glsl.
struct BinTriangle {
    i64vec4 edgeC;          // xyz: c of edges 0..2
    ivec4 edgeA;            // xyz: a of edges 0..2, w: tie bits (bit k: edge k owns ties)
    ivec4 edgeB;            // xyz: b of edges 0..2, w: index into the homogeneous array or -1
    ivec4 bounds;           // half-open pixel rectangle x0, y0, x1, y1
    vec4 zNdc;              // xyz: depth-buffer value of each vertex, w: 1 / |double area|
    vec4 invW;              // xyz: 1 / clip w of each vertex
    uint order;             // order key: global quad index * 2 + sub-triangle, which is
                            // also the index of the record (setup.comp), so that a
                            // fragment's rank names its triangle
    uint materialIndex;
    uint attributeFlags;    // TRIANGLE_FACE_NORMAL, TRIANGLE_HAS_UVS
};

#endif

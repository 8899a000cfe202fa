// Data layouts shared by the host and every shader. The host mirror is
// crates/translucid/src/shader_types.rs; a test checks the two agree.
#ifndef TRANSLUCID_LAYOUT_GLSL
#define TRANSLUCID_LAYOUT_GLSL

#define MATERIAL_LIT 1u
#define MATERIAL_DOUBLE_SIDED 2u

// One material (std430, 48 bytes).
struct Material {
    vec4 baseColour;        // linear RGB, alpha = coverage
    vec4 tintTransmission;  // xyz: transmission tint, w: transmission
    float reflectance;
    float alphaCutoff;      // < 0: no cutoff
    int textureIndex;       // < 0: no texture
    uint flags;             // MATERIAL_*
};

#define DRAW_HAS_NORMALS 1u
#define DRAW_HAS_UVS 2u

// One draw (std430, 144 bytes).
struct DrawInfo {
    mat4 model;
    mat4 normalMatrix;      // shading::normal_matrix of model, in a mat4
    uint materialIndex;
    uint flags;             // DRAW_*
    uint firstQuad;         // index of the draw's first quad in the scene's quad buffer
    uint quadCount;
    vec4 tint;              // multiplied into the draw's vertex colours
};

// Per-frame constants (std140, 160 bytes).
struct FrameInfo {
    mat4 viewProj;
    vec4 lightDirection;    // xyz, towards the light, normalised
    vec4 lightColour;
    vec4 ambient;
    vec4 viewport;          // width, height, 1/width, 1/height
    // Device depth = x - y / d + z d at order depth d; w is 1 when the order depth is device
    // depth + 1 (orthographic projections), 0 when it is clip w.
    vec4 depthMapping;
    vec4 eye;               // xyz: the camera's position in the world
};

#endif

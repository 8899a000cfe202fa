// The attribute records setup writes and the bin rasters shade from (interface_bins.glsl says
// what a record holds): the constants that say which of its sections a scene has, and where
// each section starts. setup.comp and bin_fragment.glsl include it, so that writer and
// readers share one layout; the host sizes records from the same sections
// (methods/bins/layout.rs: attribute_texels).
#ifndef TRANSLUCID_QUAD_ATTRIBUTES_GLSL
#define TRANSLUCID_QUAD_ATTRIBUTES_GLSL

#include "bin_triangle.glsl"

// What shading can read, fixed when the pipeline is made (constant ids shared by setup and
// the rasters; methods/bins/features.rs sets them from the frame's draws).
#include "interface_specialization.glsl"

int colourTexels() {
    return VERTEX_COLOURS ? (FLAT_COLOURS ? FLAT_COLOUR_TEXELS : COLOUR_TEXELS) : 0;
}

int normalTexels() {
    return VERTEX_NORMALS ? NORMAL_TEXELS : (FACE_NORMALS ? FACE_NORMAL_TEXELS : 0);
}

int uvTexels() {
    return TEXTURES ? UV_TEXELS : 0;
}

// Texels of one quad's record.
int attributeTexels() {
    return colourTexels() + normalTexels() + uvTexels();
}

// The first texel of each section of quad q's record.
int colourTexel(uint q) {
    return int(q) * attributeTexels();
}

int normalTexel(uint q) {
    return colourTexel(q) + colourTexels();
}

int uvTexel(uint q) {
    return normalTexel(q) + normalTexels();
}

#endif

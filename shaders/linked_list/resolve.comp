#version 450
// The linked_list method's second pass, one invocation per pixel: the pixel's nodes in the
// reference's order (depth, then draw, then primitive), composited front to back over the
// frame (the opaque layer and any tail). The order is found in sweeps: each keeps the SELECT
// nearest nodes after the last one composited, so that lists of any length come out exact.
//
// A compute pass, not a full-screen fragment pass: lavapipe 22.3 clips the full-screen
// triangle into two, and its fragments in the blocks both halves share came out wrong
// (lists intact, composites off by up to 70/255 along the screen's diagonal). Every lane
// here runs the loops, past the frame too (its store is skipped): partly active lanes are
// what went wrong. The selection is an insertion network over constant indices and the
// loops are do-whiles (raster.comp says why).

#extension GL_EXT_control_flow_attributes : require

#define LIST_SET 0
#include "linked_list.glsl"
#include "colour.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// The frame's colour, composited in place.
#include "interface_linked_list_resolve.glsl"

#define SELECT 16u
// Greater than every key: a depth's bits are never all ones (a NaN).
const uvec3 NO_KEY = uvec3(0xFFFFFFFFu);

uvec3 nodeKey(uint node) {
    uint at = node * NODE_WORDS;
    return uvec3(nodeWord(at + NODE_DEPTH), nodeWord(at + 4u), nodeWord(at + 5u));
}

// Depths are positive floats, whose bits order as they do.
bool before(uvec3 a, uvec3 b) {
    return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    bool inside = pixel.x < g_list.width && pixel.y < g_list.height;
    uint head = inside ? g_heads[headIndex(pixel)] : LIST_END;
    vec3 radiance = vec3(0.0);
    vec3 transmittance = vec3(1.0);
    if (head != LIST_END) {
        uvec3 last = uvec3(0u);
        bool started = false;
        bool more;
        do {
            uvec3 keys[SELECT];
            uint nodes[SELECT];
            [[unroll]] for (uint j = 0u; j < SELECT; j++) {
                keys[j] = NO_KEY;
                nodes[j] = LIST_END;
            }
            uint found = 0u;
            uint n = head;
            do {
                uvec3 key = nodeKey(n);
                uint node = n;
                n = nodeWord(n * NODE_WORDS + NODE_NEXT);
                if (!started || before(last, key)) {
                    found++;
                    // Into the sorted selection; what falls off the end is dropped.
                    [[unroll]] for (uint j = 0u; j < SELECT; j++) {
                        bool earlier = before(key, keys[j]);
                        uvec3 k = keys[j];
                        uint m = nodes[j];
                        keys[j] = earlier ? key : k;
                        nodes[j] = earlier ? node : m;
                        key = earlier ? k : key;
                        node = earlier ? m : node;
                    }
                }
            } while (n != LIST_END);
            [[unroll]] for (uint j = 0u; j < SELECT; j++) {
                if (j < found) {
                    uint at = nodes[j] * NODE_WORDS;
                    vec2 rg = unpackHalf2x16(nodeWord(at));
                    vec2 bt = unpackHalf2x16(nodeWord(at + 1u));
                    vec2 gb = unpackHalf2x16(nodeWord(at + 2u));
                    radiance += transmittance * vec3(rg, bt.x);
                    transmittance *= vec3(bt.y, gb);
                }
            }
            more = found > SELECT;
            last = keys[SELECT - 1u];
            started = true;
        } while (more);
    }
    if (inside && head != LIST_END) {
        vec4 behind = imageLoad(u_colour, ivec2(pixel));
        vec3 result = storedColour(radiance + transmittance * behind.rgb);
        imageStore(u_colour, ivec2(pixel), vec4(result, behind.a));
    }
}

// The linked_list method's buffers (set LIST_SET: 2 in the append pass, after the scene's,
// 0 in the resolve, which also binds the frame's colour, methods/linked_list): a head per
// pixel of the frame, the pool of nodes, and the counters. A node is NODE_WORDS words: the
// fragment's radiance and transmittance as six halves, its order depth, the draw and the
// primitive that break depth ties, and the next node of its pixel's list.
//
// The pool is one buffer, bound twice: as a storage buffer, as far as one binding reaches,
// and as a storage texel buffer, which reaches further (512 MB of words on lavapipe against
// 128 MB). A pool past one storage binding is read and written through the texel view
// (constant 0); one within it through the storage buffer, whose stores are cheaper on
// lavapipe.
#ifndef TRANSLUCID_LINKED_LIST_GLSL
#define TRANSLUCID_LINKED_LIST_GLSL

#ifndef LIST_SET
#define LIST_SET 2
#endif

#define LIST_END 0xFFFFFFFFu
#define NODE_WORDS 7u
#define NODE_DEPTH 3u
#define NODE_NEXT 6u

#include "interface_linked_list.glsl"
#include "interface_specialization.glsl"

uint headIndex(uvec2 pixel) {
    return pixel.y * g_list.width + pixel.x;
}

uint nodeWord(uint at) {
    return NODES_AS_TEXELS ? imageLoad(u_nodeTexels, int(at)).r : g_nodes[at];
}

void setNodeWord(uint at, uint word) {
    if (NODES_AS_TEXELS) {
        imageStore(u_nodeTexels, int(at), uvec4(word));
    } else {
        g_nodes[at] = word;
    }
}

#endif

// The depth_peeling method's shared definitions (methods/depth_peeling). A depth range
// holds (-near, far) of the fragments a pixel has left to peel, so that one MAX blend keeps
// both ends; NO_RANGE is its clear value, an empty range (near > far).
#ifndef TRANSLUCID_DEPTH_PEELING_GLSL
#define TRANSLUCID_DEPTH_PEELING_GLSL

const float NO_DEPTH = -3.4028235e38;
const vec2 NO_RANGE = vec2(NO_DEPTH);

bool rangeHolds(vec2 range) {
    return -range.x <= range.y;
}

#endif

// The range of colours translucid stores. Included by shading.glsl and by the passes that
// write a method's final colour without shading.
#ifndef TRANSLUCID_COLOUR_GLSL
#define TRANSLUCID_COLOUR_GLSL

// The largest colour value translucid takes and gives (shading::MAX_COLOUR): the largest
// finite half float. Radiance and every method's output are clamped to it.
const float MAX_COLOUR = 65504.0;

// A method's final colour as it is stored: never past MAX_COLOUR (an f16 target would hold
// infinity).
vec3 storedColour(vec3 c) {
    return min(c, vec3(MAX_COLOUR));
}

#endif

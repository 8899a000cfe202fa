/*
 * The standalone C tests' one asset: a red, half-transparent quad two units in front of the
 * eye, facing it (misuse.c, threads.c).
 */
#ifndef TRANSLUCID_TESTS_RED_QUAD_H
#define TRANSLUCID_TESTS_RED_QUAD_H

#include <string.h>

#include "translucid.h"

static const float k_positions[] = {-1, -1, -2, 1, -1, -2, 1, 1, -2, -1, 1, -2};
static const uint32_t k_quad[] = {0, 1, 2, 3};

static translucid_mesh_create_info mesh_info(void) {
    translucid_mesh_create_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    info.primitive = TRANSLUCID_PRIMITIVE_QUADS;
    info.vertex_count = 4;
    info.positions = k_positions;
    info.index_count = 4;
    info.indices = k_quad;
    return info;
}

static translucid_material_create_info material_info(void) {
    translucid_material_create_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
    info.base_colour[0] = 1.0f;
    info.base_colour[3] = 0.5f;
    return info;
}

#endif

/* ras_mesh_shapes.c — the built-in shapes: triangle, plane, cube, UV sphere,
 * torus and the Utah teapot.
 *
 * Every shape is counter-clockwise seen from outside, has unit normals and
 * UVs in [0,1]; shapes with a pole (sphere, teapot lid and bottom) leave out
 * the zero-area triangles the pole would create, so a face normal can always
 * be computed. The teapot is tessellated from Newell's 32 bicubic Bézier
 * patches; the data is z-up and is turned to the project's y-up world (spout
 * to +x).
 */
#include "ras_mesh.h"

#include <assert.h> /* assert */
#include <limits.h> /* UINT_MAX */
#include <math.h>   /* sqrtf, sinf, cosf, isfinite */
#include <stdlib.h> /* calloc, free */

#include "ras_mesh_parts.h"

/* ------------------------------------------------------------------------ */
/* Built-in shapes                                                           */

ras_mesh *ras_mesh_create_triangle(vec3s a, vec3s b, vec3s c, vec3s color) {
    ras_mesh *mesh = ras_mesh_create(3, 1);
    if (!mesh) return NULL;
    mesh->positions[0] = a;
    mesh->positions[1] = b;
    mesh->positions[2] = c;
    /* A degenerate triangle has no plane; +z is what a triangle drawn in the
     * xy plane facing the default camera would have. */
    vec3s n = ras_mesh_unit_or(face_normal_raw(a, b, c), v3(0, 0, 1));
    const vec2s uv[3] = {{{0, 0}}, {{1, 0}}, {{0, 1}}};
    for (int i = 0; i < 3; i++) {
        mesh->normals[i] = n;
        mesh->uvs[i] = uv[i];
        mesh->colors[i] = color;
        mesh->indices[i] = (unsigned)i;
    }
    mesh->has_uv = true;
    return mesh;
}

/* Grid sizes come from ints given by the caller; products are formed in
 * size_t and refused when they cannot be indexed. Returns false when a
 * (rows+1) x (cols+1) grid with 2*rows*cols triangles does not fit. */
static bool grid_counts(int rows, int cols, size_t *verts, size_t *tris) {
    size_t r = (size_t)rows, c = (size_t)cols;
    if (r + 1 > SIZE_MAX / (c + 1)) return false;
    *verts = (r + 1) * (c + 1);
    if (r > SIZE_MAX / 2 / (c ? c : 1)) return false;
    *tris = 2 * r * c;
    return *verts <= (size_t)UINT_MAX;
}

ras_mesh *ras_mesh_create_plane(float size, int divisions) {
    if (divisions < 1) divisions = 1;
    size_t nv, nt;
    if (!grid_counts(divisions, divisions, &nv, &nt)) return NULL;
    ras_mesh *mesh = ras_mesh_create(nv, nt);
    if (!mesh) return NULL;
    const size_t d = (size_t)divisions, row = d + 1;
    const float half = 0.5f * size;
    /* Vertex (i, j): i along +x (u), j along -z (v), so the picture's up
     * points away from a camera that looks down -z at the floor. */
    for (size_t j = 0; j <= d; j++)
        for (size_t i = 0; i <= d; i++) {
            float u = (float)i / (float)d, v = (float)j / (float)d;
            size_t k = j * row + i;
            mesh->positions[k] = v3(-half + size * u, 0.0f, half - size * v);
            mesh->normals[k] = v3(0, 1, 0);
            mesh->uvs[k] = (vec2s){{u, v}};
        }
    unsigned *out = mesh->indices;
    for (size_t j = 0; j < d; j++)
        for (size_t i = 0; i < d; i++) {
            unsigned a = (unsigned)(j * row + i), b = a + 1, c = (unsigned)(b + row), e = (unsigned)(a + row);
            /* (+x, then +x-z): the cross product is +y. */
            *out++ = a, *out++ = b, *out++ = c;
            *out++ = a, *out++ = c, *out++ = e;
        }
    ras_mesh_fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

ras_mesh *ras_mesh_create_cube(float size) {
    ras_mesh *mesh = ras_mesh_create(24, 12);
    if (!mesh) return NULL;
    /* Each face: outward normal n and in-face axes s (u) and t (v) with
     * s x t = n, so corners listed (-s-t, +s-t, +s+t, -s+t) run counter-
     * clockwise seen from outside and the picture stands upright on the
     * side faces. */
    static const float faces[6][3][3] = {
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
    };
    static const float corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    const float h = 0.5f * size;
    for (int f = 0; f < 6; f++) {
        vec3s n = v3(faces[f][0][0], faces[f][0][1], faces[f][0][2]);
        vec3s s = v3(faces[f][1][0], faces[f][1][1], faces[f][1][2]);
        vec3s t = v3(faces[f][2][0], faces[f][2][1], faces[f][2][2]);
        for (int c = 0; c < 4; c++) {
            int k = 4 * f + c;
            vec3s p = glms_vec3_add(glms_vec3_scale(n, h),
                                    glms_vec3_add(glms_vec3_scale(s, corner[c][0] * h),
                                                  glms_vec3_scale(t, corner[c][1] * h)));
            mesh->positions[k] = p;
            mesh->normals[k] = n;
            mesh->uvs[k] = (vec2s){{0.5f * (corner[c][0] + 1.0f), 0.5f * (corner[c][1] + 1.0f)}};
        }
        unsigned b = (unsigned)(4 * f);
        unsigned *out = &mesh->indices[6 * f];
        out[0] = b, out[1] = b + 1, out[2] = b + 2;
        out[3] = b, out[4] = b + 2, out[5] = b + 3;
    }
    ras_mesh_fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

ras_mesh *ras_mesh_create_uv_sphere(float radius, int stacks, int slices) {
    if (stacks < 2) stacks = 2;
    if (slices < 3) slices = 3;
    size_t nv, nt;
    if (!grid_counts(stacks, slices, &nv, &nt)) return NULL;
    /* The first and last stacks are fans around the poles: one of each
     * quad's two triangles has zero area there and is left out. */
    nt -= 2 * (size_t)slices;
    ras_mesh *mesh = ras_mesh_create(nv, nt);
    if (!mesh) return NULL;
    const size_t st = (size_t)stacks, sl = (size_t)slices, row = sl + 1;
    /* theta from the north pole (+y) down, phi from +z towards +x: seen from
     * the front (+z), u grows to the right and v upwards. The seam column is
     * duplicated (u = 0 and u = 1) and so are the poles (one per slice, with
     * u at the middle of the slice) so UVs need no wrap. */
    for (size_t i = 0; i <= st; i++) {
        double theta = RAS_PI * (double)i / (double)st;
        for (size_t j = 0; j <= sl; j++) {
            double phi = 2.0 * RAS_PI * (double)j / (double)sl;
            vec3s n = v3((float)(sin(theta) * sin(phi)), (float)cos(theta),
                                  (float)(sin(theta) * cos(phi)));
            if (i == 0) n = v3(0, 1, 0);   /* exact, not sin(0)*... rounding */
            if (i == st) n = v3(0, -1, 0);
            size_t k = i * row + j;
            float u = (float)j / (float)sl;
            if ((i == 0 || i == st) && j < sl) u = ((float)j + 0.5f) / (float)sl;
            mesh->positions[k] = glms_vec3_scale(n, radius);
            mesh->normals[k] = n;
            mesh->uvs[k] = (vec2s){{u, 1.0f - (float)i / (float)st}};
        }
    }
    unsigned *out = mesh->indices;
    for (size_t i = 0; i < st; i++)
        for (size_t j = 0; j < sl; j++) {
            unsigned a = (unsigned)(i * row + j), d = a + 1, b = (unsigned)(a + row), c = b + 1;
            /* a top-left, b bottom-left, c bottom-right, d top-right seen
             * from outside: (a, b, c) and (a, c, d) run counter-clockwise. */
            if (i != st - 1) *out++ = a, *out++ = b, *out++ = c; /* b, c meet at the south pole */
            if (i != 0) *out++ = a, *out++ = c, *out++ = d;      /* a, d meet at the north pole */
        }
    assert((size_t)(out - mesh->indices) == 3 * nt);
    ras_mesh_fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

ras_mesh *ras_mesh_create_torus(float major_radius, float minor_radius, int rings, int sides) {
    if (rings < 3) rings = 3;
    if (sides < 3) sides = 3;
    size_t nv, nt;
    if (!grid_counts(rings, sides, &nv, &nt)) return NULL;
    ras_mesh *mesh = ras_mesh_create(nv, nt);
    if (!mesh) return NULL;
    const size_t nr = (size_t)rings, ns = (size_t)sides, row = ns + 1;
    /* Around the y axis: phi (u) goes round the ring from +z towards +x,
     * theta (v) round the tube starting at the outer equator, going up.
     * d/dphi x d/dtheta points out of the tube, which fixes the winding. */
    for (size_t i = 0; i <= nr; i++) {
        double phi = 2.0 * RAS_PI * (double)i / (double)nr;
        vec3s e = v3((float)sin(phi), 0.0f, (float)cos(phi));
        for (size_t j = 0; j <= ns; j++) {
            double theta = 2.0 * RAS_PI * (double)j / (double)ns;
            vec3s n = glms_vec3_add(glms_vec3_scale(e, (float)cos(theta)),
                                    v3(0.0f, (float)sin(theta), 0.0f));
            size_t k = i * row + j;
            mesh->positions[k] = glms_vec3_add(glms_vec3_scale(e, major_radius),
                                               glms_vec3_scale(n, minor_radius));
            mesh->normals[k] = ras_mesh_unit_or(n, e);
            mesh->uvs[k] = (vec2s){{(float)i / (float)nr, (float)j / (float)ns}};
        }
    }
    unsigned *out = mesh->indices;
    for (size_t i = 0; i < nr; i++)
        for (size_t j = 0; j < ns; j++) {
            unsigned a = (unsigned)(i * row + j), b = (unsigned)(a + row), c = b + 1, d = a + 1;
            *out++ = a, *out++ = b, *out++ = c;
            *out++ = a, *out++ = c, *out++ = d;
        }
    ras_mesh_fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

/* ------------------------------------------------------------------------ */
/* The Utah teapot                                                           */

/* Newell's teapot (1975, public domain): 32 bicubic Bézier patches over 306
 * control points, z up, as in the classic "teaset" data; indices zero-based.
 * Patches 0-3 rim, 4-11 body, 12-15 handle, 16-19 spout, 20-23 lid knob,
 * 24-27 lid, 28-31 bottom (Frank Crow's addition). Four points (204, 205,
 * 215, 222) are part of the published table but used by no patch. In every
 * patch, d/ds x d/dt (s = row, t = column of the 4x4 grid) points inward. */
static const short teapot_patches[32][16] = {
    {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
    {3, 16, 17, 18, 7, 19, 20, 21, 11, 22, 23, 24, 15, 25, 26, 27},
    {18, 28, 29, 30, 21, 31, 32, 33, 24, 34, 35, 36, 27, 37, 38, 39},
    {30, 40, 41, 0, 33, 42, 43, 4, 36, 44, 45, 8, 39, 46, 47, 12},
    {12, 13, 14, 15, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59},
    {15, 25, 26, 27, 51, 60, 61, 62, 55, 63, 64, 65, 59, 66, 67, 68},
    {27, 37, 38, 39, 62, 69, 70, 71, 65, 72, 73, 74, 68, 75, 76, 77},
    {39, 46, 47, 12, 71, 78, 79, 48, 74, 80, 81, 52, 77, 82, 83, 56},
    {56, 57, 58, 59, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 95},
    {59, 66, 67, 68, 87, 96, 97, 98, 91, 99, 100, 101, 95, 102, 103, 104},
    {68, 75, 76, 77, 98, 105, 106, 107, 101, 108, 109, 110, 104, 111, 112, 113},
    {77, 82, 83, 56, 107, 114, 115, 84, 110, 116, 117, 88, 113, 118, 119, 92},
    {120, 121, 122, 123, 124, 125, 126, 127, 128, 129, 130, 131, 132, 133, 134, 135},
    {123, 136, 137, 120, 127, 138, 139, 124, 131, 140, 141, 128, 135, 142, 143, 132},
    {132, 133, 134, 135, 144, 145, 146, 147, 148, 149, 150, 151, 68, 152, 153, 154},
    {135, 142, 143, 132, 147, 155, 156, 144, 151, 157, 158, 148, 154, 159, 160, 68},
    {161, 162, 163, 164, 165, 166, 167, 168, 169, 170, 171, 172, 173, 174, 175, 176},
    {164, 177, 178, 161, 168, 179, 180, 165, 172, 181, 182, 169, 176, 183, 184, 173},
    {173, 174, 175, 176, 185, 186, 187, 188, 189, 190, 191, 192, 193, 194, 195, 196},
    {176, 183, 184, 173, 188, 197, 198, 185, 192, 199, 200, 189, 196, 201, 202, 193},
    {203, 203, 203, 203, 206, 207, 208, 209, 210, 210, 210, 210, 211, 212, 213, 214},
    {203, 203, 203, 203, 209, 216, 217, 218, 210, 210, 210, 210, 214, 219, 220, 221},
    {203, 203, 203, 203, 218, 223, 224, 225, 210, 210, 210, 210, 221, 226, 227, 228},
    {203, 203, 203, 203, 225, 229, 230, 206, 210, 210, 210, 210, 228, 231, 232, 211},
    {211, 212, 213, 214, 233, 234, 235, 236, 237, 238, 239, 240, 241, 242, 243, 244},
    {214, 219, 220, 221, 236, 245, 246, 247, 240, 248, 249, 250, 244, 251, 252, 253},
    {221, 226, 227, 228, 247, 254, 255, 256, 250, 257, 258, 259, 253, 260, 261, 262},
    {228, 231, 232, 211, 256, 263, 264, 233, 259, 265, 266, 237, 262, 267, 268, 241},
    {269, 269, 269, 269, 278, 279, 280, 281, 274, 275, 276, 277, 270, 271, 272, 273},
    {269, 269, 269, 269, 281, 288, 289, 290, 277, 285, 286, 287, 273, 282, 283, 284},
    {269, 269, 269, 269, 290, 297, 298, 299, 287, 294, 295, 296, 284, 291, 292, 293},
    {269, 269, 269, 269, 299, 304, 305, 278, 296, 302, 303, 274, 293, 300, 301, 270},
};

static const float teapot_points[306][3] = {
    /*   0 */ {1.4, 0.0, 2.4}, {1.4, -0.784, 2.4}, {0.784, -1.4, 2.4}, {0.0, -1.4, 2.4},
    /*   4 */ {1.3375, 0.0, 2.53125}, {1.3375, -0.749, 2.53125}, {0.749, -1.3375, 2.53125}, {0.0, -1.3375, 2.53125},
    /*   8 */ {1.4375, 0.0, 2.53125}, {1.4375, -0.805, 2.53125}, {0.805, -1.4375, 2.53125}, {0.0, -1.4375, 2.53125},
    /*  12 */ {1.5, 0.0, 2.4}, {1.5, -0.84, 2.4}, {0.84, -1.5, 2.4}, {0.0, -1.5, 2.4},
    /*  16 */ {-0.784, -1.4, 2.4}, {-1.4, -0.784, 2.4}, {-1.4, 0.0, 2.4}, {-0.749, -1.3375, 2.53125},
    /*  20 */ {-1.3375, -0.749, 2.53125}, {-1.3375, 0.0, 2.53125}, {-0.805, -1.4375, 2.53125}, {-1.4375, -0.805, 2.53125},
    /*  24 */ {-1.4375, 0.0, 2.53125}, {-0.84, -1.5, 2.4}, {-1.5, -0.84, 2.4}, {-1.5, 0.0, 2.4},
    /*  28 */ {-1.4, 0.784, 2.4}, {-0.784, 1.4, 2.4}, {0.0, 1.4, 2.4}, {-1.3375, 0.749, 2.53125},
    /*  32 */ {-0.749, 1.3375, 2.53125}, {0.0, 1.3375, 2.53125}, {-1.4375, 0.805, 2.53125}, {-0.805, 1.4375, 2.53125},
    /*  36 */ {0.0, 1.4375, 2.53125}, {-1.5, 0.84, 2.4}, {-0.84, 1.5, 2.4}, {0.0, 1.5, 2.4},
    /*  40 */ {0.784, 1.4, 2.4}, {1.4, 0.784, 2.4}, {0.749, 1.3375, 2.53125}, {1.3375, 0.749, 2.53125},
    /*  44 */ {0.805, 1.4375, 2.53125}, {1.4375, 0.805, 2.53125}, {0.84, 1.5, 2.4}, {1.5, 0.84, 2.4},
    /*  48 */ {1.75, 0.0, 1.875}, {1.75, -0.98, 1.875}, {0.98, -1.75, 1.875}, {0.0, -1.75, 1.875},
    /*  52 */ {2.0, 0.0, 1.35}, {2.0, -1.12, 1.35}, {1.12, -2.0, 1.35}, {0.0, -2.0, 1.35},
    /*  56 */ {2.0, 0.0, 0.9}, {2.0, -1.12, 0.9}, {1.12, -2.0, 0.9}, {0.0, -2.0, 0.9},
    /*  60 */ {-0.98, -1.75, 1.875}, {-1.75, -0.98, 1.875}, {-1.75, 0.0, 1.875}, {-1.12, -2.0, 1.35},
    /*  64 */ {-2.0, -1.12, 1.35}, {-2.0, 0.0, 1.35}, {-1.12, -2.0, 0.9}, {-2.0, -1.12, 0.9},
    /*  68 */ {-2.0, 0.0, 0.9}, {-1.75, 0.98, 1.875}, {-0.98, 1.75, 1.875}, {0.0, 1.75, 1.875},
    /*  72 */ {-2.0, 1.12, 1.35}, {-1.12, 2.0, 1.35}, {0.0, 2.0, 1.35}, {-2.0, 1.12, 0.9},
    /*  76 */ {-1.12, 2.0, 0.9}, {0.0, 2.0, 0.9}, {0.98, 1.75, 1.875}, {1.75, 0.98, 1.875},
    /*  80 */ {1.12, 2.0, 1.35}, {2.0, 1.12, 1.35}, {1.12, 2.0, 0.9}, {2.0, 1.12, 0.9},
    /*  84 */ {2.0, 0.0, 0.45}, {2.0, -1.12, 0.45}, {1.12, -2.0, 0.45}, {0.0, -2.0, 0.45},
    /*  88 */ {1.5, 0.0, 0.225}, {1.5, -0.84, 0.225}, {0.84, -1.5, 0.225}, {0.0, -1.5, 0.225},
    /*  92 */ {1.5, 0.0, 0.15}, {1.5, -0.84, 0.15}, {0.84, -1.5, 0.15}, {0.0, -1.5, 0.15},
    /*  96 */ {-1.12, -2.0, 0.45}, {-2.0, -1.12, 0.45}, {-2.0, 0.0, 0.45}, {-0.84, -1.5, 0.225},
    /* 100 */ {-1.5, -0.84, 0.225}, {-1.5, 0.0, 0.225}, {-0.84, -1.5, 0.15}, {-1.5, -0.84, 0.15},
    /* 104 */ {-1.5, 0.0, 0.15}, {-2.0, 1.12, 0.45}, {-1.12, 2.0, 0.45}, {0.0, 2.0, 0.45},
    /* 108 */ {-1.5, 0.84, 0.225}, {-0.84, 1.5, 0.225}, {0.0, 1.5, 0.225}, {-1.5, 0.84, 0.15},
    /* 112 */ {-0.84, 1.5, 0.15}, {0.0, 1.5, 0.15}, {1.12, 2.0, 0.45}, {2.0, 1.12, 0.45},
    /* 116 */ {0.84, 1.5, 0.225}, {1.5, 0.84, 0.225}, {0.84, 1.5, 0.15}, {1.5, 0.84, 0.15},
    /* 120 */ {-1.6, 0.0, 2.025}, {-1.6, -0.3, 2.025}, {-1.5, -0.3, 2.25}, {-1.5, 0.0, 2.25},
    /* 124 */ {-2.3, 0.0, 2.025}, {-2.3, -0.3, 2.025}, {-2.5, -0.3, 2.25}, {-2.5, 0.0, 2.25},
    /* 128 */ {-2.7, 0.0, 2.025}, {-2.7, -0.3, 2.025}, {-3.0, -0.3, 2.25}, {-3.0, 0.0, 2.25},
    /* 132 */ {-2.7, 0.0, 1.8}, {-2.7, -0.3, 1.8}, {-3.0, -0.3, 1.8}, {-3.0, 0.0, 1.8},
    /* 136 */ {-1.5, 0.3, 2.25}, {-1.6, 0.3, 2.025}, {-2.5, 0.3, 2.25}, {-2.3, 0.3, 2.025},
    /* 140 */ {-3.0, 0.3, 2.25}, {-2.7, 0.3, 2.025}, {-3.0, 0.3, 1.8}, {-2.7, 0.3, 1.8},
    /* 144 */ {-2.7, 0.0, 1.575}, {-2.7, -0.3, 1.575}, {-3.0, -0.3, 1.35}, {-3.0, 0.0, 1.35},
    /* 148 */ {-2.5, 0.0, 1.125}, {-2.5, -0.3, 1.125}, {-2.65, -0.3, 0.9375}, {-2.65, 0.0, 0.9375},
    /* 152 */ {-2.0, -0.3, 0.9}, {-1.9, -0.3, 0.6}, {-1.9, 0.0, 0.6}, {-3.0, 0.3, 1.35},
    /* 156 */ {-2.7, 0.3, 1.575}, {-2.65, 0.3, 0.9375}, {-2.5, 0.3, 1.125}, {-1.9, 0.3, 0.6},
    /* 160 */ {-2.0, 0.3, 0.9}, {1.7, 0.0, 1.425}, {1.7, -0.66, 1.425}, {1.7, -0.66, 0.6},
    /* 164 */ {1.7, 0.0, 0.6}, {2.6, 0.0, 1.425}, {2.6, -0.66, 1.425}, {3.1, -0.66, 0.825},
    /* 168 */ {3.1, 0.0, 0.825}, {2.3, 0.0, 2.1}, {2.3, -0.25, 2.1}, {2.4, -0.25, 2.025},
    /* 172 */ {2.4, 0.0, 2.025}, {2.7, 0.0, 2.4}, {2.7, -0.25, 2.4}, {3.3, -0.25, 2.4},
    /* 176 */ {3.3, 0.0, 2.4}, {1.7, 0.66, 0.6}, {1.7, 0.66, 1.425}, {3.1, 0.66, 0.825},
    /* 180 */ {2.6, 0.66, 1.425}, {2.4, 0.25, 2.025}, {2.3, 0.25, 2.1}, {3.3, 0.25, 2.4},
    /* 184 */ {2.7, 0.25, 2.4}, {2.8, 0.0, 2.475}, {2.8, -0.25, 2.475}, {3.525, -0.25, 2.49375},
    /* 188 */ {3.525, 0.0, 2.49375}, {2.9, 0.0, 2.475}, {2.9, -0.15, 2.475}, {3.45, -0.15, 2.5125},
    /* 192 */ {3.45, 0.0, 2.5125}, {2.8, 0.0, 2.4}, {2.8, -0.15, 2.4}, {3.2, -0.15, 2.4},
    /* 196 */ {3.2, 0.0, 2.4}, {3.525, 0.25, 2.49375}, {2.8, 0.25, 2.475}, {3.45, 0.15, 2.5125},
    /* 200 */ {2.9, 0.15, 2.475}, {3.2, 0.15, 2.4}, {2.8, 0.15, 2.4}, {0.0, 0.0, 3.15},
    /* 204 */ {0.0, -0.002, 3.15}, {0.002, 0.0, 3.15}, {0.8, 0.0, 3.15}, {0.8, -0.45, 3.15},
    /* 208 */ {0.45, -0.8, 3.15}, {0.0, -0.8, 3.15}, {0.0, 0.0, 2.85}, {0.2, 0.0, 2.7},
    /* 212 */ {0.2, -0.112, 2.7}, {0.112, -0.2, 2.7}, {0.0, -0.2, 2.7}, {-0.002, 0.0, 3.15},
    /* 216 */ {-0.45, -0.8, 3.15}, {-0.8, -0.45, 3.15}, {-0.8, 0.0, 3.15}, {-0.112, -0.2, 2.7},
    /* 220 */ {-0.2, -0.112, 2.7}, {-0.2, 0.0, 2.7}, {0.0, 0.002, 3.15}, {-0.8, 0.45, 3.15},
    /* 224 */ {-0.45, 0.8, 3.15}, {0.0, 0.8, 3.15}, {-0.2, 0.112, 2.7}, {-0.112, 0.2, 2.7},
    /* 228 */ {0.0, 0.2, 2.7}, {0.45, 0.8, 3.15}, {0.8, 0.45, 3.15}, {0.112, 0.2, 2.7},
    /* 232 */ {0.2, 0.112, 2.7}, {0.4, 0.0, 2.55}, {0.4, -0.224, 2.55}, {0.224, -0.4, 2.55},
    /* 236 */ {0.0, -0.4, 2.55}, {1.3, 0.0, 2.55}, {1.3, -0.728, 2.55}, {0.728, -1.3, 2.55},
    /* 240 */ {0.0, -1.3, 2.55}, {1.3, 0.0, 2.4}, {1.3, -0.728, 2.4}, {0.728, -1.3, 2.4},
    /* 244 */ {0.0, -1.3, 2.4}, {-0.224, -0.4, 2.55}, {-0.4, -0.224, 2.55}, {-0.4, 0.0, 2.55},
    /* 248 */ {-0.728, -1.3, 2.55}, {-1.3, -0.728, 2.55}, {-1.3, 0.0, 2.55}, {-0.728, -1.3, 2.4},
    /* 252 */ {-1.3, -0.728, 2.4}, {-1.3, 0.0, 2.4}, {-0.4, 0.224, 2.55}, {-0.224, 0.4, 2.55},
    /* 256 */ {0.0, 0.4, 2.55}, {-1.3, 0.728, 2.55}, {-0.728, 1.3, 2.55}, {0.0, 1.3, 2.55},
    /* 260 */ {-1.3, 0.728, 2.4}, {-0.728, 1.3, 2.4}, {0.0, 1.3, 2.4}, {0.224, 0.4, 2.55},
    /* 264 */ {0.4, 0.224, 2.55}, {0.728, 1.3, 2.55}, {1.3, 0.728, 2.55}, {0.728, 1.3, 2.4},
    /* 268 */ {1.3, 0.728, 2.4}, {0.0, 0.0, 0.0}, {1.5, 0.0, 0.15}, {1.5, 0.84, 0.15},
    /* 272 */ {0.84, 1.5, 0.15}, {0.0, 1.5, 0.15}, {1.5, 0.0, 0.075}, {1.5, 0.84, 0.075},
    /* 276 */ {0.84, 1.5, 0.075}, {0.0, 1.5, 0.075}, {1.425, 0.0, 0.0}, {1.425, 0.798, 0.0},
    /* 280 */ {0.798, 1.425, 0.0}, {0.0, 1.425, 0.0}, {-0.84, 1.5, 0.15}, {-1.5, 0.84, 0.15},
    /* 284 */ {-1.5, 0.0, 0.15}, {-0.84, 1.5, 0.075}, {-1.5, 0.84, 0.075}, {-1.5, 0.0, 0.075},
    /* 288 */ {-0.798, 1.425, 0.0}, {-1.425, 0.798, 0.0}, {-1.425, 0.0, 0.0}, {-1.5, -0.84, 0.15},
    /* 292 */ {-0.84, -1.5, 0.15}, {0.0, -1.5, 0.15}, {-1.5, -0.84, 0.075}, {-0.84, -1.5, 0.075},
    /* 296 */ {0.0, -1.5, 0.075}, {-1.425, -0.798, 0.0}, {-0.798, -1.425, 0.0}, {0.0, -1.425, 0.0},
    /* 300 */ {0.84, -1.5, 0.15}, {1.5, -0.84, 0.15}, {0.84, -1.5, 0.075}, {1.5, -0.84, 0.075},
    /* 304 */ {0.798, -1.425, 0.0}, {1.425, -0.798, 0.0},
};

/* Cubic Bernstein basis and its derivative at t. */
static void bernstein(float t, float b[4], float db[4]) {
    float s = 1.0f - t;
    b[0] = s * s * s;
    b[1] = 3.0f * t * s * s;
    b[2] = 3.0f * t * t * s;
    b[3] = t * t * t;
    db[0] = -3.0f * s * s;
    db[1] = 3.0f * s * s - 6.0f * t * s;
    db[2] = 6.0f * t * s - 3.0f * t * t;
    db[3] = 3.0f * t * t;
}

/* Point and outward (unnormalised) normal of patch `p` at (s, t), in the
 * y-up frame: (x, y, z)_data -> (x, z, -y), a rotation, so orientation holds.
 * size->x is |dP/ds|^2 + |dP/dt|^2, the scale a degenerate normal is judged by. */
static void teapot_eval(int p, float s, float t, vec3s *pos, vec3s *normal, vec3s *size) {
    float bs[4], dbs[4], bt[4], dbt[4];
    bernstein(s, bs, dbs);
    bernstein(t, bt, dbt);
    vec3s P = glms_vec3_zero(), Ds = glms_vec3_zero(), Dt = glms_vec3_zero();
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            const float *c = teapot_points[teapot_patches[p][4 * i + j]];
            vec3s cp = v3(c[0], c[2], -c[1]);
            P = glms_vec3_add(P, glms_vec3_scale(cp, bs[i] * bt[j]));
            Ds = glms_vec3_add(Ds, glms_vec3_scale(cp, dbs[i] * bt[j]));
            Dt = glms_vec3_add(Dt, glms_vec3_scale(cp, bs[i] * dbt[j]));
        }
    *pos = P;
    *normal = glms_vec3_cross(Dt, Ds);
    *size = v3(glms_vec3_dot(Ds, Ds) + glms_vec3_dot(Dt, Dt), 0.0f, 0.0f);
}

ras_mesh *ras_mesh_create_teapot(int divisions) {
    /* One segment per patch is not a teapot: the spout-tip patches' corners
     * are collinear, so their two triangles would have zero area. */
    if (divisions < 2) divisions = 2;
    size_t nv1, nt1;
    if (!grid_counts(divisions, divisions, &nv1, &nt1)) return NULL;
    if (nv1 > SIZE_MAX / 32 || nt1 > SIZE_MAX / 32 || 32 * nv1 > (size_t)UINT_MAX) return NULL;
    const size_t n = (size_t)divisions, row = n + 1;

    /* Which patch edges collapse to a point (the lid knob's top, the bottom's
     * centre): every control point of that edge is the same one. */
    bool collapsed[32][4]; /* s = 0, s = 1, t = 0, t = 1 */
    size_t degenerate = 0;
    for (int p = 0; p < 32; p++) {
        const short *c = teapot_patches[p];
        collapsed[p][0] = c[0] == c[1] && c[1] == c[2] && c[2] == c[3];
        collapsed[p][1] = c[12] == c[13] && c[13] == c[14] && c[14] == c[15];
        collapsed[p][2] = c[0] == c[4] && c[4] == c[8] && c[8] == c[12];
        collapsed[p][3] = c[3] == c[7] && c[7] == c[11] && c[11] == c[15];
        for (int e = 0; e < 4; e++) degenerate += collapsed[p][e] ? n : 0;
    }
    ras_mesh *mesh = ras_mesh_create(32 * nv1, 32 * nt1 - degenerate);
    if (!mesh) return NULL;

    bool repair_any = false;
    bool *repair = ras_mesh_calloc(mesh->vertex_count, sizeof *repair);
    if (!repair) {
        ras_mesh_destroy(mesh);
        return NULL;
    }
    unsigned *out = mesh->indices;
    for (int p = 0; p < 32; p++) {
        size_t base = (size_t)p * nv1;
        for (size_t i = 0; i <= n; i++)
            for (size_t j = 0; j <= n; j++) {
                float s = (float)i / (float)n, t = (float)j / (float)n;
                vec3s pos, nrm, ds_dt;
                teapot_eval(p, s, t, &pos, &nrm, &ds_dt);
                /* On a collapsed edge one derivative vanishes, but only up to
                 * rounding (the basis derivatives sum to ~1e-7, not 0), so
                 * the cross product is tiny noise rather than zero: detect
                 * the edge from the data, and tiny normals relative to the
                 * derivatives elsewhere. */
                bool on_pole = (i == 0 && collapsed[p][0]) || (i == n && collapsed[p][1]) ||
                               (j == 0 && collapsed[p][2]) || (j == n && collapsed[p][3]);
                if (on_pole || !ras_mesh_normal_ok(nrm) ||
                    glms_vec3_dot(nrm, nrm) < 1e-10f * ds_dt.x * ds_dt.x) {
                    /* A step into the patch gives the limit direction (the
                     * surface is smooth there, only its parametrisation is not). */
                    const float step = 1e-3f;
                    vec3s dummy, dummy_d;
                    teapot_eval(p, s + (s < 0.5f ? step : -step),
                                         t + (t < 0.5f ? step : -step), &dummy, &nrm, &dummy_d);
                }
                size_t k = base + i * row + j;
                mesh->positions[k] = pos;
                if (ras_mesh_normal_ok(nrm)) mesh->normals[k] = ras_mesh_unit_or(nrm, v3(0, 1, 0));
                else repair[k] = repair_any = true;
                /* v = 1 at s = 0: the body patches run from the rim down. */
                mesh->uvs[k] = (vec2s){{t, 1.0f - s}};
            }
        for (size_t i = 0; i < n; i++)
            for (size_t j = 0; j < n; j++) {
                unsigned a = (unsigned)(base + i * row + j), b = a + 1, d = (unsigned)(a + row), c = d + 1;
                /* a=(i,j) b=(i,j+1) c=(i+1,j+1) d=(i+1,j): (b-a) x (c-a) ~ Dt x Ds,
                 * outward. A triangle with an edge on a collapsed patch edge
                 * has zero area and is skipped. */
                bool ab_collapsed = (i == 0 && collapsed[p][0]);       /* a, b on s = 0 */
                bool cd_collapsed = (i + 1 == n && collapsed[p][1]);   /* c, d on s = 1 */
                bool ad_collapsed = (j == 0 && collapsed[p][2]);       /* a, d on t = 0 */
                bool bc_collapsed = (j + 1 == n && collapsed[p][3]);   /* b, c on t = 1 */
                if (!ab_collapsed && !bc_collapsed) *out++ = a, *out++ = b, *out++ = c;
                if (!cd_collapsed && !ad_collapsed) *out++ = a, *out++ = c, *out++ = d;
            }
    }
    assert((size_t)(out - mesh->indices) == 3 * mesh->triangle_count);
    if (repair_any) ras_mesh_smooth_normals(mesh, repair);
    free(repair);

    /* Centre the bounding box on the origin and scale the longest side
     * (spout to handle) to 2: the teapot then fits the box [-1, 1]^3 like
     * the unit sphere, so a scene can swap one for the other. */
    mat4s fit = ras_mesh_fit_matrix(mesh, 2.0f);
    for (size_t k = 0; k < mesh->vertex_count; k++)
        mesh->positions[k] = ras_mat4_mulv3(fit, mesh->positions[k], 1.0f);
    ras_mesh_fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}


/* test_mesh.c — cmocka tests for common/ras_mesh: loading through assimp and
 * the built-in shapes.
 *
 * Model files are written at test time into a private temporary directory
 * (made by the group setup, removed by the group teardown), so the suite
 * needs no data files and never touches the source tree.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#endif

#include <setjmp.h> /* required by cmocka.h */
#include <stdarg.h> /* required by cmocka.h */
#include <stddef.h> /* required by cmocka.h */
#include <stdint.h> /* required by cmocka.h; SIZE_MAX */

#include <cmocka.h>

#include "ras_mesh.h"

#include <limits.h>  /* INT_MAX */
#include <stdbool.h> /* bool */
#include <math.h>   /* fabsf, sqrtf, isfinite */
#include <stdio.h>  /* snprintf, fopen */
#include <stdlib.h> /* mkdtemp, calloc */
#include <string.h> /* strstr, memcpy */
#include <unistd.h> /* rmdir */

/* ------------------------------------------------------------------------ */
/* Fixture: a temporary directory for the generated model files             */

#define MAX_FILES 32

typedef struct fixture {
    char dir[256];
    char files[MAX_FILES][512];
    int file_count;
} fixture;

static int group_setup(void **state) {
    fixture *fx = calloc(1, sizeof *fx);
    if (!fx) return -1;
    snprintf(fx->dir, sizeof fx->dir, "/tmp/raster101_test_mesh_XXXXXX");
    if (!mkdtemp(fx->dir)) {
        free(fx);
        return -1;
    }
    *state = fx;
    return 0;
}

static int group_teardown(void **state) {
    fixture *fx = *state;
    if (!fx) return 0;
    for (int i = 0; i < fx->file_count; i++) remove(fx->files[i]);
    rmdir(fx->dir);
    free(fx);
    return 0;
}

/* Writes `text` to <tmpdir>/<name> and returns the full path (owned by fx). */
static const char *write_model(void **state, const char *name, const char *text) {
    fixture *fx = *state;
    assert_true(fx->file_count < MAX_FILES);
    /* Formatted into a local first: gcc cannot tell fx->dir from fx->files
     * apart and warns (-Wrestrict) about a possible overlap. */
    char full[sizeof fx->files[0]];
    snprintf(full, sizeof full, "%s/%s", fx->dir, name);
    char *path = fx->files[fx->file_count++];
    memcpy(path, full, sizeof full);
    FILE *f = fopen(path, "wb");
    if (!f) fail_msg("could not create the test model file %s", path);
    fputs(text, f);
    fclose(f);
    return path;
}

/* Loads a model that must load, failing the test with assimp's/our message. */
static ras_mesh *load_ok(const char *path) {
    ras_error err = {{0}};
    ras_mesh *mesh = ras_mesh_load(path, &err);
    if (!mesh) fail_msg("expected %s to load, but ras_mesh_load failed: %s", path, err.msg);
    return mesh;
}

/* ------------------------------------------------------------------------ */
/* Helpers for mesh invariants                                               */

static vec3s tri_pos(const ras_mesh *m, size_t t, int k) { return m->positions[m->indices[3 * t + k]]; }

static vec3s face_normal(const ras_mesh *m, size_t t) {
    vec3s a = tri_pos(m, t, 0), b = tri_pos(m, t, 1), c = tri_pos(m, t, 2);
    return glms_vec3_cross(glms_vec3_sub(b, a), glms_vec3_sub(c, a));
}

static vec3s tri_centroid(const ras_mesh *m, size_t t) {
    vec3s s = glms_vec3_add(tri_pos(m, t, 0), glms_vec3_add(tri_pos(m, t, 1), tri_pos(m, t, 2)));
    return glms_vec3_scale(s, 1.0f / 3.0f);
}

/* Every index in range, every position/normal/uv finite, every normal unit. */
static void check_well_formed(const ras_mesh *m, const char *what) {
    assert_non_null(m);
    for (size_t i = 0; i < 3 * m->triangle_count; i++)
        if (m->indices[i] >= m->vertex_count)
            fail_msg("%s: index %zu is %u but there are only %zu vertices", what, i, m->indices[i],
                     m->vertex_count);
    for (size_t v = 0; v < m->vertex_count; v++) {
        if (!ras_vec3_finite(m->positions[v]) || !ras_vec3_finite(m->normals[v]) ||
            !ras_vec2_finite(m->uvs[v]))
            fail_msg("%s: vertex %zu has a non-finite position, normal or uv", what, v);
        float len = glms_vec3_norm(m->normals[v]);
        if (fabsf(len - 1.0f) > 1e-4f)
            fail_msg("%s: normal of vertex %zu has length %g, expected 1 (normals must be unit)",
                     what, v, (double)len);
    }
}

static void check_uv_in_unit_square(const ras_mesh *m, const char *what) {
    for (size_t v = 0; v < m->vertex_count; v++) {
        vec2s uv = m->uvs[v];
        if (uv.x < 0.0f || uv.x > 1.0f || uv.y < 0.0f || uv.y > 1.0f)
            fail_msg("%s: vertex %zu has uv (%g, %g), expected both in [0, 1]", what, v,
                     (double)uv.x, (double)uv.y);
    }
}

/* For a closed shape that is star-shaped around `centre`: every face normal
 * (cross product, i.e. the winding) points away from it. */
static void check_outward_winding(const ras_mesh *m, vec3s centre, const char *what) {
    for (size_t t = 0; t < m->triangle_count; t++) {
        vec3s n = face_normal(m, t);
        vec3s out = glms_vec3_sub(tri_centroid(m, t), centre);
        if (!(glms_vec3_dot(n, out) > 0.0f))
            fail_msg("%s: triangle %zu is clockwise seen from outside (face normal . outward = %g); "
                     "expected counter-clockwise — swap two corners",
                     what, t, (double)glms_vec3_dot(n, out));
    }
}

/* Stored vertex normals lean the same way as the face they belong to. */
static void check_normals_match_faces(const ras_mesh *m, float min_cos, const char *what) {
    for (size_t t = 0; t < m->triangle_count; t++) {
        vec3s f = glms_vec3_normalize(face_normal(m, t));
        for (int k = 0; k < 3; k++) {
            unsigned v = m->indices[3 * t + k];
            float c = glms_vec3_dot(f, m->normals[v]);
            if (!(c >= min_cos))
                fail_msg("%s: triangle %zu corner %d: stored normal and face normal have cos %g, "
                         "expected >= %g (normal flipped or winding wrong)",
                         what, t, k, (double)c, (double)min_cos);
        }
    }
}

static void assert_vec3_near(vec3s got, vec3s want, float tol, const char *what) {
    if (!(fabsf(got.x - want.x) <= tol && fabsf(got.y - want.y) <= tol && fabsf(got.z - want.z) <= tol))
        fail_msg("%s: got (%g, %g, %g), expected (%g, %g, %g) within %g", what, (double)got.x,
                 (double)got.y, (double)got.z, (double)want.x, (double)want.y, (double)want.z,
                 (double)tol);
}

/* ------------------------------------------------------------------------ */
/* Loading                                                                   */

/* One OBJ triangle loads with its positions, a generated +z normal, white colour and no UVs. */
static void test_mesh_load_obj_triangle(void **state) {
    const char *path = write_model(state, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    ras_mesh *m = load_ok(path);
    assert_int_equal(m->vertex_count, 3);
    assert_int_equal(m->triangle_count, 1);
    check_well_formed(m, "tri.obj");
    assert_vec3_near(tri_pos(m, 0, 0), (vec3s){{0, 0, 0}}, 0, "first corner");
    assert_vec3_near(tri_pos(m, 0, 1), (vec3s){{1, 0, 0}}, 0, "second corner (order kept)");
    assert_vec3_near(tri_pos(m, 0, 2), (vec3s){{0, 1, 0}}, 0, "third corner (order kept)");
    for (size_t v = 0; v < 3; v++) {
        assert_vec3_near(m->normals[v], (vec3s){{0, 0, 1}}, 1e-6f, "generated normal of a CCW xy triangle");
        assert_vec3_near(m->colors[v], (vec3s){{1, 1, 1}}, 0, "colour without vertex colours in the file");
    }
    assert_false(m->has_uv);
    assert_false(m->has_normals_from_file);
    ras_mesh_destroy(m);
}

/* A quad face is triangulated into two triangles that keep its winding. */
static void test_mesh_load_obj_quad_two_triangles(void **state) {
    const char *path = write_model(state, "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    ras_mesh *m = load_ok(path);
    assert_int_equal(m->vertex_count, 4);
    assert_int_equal(m->triangle_count, 2);
    check_well_formed(m, "quad.obj");
    for (size_t t = 0; t < 2; t++)
        assert_vec3_near(glms_vec3_normalize(face_normal(m, t)), (vec3s){{0, 0, 1}}, 1e-6f,
                         "face normal of a triangulated CCW quad");
    ras_mesh_destroy(m);
}

/* A convex pentagon (n-gon) is triangulated into three triangles covering its area. */
static void test_mesh_load_obj_pentagon_three_triangles(void **state) {
    const char *path = write_model(state, "pent.obj",
                                   "v 0 0 0\nv 1 0 0\nv 1.3 0.8 0\nv 0.5 1.4 0\nv -0.3 0.8 0\nf 1 2 3 4 5\n");
    ras_mesh *m = load_ok(path);
    assert_int_equal(m->triangle_count, 3);
    check_well_formed(m, "pent.obj");
    float area = 0.0f;
    for (size_t t = 0; t < 3; t++) {
        vec3s n = face_normal(m, t);
        if (!(n.z > 0.0f)) fail_msg("pentagon triangle %zu is wound clockwise (n.z = %g)", t, (double)n.z);
        area += 0.5f * n.z;
    }
    /* Shoelace area of the pentagon: 1.52. */
    if (fabsf(area - 1.52f) > 1e-5f)
        fail_msg("triangles cover area %g, expected the pentagon's 1.52 (overlap or gap)", (double)area);
    ras_mesh_destroy(m);
}

/* A closed OBJ without normals gets smooth unit normals that point outward. */
static void test_mesh_load_obj_missing_normals_generated(void **state) {
    /* A tetrahedron, faces CCW from outside. */
    const char *path = write_model(state, "tet.obj",
                                   "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                   "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    ras_mesh *m = load_ok(path);
    assert_int_equal(m->triangle_count, 4);
    check_well_formed(m, "tet.obj");
    assert_false(m->has_normals_from_file);
    vec3s centre = {{0.25f, 0.25f, 0.25f}};
    check_outward_winding(m, centre, "tet.obj");
    for (size_t v = 0; v < m->vertex_count; v++) {
        vec3s out = glms_vec3_sub(m->positions[v], centre);
        if (!(glms_vec3_dot(out, m->normals[v]) > 0.0f))
            fail_msg("generated normal of vertex %zu points inward", v);
    }
    ras_mesh_destroy(m);
}

/* Normals and UVs from the file are kept (normalised); a zero normal is replaced by the face normal. */
static void test_mesh_load_obj_file_normals_and_uvs(void **state) {
    const char *path = write_model(state, "nuv.obj",
                                   "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                   "vt 0 0\nvt 1 0\nvt 0 1\n"
                                   "vn 0 0 2\nvn 0 0 0\n"
                                   "f 1/1/1 2/2/1 3/3/2\n");
    ras_mesh *m = load_ok(path);
    check_well_formed(m, "nuv.obj");
    assert_true(m->has_uv);
    assert_true(m->has_normals_from_file);
    for (size_t v = 0; v < m->vertex_count; v++) {
        assert_vec3_near(m->normals[v], (vec3s){{0, 0, 1}}, 1e-6f,
                         "file normal (0,0,2) normalised, or zero normal repaired from the face");
        vec3s p = m->positions[v];
        assert_true(fabsf(m->uvs[v].x - p.x) < 1e-6f && fabsf(m->uvs[v].y - p.y) < 1e-6f);
    }
    ras_mesh_destroy(m);
}

/* A face that names a vertex that does not exist is rejected with a message saying so. */
static void test_mesh_load_obj_bad_index_fails(void **state) {
    const char *path = write_model(state, "badindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    ras_error err = {{0}};
    ras_mesh *m = ras_mesh_load(path, &err);
    if (m) fail_msg("f 1 2 9 with 3 vertices loaded as %zu triangles; expected an error", m->triangle_count);
    if (!strstr(err.msg, "range") && !strstr(err.msg, "index"))
        fail_msg("error for an out-of-range index does not say so: \"%s\"", err.msg);
    if (!strstr(err.msg, path)) fail_msg("error does not name the file: \"%s\"", err.msg);
}

/* A missing file fails with a message that names the path. */
static void test_mesh_load_missing_file_names_path(void **state) {
    (void)state;
    const char *path = "/nonexistent/raster101/no_such_model.obj";
    ras_error err = {{0}};
    ras_mesh *m = ras_mesh_load(path, &err);
    assert_null(m);
    if (!strstr(err.msg, path)) fail_msg("error does not name the missing path: \"%s\"", err.msg);
    ras_mesh_load(path, NULL); /* a NULL err is allowed */
}

/* A file of garbage fails with a message rather than a crash or an empty mesh. */
static void test_mesh_load_garbage_fails(void **state) {
    const char *path = write_model(state, "garbage.obj", "this is not a model\n%%%% ~~~ \x01\x02\n");
    ras_error err = {{0}};
    assert_null(ras_mesh_load(path, &err));
    if (err.msg[0] == '\0') fail_msg("garbage file: no error message was set");
    const char *path2 = write_model(state, "garbage.xyz123", "\x7f\x45\x4c\x46 binary junk");
    err.msg[0] = '\0';
    assert_null(ras_mesh_load(path2, &err));
    if (!strstr(err.msg, path2)) fail_msg("unknown format: error does not name the file: \"%s\"", err.msg);
}

/* A file with only lines has no triangles and is refused. */
static void test_mesh_load_lines_only_fails(void **state) {
    const char *path = write_model(state, "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
    ras_error err = {{0}};
    assert_null(ras_mesh_load(path, &err));
    if (!strstr(err.msg, "triangle")) fail_msg("lines-only file: error does not mention triangles: \"%s\"", err.msg);
}

/* A NaN coordinate is refused instead of reaching the rasterizer. */
static void test_mesh_load_nan_position_fails(void **state) {
    const char *path = write_model(state, "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    ras_error err = {{0}};
    ras_mesh *m = ras_mesh_load(path, &err);
    if (m) {
        /* Should assimp ever parse "nan" as 0, the mesh must at least be finite. */
        check_well_formed(m, "nan.obj");
        ras_mesh_destroy(m);
        return;
    }
    if (!strstr(err.msg, "finite")) fail_msg("NaN position: error does not say why: \"%s\"", err.msg);
}

/* An ASCII PLY with a quad face and vertex colours loads as two coloured triangles. */
static void test_mesh_load_ply_with_colors(void **state) {
    const char *path = write_model(state, "quad.ply",
                                   "ply\nformat ascii 1.0\nelement vertex 4\n"
                                   "property float x\nproperty float y\nproperty float z\n"
                                   "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                   "0 0 0 255 0 0\n1 0 0 255 0 0\n1 1 0 255 0 0\n0 1 0 255 0 0\n"
                                   "4 0 1 2 3\n");
    ras_mesh *m = load_ok(path);
    assert_int_equal(m->triangle_count, 2);
    check_well_formed(m, "quad.ply");
    for (size_t v = 0; v < m->vertex_count; v++)
        assert_vec3_near(m->colors[v], (vec3s){{1, 0, 0}}, 1e-3f, "PLY vertex colour red");
    for (size_t t = 0; t < 2; t++)
        if (!(face_normal(m, t).z > 0.0f)) fail_msg("PLY triangle %zu lost its winding", t);
    ras_mesh_destroy(m);
}

/* An ASCII STL with two facets loads as two triangles with unit normals. */
static void test_mesh_load_stl(void **state) {
    const char *path = write_model(state, "two.stl",
                                   "solid two\n"
                                   "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n"
                                   "  vertex 1 1 0\n endloop\nendfacet\n"
                                   "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 1 0\n"
                                   "  vertex 0 1 0\n endloop\nendfacet\n"
                                   "endsolid two\n");
    ras_mesh *m = load_ok(path);
    assert_int_equal(m->triangle_count, 2);
    check_well_formed(m, "two.stl");
    check_normals_match_faces(m, 0.999f, "two.stl");
    ras_mesh_destroy(m);
}

/* Node transforms are applied to every instance, and a mirroring node keeps the winding outward. */
static void test_mesh_load_gltf_applies_node_transforms(void **state) {
    /* One triangle (0,0,0) (1,0,0) (0,1,0) used by two nodes: translated by
     * +10 in x, and mirrored in x (scale -1, 1, 1). */
    const char *path = write_model(
        state, "two_nodes.gltf",
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0,\"translation\":[10,0,0]},{\"mesh\":0,\"scale\":[-1,1,1]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"mode\":4}]}],"
        "\"buffers\":[{\"byteLength\":36,\"uri\":\"data:application/octet-stream;base64,"
        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}],"
        "\"accessors\":[{\"bufferView\":0,\"byteOffset\":0,\"componentType\":5126,\"count\":3,"
        "\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]}]}");
    ras_mesh *m = load_ok(path);
    assert_int_equal(m->triangle_count, 2);
    check_well_formed(m, "two_nodes.gltf");
    vec3s lo, hi;
    ras_mesh_bounds(m, &lo, &hi);
    assert_vec3_near(lo, (vec3s){{-1, 0, 0}}, 1e-6f, "bounds low: the mirrored copy reaches x = -1");
    assert_vec3_near(hi, (vec3s){{11, 1, 0}}, 1e-6f, "bounds high: the translated copy reaches x = 11");
    for (size_t t = 0; t < 2; t++)
        if (!(face_normal(m, t).z > 0.0f))
            fail_msg("instance %zu faces -z: a mirroring node transform must swap two corners", t);
    check_normals_match_faces(m, 0.999f, "two_nodes.gltf");
    ras_mesh_destroy(m);
}

/* ------------------------------------------------------------------------ */
/* Allocation guards                                                         */

/* Sizes that overflow size_t or 32-bit indices give NULL instead of a short allocation. */
static void test_mesh_create_guards_overflow(void **state) {
    (void)state;
    assert_null(ras_mesh_create(SIZE_MAX, 1));
    assert_null(ras_mesh_create(1, SIZE_MAX));
    assert_null(ras_mesh_create(1, SIZE_MAX / 3 + 1));
    assert_null(ras_mesh_create_uv_sphere(1.0f, INT_MAX, INT_MAX));
    assert_null(ras_mesh_create_plane(1.0f, INT_MAX));
    ras_mesh *empty = ras_mesh_create(0, 0);
    assert_non_null(empty);
    ras_mesh_destroy(empty);
    ras_mesh_destroy(NULL); /* allowed */
}

/* ------------------------------------------------------------------------ */
/* Built-in shapes                                                           */

/* The built-in triangle keeps its corners, has the face normal, the given colour and corner UVs. */
static void test_mesh_triangle_builtin(void **state) {
    (void)state;
    vec3s red = {{1, 0, 0}};
    ras_mesh *m = ras_mesh_create_triangle((vec3s){{0, 0, 0}}, (vec3s){{2, 0, 0}}, (vec3s){{0, 2, 0}}, red);
    check_well_formed(m, "triangle");
    assert_int_equal(m->triangle_count, 1);
    check_normals_match_faces(m, 0.9999f, "triangle");
    for (int i = 0; i < 3; i++) assert_vec3_near(m->colors[i], red, 0, "triangle colour");
    check_uv_in_unit_square(m, "triangle");
    ras_mesh_destroy(m);
    /* A degenerate triangle still gets unit, finite normals. */
    m = ras_mesh_create_triangle((vec3s){{1, 1, 1}}, (vec3s){{1, 1, 1}}, (vec3s){{1, 1, 1}}, red);
    check_well_formed(m, "degenerate triangle");
    ras_mesh_destroy(m);
}

/* The plane lies in xz, faces +y (normals and winding), spans [-s/2, s/2] and UVs cover [0,1]². */
static void test_mesh_plane_counts_normals_uvs(void **state) {
    (void)state;
    ras_mesh *m = ras_mesh_create_plane(4.0f, 3);
    check_well_formed(m, "plane");
    assert_int_equal(m->vertex_count, 16);
    assert_int_equal(m->triangle_count, 18);
    check_uv_in_unit_square(m, "plane");
    for (size_t v = 0; v < m->vertex_count; v++)
        assert_vec3_near(m->normals[v], (vec3s){{0, 1, 0}}, 0, "plane normal");
    for (size_t t = 0; t < m->triangle_count; t++)
        if (!(face_normal(m, t).y > 0.0f)) fail_msg("plane triangle %zu faces down (clockwise from above)", t);
    vec3s lo, hi;
    ras_mesh_bounds(m, &lo, &hi);
    assert_vec3_near(lo, (vec3s){{-2, 0, -2}}, 1e-6f, "plane bounds low");
    assert_vec3_near(hi, (vec3s){{2, 0, 2}}, 1e-6f, "plane bounds high");
    float umin = 1, umax = 0, vmin = 1, vmax = 0;
    for (size_t v = 0; v < m->vertex_count; v++) {
        umin = fminf(umin, m->uvs[v].x), umax = fmaxf(umax, m->uvs[v].x);
        vmin = fminf(vmin, m->uvs[v].y), vmax = fmaxf(vmax, m->uvs[v].y);
    }
    if (umin != 0 || umax != 1 || vmin != 0 || vmax != 1)
        fail_msg("plane uv spans [%g,%g]x[%g,%g], expected [0,1]x[0,1]", (double)umin, (double)umax,
                 (double)vmin, (double)vmax);
    ras_mesh_destroy(m);
}

/* The cube has 24 vertices, 12 outward CCW triangles and flat normals equal to the face normals. */
static void test_mesh_cube_counts_and_flat_normals(void **state) {
    (void)state;
    ras_mesh *m = ras_mesh_create_cube(2.0f);
    check_well_formed(m, "cube");
    assert_int_equal(m->vertex_count, 24);
    assert_int_equal(m->triangle_count, 12);
    check_outward_winding(m, glms_vec3_zero(), "cube");
    check_normals_match_faces(m, 0.9999f, "cube");
    check_uv_in_unit_square(m, "cube");
    vec3s lo, hi;
    ras_mesh_bounds(m, &lo, &hi);
    assert_vec3_near(lo, (vec3s){{-1, -1, -1}}, 1e-6f, "cube of size 2: bounds low");
    assert_vec3_near(hi, (vec3s){{1, 1, 1}}, 1e-6f, "cube of size 2: bounds high");
    ras_mesh_destroy(m);
}

/* The sphere has the expected counts, points on the radius, outward winding and stored normals along the faces. */
static void test_mesh_sphere_outward_and_normals(void **state) {
    (void)state;
    const int stacks = 8, slices = 12;
    ras_mesh *m = ras_mesh_create_uv_sphere(1.5f, stacks, slices);
    check_well_formed(m, "sphere");
    assert_int_equal(m->vertex_count, (size_t)(stacks + 1) * (slices + 1));
    /* Two triangles per quad, minus one per quad in the two pole stacks. */
    assert_int_equal(m->triangle_count, (size_t)2 * slices * (stacks - 1));
    check_outward_winding(m, glms_vec3_zero(), "sphere");
    check_normals_match_faces(m, 0.8f, "sphere");
    check_uv_in_unit_square(m, "sphere");
    for (size_t v = 0; v < m->vertex_count; v++) {
        float r = glms_vec3_norm(m->positions[v]);
        if (fabsf(r - 1.5f) > 1e-5f) fail_msg("sphere vertex %zu at radius %g, expected 1.5", v, (double)r);
        vec3s radial = glms_vec3_normalize(m->positions[v]);
        assert_vec3_near(m->normals[v], radial, 1e-5f, "sphere normal is the radial direction");
    }
    ras_mesh_destroy(m);
}

/* The torus winds outward from its tube and its normals point out of the tube. */
static void test_mesh_torus_outward(void **state) {
    (void)state;
    const float R = 1.0f, r = 0.3f;
    ras_mesh *m = ras_mesh_create_torus(R, r, 16, 8);
    check_well_formed(m, "torus");
    assert_int_equal(m->vertex_count, 17 * 9);
    assert_int_equal(m->triangle_count, 2 * 16 * 8);
    check_uv_in_unit_square(m, "torus");
    check_normals_match_faces(m, 0.7f, "torus");
    for (size_t t = 0; t < m->triangle_count; t++) {
        vec3s c = tri_centroid(m, t);
        /* Nearest point of the tube's centre circle. */
        float len = sqrtf(c.x * c.x + c.z * c.z);
        vec3s axis_pt = {{R * c.x / len, 0.0f, R * c.z / len}};
        if (!(glms_vec3_dot(face_normal(m, t), glms_vec3_sub(c, axis_pt)) > 0.0f))
            fail_msg("torus triangle %zu faces into the tube (clockwise from outside)", t);
    }
    ras_mesh_destroy(m);
}

/* Every built-in shape, at the smallest and silly parameters, is well formed (no NaN, unit normals). */
static void test_mesh_builtins_well_formed_at_extremes(void **state) {
    (void)state;
    ras_mesh *shapes[] = {
        ras_mesh_create_plane(1.0f, 0),        ras_mesh_create_plane(1.0f, 1),
        ras_mesh_create_uv_sphere(1.0f, 0, 0), ras_mesh_create_uv_sphere(1.0f, 2, 3),
        ras_mesh_create_torus(1.0f, 0.5f, 0, 0), ras_mesh_create_teapot(0),
        ras_mesh_create_teapot(1),
    };
    /* Fewer than 2 teapot divisions would make flat triangles: 2 is the minimum. */
    assert_int_equal(shapes[5]->triangle_count, 64 * 2 * 2 - 8 * 2);
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++) {
        char what[32];
        snprintf(what, sizeof what, "shape #%zu", i);
        check_well_formed(shapes[i], what);
        check_uv_in_unit_square(shapes[i], what);
        if (shapes[i]->triangle_count == 0) fail_msg("%s has no triangles", what);
        for (size_t t = 0; t < shapes[i]->triangle_count; t++)
            if (!(glms_vec3_norm(face_normal(shapes[i], t)) > 0.0f))
                fail_msg("%s: triangle %zu has zero area", what, t);
        ras_mesh_destroy(shapes[i]);
    }
}

/* The teapot has 32 patches x 2n² triangles minus the n dropped at each of the 8 pole edges. */
static void test_mesh_teapot_triangle_count(void **state) {
    (void)state;
    for (int n = 2; n <= 16; n *= 2) {
        ras_mesh *m = ras_mesh_create_teapot(n);
        assert_non_null(m);
        size_t want = (size_t)(64 * n * n - 8 * n);
        if (m->triangle_count != want)
            fail_msg("teapot(%d): %zu triangles, expected 64n^2 - 8n = %zu", n, m->triangle_count, want);
        assert_int_equal(m->vertex_count, (size_t)32 * (n + 1) * (n + 1));
        ras_mesh_destroy(m);
    }
}

/* Teapot normals are finite and unit (also at the lid and bottom poles) and agree with the winding. */
static void test_mesh_teapot_normals_finite_and_outward(void **state) {
    (void)state;
    ras_mesh *m = ras_mesh_create_teapot(8);
    check_well_formed(m, "teapot");
    check_uv_in_unit_square(m, "teapot");
    /* Bézier normals vary inside a triangle, so compare loosely: the same half-space. */
    check_normals_match_faces(m, 0.0f, "teapot");
    /* The poles: the knob's top (the highest point) and the bottom's centre
     * below it, where one patch derivative vanishes. Normals straight up and down. */
    size_t top = 0;
    for (size_t v = 1; v < m->vertex_count; v++)
        if (m->positions[v].y > m->positions[top].y) top = v;
    vec3s axis = m->positions[top];
    int poles_seen = 0;
    for (size_t v = 0; v < m->vertex_count; v++) {
        vec3s p = m->positions[v];
        if (fabsf(p.x - axis.x) > 1e-4f || fabsf(p.z - axis.z) > 1e-4f) continue;
        bool is_top = fabsf(p.y - axis.y) < 1e-5f, is_bottom = p.y < axis.y - 1.0f;
        if (!is_top && !is_bottom) continue;
        poles_seen++;
        float want = is_top ? 1.0f : -1.0f;
        if (!(m->normals[v].y * want > 0.99f))
            fail_msg("%s pole vertex %zu has normal (%g, %g, %g), expected (0, %g, 0)",
                     is_top ? "lid" : "bottom", v, (double)m->normals[v].x, (double)m->normals[v].y,
                     (double)m->normals[v].z, (double)want);
    }
    if (poles_seen < 16) fail_msg("found only %d pole vertices on the teapot's axis, expected 4 patches x 9 at each pole", poles_seen);
    ras_mesh_destroy(m);
}

/* The teapot is centred and its longest side is 2 (it fits [-1,1]³), spout towards +x. */
static void test_mesh_teapot_fits_unit_box(void **state) {
    (void)state;
    ras_mesh *m = ras_mesh_create_teapot(6);
    vec3s lo, hi;
    ras_mesh_bounds(m, &lo, &hi);
    vec3s centre = glms_vec3_scale(glms_vec3_add(lo, hi), 0.5f);
    assert_vec3_near(centre, glms_vec3_zero(), 1e-5f, "teapot bounding-box centre");
    float largest = glms_vec3_max(glms_vec3_sub(hi, lo));
    if (fabsf(largest - 2.0f) > 1e-5f) fail_msg("teapot longest side %g, expected 2", (double)largest);
    if (!(hi.x - lo.x > hi.y - lo.y && hi.x - lo.x > hi.z - lo.z))
        fail_msg("teapot is not lying along x (spout to handle); y must be up");
    ras_mesh_destroy(m);
}

/* The fit matrix moves the bounding-box centre to the origin and the longest side to `size`. */
static void test_mesh_fit_matrix_maps_bbox(void **state) {
    (void)state;
    ras_mesh *m = ras_mesh_create(2, 0);
    m->positions[0] = (vec3s){{1, 2, 5}};
    m->positions[1] = (vec3s){{3, 4, 11}};
    mat4s fit = ras_mesh_fit_matrix(m, 2.0f);
    /* Longest side z = 6 → scale 1/3, centre (2, 3, 8). */
    assert_vec3_near(glms_mat4_mulv3(fit, m->positions[0], 1.0f), (vec3s){{-1.0f / 3, -1.0f / 3, -1}}, 1e-6f,
                     "low corner after fit");
    assert_vec3_near(glms_mat4_mulv3(fit, m->positions[1], 1.0f), (vec3s){{1.0f / 3, 1.0f / 3, 1}}, 1e-6f,
                     "high corner after fit");
    assert_vec3_near(glms_mat4_mulv3(fit, (vec3s){{2, 3, 8}}, 1.0f), glms_vec3_zero(), 1e-6f,
                     "bbox centre goes to the origin");
    ras_mesh_destroy(m);
}

/* A mesh with no extent (one point) is only translated: scale 1, never Inf. */
static void test_mesh_fit_matrix_degenerate_scale_one(void **state) {
    (void)state;
    ras_mesh *m = ras_mesh_create(3, 0);
    for (int i = 0; i < 3; i++) m->positions[i] = (vec3s){{5, -2, 7}};
    mat4s fit = ras_mesh_fit_matrix(m, 2.0f);
    mat4s want = ras_mat4_rows(1, 0, 0, -5, 0, 1, 0, 2, 0, 0, 1, -7, 0, 0, 0, 1);
    if (!ras_mat4_near(fit, want, 1e-6f)) {
        char buf[256];
        ras_mat4_format(fit, buf, sizeof buf);
        fail_msg("fit of a single point should be a pure translation, got\n%s", buf);
    }
    ras_mesh_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mesh_load_obj_triangle),
        cmocka_unit_test(test_mesh_load_obj_quad_two_triangles),
        cmocka_unit_test(test_mesh_load_obj_pentagon_three_triangles),
        cmocka_unit_test(test_mesh_load_obj_missing_normals_generated),
        cmocka_unit_test(test_mesh_load_obj_file_normals_and_uvs),
        cmocka_unit_test(test_mesh_load_obj_bad_index_fails),
        cmocka_unit_test(test_mesh_load_missing_file_names_path),
        cmocka_unit_test(test_mesh_load_garbage_fails),
        cmocka_unit_test(test_mesh_load_lines_only_fails),
        cmocka_unit_test(test_mesh_load_nan_position_fails),
        cmocka_unit_test(test_mesh_load_ply_with_colors),
        cmocka_unit_test(test_mesh_load_stl),
        cmocka_unit_test(test_mesh_load_gltf_applies_node_transforms),
        cmocka_unit_test(test_mesh_create_guards_overflow),
        cmocka_unit_test(test_mesh_triangle_builtin),
        cmocka_unit_test(test_mesh_plane_counts_normals_uvs),
        cmocka_unit_test(test_mesh_cube_counts_and_flat_normals),
        cmocka_unit_test(test_mesh_sphere_outward_and_normals),
        cmocka_unit_test(test_mesh_torus_outward),
        cmocka_unit_test(test_mesh_builtins_well_formed_at_extremes),
        cmocka_unit_test(test_mesh_teapot_triangle_count),
        cmocka_unit_test(test_mesh_teapot_normals_finite_and_outward),
        cmocka_unit_test(test_mesh_teapot_fits_unit_box),
        cmocka_unit_test(test_mesh_fit_matrix_maps_bbox),
        cmocka_unit_test(test_mesh_fit_matrix_degenerate_scale_one),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}

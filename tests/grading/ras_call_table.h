/* ras_call_table.h — the student functions that grading records in the
 * sandboxed worker and answers in the trusted replay (tests/grading/ras_call.c,
 * ras_call.h): one row each. A graded function is added by adding its row.
 *
 * Everything is generated from these rows: the functions' numbers and names in
 * the record and the messages, each __wrap_NAME of ras_call.c (record and
 * replay), and the -Wl,--wrap=NAME list of each test_hwN_worker/_replay
 * (tests/grading/CMakeLists.txt reads the hw and the name that open each row).
 * A row's signature is checked at compile time against the header's declaration.
 * An assignment's first row makes it graded: tests/grading/CMakeLists.txt
 * then builds its worker and replay from its CMake declaration
 * (raster101_assignment: its folder's headers, what it DEPENDS on) and nothing
 * else needs an edit; a new kind of input or output needs its IN_/OUT_ macro
 * in ras_call.c.
 *
 *   FN(hw, name, returns, (parameters), (arguments), (inputs), (outputs))
 *       returns a value, recorded whole;
 *   FN_VOID(hw, name, (parameters), (arguments), (inputs), (outputs))
 *       returns nothing;
 *   FN_CUSTOM(hw, name, returns, (parameters))
 *       its wrapper is written by hand in ras_call.c (rasterize_triangle:
 *       the fragments it shades through ctx->shade are recorded one by one and
 *       shaded again in the replay).
 * hw: N of the assignment hwN whose header declares it (a build for an
 * assignment wraps the rows of that assignment and of every assignment it
 * builds on, its DEPENDS). (arguments): the parameters' names, in order.
 * (inputs): what the call's result depends on, hashed so that the replay
 * knows the record answers this very call (never a pointer's value, which
 * differs between the two processes; the kinds are ras_call.c's macros):
 *   IN(v)                 the bytes of v
 *   IN_ARRAY(p, n)        the n elements at p, if p
 *   IN_TRIANGLE(t)        a ras_triangle's fields
 *   IN_FB_SIZE(fb)        a framebuffer's width, height and samples, if fb
 *   IN_PAYLOAD(p)         a fragment_shader_payload's values (not its pointers)
 *   IN_TEXTURE(tex)       a texture's size and level count
 *   IN_RENDER_OPTIONS(o)  hw3_render's shader, filter and angle, if o
 *   IN_IMAGE_SIZE(img)    an image's width and height, if img
 * (outputs): what else the call writes that the test sees (recorded whole):
 *   OUT(p)                *p, if p
 *   OUT_COUNTERS(p)       *p->counters of a shader payload, if p
 *   OUT_IMAGE(img)        an image's pixels, if img
 *   OUT_ERROR(err)        a ras_error; its message is cut at its last byte
 *                         after the call (the record is untrusted text)
 */
#ifndef RAS_CALL_TABLE_H
#define RAS_CALL_TABLE_H

/* clang-format off */
#define RAS_CALL_TABLE(FN, FN_VOID, FN_CUSTOM)                                                     \
    FN(1, get_model_matrix, mat4s, (float angle), (angle), (IN(angle)), ())                       \
    FN(1, get_projection_matrix, mat4s, (float fov, float aspect, float n, float f),              \
       (fov, aspect, n, f), (IN(fov) IN(aspect) IN(n) IN(f)), ())                                 \
    FN(1, get_rotation, mat4s, (vec3s axis, float angle), (axis, angle),                          \
       (IN(axis) IN(angle)), ())                                                                  \
    FN(2, inside_triangle, bool, (float x, float y, const ras_triangle *t), (x, y, t),            \
       (IN(x) IN(y) IN_TRIANGLE(t)), ())                                                          \
    FN(2, compute_barycentric_2d, bool,                                                           \
       (float x, float y, const ras_triangle *t, vec3s *bary), (x, y, t, bary),                   \
       (IN(x) IN(y) IN_TRIANGLE(t)), (OUT(bary)))                                                 \
    FN_CUSTOM(2, rasterize_triangle, void, (const ras_triangle *t, const ras_raster_ctx *ctx))    \
    FN(2, resolve_pixel, vec3s, (const ras_framebuffer *fb, int x, int y), (fb, x, y),            \
       (IN(x) IN(y) IN_FB_SIZE(fb)), ())                                                          \
    FN(3, perspective_correct_barycentric, vec3s, (const ras_triangle *t, vec3s bary),            \
       (t, bary), (IN_TRIANGLE(t) IN(bary)), ())                                                  \
    FN(3, interpolate_vec3, vec3s,                                                                \
       (const ras_triangle *t, vec3s bary, const vec3s attr[3], bool perspective),                \
       (t, bary, attr, perspective),                                                              \
       (IN_TRIANGLE(t) IN(bary) IN_ARRAY(attr, 3) IN(perspective)), ())                           \
    FN(3, interpolate_vec2, vec2s,                                                                \
       (const ras_triangle *t, vec3s bary, const vec2s attr[3], bool perspective),                \
       (t, bary, attr, perspective),                                                              \
       (IN_TRIANGLE(t) IN(bary) IN_ARRAY(attr, 3) IN(perspective)), ())                           \
    FN(3, normal_fragment_shader, vec3s, (const fragment_shader_payload *payload), (payload),     \
       (IN_PAYLOAD(payload)), (OUT_COUNTERS(payload)))                                            \
    FN(3, blinn_phong_lighting, vec3s,                                                            \
       (const fragment_shader_payload *payload, vec3s kd, vec3s point, vec3s normal),             \
       (payload, kd, point, normal), (IN_PAYLOAD(payload) IN(kd) IN(point) IN(normal)),           \
       (OUT_COUNTERS(payload)))                                                                   \
    FN(3, phong_fragment_shader, vec3s, (const fragment_shader_payload *payload), (payload),      \
       (IN_PAYLOAD(payload)), (OUT_COUNTERS(payload)))                                            \
    FN(3, texture_fragment_shader, vec3s, (const fragment_shader_payload *payload), (payload),    \
       (IN_PAYLOAD(payload)), (OUT_COUNTERS(payload)))                                            \
    FN_VOID(3, tangent_frame, (vec3s n, vec3s *t, vec3s *b), (n, t, b), (IN(n)),                  \
            (OUT(t) OUT(b)))                                                                      \
    FN(3, bump_normal, vec3s, (const fragment_shader_payload *payload), (payload),                \
       (IN_PAYLOAD(payload)), (OUT_COUNTERS(payload)))                                            \
    FN(3, bump_fragment_shader, vec3s, (const fragment_shader_payload *payload), (payload),       \
       (IN_PAYLOAD(payload)), (OUT_COUNTERS(payload)))                                            \
    FN(3, displacement_fragment_shader, vec3s, (const fragment_shader_payload *payload),          \
       (payload), (IN_PAYLOAD(payload)), (OUT_COUNTERS(payload)))                                 \
    FN(3, texture_sample_bilinear, vec3s, (const ras_texture *tex, float u, float v),             \
       (tex, u, v), (IN_TEXTURE(tex) IN(u) IN(v)), ())                                            \
    FN(3, texture_sample_trilinear, vec3s, (const ras_texture *tex, vec2s uv, vec2s dx, vec2s dy),\
       (tex, uv, dx, dy), (IN_TEXTURE(tex) IN(uv) IN(dx) IN(dy)), ())                             \
    FN(3, hw3_render, bool,                                                                       \
       (const ras_scene *scene, ras_scene_assets *assets, const hw3_render_options *opt,          \
        ras_image *out, ras_counters *stats, ras_error *err),                                     \
       (scene, assets, opt, out, stats, err), (IN_RENDER_OPTIONS(opt) IN_IMAGE_SIZE(out)),        \
       (OUT_IMAGE(out) OUT(stats) OUT_ERROR(err)))
/* clang-format on */

#endif

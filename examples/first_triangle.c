/* first_triangle.c — the core in one page: one triangle through the pipeline
 * into a PNG, with no scene file, no window and no shell.
 *
 *   build/bin/first_triangle [out.png]      (default: first_triangle.png)
 *
 * The frame is the whole lesson: a mesh, the three matrices (hw1's
 * projection), the pipeline's stages (common/README.md: vertex → clip →
 * setup → hw2's rasterize_triangle → colour), the image. With the handout's
 * stubs the rasterizer draws nothing yet and says so; with yours, a triangle.
 */
#include "ras_image.h"
#include "ras_mesh.h"
#include "ras_pipeline.h"
#include "rasterizer.h" /* hw2: rasterize_triangle */
#include "transform.h"  /* hw1: get_projection_matrix */

#include <stdio.h>

int main(int argc, char **argv) {
    const char *out = argc > 1 ? argv[1] : "first_triangle.png";
    ras_error err = {0};
    /* hw2's green triangle, 7 units in front of the eye (eye at z = +5, looking down −z). */
    ras_mesh *mesh = ras_mesh_create_triangle((vec3s){{2, 0, -2}}, (vec3s){{0, 2, -2}},
                                              (vec3s){{-2, 0, -2}}, (vec3s){{0.85f, 0.93f, 0.73f}});
    ras_pipeline_config cfg = {.width = 400, .height = 400, .clear_color = {{0, 0, 0}},
                               .varyings = RAS_VARYING_COLOR, .rasterize = rasterize_triangle};
    ras_pipeline *p = mesh ? ras_pipeline_create(&cfg, &err) : NULL;
    ras_image *image = p ? ras_image_create(cfg.width, cfg.height, &err) : NULL;
    bool ok = image != NULL;
    if (ok) {
        ras_pipeline_begin_frame(p);
        mat4s model = glms_mat4_identity(), view = ras_view_matrix_eye((vec3s){{0, 0, 5}});
        mat4s projection = get_projection_matrix(45, 1, 0.1f, 50);
        ok = ras_pipeline_draw_mesh(p, mesh, model, view, projection, &err);
        if (ok) ras_pipeline_end_frame(p, image);
        ok = ok && ras_image_save(image, out, &err);
    }
    if (ok)
        printf("first_triangle: wrote %s: %llu triangle(s) rasterized, %llu pixels covered\n", out,
               (unsigned long long)p->counters.triangles_rasterized,
               (unsigned long long)p->counters.samples_covered);
    else
        fprintf(stderr, "first_triangle: %s\n", err.msg[0] ? err.msg : "out of memory");
    ras_image_destroy(image);
    ras_pipeline_destroy(p);
    ras_mesh_destroy(mesh);
    return ok ? 0 : 1;
}

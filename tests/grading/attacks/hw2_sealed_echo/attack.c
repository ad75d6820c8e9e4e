#define compute_barycentric_2d atk_stub_compute_barycentric_2d
/* @STUB@ today's hw2 TODO stub (hw2_rasterize/rasterizer.c), written here by _lib/assemble */
#undef compute_barycentric_2d
#include "transform.h" /* get_model_matrix: the reference's, in a sealed run */
#include <stdint.h>
#include <string.h>
/* A sealed-run value echo: in a run linked with hw1's reference (hw2 graded on
 * its own code), the barycentrics returned carry a marker (12345.678) and
 * bytes of the reference get_model_matrix's machine code, so a grader that
 * quotes "got (...)" hands them out (issue 24: 9 bytes per test). */
bool compute_barycentric_2d(float x, float y, const ras_triangle *t, vec3s *bary) {
    (void)x; (void)y; (void)t;
    unsigned char code[8];
    memcpy(code, (const void *)(uintptr_t)&get_model_matrix, sizeof code);
    float b, c;
    memcpy(&b, code, 4);
    memcpy(&c, code + 4, 4);
    *bary = (vec3s){{12345.678f, b, c}};
    return true;
}

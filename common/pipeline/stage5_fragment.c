/* stage5_fragment.c — see stage5_fragment.h. */
#include "stage5_fragment.h"

vec3s ras_shade_vertex_color(const ras_triangle *t, const ras_fragment *f, void *user) {
    (void)user;
    vec3s c = glms_vec3_scale(t->color[0], f->bary.x);
    c = glms_vec3_muladds(t->color[1], f->bary.y, c);
    return glms_vec3_muladds(t->color[2], f->bary.z, c);
}

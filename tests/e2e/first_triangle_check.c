/* first_triangle_check.c — holds examples/first_triangle.c to hand-worked
 * numbers, so the example stays a working program and not only a page:
 *
 *   first_triangle_check OUT.png COVERED
 *
 * OUT.png is what the example wrote, COVERED the pixel count it printed. The
 * triangle (±2, 0) – (0, 2) at z = −2 seen from z = +5 lies 7 units away; a
 * 45° field of view maps 7·tan 22.5° = 2.8995 units to the 200 pixels from
 * the centre to the edge, so its corners land 137.96 pixels left, right and
 * above the centre: an area of 137.96² = 19 033 pixels. Every pixel is either
 * the triangle's colour or black; the coloured ones number COVERED, within
 * one perimeter (666 pixels) of that area, and sit above the centre row.
 */
#include "ras_image.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int near_byte(float got, float want) {
    return fabsf(got - want) <= 0.5f / 255.0f + 1e-6f;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: first_triangle_check OUT.png COVERED\n");
        return 2;
    }
    ras_error err = {0};
    ras_image *img = ras_image_load(argv[1], &err);
    if (!img) {
        fprintf(stderr, "first_triangle_check: %s\n", err.msg);
        return 1;
    }
    const double half = 200.0 * 2.0 / (7.0 * tan(22.5 * M_PI / 180.0)); /* 137.96 */
    const double area = half * half, perimeter = 2 * half + 2 * sqrt(2.0) * half;
    const vec3s colour = {{0.85f, 0.93f, 0.73f}};
    long coloured = 0, stray = 0, below = 0;
    for (int row = 0; row < img->height; row++)
        for (int col = 0; col < img->width; col++) {
            vec3s c = ras_image_get(img, col, row);
            if (near_byte(c.x, colour.x) && near_byte(c.y, colour.y) && near_byte(c.z, colour.z)) {
                coloured++;
                below += row > 200;
            } else if (c.x != 0 || c.y != 0 || c.z != 0) {
                stray++;
            }
        }
    int fails = 0;
    if (img->width != 400 || img->height != 400)
        fails += fprintf(stderr, "FAIL: expected a 400x400 image, got %dx%d\n", img->width,
                         img->height) > 0;
    if (fabs((double)coloured - area) > perimeter)
        fails += fprintf(stderr, "FAIL: expected %.0f ± %.0f pixels of the triangle's colour, got %ld\n",
                         area, perimeter, coloured) > 0;
    if (coloured != atol(argv[2]))
        fails += fprintf(stderr, "FAIL: the example printed %s pixels covered, the image has %ld\n",
                         argv[2], coloured) > 0;
    if (stray || below)
        fails += fprintf(stderr, "FAIL: %ld pixels neither the colour nor black, %ld coloured below the "
                         "centre row (expected none: the triangle points up)\n", stray, below) > 0;
    if (!fails) printf("first_triangle_check: ok: %ld pixels (hand-worked %.0f)\n", coloured, area);
    ras_image_destroy(img);
    return fails ? 1 : 0;
}

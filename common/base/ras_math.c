/* ras_math.c — see ras_math.h. */
#include "ras_math.h"

#include <math.h>  /* fabsf, isfinite */
#include <stdio.h> /* snprintf */

mat4s ras_mat4_rows(float a00, float a01, float a02, float a03,
                    float a10, float a11, float a12, float a13,
                    float a20, float a21, float a22, float a23,
                    float a30, float a31, float a32, float a33) {
    mat4s m;
    const float rows[4][4] = {{a00, a01, a02, a03},
                              {a10, a11, a12, a13},
                              {a20, a21, a22, a23},
                              {a30, a31, a32, a33}};
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            m.raw[c][r] = rows[r][c];
    return m;
}

mat4s ras_mat4_mul(mat4s a, mat4s b) {
    mat4s m;
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            m.raw[c][r] = ((a.raw[0][r] * b.raw[c][0] + a.raw[1][r] * b.raw[c][1]) +
                           a.raw[2][r] * b.raw[c][2]) +
                          a.raw[3][r] * b.raw[c][3];
    return m;
}

float ras_mat4_max_diff(mat4s a, mat4s b) {
    float worst = 0.0f;
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            float d = fabsf(a.raw[c][r] - b.raw[c][r]);
            if (!(d <= worst)) /* also catches NaN */
                worst = isnan(d) ? INFINITY : d;
        }
    return worst;
}

bool ras_mat4_near(mat4s a, mat4s b, float tol) { return ras_mat4_max_diff(a, b) <= tol; }

void ras_mat4_format(mat4s m, char *buf, int size) {
    int n = 0;
    for (int r = 0; r < 4 && n < size; r++)
        n += snprintf(buf + n, (size_t)(size - n), "  [%9.4f %9.4f %9.4f %9.4f]\n",
                      m.raw[0][r], m.raw[1][r], m.raw[2][r], m.raw[3][r]);
}


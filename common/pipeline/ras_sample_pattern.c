/* ras_sample_pattern.c — see ras_sample_pattern.h. */
#include "ras_sample_pattern.h"

/* D3D11 / Vulkan standard sample locations, 1/16 px from the centre. */
static const signed char standard2[2][2] = {{4, 4}, {-4, -4}};
static const signed char standard4[4][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
static const signed char standard8[8][2] = {{1, -3}, {-1, 3}, {5, 1},  {-3, -5},
                                            {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
static const signed char standard16[16][2] = {
    {1, 1},  {-1, -3}, {-3, 2},  {4, -1},  {-5, -2}, {2, 5},   {5, 3},  {3, -5},
    {-2, 6}, {0, -7},  {-4, -6}, {-6, 4},  {-8, 0},  {7, -4},  {6, 7},  {-7, -8}};

ras_sample_pattern ras_sample_pattern_center(void) {
    ras_sample_pattern p = {.kind = RAS_PATTERN_ORDERED, .count = 1};
    p.offsets[0] = (vec2s){{0.5f, 0.5f}};
    return p;
}

static void fill_standard(ras_sample_pattern *p, const signed char (*table)[2], int n) {
    p->count = n;
    for (int i = 0; i < n; i++)
        p->offsets[i] = (vec2s){{0.5f + table[i][0] / 16.0f, 0.5f + table[i][1] / 16.0f}};
}

bool ras_sample_pattern_make(ras_pattern_kind kind, int count, ras_sample_pattern *out,
                             ras_error *err) {
    ras_sample_pattern p = {.kind = kind};
    if (kind == RAS_PATTERN_ORDERED) {
        int n = count == 1 ? 1 : count == 4 ? 2 : count == 16 ? 4 : count == 64 ? 8 : 0;
        if (!n)
            return ras_error_set(err,
                                 "the ordered grid has no %d-sample version: expected 1, 4 "
                                 "(2x2), 16 (4x4) or 64 (8x8) samples",
                                 count);
        p.count = n * n;
        /* Row-major from the bottom row, left to right. */
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++)
                p.offsets[j * n + i] = (vec2s){{(i + 0.5f) / n, (j + 0.5f) / n}};
    } else {
        switch (count) {
        case 1: p = ras_sample_pattern_center(); p.kind = kind; break;
        case 2: fill_standard(&p, standard2, 2); break;
        case 4: fill_standard(&p, standard4, 4); break;
        case 8: fill_standard(&p, standard8, 8); break;
        case 16: fill_standard(&p, standard16, 16); break;
        default:
            return ras_error_set(err,
                                 "the standard pattern has no %d-sample version: expected 1, "
                                 "2, 4, 8 or 16 samples",
                                 count);
        }
    }
    *out = p;
    return true;
}

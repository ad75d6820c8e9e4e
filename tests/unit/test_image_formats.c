/* test_image_formats.c — image files read by content, bounded before they
 * decode (common/io/ras_image.h, ras_jpeg.h): the header sizes the decoders
 * would find (junk before a JPEG frame, BigTIFF, OS/2 BMP), the formats
 * refused, the JPEG scan and time limits, and libjpeg's pixels against
 * OpenCV's decode of the same bytes (the decoder this one replaced).
 */
#include "cv_bridge.h"
#include "ras_dump.h"
#include "ras_image.h"
#include "ras_jpeg.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>
#include <fcntl.h>
#include <jpeglib.h>

/* A JPEG of a w x h gradient made with libjpeg (components: 1 grey, 3 YCbCr,
 * 4 CMYK), progressive or not; malloc'ed, *len its size. */
static uint8_t *make_jpeg(int w, int h, int components, bool progressive, size_t *len) {
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    unsigned char *out = NULL;
    unsigned long out_len = 0;
    jpeg_mem_dest(&c, &out, &out_len);
    c.image_width = (JDIMENSION)w;
    c.image_height = (JDIMENSION)h;
    c.input_components = components;
    c.in_color_space = components == 1 ? JCS_GRAYSCALE : components == 3 ? JCS_RGB : JCS_CMYK;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 90, TRUE);
    if (progressive) jpeg_simple_progression(&c);
    jpeg_start_compress(&c, TRUE);
    unsigned char *row = malloc((size_t)w * (size_t)components);
    while (c.next_scanline < c.image_height) {
        for (int x = 0; x < w; x++)
            for (int k = 0; k < components; k++)
                row[x * components + k] =
                    (unsigned char)((x * 255 / w + (int)c.next_scanline * 3 + k * 70) & 255);
        jpeg_write_scanlines(&c, &row, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    free(row);
    uint8_t *copy = malloc(out_len);
    memcpy(copy, out, out_len);
    free(out);
    *len = out_len;
    return copy;
}

/* Inserts `n` bytes at offset `at`; returns the new buffer (frees the old). */
static uint8_t *insert(uint8_t *d, size_t *len, size_t at, const void *bytes, size_t n) {
    uint8_t *o = malloc(*len + n);
    memcpy(o, d, at);
    memcpy(o + at, bytes, n);
    memcpy(o + at + n, d + at, *len - at);
    free(d);
    *len += n;
    return o;
}

/* Offset of the first marker `m` (FF m) in a JPEG's header part. */
static size_t marker_at(const uint8_t *d, size_t len, uint8_t m) {
    for (size_t i = 2; i + 1 < len; i++)
        if (d[i] == 0xFF && d[i + 1] == m) return i;
    return 0;
}

static void write_file(const char *path, const uint8_t *d, size_t len) {
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(d, 1, len, f), len);
    assert_int_equal(fclose(f), 0);
}

/* libjpeg here gives byte for byte what OpenCV's imdecode gave: baseline,
 * progressive, grey, CMYK, and each EXIF orientation (a transpose and flips). */
static void test_jpeg_pixels_match_opencv(void **state) {
    (void)state;
    static const struct {
        int components;
        bool progressive;
        int orientation; /* 0: no EXIF */
    } cases[] = {{3, false, 0}, {3, true, 0}, {1, false, 0}, {4, false, 0}, {3, false, 2},
                 {3, false, 3}, {3, false, 5}, {3, false, 6}, {3, true, 8}};
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        size_t len = 0;
        uint8_t *jpg = make_jpeg(37, 23, cases[k].components, cases[k].progressive, &len);
        if (cases[k].orientation) {
            /* APP1: "Exif\0\0", a little-endian TIFF header, IFD0 with the
             * orientation tag (0x0112, SHORT, 1). */
            uint8_t app1[] = {0xFF, 0xE1, 0, 34, 'E', 'x', 'i', 'f', 0, 0, 'I', 'I', 42, 0, 8, 0,
                              0, 0, 1, 0, 0x12, 0x01, 3, 0, 1, 0, 0, 0,
                              (uint8_t)cases[k].orientation, 0, 0, 0, 0, 0, 0, 0};
            jpg = insert(jpg, &len, 2, app1, sizeof app1);
        }
        int w = 0, h = 0, cw = 0, ch = 0;
        char msg[512] = "", cmsg[512] = "";
        ras_jpeg_limits lim = {0};
        uint8_t *mine = ras_jpeg_decode_rgb8(jpg, len, &lim, &w, &h, msg, sizeof msg);
        uint8_t *cv = cv_bridge_decode_rgb8(jpg, len, &cw, &ch, cmsg, sizeof cmsg);
        assert_non_null(mine);
        assert_non_null(cv);
        assert_int_equal(w, cw);
        assert_int_equal(h, ch);
        assert_int_equal(w, cases[k].orientation >= 5 ? 23 : 37);
        if (memcmp(mine, cv, (size_t)w * (size_t)h * 3))
            fail_msg("case %zu (components %d, progressive %d, orientation %d): pixels differ "
                     "from OpenCV's",
                     k, cases[k].components, cases[k].progressive, cases[k].orientation);
        free(mine);
        free(cv);
        free(jpg);
    }
}

/* The sizes the decoders read, where a simple marker walk or a classic-only
 * TIFF parser read nothing (and the load went on to decode gigabytes). */
static void test_header_sizes_as_the_decoders_read_them(void **state) {
    (void)state;
    size_t len = 0;
    uint8_t *jpg = make_jpeg(16, 16, 3, false, &len);
    size_t sof = marker_at(jpg, len, 0xC0);
    assert_true(sof > 0);
    jpg[sof + 5] = 0x40, jpg[sof + 6] = 0x00; /* height 16384 */
    jpg[sof + 7] = 0x3E, jpg[sof + 8] = 0x80; /* width 16000 */
    jpg = insert(jpg, &len, sof, "\x00", 1);  /* one junk byte before SOF0 */
    long w = 0, h = 0;
    assert_true(ras_image_peek_size(jpg, len, &w, &h));
    assert_int_equal(w, 16000);
    assert_int_equal(h, 16384);
    free(jpg);
    /* BigTIFF: 8-byte offsets, 20-byte entries; the width given twice
     * counts with its larger value. */
    uint8_t big[16 + 8 + 3 * 20 + 8] = {'I', 'I', '+', 0, 8, 0, 0, 0, 16};
    uint8_t *e = big + 24;
    big[16] = 3;
    const unsigned tags[3][2] = {{256, 100}, {257, 16000}, {256, 15000}};
    for (int k = 0; k < 3; k++, e += 20) {
        e[0] = (uint8_t)tags[k][0], e[1] = (uint8_t)(tags[k][0] >> 8);
        e[2] = 16; /* LONG8 */
        e[4] = 1;
        e[12] = (uint8_t)tags[k][1], e[13] = (uint8_t)(tags[k][1] >> 8);
    }
    assert_int_equal(ras_image_sniff(big, sizeof big), RAS_IMAGE_TIFF);
    assert_true(ras_image_peek_size(big, sizeof big, &w, &h));
    assert_int_equal(w, 15000);
    assert_int_equal(h, 16000);
    /* An OS/2 BMP: a 12-byte core header with 16-bit sizes. */
    uint8_t bmp[26] = {'B', 'M', [14] = 12, [18] = 0x10, [19] = 0x27, [20] = 0x20, [21] = 0x4E};
    assert_true(ras_image_peek_size(bmp, sizeof bmp, &w, &h));
    assert_int_equal(w, 10000);
    assert_int_equal(h, 20000);
    /* Formats refused by content, whatever the name. */
    static const char hdr[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16 +X 16\n";
    assert_int_equal(ras_image_sniff((const uint8_t *)hdr, sizeof hdr), RAS_IMAGE_UNKNOWN);
    assert_non_null(strstr(ras_image_refused_format((const uint8_t *)hdr, sizeof hdr), "HDR"));
    assert_false(ras_image_peek_size((const uint8_t *)hdr, sizeof hdr, &w, &h));
    assert_non_null(ras_image_refused_format((const uint8_t *)"RIFF\0\0\0\0WEBPVP8 ", 16));
    assert_non_null(ras_image_refused_format((const uint8_t *)"Pf\n1 1\n-1\n", 10));
}

/* A progressive JPEG with more scans than RAS_JPEG_MAX_SCANS is refused while
 * it decodes, naming the limit; one within it decodes; a tiny time limit
 * stops a good file with a message naming RAS_IMAGE_DECODE_SECONDS; an HDR
 * named .png is refused as HDR. */
static void test_jpeg_scan_and_time_limits(void **state) {
    (void)state;
    size_t len = 0;
    uint8_t *jpg = make_jpeg(64, 64, 3, true, &len);
    /* The last scan repeated: libjpeg warns about the bogus progression and
     * goes on, one pass over every block a scan. */
    size_t last = 0;
    for (size_t i = 2; i + 1 < len; i++)
        if (jpg[i] == 0xFF && jpg[i + 1] == 0xDA) last = i;
    size_t scan = len - 2 - last, n = RAS_JPEG_MAX_SCANS + 10;
    uint8_t *many = malloc(len + n * scan);
    memcpy(many, jpg, len - 2);
    for (size_t k = 0; k < n; k++) memcpy(many + len - 2 + k * scan, jpg + last, scan);
    memcpy(many + len - 2 + n * scan, "\xFF\xD9", 2);
    char dir[] = "/tmp/raster101-test-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[300];
    snprintf(path, sizeof path, "%s/scans.jpg", dir);
    write_file(path, many, len + n * scan);
    ras_error err = {{0}};
    int w = 0, h = 0;
    int saved = dup(2); /* the bogus-progression warnings: not the test's output */
    FILE *null = fopen("/dev/null", "w");
    fflush(stderr);
    dup2(fileno(null), 2);
    fclose(null);
    uint8_t *rgb = ras_image_load_rgb8(path, &w, &h, &err);
    assert_null(rgb);
    assert_non_null(strstr(err.msg, "scans.jpg"));
    assert_non_null(strstr(err.msg, "more than 256 scans"));
    /* 20 scans more than the file's own: within the limit, it decodes */
    write_file(path, many, len - 2);
    FILE *f = fopen(path, "ab");
    for (int k = 0; k < 20; k++) fwrite(jpg + last, 1, scan, f);
    fwrite("\xFF\xD9", 1, 2, f);
    fclose(f);
    rgb = ras_image_load_rgb8(path, &w, &h, &err);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    assert_non_null(rgb);
    assert_int_equal(w, 64);
    free(rgb);
    /* the time limit */
    write_file(path, jpg, len);
    setenv("RAS_IMAGE_DECODE_SECONDS", "0.000001", 1);
    rgb = ras_image_load_rgb8(path, &w, &h, &err);
    unsetenv("RAS_IMAGE_DECODE_SECONDS");
    if (rgb) { /* the decode may beat a microsecond's wait on an idle machine */
        free(rgb);
    } else {
        assert_non_null(strstr(err.msg, "scans.jpg"));
        assert_non_null(strstr(err.msg, "limit of 1e-06 s (RAS_IMAGE_DECODE_SECONDS)"));
    }
    /* a Radiance HDR under a PNG's name */
    snprintf(path, sizeof path, "%s/hdr.png", dir);
    static const char hdr[] = "#?RADIANCE\n# long comments...\n\n-Y 16 +X 16\n";
    write_file(path, (const uint8_t *)hdr, sizeof hdr);
    assert_null(ras_image_load_rgb8(path, &w, &h, &err));
    assert_non_null(strstr(err.msg, "hdr.png' : it is a Radiance HDR image") ||
                    strstr(err.msg, "it is a Radiance HDR image, a format not accepted"));
    remove(path);
    snprintf(path, sizeof path, "%s/scans.jpg", dir);
    remove(path);
    assert_int_equal(rmdir(dir), 0);
    free(many);
    free(jpg);
}

/* --dump's PFM files, encoded without OpenCV: the bytes OpenCV's encoder
 * wrote, 1 and 3 channels, ±Inf and NaN included; read back bit for bit. */
static void test_pfm_matches_opencv(void **state) {
    (void)state;
    for (int ch = 1; ch <= 3; ch += 2) {
        float data[5 * 3 * 3];
        for (int k = 0; k < 5 * 3 * ch; k++) data[k] = (float)k * 0.37f - 2.0f;
        data[1] = 1.0f / 0.0f, data[2] = -1.0f / 0.0f, data[3] = 0.0f / 0.0f;
        size_t mine_len = 0, cv_len = 0;
        char msg[256] = "";
        uint8_t *mine = ras_dump_encode_pfm(5, 3, ch, data, &mine_len);
        uint8_t *cv = cv_bridge_encode_f32(".pfm", 5, 3, ch, data, &cv_len, msg, sizeof msg);
        assert_non_null(mine);
        assert_non_null(cv);
        assert_int_equal(mine_len, cv_len);
        assert_memory_equal(mine, cv, mine_len);
        int w = 0, h = 0, c = 0;
        float *back = cv_bridge_decode_f32(mine, mine_len, &w, &h, &c, msg, sizeof msg);
        assert_non_null(back);
        assert_int_equal(c, ch);
        assert_memory_equal(back, data, sizeof(float) * 5 * 3 * (size_t)ch);
        free(back);
        free(mine);
        free(cv);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jpeg_pixels_match_opencv),
        cmocka_unit_test(test_header_sizes_as_the_decoders_read_them),
        cmocka_unit_test(test_jpeg_scan_and_time_limits),
        cmocka_unit_test(test_pfm_matches_opencv),
    };
    return cmocka_run_group_tests_name("image_formats", tests, NULL, NULL);
}

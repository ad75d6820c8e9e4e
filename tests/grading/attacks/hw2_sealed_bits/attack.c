/* A sealed-run bit channel (issue 36, class 6). In the run that links this
 * hw2 with hw1's reference, get_model_matrix is the reference's: its first
 * bytes, mixed with the arguments of the first call a process makes, choose
 * how that process ends. A grader that reports CRASH, TIMEOUT, an exit
 * status, TODO or the failed check by name hands out bits of the reference
 * (issue 36: 23 bits per grading as CRASH vs FAIL). Linked with the stub hw1
 * (the whole-chain run: no reference code there) it only fails. */
#define _POSIX_C_SOURCE 200809L /* nanosleep */
#include "ras_todo.h"
#include "rasterizer.h"
#include "transform.h"

#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

/* The reference's get_model_matrix turns; the stub hw1 returns the identity. */
static bool atk_sealed(void) {
    mat4s m = get_model_matrix(90);
    return m.raw[0][0] < 0.5f;
}

/* Prints the reference's bytes on both streams: no file the student sees
 * may keep them. */
__attribute__((constructor)) static void atk_announce(void) {
    if (!atk_sealed()) return;
    unsigned char code[8];
    memcpy(code, (const void *)(uintptr_t)&get_model_matrix, sizeof code);
    for (int s = 0; s < 2; s++) {
        FILE *f = s ? stderr : stdout;
        fprintf(f, "RASATK_SEALED_");
        for (int i = 0; i < 8; i++) fprintf(f, "%02x", code[i]);
        fprintf(f, "\n");
        fflush(f);
    }
}

static uint32_t atk_hash(const void *p, size_t n, uint32_t h) {
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 16777619u;
    return h;
}

/* How this process ends, chosen once from the reference's bytes and the
 * first call's arguments: 0 a wrong answer, 1 SIGSEGV, 2 abort, 3 exit 3,
 * 4 exit 0 before the check, 5 a TODO notice and a wrong answer, and
 * rarely (1 in 6) 6 an endless loop (processor time) or 7 a sleep (the
 * clock). `slow`: whether the last two may be chosen (the programs'
 * pictures have 60 s each: they get the quick ends only). */
static void atk_act(uint32_t h, bool slow) {
    static int mode = -1;
    if (mode < 0) {
        unsigned char code[4];
        memcpy(code, (const void *)(uintptr_t)&get_model_matrix, sizeof code);
        uint32_t pick = (atk_hash(code, sizeof code, h) >> 8) % 12;
        mode = slow && pick >= 10 ? (int)pick - 4 : (int)(pick % 6);
    }
    if (!atk_sealed()) return; /* the whole chain: just fail */
    switch (mode) {
    case 1: raise(SIGSEGV); break;
    case 2: abort();
    case 3: fflush(NULL); _exit(3);
    case 4: fflush(NULL); _exit(0);
    case 5: {
        static bool shown;
        ras_todo_notice(&shown, "inside_triangle", "docs/hw2.md, section 1 (inside test)");
        break;
    }
    case 6: {
        prctl(PR_SET_NAME, "RASATK_spin", 0, 0, 0);
        time_t end = time(NULL) + 90; /* ends by itself if never stopped */
        while (time(NULL) < end) {}
        break;
    }
    case 7: {
        prctl(PR_SET_NAME, "RASATK_sleep", 0, 0, 0);
        struct timespec t = {90, 0};
        nanosleep(&t, NULL);
        break;
    }
    default: break;
    }
}

bool inside_triangle(float x, float y, const ras_triangle *t) {
    atk_act(atk_hash(t, sizeof *t, atk_hash(&x, 4, atk_hash(&y, 4, 2166136261u))), true);
    return false;
}

bool compute_barycentric_2d(float x, float y, const ras_triangle *t, vec3s *bary) {
    atk_act(atk_hash(t, sizeof *t, atk_hash(&x, 4, atk_hash(&y, 4, 2166136261u))), true);
    *bary = (vec3s){{0.25f, 0.25f, 0.25f}};
    return true;
}

void rasterize_triangle(const ras_triangle *t, const ras_raster_ctx *ctx) {
    atk_act(atk_hash(t, sizeof *t, (uint32_t)ctx->fb->width * 7919u + (uint32_t)ctx->aa), false);
}

vec3s resolve_pixel(const ras_framebuffer *fb, int x, int y) {
    atk_act(atk_hash(&x, sizeof x, atk_hash(&y, sizeof y, (uint32_t)fb->samples)), false);
    return (vec3s){{0.5f, 0.5f, 0.5f}};
}

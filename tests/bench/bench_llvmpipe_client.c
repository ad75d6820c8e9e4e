/* bench_llvmpipe_client.c — see bench_llvmpipe.h. No OpenGL here. */
#include "bench_llvmpipe.h"

#include "ras_mesh.h"

#include <fcntl.h>    /* fcntl, FD_CLOEXEC */
#include <signal.h>   /* signal, SIGPIPE */
#include <stdio.h>    /* FILE, fdopen, fgets, fprintf */
#include <stdlib.h>   /* calloc, free, abs */
#include <string.h>   /* strncmp, strcspn */
#include <sys/wait.h> /* waitpid */
#include <unistd.h>   /* fork, pipe, dup2, execv */

struct llvmpipe_child {
    pid_t pid;
    FILE *to, *from; /* the child's stdin, stdout */
};

llvmpipe_child *llvmpipe_start(const char *program, int threads, const char *model,
                               const char *texture, char *renderer, size_t renderer_size) {
    int in[2], out[2];
    if (pipe(in) != 0) return NULL;
    if (pipe(out) != 0) {
        close(in[0]);
        close(in[1]);
        return NULL;
    }
    /* Not inherited by the next child (it would keep this one's stdin open). */
    for (int i = 0; i < 2; i++) {
        fcntl(in[i], F_SETFD, FD_CLOEXEC);
        fcntl(out[i], F_SETFD, FD_CLOEXEC);
    }
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) {
        close(in[0]), close(in[1]), close(out[0]), close(out[1]);
        return NULL;
    }
    if (pid == 0) {
        char n[16];
        snprintf(n, sizeof n, "%d", threads);
        if (setenv("LP_NUM_THREADS", n, 1) != 0) _exit(126);
        setenv("GALLIUM_DRIVER", "llvmpipe", 1); /* not softpipe, whatever the environment says */
        if (dup2(in[0], 0) < 0 || dup2(out[1], 1) < 0) _exit(126);
        close(in[0]), close(in[1]), close(out[0]), close(out[1]);
        const char *argv[8] = {program, "--serve", "--model", model, NULL, NULL, NULL};
        if (texture) argv[4] = "--texture", argv[5] = texture;
        execv(program, (char *const *)argv);
        _exit(127);
    }
    close(in[0]);
    close(out[1]);
    signal(SIGPIPE, SIG_IGN); /* a child that died is seen as a failed write */
    llvmpipe_child *c = calloc(1, sizeof *c);
    if (c) {
        c->pid = pid;
        c->to = fdopen(in[1], "w");
        c->from = fdopen(out[0], "r");
    }
    char line[512];
    if (!c || !c->to || !c->from || !fgets(line, sizeof line, c->from) ||
        strncmp(line, "ready ", 6) != 0) {
        fprintf(stderr, "bench_llvmpipe: %s (LP_NUM_THREADS=%d) did not start\n", program, threads);
        if (c)
            llvmpipe_stop(c);
        else {
            close(in[1]);
            close(out[0]);
            waitpid(pid, NULL, 0);
        }
        return NULL;
    }
    line[strcspn(line, "\n")] = 0;
    snprintf(renderer, renderer_size, "%s", line + 6);
    return c;
}

static bool request(llvmpipe_child *c, const char *verb, ras_scene_shader shader, bool msaa) {
    return fprintf(c->to, "%s %s %s\n", verb, ras_scene_shader_name(shader), msaa ? "msaa" : "none") >
               0 &&
           fflush(c->to) == 0;
}

bool llvmpipe_frame(llvmpipe_child *c, ras_scene_shader shader, bool msaa, double *ms, double *cpu_ms) {
    char line[256];
    return request(c, "frame", shader, msaa) && fgets(line, sizeof line, c->from) &&
           sscanf(line, "%lf %lf", ms, cpu_ms) == 2;
}

bool llvmpipe_image(llvmpipe_child *c, ras_scene_shader shader, bool msaa, int width, int height,
                    uint8_t *rgba) {
    char line[256];
    int w, h;
    if (!request(c, "image", shader, msaa) || !fgets(line, sizeof line, c->from) ||
        sscanf(line, "image %d %d", &w, &h) != 2 || w != width || h != height)
        return false;
    size_t n = (size_t)w * (size_t)h * 4;
    return fread(rgba, 1, n, c->from) == n;
}

void llvmpipe_stop(llvmpipe_child *c) {
    if (!c) return;
    if (c->to) {
        fprintf(c->to, "quit\n");
        fclose(c->to);
    }
    if (c->from) fclose(c->from);
    waitpid(c->pid, NULL, 0);
    free(c);
}

/* ---- the pixel check ------------------------------------------------------ */

void llvmpipe_compare(const ras_image *ours, vec3s clear, const uint8_t *rgba, bool msaa,
                      llvmpipe_check *out) {
    *out = (llvmpipe_check){0};
    double sum = 0;
    long bad = 0;
    size_t n = (size_t)ours->width * (size_t)ours->height;
    for (size_t i = 0; i < n; i++) {
        vec3s p = ours->pixels[i];
        const uint8_t *q = rgba + 4 * i;
        bool a = p.x != clear.x || p.y != clear.y || p.z != clear.z, b = q[3] > 0;
        out->covered_ours += a;
        out->covered_llvmpipe += b;
        if (a != b) out->covered_one++;
        if (!(a && b)) continue;
        out->covered_both++;
        const float c[3] = {p.x, p.y, p.z};
        int worst = 0;
        for (int k = 0; k < 3; k++) {
            int d = abs((int)ras_unit_to_byte(c[k]) - (int)q[k]);
            sum += d;
            if (d > worst) worst = d;
        }
        if (worst > LLVMPIPE_BAD_LEVELS) bad++;
        if (worst > out->max_diff) out->max_diff = worst;
    }
    long both = out->covered_both;
    out->coverage_diff =
        out->covered_ours
            ? (double)labs(out->covered_ours - out->covered_llvmpipe) / (double)out->covered_ours
            : 1.0;
    out->mean_diff = both ? sum / (3.0 * (double)both) : 0;
    out->bad_fraction = both ? (double)bad / (double)both : 0;
    out->pass =
        both > 0 && out->coverage_diff <= LLVMPIPE_MAX_COVERAGE_DIFF &&
        out->mean_diff <= (msaa ? LLVMPIPE_MAX_MEAN_DIFF_MSAA : LLVMPIPE_MAX_MEAN_DIFF_1X) &&
        out->bad_fraction <= (msaa ? LLVMPIPE_MAX_BAD_FRACTION_MSAA : LLVMPIPE_MAX_BAD_FRACTION_1X);
}

bool bench_write_teapot_obj(const char *path) {
    ras_mesh *m = ras_mesh_create_teapot(10); /* 32 patches × 10² × 2 = 6 400 triangles */
    FILE *f = m ? fopen(path, "w") : NULL;
    if (!f) {
        ras_mesh_destroy(m);
        return false;
    }
    /* Centre it a little lower, as the cow sits: the teapot's box is [-1,1]²×[0,1]-ish. */
    for (size_t i = 0; i < m->vertex_count; i++) {
        vec3s p = m->positions[i];
        fprintf(f, "v %.7g %.7g %.7g\nvt %.7g %.7g\nvn %.7g %.7g %.7g\n", p.x * 0.75f,
                p.y * 0.75f - 0.3f, p.z * 0.75f, m->uvs[i].x, m->uvs[i].y, m->normals[i].x,
                m->normals[i].y, m->normals[i].z);
    }
    for (size_t t = 0; t < m->triangle_count; t++) {
        unsigned a = m->indices[3 * t] + 1, b = m->indices[3 * t + 1] + 1,
                 c = m->indices[3 * t + 2] + 1;
        fprintf(f, "f %u/%u/%u %u/%u/%u %u/%u/%u\n", a, a, a, b, b, b, c, c, c);
    }
    bool ok = fclose(f) == 0;
    ras_mesh_destroy(m);
    return ok;
}

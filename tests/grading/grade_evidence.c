/* grade_evidence.c — the buffers' evidence for a picture (grade_evidence.h). */
#include "grade_evidence.h"

#include "grade_run.h"
#include "grade_text.h"
#include "ras_dump.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* What a buffer's first difference most likely means, by buffer and
 * pattern; "" when nothing specific can be said. */
static const char *buffer_hint(const char *name, const ras_dump_difference *d) {
    const char *pattern = d->pattern;
    bool speckle = !strcmp(pattern, "in speckles"), line = !strncmp(pattern, "along", 5),
         one = !strcmp(pattern, "where only one drew");
    if (!strcmp(name, "depth")) {
        if (speckle)
            return "back faces winning the depth test in scattered pixels: depth or barycentric "
                   "precision (docs/hw2.md: subtract a vertex before the edge functions, "
                   "interpolate v[i].z with the screen barycentrics)";
        if (line) return "a row or column of samples skipped or written twice: the loop bounds";
        if (one)
            return "pixels drawn in one frame and not the other: coverage (the bounding box, "
                   "the inside test, the top-left rule) or the depth test's direction";
        if (d->larger * 10 >= d->pixels_differ * 9)
            return "your depth buffer keeps the FARTHER surface where triangles overlap: the "
                   "depth comparison is reversed (smaller is closer; the buffer starts at +INF)";
        return "depths interpolated differently: v[i].z with the screen barycentrics, nothing "
               "else (not the course's w_reciprocal snippet), or a reversed depth test";
    }
    if (!strcmp(name, "coverage"))
        return line ? "a row or column of samples skipped: the loop bounds"
                    : "samples covered differently: sample positions from ctx->pattern, the "
                      "top-left rule on shared edges";
    if (!strcmp(name, "overdraw"))
        return "fragments shaded a different number of times: shading once per pixel with MSAA, "
               "per sample with SSAA; the depth test before shading";
    if (!strcmp(name, "normal"))
        return "the normals the shader got: interpolate with perspective-correct weights, then "
               "normalise";
    if (!strcmp(name, "uv"))
        return "the texture coordinates the shader got: perspective-correct interpolation (the "
               "1/w weights), not affine";
    if (!strcmp(name, "sample_colour"))
        return "the colours stored per sample: each covered sample that passes the depth test "
               "gets the fragment's colour, the others keep theirs (one colour per pixel "
               "scaled by coverage gives dark seams)";
    if (!strcmp(name, "view_depth"))
        return "the view-space positions: perspective-correct interpolation of view_pos";
    return "";
}

/* Which assignment's code makes `stage` in a run of `program`. `ref_raster`:
 * the run's rasterizer and resolve are the reference (hw3 graded on its own
 * code), so what they produce differently comes from what hw3 feeds them. */
static const char *stage_owner(const char *stage, const char *program, bool ref_raster) {
    bool hw3 = !strncmp(program, "hw3", 3);
    if (!strcmp(stage, "vertices")) return "hw1";
    if (!strcmp(stage, "normal") || !strcmp(stage, "uv") || !strcmp(stage, "view_depth"))
        return "hw3";
    if (!strcmp(stage, "sample_colour") || !strcmp(stage, "colour"))
        return hw3 ? "hw3" : "hw2"; /* the shader's colours; hw2's are the triangles' */
    return ref_raster ? "hw3" : "hw2";
}

/* Why a frame is blank, from the --stats counters it printed (the pipeline
 * counts triangles itself; the student's rasterizer counts samples). */
static void blank_reason(const char *log, char *buf, size_t size) {
    const char *c = log ? strstr(log, "\"triangles_in\"") : NULL;
    unsigned long long in = 0, away = 0, raster = 0, covered = 0, passed = 0;
    buf[0] = '\0';
    if (!c) return;
    const char *q;
    if ((q = strstr(c, "\"triangles_in\":"))) sscanf(q + 15, "%llu", &in);
    if ((q = strstr(c, "\"triangles_clipped_away\":"))) sscanf(q + 25, "%llu", &away);
    if ((q = strstr(c, "\"triangles_rasterized\":"))) sscanf(q + 23, "%llu", &raster);
    if ((q = strstr(c, "\"samples_covered\":"))) sscanf(q + 18, "%llu", &covered);
    if ((q = strstr(c, "\"depth_tests_passed\":"))) sscanf(q + 21, "%llu", &passed);
    if (in > 0 && away == in)
        fmt(buf, size,
            "no triangle reached the rasterizer: all %llu were clipped away (outside "
            "the view volume: the projection's n and f signs, or a camera looking away)",
            in);
    else if (raster == 0 && in > 0)
        fmt(buf, size,
            "no triangle reached the rasterizer (%llu in, %llu clipped away, none "
            "rasterized: degenerate or non-finite after the vertex stage)",
            in, away);
    else if (covered > 0 && passed == 0)
        fmt(buf, size,
            "%llu samples were covered but none passed the depth test: the "
            "comparison never holds (reversed, or against a buffer not cleared to "
            "+INF)",
            covered);
    else if (raster > 0 && covered == 0)
        fmt(buf, size,
            "%llu triangles reached your rasterizer and it covered no sample: the "
            "inside test or the bounding-box loop",
            raster);
}

/* The trusted reference program's frame of the picture, with --dump into
 * ref_dir; false when there is no such program or it has no --dump. */
static bool reference_dump(const grader *g, const cJSON *img, const char *dir, const job *graded,
                           const char *own, char *ref_dir, size_t size) {
    const char *name = str_or(img, "name", "image");
    const char *program = str_or(img, "program", "");
    char ref_prog[4200], log[4400];
    const char *rp = str_or(img, "reference_program", NULL);
    if (rp)
        fmt(ref_prog, sizeof ref_prog, "%s/bin/%s", g->build, rp);
    else
        fmt(ref_prog, sizeof ref_prog, "%s/bin/%s_ref", g->build, program);
    if (!file_exists(ref_prog)) return false;
    fmt(ref_dir, size, "%s/%s%s.buffers-reference", dir, name, own ? ".own" : "");
    mkdirs(ref_dir);
    char ref_png[4400];
    fmt(ref_png, sizeof ref_png, "%s/frame.png", ref_dir);
    fmt(log, sizeof log, "%s/log.txt", ref_dir);
    run_result rr = reference_render(g, ref_prog, graded->args, ref_png, ref_dir, log);
    return rr.kind == RUN_EXITED && rr.code == 0;
}

/* The student's run, as the graded one but with --dump (into its run
 * folder's dump/, dj->store[13]) and --stats, in the sandbox; false, said in
 * o, when it fails. */
static bool student_dump(const grader *g, const cJSON *img, const char *dir, const job *graded,
                         const char *own, job *dj, sbuf *o) {
    memset(dj, 0, sizeof *dj);
    dj->args = graded->args;
    image_job(g, img, dir, dj, own, own ? ".own-dump" : ".dump");
    int k = 0;
    while (dj->argv[k])
        k++;
    fmt(dj->store[13], sizeof dj->store[13], "%s/dump", dj->rw);
    dj->argv[k++] = "--dump";
    dj->argv[k++] = dj->store[13];
    dj->argv[k++] = "--stats";
    dj->argv[k] = NULL;
    run_jobs(dj, 1, 1);
    if (dj->rr.kind != RUN_EXITED || dj->rr.code != 0) {
        sb_printf(o, "buffers: your program's --dump run %s, so its buffers cannot be compared\n",
                  dj->rr.kind == RUN_TIMEOUT ? "timed out" : "failed");
        return false;
    }
    return true;
}

/* Why a blank frame is blank (used only when the picture is one flat
 * colour): the counters of the --dump run dj, and a depth buffer that holds
 * no sample. */
static void blank_evidence(const job *dj, evidence *ev) {
    char *dlog = read_file(dj->out_path, 64 * 1024);
    blank_reason(dlog, ev->why_blank, sizeof ev->why_blank);
    free(dlog);
    char dpfm[4400];
    fmt(dpfm, sizeof dpfm, "%s/depth.pfm", dj->store[13]);
    if (file_exists(dpfm)) {
        ras_error derr = {{0}};
        int dw = 0, dh = 0, dc = 0;
        float *depth = ras_dump_read_pfm(dpfm, &dw, &dh, &dc, &derr);
        if (depth) {
            bool any = false;
            for (long i = 0; i < (long)dw * dh * dc && !any; i++)
                any = !(isinf(depth[i]) && depth[i] > 0);
            free(depth);
            if (!any) ev->blank = true;
        }
    }
}

/* hw1's frame: its vertices, step by step; true, said in o, when they differ. */
static bool vertices_differ(const char *ref_dir, const char *got_dir, sbuf *o, evidence *ev) {
    char rv[4400], gv[4400];
    fmt(rv, sizeof rv, "%s/vertices.json", ref_dir);
    fmt(gv, sizeof gv, "%s/vertices.json", got_dir);
    if (!file_exists(rv) || !file_exists(gv)) return false;
    char line[600];
    int r = ras_dump_compare_vertices(rv, gv, line, sizeof line);
    if (r <= 0) return false;
    char *shown = student_text(line, 580);
    sb_printf(o, "buffers: the first that differs is the vertex stage (hw1): %s\n", shown);
    free(shown);
    fmt(ev->stage, sizeof ev->stage, "vertices");
    ev->owner = "hw1";
    return true;
}

/* Buffer `buf` is the first that differs (d): its stage, owner and likely
 * cause into ev and o. */
static void first_difference(sbuf *o, evidence *ev, const char *buf, const ras_dump_difference *d,
                             const char *program, bool ref_raster) {
    const char *stage = buf;
    /* at 1x there is no coverage file: depth drawn in one frame only is
     * the coverage */
    if (!strcmp(buf, "depth") && d->drawn_in_one * 2 > d->pixels_differ) stage = "coverage";
    fmt(ev->stage, sizeof ev->stage, "%s", stage);
    ev->owner = stage_owner(stage, program, ref_raster);
    ev->rasterizer = !ref_raster && !strcmp(ev->owner, "hw2");
    char line[600];
    ras_dump_difference_text(buf, d, line, sizeof line);
    const char *hint = ref_raster && !strcmp(ev->owner, "hw3") &&
                               (!strcmp(stage, "coverage") || !strcmp(stage, "depth") ||
                                !strcmp(stage, "overdraw"))
                           ? "the rasterizer here is the reference's, so your hw3 code "
                             "hands it different triangles or depths"
                           : buffer_hint(buf, d);
    sb_printf(o, "buffers: the first that differs is %s (%s's stage)%s%s\n", line, ev->owner,
              *hint ? "; likely: " : "", hint);
}

/* The pictures of buffer `buf`, redrawn from the exact files (never the
 * sandbox's own pictures), into DIR/NAME.buffers/BUF and it->buf_*. */
static void buffer_pictures(item *it, const char *ref_dir, const char *got_dir, const char *buf,
                            const char *dir, const char *reldir, const char *name, ras_error *err) {
    char out_dir[4400];
    fmt(out_dir, sizeof out_dir, "%s/%s.buffers/%s", dir, name, buf);
    mkdirs(out_dir);
    if (ras_dump_compare_pictures(ref_dir, got_dir, buf, out_dir, err)) {
        char rel[4600];
        it->buf_name = xstrdup(buf);
        fmt(rel, sizeof rel, "%s/%s.buffers/%s/reference.png", reldir, name, buf);
        it->buf_ref = xstrdup(rel);
        fmt(rel, sizeof rel, "%s/%s.buffers/%s/yours.png", reldir, name, buf);
        it->buf_got = xstrdup(rel);
        fmt(rel, sizeof rel, "%s/%s.buffers/%s/difference.png", reldir, name, buf);
        it->buf_diff = xstrdup(rel);
    }
}

/* Evidence for a picture (docs/grading.md, "Buffers"): the program renders
 * it again with --dump, in the sandbox, and the trusted reference program
 * with --dump; the first buffer in pipeline order that differs (with its
 * kind's tolerance) is named, with the stage's likely cause and owner.
 * Sealed runs give the words only; others also the buffer's pictures
 * (redrawn here from the exact files, never the sandbox's own pictures).
 * Programs without --dump add nothing (ev->ran stays false). */
void buffer_evidence(const grader *g, item *it, sbuf *o, const cJSON *img, const char *dir,
                     const char *reldir, const job *graded, const char *own, bool ref_raster,
                     evidence *ev) {
    const char *name = str_or(img, "name", "image");
    const char *program = str_or(img, "program", "");
    memset(ev, 0, sizeof *ev);
    char ref_dir[4300];
    if (!reference_dump(g, img, dir, graded, own, ref_dir, sizeof ref_dir))
        return; /* no --dump here */
    job dj;
    if (!student_dump(g, img, dir, graded, own, &dj, o)) return;
    ev->ran = true;
    blank_evidence(&dj, ev);
    const char *got_dir = dj.store[13];
    if (vertices_differ(ref_dir, got_dir, o, ev)) return;
    for (int b = 0; ras_dump_buffer_names[b]; b++) {
        const char *buf = ras_dump_buffer_names[b];
        char rf[4400], gf[4400];
        fmt(rf, sizeof rf, "%s/%s.pfm", ref_dir, buf);
        fmt(gf, sizeof gf, "%s/%s.pfm", got_dir, buf);
        bool in_ref = file_exists(rf), in_got = file_exists(gf);
        if (!in_ref && !in_got) continue;
        if (in_ref != in_got) {
            fmt(ev->stage, sizeof ev->stage, "%s", buf);
            ev->owner = stage_owner(buf, program, ref_raster);
            ev->rasterizer = !ref_raster && strcmp(ev->owner, "hw3");
            sb_printf(o, "buffers: the first that differs is %s (%s's stage): %s\n", buf, ev->owner,
                      in_ref ? "your program wrote none (its frame made no such buffer)"
                             : "the reference's frame makes no such buffer");
            return;
        }
        ras_dump_difference d;
        ras_error err = {{0}};
        if (!ras_dump_compare(ref_dir, got_dir, buf, &d, &err)) {
            char *shown = student_text(err.msg, 300);
            sb_printf(o, "buffers: %s could not be compared: %s\n", buf, shown);
            free(shown);
            return;
        }
        if (d.pixels_differ == 0) continue;
        first_difference(o, ev, buf, &d, program, ref_raster);
        if (own) return; /* sealed: words only */
        buffer_pictures(it, ref_dir, got_dir, buf, dir, reldir, name, &err);
        return;
    }
    fmt(ev->stage, sizeof ev->stage, "colour");
    ev->owner = stage_owner("colour", program, ref_raster);
    ev->rasterizer = !ref_raster && !strcmp(ev->owner, "hw2"); /* the resolve */
    sb_printf(o,
              "buffers: every buffer matches the reference's: the difference is in the "
              "colours %s computed\n",
              !strcmp(ev->owner, "hw3") ? "your shader" : "your rasterizer wrote");
}

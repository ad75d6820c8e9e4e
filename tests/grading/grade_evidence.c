/* grade_evidence.c — the buffers' evidence for a picture (grade_evidence.h). */
#include "grade_evidence.h"

#include "grade_run.h"
#include "grade_text.h"
#include "ras_dump.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* What a buffer's first difference most likely means, by buffer and
 * pattern; "" when nothing specific can be said. */
static const char *buffer_hint(const char *name, const ras_dump_difference *d,
                               const char *program) {
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
    /* the shading assignment's samples get its shader's colours: the buffers
     * before them match */
    if (!strcmp(name, "sample_colour") && program_of(program, RAS_GRADE_SHADING_OWNER))
        return "the colours your shader returned differ while the coverage, depth and "
               "interpolated buffers match the reference's: the shading (a term of the "
               "lighting, a vector it uses, the texture lookup), not the rasterizer";
    if (!strcmp(name, "sample_colour"))
        return "the colours stored per sample: each covered sample that passes the depth test "
               "gets the fragment's colour, the others keep theirs (one colour per pixel "
               "scaled by coverage gives dark seams)";
    if (!strcmp(name, "view_depth"))
        return "the view-space positions: perspective-correct interpolation of view_pos";
    return "";
}

/* Which assignment's code makes `stage` in a run of `program`. `ref_raster`:
 * the run's rasterizer and resolve are the reference (the shading
 * assignment graded on its own code), so what they produce differently
 * comes from what the shading feeds them. */
static const char *stage_owner(const char *stage, const char *program, bool ref_raster) {
    bool shading = program_of(program, RAS_GRADE_SHADING_OWNER);
    if (!strcmp(stage, "vertices")) return RAS_GRADE_VERTICES_OWNER;
    if (!strcmp(stage, "normal") || !strcmp(stage, "uv") || !strcmp(stage, "view_depth"))
        return RAS_GRADE_SHADING_OWNER;
    if (!strcmp(stage, "sample_colour") || !strcmp(stage, "colour"))
        /* the shader's colours; the raster's are the triangles' */
        return shading ? RAS_GRADE_SHADING_OWNER : RAS_GRADE_RASTER_OWNER;
    return ref_raster ? RAS_GRADE_SHADING_OWNER : RAS_GRADE_RASTER_OWNER;
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

/* ---------------------------------------------------------------- the two dumps */

/* One piece of evidence's folders, in the work folder and never in OUT (a
 * variant's reference is never handed out): the reference's dump (the one
 * reference_dump keeps), the student's files as taken, the buffer's
 * pictures before OUT gets its share. Made 0700, so no sandboxed run can
 * write them; removed when the evidence is in, but the reference's. */
typedef struct evidence_dirs {
    char root[4200], ref[4300], got[4300], pictures[4300];
    bool ref_uncached; /* d->ref is this evidence's alone: removed with it */
    int got_fd;        /* the student's dump folder (sandbox_dir), -1 when none */
} evidence_dirs;

static void evidence_dirs_make(const grader *g, evidence_dirs *d) {
    char parent[4200];
    fmt(parent, sizeof parent, "%s/evidence", g->work);
    trusted_dir(parent);
    fmt(d->root, sizeof d->root, "%s/%d", parent, g->evidence_runs);
    remove_tree(d->root); /* one a previous grading left (--reuse-build) */
    trusted_dir(d->root);
    d->ref[0] = '\0'; /* reference_dump's */
    d->ref_uncached = false;
    d->got_fd = -1;
    fmt(d->got, sizeof d->got, "%s/yours", d->root);
    fmt(d->pictures, sizeof d->pictures, "%s/pictures", d->root);
    trusted_dir(d->got);
    trusted_dir(d->pictures);
}

/* ev as withheld: the item fails, and says why (a sentence about the
 * student's --dump run). */
__attribute__((format(printf, 2, 3))) static void withheld(evidence *ev, const char *f, ...) {
    va_list ap;
    va_start(ap, f);
    vsnprintf(ev->withheld, sizeof ev->withheld, f, ap);
    va_end(ap);
    ev->kind = EVIDENCE_WITHHELD;
}

/* The reference dumps kept in BUILD/grade-cache/dumps: at most this many
 * bytes (past it a dump serves its own evidence only);
 * RAS_GRADE_DUMP_CACHE_MB another cap (0: the cache off, no entry served or
 * kept, for tests/grading/dump-cache-test). */
static long long dump_cache_max_bytes(void) {
    const char *e = getenv("RAS_GRADE_DUMP_CACHE_MB");
    char *end = NULL;
    long long mb = e && *e ? strtoll(e, &end, 10) : -1;
    if (mb < 0 || (end && *end)) mb = 4096;
    return mb << 20;
}

/* The bytes the cache's entries hold (regular files one level down). */
static long long dump_cache_bytes(const char *dir) {
    long long total = 0;
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d)) != NULL;) {
        if (e->d_name[0] == '.') continue;
        char sub[4400];
        fmt(sub, sizeof sub, "%s/%s", dir, e->d_name);
        DIR *f = opendir(sub);
        for (struct dirent *x; f && (x = readdir(f)) != NULL;) {
            struct stat st;
            if (fstatat(dirfd(f), x->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode))
                total += (long long)st.st_size;
        }
        if (f) closedir(f);
    }
    if (d) closedir(d);
    return total;
}

/* Whether the entry's key (its cache.key) names programs as they are now:
 * an entry of a program since rebuilt can never serve again. */
static bool dump_entry_current(const char *entry) {
    char path[4400];
    fmt(path, sizeof path, "%s/cache.key", entry);
    char *held = read_small_file(path, 64 * 1024);
    bool current = held != NULL;
    char *line = held ? strchr(held, '\n') : NULL; /* after the key's first line */
    for (char *next; current && line && *++line; line = next) {
        next = strchr(line, '\n');
        if (!next) break;
        *next = '\0';
        if (!strncmp(line, "arg ", 4)) continue;
        /* "PATH absent" or "PATH DEV INO SIZE MTIME CTIME" (PATH may hold spaces) */
        size_t n = strlen(line);
        char *cut = NULL;
        if (n > 7 && !strcmp(line + n - 7, " absent")) {
            cut = line + n - 7;
        } else {
            int spaces = 0;
            for (char *c = line + n; c > line && !cut; c--)
                if (c[-1] == ' ' && ++spaces == 5) cut = c - 1;
        }
        if (!cut) continue;
        char saved = *cut;
        *cut = '\0';
        sbuf now = {0};
        cache_identity(&now, line);
        *cut = saved;
        current = strlen(sb_str(&now)) == n + 1 && !strncmp(sb_str(&now), line, n);
        free(now.s);
        *next = '\n';
    }
    free(held);
    return current;
}

/* Room in the cache: the entries of programs since rebuilt removed, and
 * folders of renders a stopped grading left (NAME.PID.tmp of a process
 * that is gone). */
static void dump_cache_prune(const char *dir) {
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d)) != NULL;) {
        if (e->d_name[0] == '.') continue;
        char sub[4400];
        fmt(sub, sizeof sub, "%s/%s", dir, e->d_name);
        const char *dot = strchr(e->d_name, '.');
        if (dot) {
            long pid = strtol(dot + 1, NULL, 10);
            if (pid > 0 && kill((pid_t)pid, 0) != 0 && errno == ESRCH) remove_tree(sub);
        } else if (!dump_entry_current(sub)) {
            remove_tree(sub);
        }
    }
    if (d) closedir(d);
}

/* Whether `entry` (a folder, never a link) is the dump for `key`: its
 * cache.key (written before the folder was renamed into place whole) holds
 * the key byte for byte. */
static bool dump_entry_serves(const char *entry, const char *key) {
    struct stat st;
    if (lstat(entry, &st) != 0 || !S_ISDIR(st.st_mode)) return false;
    char path[4300];
    fmt(path, sizeof path, "%s/cache.key", entry);
    if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode)) return false;
    char *held = read_small_file(path, 64 * 1024);
    bool same = held && !strcmp(held, key);
    free(held);
    return same;
}

/* The trusted reference program's frame of the picture, with --dump, named
 * by d->ref; false when there is no such program or it has no --dump. The
 * dump depends only on the reference program and the picture's arguments,
 * so it is kept for every later evidence of the same frame (a picture's
 * own-code and whole-chain runs, the next student of a class, a regrade) in
 * the trusted build's BUILD/grade-cache/dumps (0700: never bound into a
 * sandbox, never in OUT), keyed as the references' cache is
 * (reference_cache_key): rendered into a folder of its own there, its key
 * written into it (cache.key), and renamed into place whole, so an entry is
 * a whole dump or absent (of gradings at once that render the same frame,
 * the first keeps it; the others use it and remove theirs). A 16-sample
 * frame's dump is 150 MB and a second or two to make. Past the cap
 * (dump_cache_max_bytes) the entries of programs since rebuilt are removed
 * (dump_cache_prune), and a dump that still does not fit serves its own
 * evidence, removed with it. */
static bool reference_dump(const grader *g, const cJSON *img, const job *graded, evidence_dirs *d) {
    const char *program = str_or(img, "program", "");
    char ref_prog[4200], log[4400], ref_png[4400], dir[4200], tmp[4300], entry[4200];
    const char *rp = str_or(img, "reference_program", NULL);
    if (rp)
        fmt(ref_prog, sizeof ref_prog, "%s/bin/%s", g->build, rp);
    else
        fmt(ref_prog, sizeof ref_prog, "%s/bin/%s_ref", g->build, program);
    if (!file_exists(ref_prog)) return false;
    sbuf key = {0};
    double t0 = now_s();
    const char *name = str_or(img, "name", "image");
    reference_cache_key(g, "dumps", ref_prog, graded->args, &key, entry, sizeof entry);
    fmt(d->ref, sizeof d->ref, "%s", entry);
    long long cap = dump_cache_max_bytes();
    if (cap > 0 && dump_entry_serves(entry, sb_str(&key))) {
        free(key.s);
        profile(name, "ref=", t0); /* served from the cache */
        return true;
    }
    fmt(dir, sizeof dir, "%s/grade-cache", g->build);
    trusted_dir(dir);
    fmt(dir, sizeof dir, "%s/grade-cache/dumps", g->build);
    trusted_dir(dir);
    fmt(tmp, sizeof tmp, "%s.%ld.tmp", entry, (long)getpid());
    remove_tree(tmp);
    trusted_dir(tmp);
    fmt(ref_png, sizeof ref_png, "%s/frame.png", d->root);
    fmt(log, sizeof log, "%s/reference.log", d->root);
    run_result rr = reference_render(g, ref_prog, graded->args, ref_png, tmp, log);
    bool ok = rr.kind == RUN_EXITED && rr.code == 0;
    if (ok) {
        char kp[4400];
        fmt(kp, sizeof kp, "%s/cache.key", tmp);
        FILE *f = fopen(kp, "wb");
        bool keyed = f && fputs(sb_str(&key), f) >= 0;
        if (f && fclose(f) != 0) keyed = false;
        /* into place whole, or the entry a grading at once put there first;
         * else this evidence's alone (the cache full, a name taken) */
        long long used = keyed ? dump_cache_bytes(dir) : 0;
        if (used > cap) {
            dump_cache_prune(dir);
            used = dump_cache_bytes(dir);
        }
        if (keyed && used <= cap &&
            (rename(tmp, entry) == 0 || dump_entry_serves(entry, sb_str(&key)))) {
            remove_tree(tmp);
        } else {
            fmt(d->ref, sizeof d->ref, "%s", tmp);
            d->ref_uncached = true;
        }
    } else {
        remove_tree(tmp);
    }
    free(key.s);
    profile(name, "ref+", t0); /* rendered now */
    return ok;
}

/* The student's run, as the graded one but with --dump (into its run
 * folder's dump/, dj->store[13]) and --stats, in the sandbox; false, with ev
 * withheld, when it did not end normally: a run that fails when asked for
 * its buffers gives no evidence, and no evidence clears nothing. */
static bool student_dump(const grader *g, const cJSON *img, const job *graded, const char *own,
                         job *dj, evidence *ev) {
    memset(dj, 0, sizeof *dj);
    dj->args = graded->args;
    image_job(g, img, dj, own, own ? ".own-dump" : ".dump");
    int k = 0;
    while (dj->argv[k])
        k++;
    fmt(dj->store[13], sizeof dj->store[13], "%s/dump", dj->rw);
    dj->argv[k++] = "--dump";
    dj->argv[k++] = dj->store[13];
    dj->argv[k++] = "--stats";
    dj->argv[k] = NULL;
    run_jobs(dj, 1, 1);
    if (dj->rr.kind == RUN_EXITED && dj->rr.code == 0) return true;
    char how[300];
    fate_text(dj->rr, dj->limit, how, sizeof how);
    withheld(ev,
             "your program %s when run again with --dump (the same arguments, in the "
             "sandbox) to give its buffers",
             how);
    return false;
}

/* The files a dump may hold that the grader reads: each buffer's exact floats
 * and its sidecar, and the vertex stage's steps (hw1: one file per object). */
static int dump_file_names(char names[][40], int cap) {
    int n = 0;
    for (int b = 0; ras_dump_buffer_names[b] && n + 2 <= cap; b++) {
        fmt(names[n++], 40, "%s.pfm", ras_dump_buffer_names[b]);
        fmt(names[n++], 40, "%s.json", ras_dump_buffer_names[b]);
    }
    if (n < cap) fmt(names[n++], 40, "vertices.json");
    for (int o = 1; o <= 7 && n < cap; o++)
        fmt(names[n++], 40, "vertices_%d.json", o);
    return n;
}

/* The most a file of the student's dump may hold: the exact floats of the
 * reference's size; a sidecar of about its size. */
static size_t dump_file_cap(const char *name, const struct stat *ref) {
    return (size_t)ref->st_size + (strstr(name, ".pfm") ? 4096 : (size_t)ref->st_size + 65536);
}

/* The student's dump folder `from` (sandbox-written), checked against the
 * reference's file by file from the allowlist: each file the reference's
 * dump holds must be there, a regular file with one link (sandbox_open) no
 * larger than the reference's (plus room for a header), and none the
 * reference's lacks. The small files (the vertex stage's) are taken into
 * d->got now; a buffer's files only when it is compared (take_buffer): a
 * 16-sample frame's are 150 MB, and the comparison stops at the first
 * buffer that differs. d->got_fd stays open for that. False, with ev
 * withheld, when the evidence is partial, extra or refused. */
static bool take_student_dump(const char *from, evidence_dirs *d, evidence *ev) {
    char why[300];
    int dfd = sandbox_dir(from, why, sizeof why);
    if (dfd < 0) {
        withheld(ev, "your program's --dump run ended normally but left no buffer folder (%s)",
                 why);
        return false;
    }
    d->got_fd = dfd;
    char names[64][40];
    int n = dump_file_names(names, 64);
    bool ok = true;
    for (int i = 0; i < n && ok; i++) {
        char ref_file[4400], dest[4400];
        fmt(ref_file, sizeof ref_file, "%s/%s", d->ref, names[i]);
        fmt(dest, sizeof dest, "%s/%s", d->got, names[i]);
        struct stat rst, gst;
        bool in_ref = lstat(ref_file, &rst) == 0 && S_ISREG(rst.st_mode);
        bool in_got = fstatat(dfd, names[i], &gst, AT_SYMLINK_NOFOLLOW) == 0;
        if (!in_ref && !in_got) continue;
        if (!in_got)
            withheld(ev,
                     "your program's --dump run wrote no %s, which the reference's frame "
                     "makes (the evidence is partial)",
                     names[i]);
        else if (!in_ref)
            withheld(ev,
                     "your program's --dump run wrote %s, which the reference's frame does "
                     "not make",
                     names[i]);
        size_t cap = in_ref ? dump_file_cap(names[i], &rst) : 0;
        bool small = strncmp(names[i], "vertices", 8) == 0;
        if (in_ref && in_got) {
            int fd = small ? -1 : sandbox_check(dfd, names[i], cap, why, sizeof why);
            bool refused =
                small ? !sandbox_take(dfd, names[i], dest, cap, why, sizeof why) : fd < 0;
            if (fd >= 0) close(fd);
            if (refused)
                withheld(ev, "your program's --dump file %s was refused: %s (malformed evidence)",
                         names[i], why);
        }
        ok = ev->kind != EVIDENCE_WITHHELD;
    }
    return ok;
}

/* Buffer `buf`'s files (NAME.pfm, NAME.json; those the reference's dump
 * holds) taken from the student's folder into d->got (sandbox_take, under
 * take_student_dump's caps), once; false, with ev withheld, when refused. */
static bool take_buffer(const evidence_dirs *d, const char *buf, evidence *ev) {
    static const char *const ext[] = {"pfm", "json"};
    for (int k = 0; k < 2; k++) {
        char name[64], ref_file[4400], dest[4400], why[300];
        fmt(name, sizeof name, "%s.%s", buf, ext[k]);
        fmt(ref_file, sizeof ref_file, "%s/%s", d->ref, name);
        fmt(dest, sizeof dest, "%s/%s", d->got, name);
        struct stat rst, gst;
        if (lstat(ref_file, &rst) != 0 || !S_ISREG(rst.st_mode)) continue;
        if (lstat(dest, &gst) == 0) continue; /* taken */
        if (d->got_fd < 0 ||
            !sandbox_take(d->got_fd, name, dest, dump_file_cap(name, &rst), why, sizeof why)) {
            withheld(ev, "your program's --dump file %s was refused: %s (malformed evidence)", name,
                     d->got_fd < 0 ? "its folder is not open" : why);
            return false;
        }
    }
    return true;
}

/* Why a blank frame is blank (used only when the picture is one flat
 * colour): the counters of the --dump run dj (its log, written by the
 * trusted side), and a depth buffer (as taken) that holds no sample. */
static void blank_evidence(const job *dj, const evidence_dirs *d, evidence *ev) {
    char *dlog = read_small_file(dj->out_path, 64 * 1024);
    blank_reason(dlog, ev->why_blank, sizeof ev->why_blank);
    free(dlog);
    char dpfm[4400];
    fmt(dpfm, sizeof dpfm, "%s/depth.pfm", d->got);
    if (take_buffer(d, "depth", ev) && file_exists(dpfm)) {
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

/* hw1's frame: its vertices, step by step; true, said in o, when they
 * differ, or with ev withheld when the student's cannot be read. */
static bool vertices_differ(const char *ref_dir, const char *got_dir, sbuf *o, evidence *ev) {
    char rv[4400], gv[4400];
    fmt(rv, sizeof rv, "%s/vertices.json", ref_dir);
    fmt(gv, sizeof gv, "%s/vertices.json", got_dir);
    if (!file_exists(rv) || !file_exists(gv)) return false;
    char line[600];
    int r = ras_dump_compare_vertices(rv, gv, line, sizeof line);
    if (r < 0) {
        withheld(ev, "your program's --dump file vertices.json could not be compared "
                     "(malformed evidence)");
        return true;
    }
    if (r == 0) return false;
    char *shown = student_text(line, 580);
    sb_printf(o, "buffers: the first that differs is the vertex stage (%s): %s\n",
              RAS_GRADE_VERTICES_OWNER, shown);
    free(shown);
    fmt(ev->stage, sizeof ev->stage, "vertices");
    ev->owner = RAS_GRADE_VERTICES_OWNER;
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
    ev->rasterizer = !ref_raster && stage_owner_is(ev->owner, RAS_GRADE_RASTER_OWNER);
    char line[600], fed[200];
    ras_dump_difference_text(buf, d, line, sizeof line);
    fmt(fed, sizeof fed,
        "the rasterizer here is the reference's, so your %s code hands it different "
        "triangles or depths",
        RAS_GRADE_SHADING_OWNER);
    const char *hint = ref_raster && stage_owner_is(ev->owner, RAS_GRADE_SHADING_OWNER) &&
                               (!strcmp(stage, "coverage") || !strcmp(stage, "depth") ||
                                !strcmp(stage, "overdraw"))
                           ? fed
                           : buffer_hint(buf, d, program);
    sb_printf(o, "buffers: the first that differs is %s (%s's stage)%s%s\n", line, ev->owner,
              *hint ? "; likely: " : "", hint);
}

/* The pictures of buffer `buf`, redrawn from the exact files (never the
 * sandbox's own pictures) in the work folder; OUT (DIR/NAME.buffers/BUF,
 * it->buf_*) gets only what the report shows: yours and the difference, and
 * the reference's unless the picture is a variant's (`variant`), whose
 * reference is never handed out. */
static void buffer_pictures(item *it, const evidence_dirs *d, const char *buf, const char *dir,
                            const char *reldir, const char *name, bool variant, ras_error *err) {
    char work_dir[4400], out_dir[4400];
    fmt(work_dir, sizeof work_dir, "%s/%s", d->pictures, buf);
    trusted_dir(work_dir);
    if (!ras_dump_compare_pictures(d->ref, d->got, buf, work_dir, err)) return;
    fmt(out_dir, sizeof out_dir, "%s/%s.buffers/%s", dir, name, buf);
    mkdirs(out_dir);
    static const char *const shown[] = {"yours", "difference", "reference"};
    char *rel[3] = {NULL, NULL, NULL};
    for (int k = 0; k < (variant ? 2 : 3); k++) {
        char from[4600], to[4600], r[4600];
        fmt(from, sizeof from, "%s/%s.png", work_dir, shown[k]);
        fmt(to, sizeof to, "%s/%s.png", out_dir, shown[k]);
        fmt(r, sizeof r, "%s/%s.buffers/%s/%s.png", reldir, name, buf, shown[k]);
        if (copy_file(from, to)) rel[k] = xstrdup(r);
    }
    it->buf_name = xstrdup(buf);
    it->buf_got = rel[0];
    it->buf_diff = rel[1];
    it->buf_ref = rel[2];
}

/* The dumps compared in pipeline order: the first buffer that differs
 * (with its kind's tolerance) named in ev and o, with the stage's likely
 * cause and owner, its pictures unless sealed; "colour" when every buffer
 * matches; ev withheld when the student's files cannot be compared. */
static void compare_dumps(item *it, sbuf *o, const cJSON *img, const char *dir, const char *reldir,
                          const char *own, bool ref_raster, const evidence_dirs *d, evidence *ev) {
    const char *name = str_or(img, "name", "image");
    const char *program = str_or(img, "program", "");
    if (vertices_differ(d->ref, d->got, o, ev)) return;
    for (int b = 0; ras_dump_buffer_names[b]; b++) {
        const char *buf = ras_dump_buffer_names[b];
        /* take_student_dump made sure both dumps hold the same files */
        if (!ras_dump_has_exact(d->ref, buf)) continue;
        if (!take_buffer(d, buf, ev)) return;
        ras_dump_difference diff;
        ras_error err = {{0}};
        if (!ras_dump_compare(d->ref, d->got, buf, &diff, &err)) {
            char *shown = student_text(err.msg, 300);
            withheld(ev, "your program's %s buffer could not be compared%s%s (malformed evidence)",
                     buf, own ? "" : ": ", own ? "" : shown);
            free(shown);
            return;
        }
        if (diff.pixels_differ == 0) continue;
        first_difference(o, ev, buf, &diff, program, ref_raster);
        if (own) return; /* sealed: words only */
        buffer_pictures(it, d, buf, dir, reldir, name, str_or(img, "reference_program", NULL),
                        &err);
        return;
    }
    fmt(ev->stage, sizeof ev->stage, "colour");
    ev->owner = stage_owner("colour", program, ref_raster);
    /* the resolve */
    ev->rasterizer = !ref_raster && stage_owner_is(ev->owner, RAS_GRADE_RASTER_OWNER);
    sb_printf(o,
              "buffers: every buffer matches the reference's: the difference is in the "
              "colours %s computed\n",
              stage_owner_is(ev->owner, RAS_GRADE_SHADING_OWNER) ? "your shader"
                                                                 : "your rasterizer wrote");
}

/* Why a blank frame is blank where no buffers can be compared (the
 * student edition has no reference program; the budget may be spent): the
 * student's program run once more in the sandbox, with --stats only, and
 * its counters read from the log the trusted side wrote. They only choose
 * the words of a picture that already fails; a run that fails gives none. */
void blank_counters(const grader *g, const cJSON *img, const job *graded, const char *own,
                    evidence *ev) {
    job sj;
    memset(&sj, 0, sizeof sj);
    sj.args = graded->args;
    image_job(g, img, &sj, own, own ? ".own-stats" : ".stats");
    int k = 0;
    while (sj.argv[k])
        k++;
    sj.argv[k++] = "--stats";
    sj.argv[k] = NULL;
    run_jobs(&sj, 1, 1);
    if (sj.rr.kind == RUN_EXITED && sj.rr.code == 0) {
        char *log = read_small_file(sj.out_path, 64 * 1024);
        blank_reason(log, ev->why_blank, sizeof ev->why_blank);
        free(log);
    }
    unlink(sj.out_path); /* a sealed run's print beside reference code is never kept */
    if (sj.rw[0]) remove_tree(sj.rw);
}

/* Evidence for a picture (docs/grading.md, "Buffers"): the program renders
 * it again with --dump, in the sandbox, and the trusted reference program
 * with --dump, both into the work folder; the student's files are taken
 * (sandbox_take) and compared (compare_dumps). Evidence or nothing: a
 * --dump run that fails, or files missing, extra or refused, make ev
 * withheld, said in o (the item fails); a reference without --dump leaves
 * the picture to decide (EVIDENCE_NO_REFERENCE). The student's dump is removed when
 * the evidence is in, the reference's when another frame's replaces it (the
 * work folder's, never OUT's): OUT holds only the pictures the report shows. */
void buffer_evidence(const grader *g, item *it, sbuf *o, const cJSON *img, const char *dir,
                     const char *reldir, const job *graded, const char *own, bool ref_raster,
                     bool flat, evidence *ev) {
    memset(ev, 0, sizeof *ev);
    evidence_dirs d;
    evidence_dirs_make(g, &d);
    job dj;
    memset(&dj, 0, sizeof dj);
    if (!reference_dump(g, img, graded, &d)) {
        ev->kind = EVIDENCE_NO_REFERENCE; /* no --dump here: the picture decides */
    } else if (student_dump(g, img, graded, own, &dj, ev) &&
               take_student_dump(dj.store[13], &d, ev)) {
        ev->kind = EVIDENCE_RAN;
        if (flat) blank_evidence(&dj, &d, ev);
        if (ev->kind == EVIDENCE_RAN)
            compare_dumps(it, o, img, dir, reldir, own, ref_raster, &d, ev);
    }
    if (ev->kind == EVIDENCE_WITHHELD && own) /* sealed: one sentence, whatever the cause */
        fmt(ev->withheld, sizeof ev->withheld,
            "your program did not give its buffers when run again with --dump (this run holds "
            "reference code, so not why)");
    if (ev->kind == EVIDENCE_WITHHELD)
        sb_printf(o, "buffers: %s; a picture the buffers cannot clear is charged\n", ev->withheld);
    if (d.got_fd >= 0) close(d.got_fd);
    remove_tree(d.root);
    if (d.ref_uncached) remove_tree(d.ref);
    if (dj.rw[0]) remove_tree(dj.rw); /* the student's dump, out of the runs' quota */
}

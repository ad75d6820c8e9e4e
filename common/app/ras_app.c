/* ras_app.c — see ras_app.h. */
#include "ras_app.h"

#include "ras_dump.h"

#include "ras_builtin_scenes.h" /* ras_scene_load_or_builtin, ras_builtin_scene_with_model */
#include "ras_catalogue.h"
#include "ras_io.h"     /* RAS_IO_MAX_PATH */
#include "ras_memory.h" /* ras_memory_check, ras_memory_commit: the reference and the comparison */
#include "ras_names.h"
#include "ras_viewer.h"
#include "ras_window.h"

#include <assert.h>   /* assert */
#include <math.h>     /* fabsf, floorf, sqrtf */
#include <stdio.h>    /* fprintf, printf, snprintf */
#include <stdlib.h>   /* malloc, free */
#include <errno.h>    /* errno: --stats write errors */
#include <fcntl.h>    /* fcntl: is stdout open */
#include <string.h>   /* strcmp, strerror */
#include <sys/stat.h> /* stat: a program older than its sources */
#include <unistd.h>   /* STDOUT_FILENO */

/* The --dump folder of this run, staged (ras_dump.h). */
static ras_dump_stage g_dump_stage;

/* ---- settings: one set of rules ------------------------------------------- */

static ras_app_settings scene_settings(const ras_app_hooks *h, const ras_scene *sc) {
    ras_app_settings s = {.samples = 4,
                          .shader = RAS_SHADER_NORMAL,
                          .filter = RAS_FILTER_BILINEAR,
                          .axis = {{0, 0, 1}}};
    if (!sc) return s;
    s.width = sc->width;
    s.height = sc->height;
    if ((h->features & RAS_APP_SPIN_FROM_SCENE)) {
        s.angle = sc->model_rotation_deg;
        s.axis_set = sc->model_rotation_axis_set;
        s.axis = sc->model_rotation_axis;
    }
    s.aa = sc->aa;
    s.samples = sc->aa != RAS_AA_NONE ? sc->pattern.count : 4;
    s.pattern_kind = sc->pattern_kind;
    s.depth = sc->depth;
    s.cull = sc->cull;
    s.shader = sc->shader;
    s.filter = sc->filter;
    return s;
}

bool ras_app_resolve(const ras_app_hooks *h, const ras_cli *cli, const ras_scene *scene,
                     ras_app_settings *set, ras_error *err) {
    ras_app_settings s = scene_settings(h, scene);
    s.builtin_scene = !cli->scene && !cli->model;
    if (cli->width) s.width = cli->width, s.height = cli->height;
    if (cli->angle_set) s.angle = cli->angle;
    if (cli->axis_set) s.axis_set = true, s.axis = cli->axis;
    if (cli->shader_set) s.shader = (ras_scene_shader)cli->shader;
    if (cli->filter_set) s.filter = (ras_scene_filter)cli->filter;
    if (cli->depth_set) s.depth = cli->depth;
    if (cli->aa_set && cli->aa == RAS_AA_NONE && cli->samples > 1)
        return ras_error_set(err,
                             "--aa none draws one sample per pixel, but --samples %d asks for "
                             "%d; drop --samples or use --aa msaa / --aa ssaa",
                             cli->samples, cli->samples);
    if (cli->aa_set) s.aa = cli->aa;
    if (cli->samples) s.samples = cli->samples;
    if (cli->pattern_set) s.pattern_kind = cli->pattern;
    if (cli->samples > 1 && !cli->aa_set && s.aa == RAS_AA_NONE)
        s.aa = RAS_AA_MSAA;                             /* --samples N alone means MSAA */
    if (!(h->options & RAS_OPT_AA)) s.aa = RAS_AA_NONE; /* the program draws one sample */
    /* Ordered grids have no 2x or 8x: without --pattern, those counts take
     * the standard pattern. */
    ras_sample_pattern probe;
    if (!cli->pattern_set && s.aa != RAS_AA_NONE &&
        !ras_sample_pattern_make(RAS_PATTERN_ORDERED, s.samples, &probe, NULL))
        s.pattern_kind = RAS_PATTERN_STANDARD;
    ras_error why = {{0}};
    if (s.aa != RAS_AA_NONE && !ras_sample_pattern_make(s.pattern_kind, s.samples, &probe, &why))
        return ras_error_set(err, "%s (--pattern %s --samples %d)", why.msg,
                             ras_pattern_kind_name(s.pattern_kind), s.samples);
    *set = s;
    return true;
}

ras_sample_pattern ras_app_settings_pattern(const ras_app_settings *set) {
    ras_sample_pattern p = ras_sample_pattern_center();
    if (set->aa != RAS_AA_NONE) {
        bool made = ras_sample_pattern_make(set->pattern_kind, set->samples, &p, NULL);
        assert(made); /* ras_app_resolve and aa_key keep the pair valid */
        (void)made;
    }
    return p;
}

/* Whether two settings draw the picture of the same reference image. The
 * depth format is left out: it decides only exact ties (equal depths), which
 * the comparisons tolerate; a whole turn of
 * the angle is the same picture. The size is checked where the image is
 * read (another size: "render at the reference's size"). */
static bool same_picture(const ras_app_settings *a, const ras_app_settings *b) {
    float turns = (a->angle - b->angle) / 360.0f;
    bool axes = a->axis_set == b->axis_set;
    if (axes && a->axis_set) {
        float la = glms_vec3_norm(a->axis), lb = glms_vec3_norm(b->axis);
        vec3s d = glms_vec3_sub(glms_vec3_scale(a->axis, 1 / la), glms_vec3_scale(b->axis, 1 / lb));
        axes = glms_vec3_norm(d) < 1e-6f;
    }
    return a->builtin_scene && b->builtin_scene && fabsf(turns) < 1e6f && turns == floorf(turns) &&
           axes && a->aa == b->aa &&
           (a->aa == RAS_AA_NONE ||
            (a->samples == b->samples && a->pattern_kind == b->pattern_kind)) &&
           a->shader == b->shader && a->filter == b->filter && a->affine == b->affine;
}

/* ---- the catalogue of reference images ------------------------------------ */

/* The catalogue in the program's reference folder, read once; NULL (err
 * set when given) when it cannot be read. */
static const ras_catalogue *catalogue(const ras_app *app, ras_error *err) {
    static ras_catalogue cat;
    static int state; /* 0 not read, 1 read, -1 failed */
    static ras_error failure;
    if (!state) {
        char path[RAS_IO_MAX_PATH];
        snprintf(path, sizeof path, "%s/catalogue.json", app->hooks->reference_dir);
        state = ras_catalogue_load(path, &cat, &failure) ? 1 : -1;
    }
    if (state < 0 && err) *err = failure;
    return state > 0 ? &cat : NULL;
}

/* The settings a catalogue entry's arguments give on this program's scene. */
static bool entry_settings(const ras_app *app, const ras_catalogue_entry *e,
                           ras_app_settings *out) {
    char *argv[RAS_CATALOGUE_MAX_ARGS + 1];
    argv[0] = (char *)app->hooks->program;
    for (int i = 0; i < e->argc; i++)
        argv[i + 1] = (char *)e->args[i];
    ras_cli cli;
    ras_error err = {{0}};
    return ras_cli_parse(e->argc + 1, argv, app->hooks->options, &cli, &err) == RAS_CLI_RUN &&
           ras_app_resolve(app->hooks, &cli, app->scene, out, &err);
}

bool ras_app_reference_name(const ras_app *app, char *buf, size_t size) {
    const ras_catalogue *cat = app->set.builtin_scene ? catalogue(app, NULL) : NULL;
    for (int i = 0; cat && i < cat->count; i++) {
        const ras_catalogue_entry *e = &cat->entries[i];
        ras_app_settings s;
        if (!strcmp(e->program, app->hooks->program) && entry_settings(app, e, &s) &&
            same_picture(&app->set, &s)) {
            snprintf(buf, size, "%s", e->reference);
            return true;
        }
    }
    return false;
}

/* "hw2_1x (no options), hw2_msaa4 (--aa msaa --samples 4), ...". */
static void list_references(const ras_app *app, char *buf, size_t size) {
    const ras_catalogue *cat = catalogue(app, NULL);
    size_t n = 0;
    buf[0] = '\0';
    for (int i = 0; cat && i < cat->count && n < size; i++) {
        const ras_catalogue_entry *e = &cat->entries[i];
        if (strcmp(e->program, app->hooks->program)) continue;
        char args[256];
        ras_catalogue_args_text(e, args, sizeof args);
        int w = snprintf(buf + n, size - n, "%s%s (%s)", n ? ", " : "", e->reference, args);
        n += w > 0 ? (size_t)w : 0;
    }
}

/* The reference and the comparison's work are held while the frame is drawn
 * and compared: checked against the budget now, before anything is drawn,
 * and committed, so the frame's own estimate sees what is left (one budget
 * for the run, not one per part: an 8192x8192 --compare took 5.2 GB under a
 * 2 GiB budget). comparison_fits is false with err when they do not fit. */
static double comparison_bytes(int width, int height) {
    return (double)width * (double)height * sizeof(vec3s) + ras_compare_work_bytes(width, height);
}

static bool comparison_fits(double bytes, const char *path, int width, int height, ras_error *err) {
    char what[RAS_IO_MAX_PATH + 128];
    snprintf(what, sizeof what, "--compare with %s (a %dx%d reference and the comparison's work)",
             path, width, height);
    return ras_memory_check(bytes, what, "compare at a smaller --size", err);
}

/* The image --compare compares with, loaded before anything is drawn so a
 * missing or mismatched one is a usage error (exit 2) that leaves no output
 * behind. NULL (message set) when there is none; `path` names it. */
static ras_image *load_reference(const ras_app *app, char *path, size_t size, ras_error *err) {
    const char *program = app->hooks->program;
    char name[RAS_CATALOGUE_NAME], list[1024];
    if (app->cli.reference) {
        snprintf(path, size, "%s", app->cli.reference);
    } else if (!app->set.builtin_scene) {
        ras_error_set(err,
                      "--compare with --%s needs --reference FILE (the reference images "
                      "show the built-in scene)",
                      app->cli.model ? "model" : "scene");
        return NULL;
    } else if (!catalogue(app, err)) {
        return NULL;
    } else if (!ras_app_reference_name(app, name, sizeof name)) {
        list_references(app, list, sizeof list);
        ras_error_set(err,
                      "no reference image for these settings; %s's references "
                      "(%s/catalogue.json) are %s; use one of those settings, or pass "
                      "--reference FILE for another",
                      program, app->hooks->reference_dir, list);
        return NULL;
    } else {
        snprintf(path, size, "%s/%s.png", app->hooks->reference_dir, name);
    }
    /* The reference must be the render's size (checked below): what it and
     * the comparison hold is known before its pixels are decoded. */
    double held = comparison_bytes(app->set.width, app->set.height);
    if (!comparison_fits(held, path, app->set.width, app->set.height, err)) return NULL;
    ras_image *expected = ras_image_load(path, err);
    if (!expected) {
        if (app->cli.reference) {
            ras_error why = *err;
            ras_error_set(err, "--reference: %s", why.msg);
        }
        return NULL;
    }
    if (!ras_compare_reference_fits(expected, path, app->set.width, app->set.height, err)) {
        ras_image_destroy(expected);
        return NULL;
    }
    ras_memory_commit(held);
    return expected;
}

/* ---- the frame ------------------------------------------------------------- */

bool ras_app_draw_frame(ras_app *app, ras_error *err) {
    const ras_app_hooks *h = app->hooks;
    ras_pipeline_config cfg;
    memset(&cfg, 0, sizeof cfg); /* the fields a program leaves out are 0 */
    if (!h->configure(app, &cfg, err)) return false;
    /* The shell's own state, not the program's to copy: --dump and the
     * window's views keep the frame's buffers, the step view draws a prefix. */
    cfg.dump = app->cli.dump != NULL || ras_app_capturing(app);
    cfg.step = app->step.on;
    cfg.step_triangles = app->step.limit;
    if (app->pipeline && ras_pipeline_config_equal(&app->pipeline_config, &cfg)) {
        ras_pipeline_begin_frame(app->pipeline);
    } else { /* a new one, made cleared (ras_pipeline_create) */
        ras_pipeline *p = ras_pipeline_create(&cfg, err);
        if (!p) return false;
        ras_pipeline_destroy(app->pipeline);
        app->pipeline = p;
        app->pipeline_config = cfg;
    }
    app->counters = &app->pipeline->counters;
    if (!h->draw(app, app->pipeline, err)) return false;
    ras_pipeline_end_frame(app->pipeline, app->image);
    return true;
}

/* The program's frame: the shell's, or one drawn another way (hooks.render). */
static bool frame(ras_app *app, ras_error *err) {
    return app->hooks->render ? app->hooks->render(app, err) : ras_app_draw_frame(app, err);
}

/* ---- headless ------------------------------------------------------------- */

/* Saves an image made from the comparison beside -o (FILE_diff.png), or in
 * the current folder without -o. */
static void save_beside(const ras_app *app, ras_image *img, const char *suffix, const char *what,
                        ras_error *err) {
    char path[RAS_IO_MAX_PATH + 16], stem[RAS_CATALOGUE_NAME];
    if (app->cli.reference || !ras_app_reference_name(app, stem, sizeof stem))
        snprintf(stem, sizeof stem, "%s", app->hooks->program);
    ras_cli_sibling_path(app->cli.output, stem, suffix, path, sizeof path);
    if (img && ras_image_save(img, path, err))
        printf("  %s: %s\n", what, path);
    else
        fprintf(stderr, "%s: no %s: %s\n", app->hooks->program, what, err->msg);
    ras_image_destroy(img);
}

/* Returns the exit status: 0 match, 1 mismatch, 2 when the comparison could
 * not be made (out of memory): an error, never the verdict "they differ". */
static int compare_with_reference(const ras_app *app, const ras_image *expected, const char *path) {
    ras_error err = {{0}};
    /* The catalogue's comparison for these settings: the grader judges the
     * same picture with the same table (ras_catalogue.h), so this verdict
     * and the grade agree. */
    const ras_catalogue *cat = catalogue(app, NULL);
    char name[RAS_CATALOGUE_NAME];
    const ras_catalogue_entry *e = cat && ras_app_reference_name(app, name, sizeof name)
                                       ? ras_catalogue_find(cat, name)
                                       : NULL;
    ras_compare_options opt = e ? e->compare : ras_compare_defaults(app->hooks->compare);
    if (e) printf("comparison %s (tests/reference/catalogue.json, as the grader)\n", e->comparison);
    ras_compare_result res;
    ras_comparison *cmp = ras_comparison_create(expected, app->image, opt.kind, &err);
    if (!cmp || !ras_comparison_result(cmp, &opt, &res, &err)) {
        fprintf(stderr, "%s: cannot compare with %s: %s\n", app->hooks->program, path, err.msg);
        ras_comparison_destroy(cmp);
        return 2;
    }
    printf("compare %s: %s\n", path, res.summary);
    printf("  PSNR %.2f dB, SSIM %.4f, %ld pixels off by more than %d/255\n", res.psnr_db, res.ssim,
           res.bad_pixels, opt.tolerance);
    save_beside(app, ras_comparison_heatmap(cmp, &err), "diff",
                "difference image (black = same, blue..red = more different)", &err);
    if (!res.pass)
        save_beside(app, ras_comparison_crop(cmp, res.worst_col, res.worst_row, &err), "worst",
                    "worst region (expected | got | difference)", &err);
    ras_comparison_destroy(cmp);
    return res.pass ? 0 : 1;
}

/* A message naming the staged --dump folder names the folder asked for. */
static void dump_words(ras_error *err) {
    if (!g_dump_stage.active) return;
    char *at = strstr(err->msg, g_dump_stage.temp);
    if (!at) return;
    char rest[sizeof err->msg];
    snprintf(rest, sizeof rest, "%s", at + strlen(g_dump_stage.temp));
    snprintf(at, sizeof err->msg - (size_t)(at - err->msg), "%s%s", g_dump_stage.target, rest);
    dump_words(err); /* the next mention */
}

static int run_headless(ras_app *app, const ras_image *expected, const char *reference_path) {
    ras_error err = {{0}};
    const char *output = app->cli.output;
    if (!frame(app, &err)) {
        dump_words(&err);
        fprintf(stderr, "%s: %s\n", app->hooks->program, err.msg);
        return 1;
    }
    if (app->cli.dump) {
        /* The pipeline's buffers (its fragment stage's among them), then
         * the whole folder into place, before -o: a dump that fails leaves
         * -o as it was. */
        int written = 0;
        if ((app->pipeline && !ras_pipeline_dump(app->pipeline, app->cli.dump, &written, &err)) ||
            !ras_dump_stage_commit(&g_dump_stage, &err)) {
            dump_words(&err);
            /* The stage's own messages already begin with "--dump". */
            const char *tag = strncmp(err.msg, "--dump", 6) == 0 ? "" : "--dump: ";
            fprintf(stderr, "%s: %s%s; '%s' and the output were left as they were\n",
                    app->hooks->program, tag, err.msg, g_dump_stage.target);
            ras_dump_stage_abort(&g_dump_stage);
            return 1;
        }
    }
    if (output && !ras_image_save(app->image, output, &err)) {
        fprintf(stderr, "%s: %s\n", app->hooks->program, err.msg);
        return 1;
    }
    if (output && (app->hooks->options & RAS_OPT_SHADING))
        fprintf(stderr, "wrote %s (%s shader, %s filter)\n", output,
                ras_name_of(&ras_names_shader, (int)app->set.shader),
                ras_name_of(&ras_names_filter, (int)app->set.filter));
    else if (output)
        fprintf(stderr, "wrote %s\n", output);
    if (app->cli.dump)
        fprintf(stderr, "wrote the frame's buffers into %s/ (docs/debugging.md)\n",
                g_dump_stage.target);
    if (app->cli.stats && app->counters) {
        char json[2048];
        ras_counters_format_json(app->counters, json, sizeof json);
        /* stdout closed, a full disk, a pipe gone: the JSON is lost, say so */
        errno = 0;
        if (puts(json) == EOF || fflush(stdout) != 0 || ferror(stdout)) {
            fprintf(stderr,
                    "%s: --stats: could not write the counters to standard output (%s); "
                    "expected a writable stdout — redirect it to a file with room\n",
                    app->hooks->program, errno ? strerror(errno) : "write error");
            return 1;
        }
    }
    return expected ? compare_with_reference(app, expected, reference_path) : 0;
}

/* ---- the window ------------------------------------------------------------ */

static int next_count(ras_pattern_kind kind, int count) {
    static const int ordered[] = {4, 16, 64, 0}, standard[] = {2, 4, 8, 16, 0};
    const int *list = kind == RAS_PATTERN_ORDERED ? ordered : standard;
    for (int i = 0; list[i]; i++)
        if (list[i] == count) return list[i + 1] ? list[i + 1] : list[0];
    return 4; /* every pattern has 4 */
}

/* m: AA mode, s: sample count, p: pattern. */
static bool aa_key(ras_app_settings *s, int key) {
    if (key == 'm')
        s->aa = s->aa == RAS_AA_NONE   ? RAS_AA_MSAA
                : s->aa == RAS_AA_MSAA ? RAS_AA_SSAA
                                       : RAS_AA_NONE;
    else if (key == 's' && s->aa == RAS_AA_NONE)
        s->aa = RAS_AA_MSAA;
    else if (key == 's')
        s->samples = next_count(s->pattern_kind, s->samples);
    else if (key == 'p')
        s->pattern_kind =
            s->pattern_kind == RAS_PATTERN_ORDERED ? RAS_PATTERN_STANDARD : RAS_PATTERN_ORDERED;
    else
        return false;
    ras_sample_pattern probe;
    if (!ras_sample_pattern_make(s->pattern_kind, s->samples, &probe, NULL))
        s->samples = 4; /* every pattern has 4 */
    return true;
}

/* ---- the step view and the buffer view ---------------------------------------- */

bool ras_app_capturing(const ras_app *app) {
    return (app->hooks->features & RAS_APP_STEP) &&
           (app->step.on || app->step.buffer != RAS_APP_BUFFER_COLOUR);
}

/* Whether the window magnifies the pixel under the mouse: always for a
 * program with the inspector, and in the step view. */
static bool inspecting(const ras_app *app) {
    unsigned f = app->hooks->features;
    return (f & RAS_APP_INSPECTOR) || ((f & RAS_APP_STEP) && app->step.on);
}

static const char *const buffer_names[RAS_APP_BUFFER_COUNT] = {"colour",   "depth",  "coverage",
                                                               "overdraw", "normal", "uv"};

/* Buffer k of the last frame (not colour): the pipeline's (its fragment
 * stage's among them). *owned: what to free. */
static bool frame_buffer(const ras_app *app, int k, ras_dump_buffer *b, float **owned) {
    *owned = NULL;
    if (k == RAS_APP_BUFFER_COLOUR) return false;
    return app->pipeline && ras_pipeline_buffer(app->pipeline, buffer_names[k], b, owned);
}

static bool frame_has_buffer(const ras_app *app, int k) {
    ras_dump_buffer b;
    float *owned = NULL;
    bool has = frame_buffer(app, k, &b, &owned);
    free(owned);
    return has;
}

/* After a frame: the count the status line shows, and the buffer shown moved
 * on past those the frame does not produce (no AA: no coverage; the normal
 * shader: no uv). */
static void step_after_frame(ras_app *app) {
    ras_app_step *st = &app->step;
    const ras_pipeline *p = app->pipeline;
    st->total = !p ? 0 : st->on ? p->step_reached : (long)p->counters.triangles_rasterized;
    if (st->limit > st->total) st->limit = st->total;
    while (st->buffer != RAS_APP_BUFFER_COLOUR && !frame_has_buffer(app, st->buffer))
        st->buffer = (ras_app_buffer)((st->buffer + 1) % RAS_APP_BUFFER_COUNT);
}

/* t, n/space, N, 0-9 (in step mode), b; true when the frame changed. */
static bool step_key(ras_app *app, int key) {
    ras_app_step *st = &app->step;
    if (key == 't') {
        st->on = !st->on;
        st->limit = 0;
    } else if (key == 'n' || key == ' ') {
        st->limit = st->on ? st->limit + 1 : 1;
        st->on = true;
    } else if (key == '-' && st->on) {
        st->limit = st->limit > 0 ? st->limit - 1 : 0;
    } else if (st->on && key >= '0' && key <= '9') {
        long jump = 1;
        for (int k = 1; k < key - '0'; k++)
            jump *= 10;
        st->limit = key == '0' ? 0 : st->limit + jump; /* clamped after the frame */
    } else if (key == 'b') {
        st->buffer = (ras_app_buffer)((st->buffer + 1) % RAS_APP_BUFFER_COUNT);
    } else {
        return false;
    }
    return true;
}

/* The buffer shown, painted as --dump paints it (ras_dump_paint); NULL when
 * the frame has none or memory runs out. */
static ras_image *buffer_picture(const ras_app *app, char *legend, size_t size) {
    ras_dump_buffer b;
    float *owned = NULL;
    if (!frame_buffer(app, app->step.buffer, &b, &owned)) return NULL;
    ras_image *img = NULL;
    uint8_t *rgb = b.width == app->image->width && b.height == app->image->height
                       ? malloc((size_t)b.width * b.height * 3)
                       : NULL;
    if (rgb) img = ras_image_create(b.width, b.height, NULL);
    if (img) {
        ras_dump_paint(&b, rgb, legend, size);
        for (long i = 0, n = (long)b.width * b.height; i < n; i++)
            img->pixels[i] =
                (vec3s){{rgb[3 * i] / 255.0f, rgb[3 * i + 1] / 255.0f, rgb[3 * i + 2] / 255.0f}};
    }
    free(rgb);
    free(owned);
    return img;
}

/* The step view's status lines: "STEP: triangle 12 of 968   buffer: depth (b)"
 * and the keys, each short enough to stay left of the magnified pixels. */
static void step_status(const ras_app *app, char *buf, size_t size) {
    const ras_app_step *st = &app->step;
    const char *next = buffer_names[(st->buffer + 1) % RAS_APP_BUFFER_COUNT];
    if (st->on)
        snprintf(buf, size,
                 "STEP: triangle %ld of %ld   buffer: %s (b)\n"
                 "n/space +1  - back 1  1-9 +1,10,100..  0 none  t off",
                 st->limit, st->total, buffer_names[st->buffer]);
    else
        snprintf(buf, size, "buffer: %s (b: %s...)  t: step", buffer_names[st->buffer], next);
}

/* The keys the shell handles for the program; true when the frame changed. */
static bool shell_key(ras_app *app, int key) {
    ras_app_settings *s = &app->set;
    unsigned keys = app->hooks->keys;
    if ((app->hooks->features & RAS_APP_STEP) && step_key(app, key))
        return true; /* before 1-5: digits step */
    if ((keys & RAS_APP_KEYS_ANGLE) && (key == 'a' || key == 'd')) {
        s->angle += key == 'a' ? 10 : -10;
        return true;
    }
    if ((keys & RAS_APP_KEYS_SHADING) && key >= '1' && key < '1' + RAS_SHADER_COUNT - 1) {
        s->shader = (ras_scene_shader)(RAS_SHADER_NORMAL + key - '1');
        return true;
    }
    if ((keys & RAS_APP_KEYS_SHADING) && key == 'f') {
        s->filter = (ras_scene_filter)((s->filter + 1) % ras_names_filter.count);
        return true;
    }
    if ((keys & RAS_APP_KEYS_AA) && aa_key(s, key)) return true;
    return app->hooks->key && app->hooks->key(app, key);
}

/* The window's picture: the frame or the buffer shown, with the inspector
 * when the mouse is on it (hw2, and every program in step mode). */
static ras_image *window_view(ras_app *app, const ras_viewer *viewer, int col, int row,
                              char *status, size_t size) {
    if (app->hooks->status) app->hooks->status(app, status, size);
    bool program = ras_viewer_showing_program(viewer);
    ras_image *picture = NULL; /* the buffer shown, when not colour */
    if (ras_app_capturing(app)) {
        char line[200], legend[200] = "";
        if (program && app->step.buffer != RAS_APP_BUFFER_COLOUR)
            picture = buffer_picture(app, legend, sizeof legend);
        step_status(app, line, sizeof line);
        size_t n = strlen(status);
        snprintf(status + n, size - n, "\n%s%s%s", line, *legend ? "\n" : "", legend);
    }
    bool inspect = inspecting(app);
    const ras_image *shown = picture ? picture : app->image;
    if (!inspect) return picture ? picture : app->image;
    ras_image *view = ras_image_clone(shown);
    char info[400] = "move the mouse over the picture to inspect a pixel";
    if (view && col >= 0 && app->pipeline && program) {
        int y = app->image->height - 1 - row;
        ras_viewer_inspect(view, shown, app->pipeline->fb, &app->pipeline->config.pattern, col, y,
                           info, sizeof info);
        size_t n = strlen(info);
        if (app->step.on && app->pipeline->has_last) {
            snprintf(info + n, sizeof info - n, "\n");
            ras_viewer_inspect_triangle(&app->pipeline->last_triangle, col, y, info + n + 1,
                                        sizeof info - n - 1);
        } else if (app->step.on) {
            snprintf(info + n, sizeof info - n, "\nno triangle drawn yet: n draws the first");
        }
    }
    ras_image_destroy(picture);
    size_t n = strlen(status);
    snprintf(status + n, size - n, "\n%s", info);
    return view;
}

static int run_window(ras_app *app) {
    const char *title = app->hooks->program;
    ras_error err = {{0}};
    ras_viewer viewer;
    ras_viewer_init(&viewer, title, app->argv0, app->hooks->reference_dir, app->hooks->compare);
    bool dirty = true, redraw = true, ok = true;
    int mouse_col = -1, mouse_row = -1;
    while (ok) {
        if (dirty) {
            ras_viewer_frame_begin(&viewer);
            if (!(ok = frame(app, &err))) break;
            ras_viewer_frame_end(&viewer);
            if ((app->hooks->features & RAS_APP_STEP)) step_after_frame(app);
            char name[RAS_CATALOGUE_NAME];
            bool found = ras_app_reference_name(app, name, sizeof name);
            ras_viewer_set_reference(&viewer, found ? name : NULL, app->set.width, app->set.height);
            dirty = false;
            redraw = true;
        }
        if (redraw) {
            char status[1200];
            ras_image *view =
                window_view(app, &viewer, mouse_col, mouse_row, status, sizeof status);
            ok = view ? ras_viewer_show(&viewer, view, status, &err)
                      : ras_error_set(&err, "out of memory");
            if (view != app->image) ras_image_destroy(view);
            redraw = false;
        }
        int key = ras_window_wait_key(title, 30);
        if (key == RAS_KEY_ESC || key == 'q' || key == -2) {
            ras_window_close(title);
            break;
        }
        if (ras_viewer_key(&viewer, key))
            redraw = true;
        else if (key >= 0 && shell_key(app, key))
            dirty = true;
        int col, row;
        if (ok && ras_window_mouse(title, &col, &row) && (col != mouse_col || row != mouse_row)) {
            if (app->hooks->mouse && app->hooks->mouse(app, col, row)) dirty = true;
            if (inspecting(app) && col >= 0 && row >= 0 && col < app->set.width &&
                row < app->set.height)
                mouse_col = col, mouse_row = row, redraw = true;
        }
    }
    ras_viewer_release(&viewer);
    if (ok) return 0;
    fprintf(stderr, "%s: %s\n", title, err.msg);
    return 1;
}

/* ---- the program ----------------------------------------------------------- */

/* Parses; returns -1 to go on, or the exit status (help, version, error). */
static int parse(ras_app *app, int argc, char **argv) {
    const ras_app_hooks *h = app->hooks;
    ras_error err = {{0}};
    switch (ras_cli_parse(argc, argv, h->options, &app->cli, &err)) {
    case RAS_CLI_HELP: {
        char help[6144];
        ras_cli_help(h->options, h->program, h->usage, help, sizeof help);
        fputs(help, stdout);
        return 0;
    }
    case RAS_CLI_VERSION: printf("%s (Raster101) %s\n", h->program, RAS_VERSION); return 0;
    case RAS_CLI_ERROR: fprintf(stderr, "%s: %s\n", h->program, err.msg); return 2;
    case RAS_CLI_RUN: break;
    }
    return -1;
}

/* The classic positional form (OUTPUT, and with RAS_APP_POSITIONAL_SHADER a SHADER)
 * and the option pairs that cannot go together. */
static bool check_arguments(ras_app *app, ras_error *err) {
    ras_cli *cli = &app->cli;
    const ras_app_hooks *h = app->hooks;
    int n = cli->positional_count, max = (h->features & RAS_APP_POSITIONAL_SHADER) ? 2 : 1;
    if (n > max || (n >= 1 && cli->output))
        return ras_error_set(
            err, "unexpected argument '%s'; expected %s (e.g. %s %s)", cli->positional[n - 1],
            (h->features & RAS_APP_POSITIONAL_SHADER) ? "-o FILE, or OUTPUT.png [SHADER]"
                                                      : "at most one output file",
            h->program, h->example);
    if (n == 2 && cli->shader_set)
        return ras_error_set(err, "the shader is given twice ('%s' and --shader %s); give one",
                             cli->positional[1], ras_name_of(&ras_names_shader, cli->shader));
    if (n == 2) {
        cli->shader = ras_name_find(&ras_names_shader, cli->positional[1], RAS_SHADER_NORMAL);
        char list[96];
        if (cli->shader < 0)
            return ras_error_set(
                err, "--shader expects %s; got '%s'",
                ras_names_list(&ras_names_shader, RAS_SHADER_NORMAL, list, sizeof list),
                cli->positional[1]);
        cli->shader_set = true;
    }
    if (n >= 1) cli->output = cli->positional[0];
    if (cli->model && cli->scene)
        return ras_error_set(err, "--model and --scene both name the scene; give one (a scene "
                                  "file names its models itself)");
    if (!cli->model && (cli->texture || cli->height_map || cli->fit))
        return ras_error_set(err, "--texture, --height and --fit go with --model FILE; add "
                                  "--model, or drop them");
    /* A file that cannot be written is a usage error: say so before any work. */
    ras_io_set_force(cli->force);
    /* A closed stdout would lose --stats, or hand fd 1 to the next file opened. */
    if (cli->stats && fcntl(STDOUT_FILENO, F_GETFD) == -1)
        return ras_error_set(err, "--stats prints to standard output, which is closed; expected "
                                  "an open stdout — redirect it to a file (> stats.json)");
    if (cli->output && !ras_image_check_output(cli->output, err)) return false;
    if (cli->dump && !cli->output && !cli->compare)
        return ras_error_set(err,
                             "--dump DIR writes the buffers of one headless frame; add -o "
                             "FILE (e.g. %s %s --dump buffers)",
                             h->program, h->example);
    /* --dump: checked now, written into a temporary folder, moved into place
     * when every buffer is there (ras_dump_stage_*). */
    if (cli->dump && !ras_dump_stage_begin(&g_dump_stage, cli->dump, err)) return false;
    if (cli->dump) cli->dump = g_dump_stage.temp;
    if (!cli->output && !cli->compare && !ras_window_available())
        return ras_error_set(err,
                             "no display to open a window on (DISPLAY is not set); render "
                             "to a file instead, e.g. %s %s",
                             h->program, h->example);
    return true;
}

/* ---- an output never replaces an input ------------------------------------ */

/* One file the run reads: `what` names it for the message. */
typedef struct run_input {
    char what[96];
    const char *path;
} run_input;

/* The k-th file this run reads (k from 0): the scene file, the reference,
 * then each object's model, texture and height map (--model, --texture and
 * --height are the built-in model scene's). False past the last. Entries
 * with no file have path NULL. */
static bool input_at(const ras_app *app, const char *ref_path, int k, run_input *in) {
    const ras_cli *cli = &app->cli;
    in->path = NULL;
    if (k == 0) {
        snprintf(in->what, sizeof in->what, "the --scene file");
        in->path = cli->scene;
        return true;
    }
    if (k == 1) {
        snprintf(in->what, sizeof in->what, "the reference image --compare reads");
        in->path = cli->compare && ref_path[0] ? ref_path : NULL;
        return true;
    }
    int i = (k - 2) / 3, part = (k - 2) % 3;
    if (!app->scene || i >= app->scene->object_count) return false;
    const ras_scene_object *o = &app->scene->objects[i];
    static const char *const flag[] = {"--model", "--texture", "--height"};
    static const char *const noun[] = {"model", "texture", "height map"};
    if (cli->model)
        snprintf(in->what, sizeof in->what, "the %s file", flag[part]);
    else
        snprintf(in->what, sizeof in->what, "the %s of object %d of the scene", noun[part], i);
    const ras_scene_map *map = part == 1 ? &o->material.texture : &o->material.height_map;
    if (part == 0)
        in->path = o->shape == RAS_SHAPE_MODEL ? o->params.model_path : NULL;
    else
        in->path = map->kind == RAS_MAP_FILE ? map->path : NULL;
    return true;
}

/* The input `out_st` (an existing file, links followed) is, if any. */
static bool input_is(const ras_app *app, const char *ref_path, const struct stat *out_st,
                     run_input *in) {
    struct stat st;
    for (int k = 0; input_at(app, ref_path, k, in); k++)
        if (in->path && stat(in->path, &st) == 0 && st.st_dev == out_st->st_dev &&
            st.st_ino == out_st->st_ino)
            return true;
    return false;
}

/* The dump writes .png, .pfm and .json files into its folder (ras_dump.c's
 * own rule for what is its): an input of those kinds in that folder could
 * be replaced by a buffer of the same name. */
static bool dump_could_replace(const char *name) {
    const char *dot = strrchr(name, '.');
    return dot && (!strcmp(dot, ".png") || !strcmp(dot, ".pfm") || !strcmp(dot, ".json"));
}

/* The input inside the existing folder `dir_st` that the dump could replace. */
static bool input_in_folder(const ras_app *app, const char *ref_path, const struct stat *dir_st,
                            run_input *in) {
    for (int k = 0; input_at(app, ref_path, k, in); k++) {
        char *real = in->path ? realpath(in->path, NULL) : NULL;
        char *slash = real ? strrchr(real, '/') : NULL;
        bool inside = false;
        if (slash && dump_could_replace(slash + 1)) {
            slash[slash == real ? 1 : 0] = '\0'; /* its folder ("/" kept) */
            struct stat st;
            inside =
                stat(real, &st) == 0 && st.st_dev == dir_st->st_dev && st.st_ino == dir_st->st_ino;
        }
        free(real);
        if (inside) return true;
    }
    return false;
}

/* -o, the difference images --compare writes beside it, and --dump must not
 * name (or reach through a link, a hard link or another spelling) a file the
 * run reads: it would be gone after the frame. Checked once the scene has
 * said which files it reads, before anything is drawn. */
static bool check_outputs_spare_inputs(const ras_app *app, const char *ref_path, ras_error *err) {
    const ras_cli *cli = &app->cli;
    run_input in;
    struct stat st;
    char files[3][RAS_IO_MAX_PATH + 16] = {"", "", ""};
    const char *opt[3] = {"-o", "--compare's difference image", "--compare's worst-pixels image"};
    if (cli->output) snprintf(files[0], sizeof files[0], "%s", cli->output);
    if (cli->compare) {
        char stem[RAS_CATALOGUE_NAME];
        if (cli->reference || !ras_app_reference_name(app, stem, sizeof stem))
            snprintf(stem, sizeof stem, "%s", app->hooks->program);
        ras_cli_sibling_path(cli->output, stem, "diff", files[1], sizeof files[1]);
        ras_cli_sibling_path(cli->output, stem, "worst", files[2], sizeof files[2]);
    }
    for (int f = 0; f < 3; f++)
        if (files[f][0] && stat(files[f], &st) == 0 && input_is(app, ref_path, &st, &in))
            return ras_error_set(err,
                                 "%s '%s' is %s ('%s'): writing it would destroy an input of "
                                 "this run; expected an output name that is none of its "
                                 "inputs — write to another file",
                                 opt[f], files[f], in.what, in.path);
    const char *dump = g_dump_stage.active ? g_dump_stage.target : NULL;
    if (dump && stat(dump, &st) == 0 && input_in_folder(app, ref_path, &st, &in))
        return ras_error_set(err,
                             "--dump '%s' holds %s ('%s'), and the dump writes its .png, .pfm "
                             "and .json buffers into that folder, which could replace it; "
                             "expected a dump folder apart from the inputs — dump into "
                             "another folder",
                             dump, in.what, in.path);
    return true;
}

/* --dump's buffers for the frame the settings ask for, committed to the
 * budget for the rest of the run (the process ends after its frame). */
static bool reserve_dump(const ras_app *app, ras_error *err) {
    double pixels = (double)app->set.width * app->set.height;
    double samples = pixels * ras_app_settings_pattern(&app->set).count;
    double bytes =
        samples * RAS_MEMORY_DUMP_BYTES_PER_SAMPLE + pixels * RAS_MEMORY_DUMP_BYTES_PER_PIXEL;
    char what[96];
    snprintf(what, sizeof what, "--dump of a %dx%d frame with %d samples per pixel", app->set.width,
             app->set.height, ras_app_settings_pattern(&app->set).count);
    if (!ras_memory_check(bytes, what, "dump a smaller --size or fewer --samples", err))
        return false;
    ras_memory_commit(bytes);
    return true;
}

/* Everything before the first frame; false with err when the input is bad
 * (exit 2). */
static bool set_up(ras_app *app, ras_image **expected, char *ref_path, size_t size,
                   ras_error *err) {
    const ras_app_hooks *h = app->hooks;
    if (!check_arguments(app, err)) return false;
    const ras_cli *cli = &app->cli;
    assert(!cli->model || h->model_scene); /* RAS_OPT_MODEL comes with a model scene */
    app->scene = cli->model ? ras_builtin_scene_with_model(h->model_scene, cli->model, cli->texture,
                                                           cli->height_map, cli->fit, err)
                            : ras_scene_load_or_builtin(cli->scene, h->scene, err);
    if (!app->scene) return false;
    if ((h->features & RAS_APP_LOAD_ASSETS) &&
        !(app->assets = (h->features & RAS_APP_WITHOUT_MAPS)
                            ? ras_scene_load_meshes(app->scene, err)
                            : ras_scene_load_assets(app->scene, err)))
        return false;
    if (!ras_app_resolve(h, &app->cli, app->scene, &app->set, err) ||
        (h->prepare && !h->prepare(app, err)))
        return false;
    /* Too big a frame, or a reference that cannot be compared with, are
     * usage errors too: found before anything is drawn or written. The
     * dump's buffers are held beside the frame: counted first, so the
     * frame's check sees the sum. */
    if (app->cli.dump && !reserve_dump(app, err)) return false;
    if (!ras_framebuffer_check_size(app->set.width, app->set.height,
                                    ras_app_settings_pattern(&app->set).count, err))
        return false;
    if (app->cli.compare && !(*expected = load_reference(app, ref_path, size, err))) return false;
    return check_outputs_spare_inputs(app, ref_path, err);
}

/* A student program built before the student's last edit runs older code:
 * say so first (after an edit without a build, build/bin/hw1_transform would
 * print the old TODO notice). Sources that cannot be read say nothing. */
static void warn_if_stale(const ras_app_hooks *hooks) {
    struct stat exe, src;
    if (!hooks->student_sources || stat("/proc/self/exe", &exe) != 0) return;
    for (const char *p = hooks->student_sources; *p;) {
        size_t n = strcspn(p, ":");
        char path[RAS_IO_MAX_PATH];
        snprintf(path, sizeof path, "%.*s", (int)n, p);
        if (stat(path, &src) == 0 && src.st_mtime > exe.st_mtime) {
            fprintf(stderr,
                    "%s: note: this program was built before your last edit of %s, so "
                    "it runs your older code; run `make build` (make grade and make "
                    "test build it too)\n",
                    hooks->program, path);
            return;
        }
        p += n + (p[n] == ':');
    }
}

int ras_app_main(int argc, char **argv, const ras_app_hooks *hooks, void *user) {
    assert(hooks->configure && hooks->draw); /* the frame's two hooks */
    ras_cli_reuse_freed_memory();            /* fewer page faults: ras_cli.h */
    ras_app app = {.hooks = hooks, .argv0 = argc > 0 ? argv[0] : hooks->program, .user = user};
    int status = parse(&app, argc, argv);
    if (status >= 0) return status;
    warn_if_stale(hooks);
    ras_error err = {{0}};
    ras_image *expected = NULL;
    char ref_path[RAS_IO_MAX_PATH + 16] = "";
    if (!set_up(&app, &expected, ref_path, sizeof ref_path, &err)) {
        fprintf(stderr, "%s: %s\n", hooks->program, err.msg);
        status = 2;
    } else if (!(app.image = ras_image_create(app.set.width, app.set.height, &err))) {
        fprintf(stderr, "%s: %s\n", hooks->program, err.msg);
        status = 1;
    } else if (app.cli.output || app.cli.compare) {
        status = run_headless(&app, expected, ref_path);
    } else {
        status = run_window(&app);
    }
    ras_dump_stage_abort(&g_dump_stage); /* not committed: nothing half-written stays */
    ras_image_destroy(expected);
    ras_image_destroy(app.image);
    ras_pipeline_destroy(app.pipeline);
    ras_scene_assets_destroy(app.assets);
    ras_scene_destroy(app.scene);
    return status;
}

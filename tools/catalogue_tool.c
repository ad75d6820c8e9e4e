/* catalogue_tool.c — raster101-catalogue: the reference catalogue
 * (tests/reference/catalogue.json, common/app/ras_catalogue.h) for scripts.
 *
 *   raster101-catalogue [--catalogue FILE] list
 *       one line an image: REFERENCE<TAB>PROGRAM<TAB>DEMO (or -)<TAB>ARGS
 *       (scripts/reference-images, scripts/demo, tests/e2e/gui_test.sh)
 *   raster101-catalogue [--catalogue FILE] programs
 *       the programs the catalogue names, one a line (tests/e2e/cli_bad_input_test.py)
 *   raster101-catalogue [--catalogue FILE] comparison REFERENCE
 *       the name of the comparison that judges REFERENCE (e.g. textured)
 *   raster101-catalogue [--catalogue FILE] check-rubric RUBRIC.json
 *       every rubric image with a "reference" must have the catalogue entry
 *       of that reference, with the same program, arguments and comparison,
 *       and every image names a comparison of the catalogue's table and no
 *       thresholds of its own (ctest catalogue_rubric); exit 1 naming each
 *       one that disagrees
 *
 * Exit status: 0 done, 1 the rubric disagrees, 2 bad arguments or files.
 */
#include "ras_catalogue.h"
#include "ras_io.h" /* ras_io_read_file */

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void list(const ras_catalogue *cat) {
    for (int i = 0; i < cat->count; i++) {
        const ras_catalogue_entry *e = &cat->entries[i];
        printf("%s\t%s\t%s\t", e->reference, e->program, e->demo[0] ? e->demo : "-");
        for (int a = 0; a < e->argc; a++) printf("%s%s", a ? " " : "", e->args[a]);
        printf("\n");
    }
}

static void programs(const ras_catalogue *cat) {
    for (int i = 0; i < cat->count; i++) {
        bool seen = false;
        for (int j = 0; j < i && !seen; j++)
            seen = !strcmp(cat->entries[j].program, cat->entries[i].program);
        if (!seen) printf("%s\n", cat->entries[i].program);
    }
}

/* One rubric image against the catalogue: 0 agrees, 1 (printed) not. */
static int check_image(const ras_catalogue *cat, const cJSON *img, const char *rubric) {
    const cJSON *ref = cJSON_GetObjectItemCaseSensitive(img, "reference");
    const cJSON *prog = cJSON_GetObjectItemCaseSensitive(img, "program");
    const cJSON *args = cJSON_GetObjectItemCaseSensitive(img, "args");
    const cJSON *comparison = cJSON_GetObjectItemCaseSensitive(img, "comparison");
    const cJSON *iname = cJSON_GetObjectItemCaseSensitive(img, "name");
    /* every image is judged by a comparison of the catalogue's one table */
    ras_compare_options opt;
    ras_error why = {{0}};
    if (!cJSON_IsString(comparison) ||
        !ras_catalogue_comparison_options(cat, comparison->valuestring, &opt, &why)) {
        printf("%s: image %s: expected \"comparison\": a name from the \"comparisons\" of "
               "tests/reference/catalogue.json%s%s; thresholds live only there\n",
               rubric, cJSON_IsString(iname) ? iname->valuestring : "?", *why.msg ? ": " : "",
               why.msg);
        return 1;
    }
    static const char *const own[] = {"metric", "tolerance", "max_bad", "min_psnr", "min_ssim"};
    for (int k = 0; k < 5; k++)
        if (cJSON_GetObjectItemCaseSensitive(img, own[k])) {
            printf("%s: image %s: has its own \"%s\"; expected only \"comparison\" (the "
                   "catalogue's table decides, for the grader and the students' tools alike)\n",
                   rubric, cJSON_IsString(iname) ? iname->valuestring : "?", own[k]);
            return 1;
        }
    if (!cJSON_IsString(ref)) return 0; /* drawn and judged without a reference image */
    char name[RAS_CATALOGUE_NAME];
    snprintf(name, sizeof name, "%.*s", (int)strcspn(ref->valuestring, "."), ref->valuestring);
    for (int i = 0; i < cat->count; i++) {
        const ras_catalogue_entry *e = &cat->entries[i];
        if (strcmp(e->reference, name)) continue;
        bool same = cJSON_IsString(prog) && !strcmp(prog->valuestring, e->program) &&
                    cJSON_GetArraySize(args) == e->argc;
        for (int a = 0; same && a < e->argc; a++) {
            const cJSON *v = cJSON_GetArrayItem(args, a);
            same = cJSON_IsString(v) && !strcmp(v->valuestring, e->args[a]);
        }
        if (same && strcmp(comparison->valuestring, e->comparison)) {
            printf("%s: image %s: expected comparison %s, as tests/reference/catalogue.json "
                   "judges %s.png; got %s; make the two agree\n",
                   rubric, name, e->comparison, name, comparison->valuestring);
            return 1;
        }
        if (same) return 0;
        char want[512];
        ras_catalogue_args_text(e, want, sizeof want);
        char *got = cJSON_PrintUnformatted(args);
        printf("%s: image %s: expected program %s with %s, as tests/reference/catalogue.json "
               "draws %s.png; got %s with %s; make the two agree\n",
               rubric, name, e->program, want, name, cJSON_IsString(prog) ? prog->valuestring : "?",
               got ? got : "no args");
        free(got);
        return 1;
    }
    printf("%s: image %s: expected an entry \"reference\": \"%s\" in "
           "tests/reference/catalogue.json, got none; add it there\n", rubric, name, name);
    return 1;
}

static int check_rubric(const ras_catalogue *cat, const char *path) {
    ras_error err = {{0}};
    size_t len = 0;
    char *text = ras_io_read_file(path, "the rubric", 1 << 22, &len, &err);
    cJSON *root = text ? cJSON_Parse(text) : NULL;
    free(text);
    const cJSON *assignments = cJSON_GetObjectItemCaseSensitive(root, "assignments");
    if (!cJSON_IsArray(assignments)) {
        fprintf(stderr, "raster101-catalogue: %s\n",
                err.msg[0] ? err.msg : "the rubric: expected a JSON object with \"assignments\"");
        cJSON_Delete(root);
        return 2;
    }
    int bad = 0, checked = 0;
    const cJSON *a, *img;
    cJSON_ArrayForEach(a, assignments) {
        const cJSON *images = cJSON_GetObjectItemCaseSensitive(a, "images");
        cJSON_ArrayForEach(img, images) {
            checked++;
            bad += check_image(cat, img, path);
        }
    }
    cJSON_Delete(root);
    printf("%d rubric images, %d disagree with the catalogue\n", checked, bad);
    return bad ? 1 : 0;
}

static const char usage[] =
    "usage: raster101-catalogue [--catalogue FILE] COMMAND\n"
    "  list                    one line a reference picture: REFERENCE, PROGRAM, DEMO (or -), ARGS\n"
    "                          (tab-separated): the program and arguments that draw it\n"
    "  programs                the programs the catalogue names, one a line\n"
    "  comparison REFERENCE    the name of the comparison that judges REFERENCE\n"
    "  check-rubric RUBRIC     every rubric image agrees with its catalogue entry (exit 1 if not)\n"
    "The catalogue is tests/reference/catalogue.json unless --catalogue FILE.\n";

int main(int argc, char **argv) {
    const char *file = RAS_REFERENCE_DIR "/catalogue.json";
    int i = 1;
    if (argc == 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        fputs(usage, stdout);
        return 0;
    }
    if (i + 1 < argc && !strcmp(argv[i], "--catalogue")) file = argv[i + 1], i += 2;
    const char *cmd = i < argc ? argv[i] : "";
    ras_catalogue *cat = malloc(sizeof *cat);
    ras_error err = {{0}};
    int status = 2;
    if (!cat || !ras_catalogue_load(file, cat, &err))
        fprintf(stderr, "raster101-catalogue: %s\n", cat ? err.msg : "out of memory");
    else if (!strcmp(cmd, "list") && i + 1 == argc)
        list(cat), status = 0;
    else if (!strcmp(cmd, "programs") && i + 1 == argc)
        programs(cat), status = 0;
    else if (!strcmp(cmd, "comparison") && i + 2 == argc) {
        const ras_catalogue_entry *e = ras_catalogue_find(cat, argv[i + 1]);
        if (e) printf("%s\n", e->comparison);
        else fprintf(stderr, "raster101-catalogue: no entry \"%s\" in the catalogue\n", argv[i + 1]);
        status = e ? 0 : 2;
    } else if (!strcmp(cmd, "check-rubric") && i + 2 == argc)
        status = check_rubric(cat, argv[i + 1]);
    else
        fprintf(stderr, "raster101-catalogue: expected list, programs, comparison REFERENCE or check-rubric "
                        "RUBRIC.json (after an optional --catalogue FILE); got '%s' (--help lists them)\n", cmd);
    free(cat);
    return status;
}

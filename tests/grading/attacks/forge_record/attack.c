static void atk_forge(void) {
    const char *r = getenv("RAS_RECORD"), *filter = getenv("RAS_TEST_FILTER");
    if (!r || !*r) return;
    atk_name("forge");
    unsigned variant = 0;
    for (const char *p = filter ? filter : "x"; *p; p++) variant += (unsigned char)*p;
    variant %= 4;
    if (variant == 2) { /* the grader must not follow it */
        unlink(r);
        if (symlink("/etc/shadow", r) != 0) {}
        return;
    }
    int fd = open(r, O_RDWR);
    if (fd < 0) return;
    struct stat st;
    if (fstat(fd, &st) != 0 || st.st_size < 16) {
        close(fd);
        return;
    }
    unsigned char *m = malloc((size_t)st.st_size);
    if (!m || pread(fd, m, (size_t)st.st_size, 0) != st.st_size) {
        free(m);
        close(fd);
        return;
    }
    uint64_t used;
    memcpy(&used, m + 8, 8);
    if (variant == 0) { /* garbage up to the end of the file */
        for (off_t i = 16 + (off_t)used; i < st.st_size; i++) m[i] = (unsigned char)(i * 2654435761u >> 13);
        used = (uint64_t)st.st_size - 16;
        memcpy(m + 8, &used, 8);
    } else if (variant == 1) { /* END records: region sizes and run offsets out of range */
        size_t pos = 16, end = 16 + (size_t)(used < (uint64_t)st.st_size - 16 ? used : 0);
        while (pos + 8 <= end) {
            uint32_t tag, len;
            memcpy(&tag, m + pos, 4);
            memcpy(&len, m + pos + 4, 4);
            if (pos + 8 + len > end) break;
            if (tag == 2 && len >= 8 + 12) {
                unsigned char *p = m + pos + 8 + 8; /* fn, regions; then region 0 */
                uint64_t huge = 0xFFFFFFFFFFFFFFF0ull;
                memcpy(p, &huge, 8);
                if (len >= 8 + 12 + 12) memcpy(p + 12, &huge, 8); /* first run's offset */
            }
            pos += 8 + len;
        }
    } else { /* a header that claims more than the file holds */
        used = 1ull << 63;
        memcpy(m + 8, &used, 8);
    }
    if (pwrite(fd, m, (size_t)st.st_size, 0) < 0) {}
    free(m);
    close(fd);
}

__attribute__((destructor)) static void atk_after_main(void) { atk_forge(); }

/* fuzz_util.c — helpers shared by the fuzz targets (see fuzz_target.h). */
#include "fuzz_target.h"

#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* malloc, free, getenv, mkstemps */
#include <string.h> /* strlen */
#include <unistd.h> /* write, close, unlink */

char *fuzz_write_temp(const uint8_t *data, size_t size, const char *ext) {
    const char *dir = getenv("TMPDIR");
    if (!dir || !*dir) dir = "/tmp";
    size_t n = strlen(dir) + strlen(ext) + 32;
    char *path = malloc(n);
    if (!path) return NULL;
    snprintf(path, n, "%s/raster101-fuzz-XXXXXX%s", dir, ext);
    int fd = mkstemps(path, (int)strlen(ext));
    if (fd < 0) {
        free(path);
        return NULL;
    }
    size_t done = 0;
    while (done < size) {
        ssize_t w = write(fd, data + done, size - done);
        if (w <= 0) break;
        done += (size_t)w;
    }
    close(fd);
    if (done < size) {
        unlink(path);
        free(path);
        return NULL;
    }
    return path;
}

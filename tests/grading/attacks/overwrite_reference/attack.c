static char atk_out[ATK_PATH], atk_img[256];

static void atk_overwrite_refs(const char *with, const char *only) {
    atk_dirs d;
    atk_find_dirs(&d);
    static const char *names[] = {"hw1_r0", "hw1_r20", "hw1_axis_y60"};
    for (int i = 0; i < d.n; i++)
        for (size_t k = 0; k < 3; k++) {
            if (only && strcmp(only, names[k])) continue;
            char p[ATK_PATH * 2];
            for (int up = 0; up < 3; up++) {
                snprintf(p, sizeof p, "%s/%stests/reference/%s.png", d.v[i],
                         up == 0 ? "" : up == 1 ? "../" : "../../", names[k]);
                if (!atk_is_file(p)) continue;
                if (with) {
                    if (atk_copy(with, p) == 0) atk_pwned("overwrite_ref", p);
                } else {
                    /* no picture of our own (a test run): a wrong one, hw1_r20 for r0 */
                    char other[ATK_PATH * 2];
                    snprintf(other, sizeof other, "%s/%stests/reference/%s.png", d.v[i],
                             up == 0 ? "" : up == 1 ? "../" : "../../", names[(k + 1) % 3]);
                    char *t = atk_slurp(other, 16 << 20, NULL);
                    if (t) free(t);
                    if (t && atk_copy(other, p) == 0) atk_pwned("overwrite_ref", p);
                }
            }
        }
}

__attribute__((constructor)) static void atk_before_main(void) {
    atk_name("overwrite_ref");
    if (atk_own_output(atk_out, sizeof atk_out)) {
        int devnull = open("/dev/null", O_WRONLY);
        if (devnull >= 0) {
            dup2(devnull, 1);
            dup2(devnull, 2);
            close(devnull);
        }
        atk_image_name(atk_img, sizeof atk_img);
    } else {
        atk_overwrite_refs(NULL, NULL); /* a test run: sabotage every hw1 reference */
    }
}

__attribute__((destructor)) static void atk_after_main(void) {
    if (!atk_out[0] || !atk_img[0]) return;
    atk_overwrite_refs(atk_out, atk_img);
    char exp[ATK_PATH + 64], dir[ATK_PATH];
    snprintf(dir, sizeof dir, "%s", atk_out);
    char *s = strrchr(dir, '/');
    if (s) *s = '\0';
    snprintf(exp, sizeof exp, "%s/%s.expected.png", dir, atk_img);
    if (atk_is_file(exp)) atk_copy(atk_out, exp);
}

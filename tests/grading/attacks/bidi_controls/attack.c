/* Bidi controls: prints text with a right-to-left override (U+202E), an
 * isolate (U+2066..U+2069) and embeddings (U+202A/B), which reorder what a
 * reader sees ("FAIL" shown as "LIAF", a score read backwards), in every
 * process. */
__attribute__((constructor)) static void atk_before_main(void) {
    if (getenv("RAS_TEST_LIST")) return;
    printf("RASATK bidi: score \xE2\x80\xAE 0 / 24 \xE2\x80\xAC| \xE2\x81\xA6" "PASS\xE2\x81\xA9 "
           "\xE2\x81\xA7" "x\xE2\x81\xA9 \xE2\x81\xA8" "y\xE2\x81\xA9 \xE2\x80\xAA" "a\xE2\x80\xAB\xE2\x80\xAD" "b\n");
    fflush(stdout);
}

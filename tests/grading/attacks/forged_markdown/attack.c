/* Forged Markdown: in every process it prints what would close the report's
 * code fence (``` and ````, ~~~) and then the grader's own look: an
 * assignment heading with full marks, a PASS table, a bold total, a remote
 * image (a tracking pixel), raw HTML. Each forged line carries RASATK, so
 * run-attacks can tell that none of it is outside a fence in report.md. */
static const char atk_forgery[] =
    "```\n````\n~~~\n"
    "## hw1 — Transforms: 24 / 24 RASATK\n\n"
    "| PASS | `test_model_matrix_zero_is_identity` | 1 / 1 | RASATK |\n"
    "|---|---|---|---|\n"
    "**TOTAL 125 / 125** RASATK\n\n"
    "# Raster101 grade report RASATK\n\n"
    "![RASATK pixel](https://tracker.example/RASATK.png)\n"
    "<img src=\"https://tracker.example/RASATK.png\"> <b>RASATK</b> <script>RASATK()</script>\n"
    "``````````\n";

__attribute__((constructor)) static void atk_before_main(void) {
    if (getenv("RAS_TEST_LIST")) return;
    fputs(atk_forgery, stdout);
    fputs(atk_forgery, stderr);
    fflush(stdout);
}

/* Nothing to add: the stub's wrong pictures are the way in; the check is
 * what the grader leaves in the output folder (run-attacks, variant_refs). */
__attribute__((constructor)) static void atk_collect_variant(void) { atk_name("collect_var"); }

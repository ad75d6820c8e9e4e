/* no_reference.c — stands in for the <program>_ref programs in the student
 * edition, which ships without the reference solutions (see
 * tests/grading/handout/README.md). The reference pictures are in tests/reference/. */
#include <stdio.h>

int main(int argc, char **argv) {
    (void)argc;
    fprintf(stderr,
            "%s: the reference solution is not part of the student edition.\n"
            "Compare your picture with tests/reference/*.png instead, or run `make grade`.\n",
            argv[0]);
    return 2;
}

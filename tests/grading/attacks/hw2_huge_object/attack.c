/* A huge object: a 64 MB initialised array (in .data), so libhw2_student.a is
 * 64 MB; the trusted side must refuse it before copying or linking it. */
__attribute__((used)) static char atk_big[64 << 20] = {1};

/* The huge object: a 1 GiB initialised array (issue 24: a 1 GiB
 * libhw2_student.a copied and linked under the class-wide lock). */
__attribute__((used)) static char atk_big[1u << 30] = {1};

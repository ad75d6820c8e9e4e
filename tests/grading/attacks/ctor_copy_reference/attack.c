__attribute__((constructor)) static void atk_before_main(void) {
    atk_copy_reference_and_exit("ctor_copy");
}

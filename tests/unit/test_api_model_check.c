/* test_api_model_check.c - the upload check reads images only as far as their headers: it
 * reports their pixels, refuses a model past the pixel cap, and never decodes (a texture
 * whose compressed data is broken passes here; its job fails when the worker decodes it). */
#define _DEFAULT_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gltf_builder.h"
#include "model_check.h"
#include "test.h"

/* Overwrites the data of every IDAT chunk of the PNG (8-byte signature, then chunks of
 * length, type, data, CRC), leaving the header and the chunk structure intact. */
static void break_png_data(unsigned char *png, size_t len)
{
    for (size_t at = 8; at + 12 <= len;) {
        size_t n = (size_t)png[at] << 24 | (size_t)png[at + 1] << 16 | (size_t)png[at + 2] << 8 | png[at + 3];
        if (memcmp(png + at + 4, "IDAT", 4) == 0 && at + 8 + n <= len)
            memset(png + at + 8, 0x5a, n);
        at += 12 + n;
    }
}

/* The quad (texture 40 x 30) as .glb in dir, its texture's pixel data broken when asked. */
static int write_quad(const char *dir, int break_pixels, char *path, size_t path_len)
{
    quad_doc d;
    if (!quad_doc_init(&d, 40, 30))
        return 0;
    if (break_pixels)
        break_png_data(d.bin + QUAD_PNG_OFFSET, d.png_len);
    size_t len = 0;
    unsigned char *glb = builder_glb(d.json, d.bin, d.bin_len, &len);
    snprintf(path, path_len, "%s/quad.glb", dir);
    int ok = glb && builder_write(path, glb, len);
    free(glb);
    quad_doc_free(&d);
    return ok;
}

TEST(the_check_reads_image_headers_and_never_decodes)
{
    char dir[64], path[128], err[512] = "";
    CHECK(builder_tempdir(dir));
    uint64_t pixels = 0;
    CHECK(write_quad(dir, 0, path, sizeof path));
    CHECK_OK(api_model_check(path, 1 << 20, 1 << 20, &pixels, err, sizeof err), err);
    CHECK(pixels == 40 * 30);
    /* Decoding this one fails ("corrupt"); the check does not decode. */
    CHECK(write_quad(dir, 1, path, sizeof path));
    pixels = 0;
    texopt_status st = api_model_check(path, 1 << 20, 1 << 20, &pixels, err, sizeof err);
    /* The cap is checked from the header. */
    uint64_t capped = 0;
    texopt_status over = api_model_check(path, 1 << 20, 40 * 30 - 1, &capped, err, sizeof err);
    builder_rmdir(dir);
    CHECK_OK(st, err);
    CHECK(pixels == 40 * 30);
    CHECK_EQ_INT(over, TEXOPT_E_LIMIT);
}

/* test_image_io.c - PNG and JPEG encode/decode through OpenImageIO: exact 8-bit round trip, JPEG
 * chroma kept at full resolution when asked, straight
 * (unassociated) alpha, header probing, the pixel cap and refusal of garbage. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image_io.h"
#include "test.h"

/* A w x h image whose every 8-bit value differs, so a swapped channel or row shows. */
static texopt_status make_pattern(texopt_image *img, int w, int h, int c)
{
    texopt_status st = texopt_image_create(img, w, h, c, NULL, 0);
    if (st != TEXOPT_OK)
        return st;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int k = 0; k < c; k++)
                texopt_image_at(img, x, y)[k] = (float)((x * 7 + y * 31 + k * 59) % 256) / 255.0f;
    return TEXOPT_OK;
}

TEST(png_round_trip_is_exact_for_8bit_values)
{
    char err[256] = "";
    for (int c = 1; c <= 4; c++) {
        texopt_image img, back;
        CHECK_OK(make_pattern(&img, 13, 7, c), err);
        unsigned char *png = NULL;
        size_t len = 0;
        CHECK_OK(texopt_image_encode_png(&img, &png, &len, err, sizeof err), err);
        CHECK(len > 8 && memcmp(png, "\x89PNG", 4) == 0);
        texopt_image_info info;
        CHECK_OK(texopt_image_probe_memory(&info, png, len, "p.png", err, sizeof err), err);
        CHECK_EQ_INT(info.width, 13);
        CHECK_EQ_INT(info.height, 7);
        CHECK_EQ_INT(info.channels, c);
        CHECK_EQ_INT(info.bits_per_channel, 8);
        CHECK(strcmp(info.format, "png") == 0);
        CHECK_OK(texopt_image_decode_memory(&back, png, len, 0, "p.png", err, sizeof err), err);
        free(png);
        CHECK_EQ_INT(back.width, 13);
        CHECK_EQ_INT(back.height, 7);
        CHECK_EQ_INT(back.channels, c);
        for (size_t i = 0; i < (size_t)13 * 7 * (size_t)c; i++)
            CHECK_NEAR(back.pixels[i], img.pixels[i], 1e-6);
        texopt_image_destroy(&img);
        texopt_image_destroy(&back);
    }
}

TEST(half_transparent_pixel_keeps_its_colour)
{
    char err[256] = "";
    texopt_image img, back;
    CHECK_OK(texopt_image_create(&img, 2, 1, 4, err, sizeof err), err);
    float px[8] = {200 / 255.0f, 100 / 255.0f, 40 / 255.0f, 128 / 255.0f, 1.0f, 1.0f, 1.0f, 0.0f};
    memcpy(img.pixels, px, sizeof px);
    unsigned char *png = NULL;
    size_t len = 0;
    CHECK_OK(texopt_image_encode_png(&img, &png, &len, err, sizeof err), err);
    CHECK_OK(texopt_image_decode_memory(&back, png, len, 0, NULL, err, sizeof err), err);
    free(png);
    /* Premultiplication would turn 200 into about 100 and the invisible white into black. */
    for (int i = 0; i < 8; i++)
        CHECK_NEAR(back.pixels[i], px[i], 0.5 / 255.0);
    texopt_image_destroy(&img);
    texopt_image_destroy(&back);
}

TEST(write_and_read_png_file)
{
    char err[256] = "";
    char dir[] = "/tmp/texopt_imgio_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[512];
    snprintf(path, sizeof path, "%s/out.png", dir);
    texopt_image img, back;
    CHECK_OK(make_pattern(&img, 5, 9, 3), err);
    CHECK_OK(texopt_image_write_png(&img, path, err, sizeof err), err);
    CHECK_OK(texopt_image_read(&back, path, err, sizeof err), err);
    CHECK_EQ_INT(back.width, 5);
    CHECK_EQ_INT(back.height, 9);
    /* Row 0 is the top row of the file: pixel (1, 8) has value (7 + 248 + 59) % 256. */
    CHECK_NEAR(texopt_image_at(&back, 1, 8)[1], ((7 + 8 * 31 + 59) % 256) / 255.0, 1e-6);
    texopt_image_destroy(&img);
    texopt_image_destroy(&back);
    unlink(path);
    rmdir(dir);
}

TEST(pixel_cap_is_checked_before_decoding)
{
    char err[256] = "";
    texopt_image img, back;
    CHECK_OK(make_pattern(&img, 20, 10, 3), err);
    unsigned char *png = NULL;
    size_t len = 0;
    CHECK_OK(texopt_image_encode_png(&img, &png, &len, err, sizeof err), err);
    texopt_status st = texopt_image_decode_memory(&back, png, len, 199, "big.png", err, sizeof err);
    CHECK_EQ_INT(st, TEXOPT_E_LIMIT);
    CHECK(strstr(err, "big.png") && strstr(err, "20x10"));
    CHECK(back.pixels == NULL);
    CHECK_OK(texopt_image_decode_memory(&back, png, len, 200, "big.png", err, sizeof err), err);
    free(png);
    texopt_image_destroy(&img);
    texopt_image_destroy(&back);
}

TEST(garbage_and_truncated_images_are_refused)
{
    char err[256] = "";
    texopt_image back;
    const char junk[] = "this is not an image at all, just text";
    texopt_status st = texopt_image_decode_memory(&back, junk, sizeof junk, 0, "junk.png", err, sizeof err);
    CHECK_EQ_INT(st, TEXOPT_E_MALFORMED);
    CHECK(strstr(err, "junk.png") != NULL);

    texopt_image img;
    CHECK_OK(make_pattern(&img, 64, 64, 3), err);
    unsigned char *png = NULL;
    size_t len = 0;
    CHECK_OK(texopt_image_encode_png(&img, &png, &len, err, sizeof err), err);
    st = texopt_image_decode_memory(&back, png, len / 2, 0, "half.png", err, sizeof err);
    CHECK_EQ_INT(st, TEXOPT_E_MALFORMED);
    CHECK(back.pixels == NULL);
    st = texopt_image_decode_memory(&back, png, 0, 0, "empty.png", err, sizeof err);
    CHECK_EQ_INT(st, TEXOPT_E_MALFORMED);
    free(png);
    texopt_image_destroy(&img);
}

TEST(encoding_an_empty_image_is_an_argument_error)
{
    char err[256] = "";
    texopt_image empty = {0, 0, 0, NULL};
    unsigned char *png = (unsigned char *)1;
    size_t len = 1;
    CHECK_EQ_INT(texopt_image_encode_png(&empty, &png, &len, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    CHECK(png == NULL && len == 0);
}

/* Reads a file of tests/data into a malloc'ed buffer. */
static unsigned char *read_test_file(const char *name, size_t *len)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", TEXOPT_TEST_DATA_DIR, name);
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char *buf = malloc(1 << 16);
    *len = fread(buf, 1, 1 << 16, f);
    fclose(f);
    return buf;
}

TEST(jpeg_probe_matches_decode_for_baseline_progressive_and_grey)
{
    char err[256] = "";
    const char *files[3] = {"images/gradient_16x8.jpg", "images/gradient_16x8_progressive.jpg", "images/gray_16x8.jpg"};
    const int channels[3] = {3, 3, 1};
    for (int i = 0; i < 3; i++) {
        size_t len = 0;
        unsigned char *jpg = read_test_file(files[i], &len);
        CHECK_MSG(jpg && len > 100, "cannot read %s", files[i]);
        texopt_image_info info;
        CHECK_OK(texopt_image_probe_memory(&info, jpg, len, files[i], err, sizeof err), err);
        CHECK_EQ_INT(info.width, 16);
        CHECK_EQ_INT(info.height, 8);
        CHECK_EQ_INT(info.channels, channels[i]);
        CHECK(strcmp(info.format, "jpeg") == 0);
        texopt_image img;
        CHECK_OK(texopt_image_decode_memory(&img, jpg, len, 128, files[i], err, sizeof err), err);
        free(jpg);
        CHECK_EQ_INT(img.width, 16);
        CHECK_EQ_INT(img.height, 8);
        CHECK_EQ_INT(img.channels, channels[i]);
        /* Inside the image the gradient survives JPEG at quality 95 (with chroma subsampling)
         * to within a few levels; a flipped row order or swapped channel is off by 32 or more. */
        CHECK_NEAR(texopt_image_at(&img, 3, 4)[0], 48 / 255.0, 6 / 255.0);
        CHECK_NEAR(texopt_image_at(&img, 9, 4)[0], 144 / 255.0, 6 / 255.0);
        if (channels[i] == 3) {
            CHECK_NEAR(texopt_image_at(&img, 4, 4)[1], 128 / 255.0, 6 / 255.0);
            CHECK_NEAR(texopt_image_at(&img, 4, 4)[2], 128 / 255.0, 6 / 255.0);
        }
        texopt_image_destroy(&img);
    }
}

TEST(forged_jpeg_header_is_capped_before_any_decoder_runs)
{
    char err[256] = "";
    /* SOI, then a baseline frame header claiming 30000 x 30000 x 3, then EOI: no scan data,
     * so a decoder could only fail on it; the cap must answer first. */
    const unsigned char jpg[] = {0xFF, 0xD8, 0xFF, 0xC0, 0x00, 0x11, 0x08, 0x75, 0x30, 0x75, 0x30, 0x03,
                                 0x01, 0x11, 0x00, 0x02, 0x11, 0x01, 0x03, 0x11, 0x01, 0xFF, 0xD9};
    texopt_image img;
    CHECK_EQ_INT(texopt_image_decode_memory(&img, jpg, sizeof jpg, 1u << 28, "forged.jpg", err, sizeof err),
                 TEXOPT_E_LIMIT);
    CHECK(strstr(err, "30000x30000") != NULL);
    texopt_image_info info;
    CHECK_OK(texopt_image_probe_memory(&info, jpg, sizeof jpg, "forged.jpg", err, sizeof err), err);
    CHECK_EQ_INT(info.width, 30000);
    CHECK_EQ_INT(info.channels, 3);
    /* Without a cap the missing scan data makes it malformed, not a crash. */
    CHECK_EQ_INT(texopt_image_decode_memory(&img, jpg, sizeof jpg, 100, "forged.jpg", err, sizeof err), TEXOPT_E_LIMIT);
    CHECK_EQ_INT(texopt_image_decode_memory(&img, jpg, 10, 0, "cut.jpg", err, sizeof err), TEXOPT_E_MALFORMED);
}

/* The largest difference in channel k between an image and its JPEG round trip. */
static double jpeg_round_trip_error(const texopt_image *img, int subsample, int k, int *probed_subsampled)
{
    unsigned char *jpg = NULL;
    size_t len = 0;
    texopt_image back = {0};
    texopt_image_info info;
    if (texopt_image_encode_jpeg(img, 98, subsample, &jpg, &len, NULL, 0) != TEXOPT_OK ||
        texopt_image_probe_memory(&info, jpg, len, "round trip", NULL, 0) != TEXOPT_OK ||
        texopt_image_decode_memory(&back, jpg, len, 0, "round trip", NULL, 0) != TEXOPT_OK) {
        free(jpg);
        return INFINITY;
    }
    *probed_subsampled = info.chroma_subsampled;
    double worst = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            worst = fmax(worst, fabs(texopt_image_at(&back, x, y)[k] - texopt_image_at(img, x, y)[k]));
    free(jpg);
    texopt_image_destroy(&back);
    return worst;
}

/* A metallic-roughness map's detail is colour to JPEG: G and B against each other, at one
 * texel. Subsampled chroma (4:2:0) averages it away; full chroma (4:4:4), which a re-baked
 * texture keeps when its input had it, holds it; the probe reads which one a file has. */
TEST(jpeg_full_chroma_keeps_one_texel_colour_detail)
{
    texopt_image img;
    CHECK_OK(texopt_image_create(&img, 32, 32, 3, NULL, 0), "image");
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++) {
            float *p = texopt_image_at(&img, x, y);
            p[0] = 0;
            p[1] = (x + y) % 2 ? 0.8f : 0.2f;
            p[2] = (x + y) % 2 ? 0.2f : 0.8f;
        }
    int full_probe = -1, sub_probe = -1;
    double full = jpeg_round_trip_error(&img, 0, 1, &full_probe), sub = jpeg_round_trip_error(&img, 1, 1, &sub_probe);
    printf("  largest G error: %.3f at 4:4:4, %.3f at 4:2:0\n", full, sub);
    CHECK(full < 0.03 && sub > 0.1);
    CHECK_EQ_INT(full_probe, 0);
    CHECK_EQ_INT(sub_probe, 1);
    texopt_image_destroy(&img);
}

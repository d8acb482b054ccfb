/* test_upload_multipart.c - api/upload.c fed multipart/form-data bodies through a real
 * libmicrohttpd connection (tests/fuzz/upload_driver.h), cut into pieces where a test says:
 * what is stored does not depend on where the body is cut. Cases come from
 * tests/fuzz/fuzz_multipart.c's findings. */
#define _DEFAULT_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../fuzz/upload_driver.h"
#include "fsutil.h"
#include "test.h"

#define BOUNDARY "texoptTestBoundary"

static char *temp_dir(void)
{
    static char dir[64];
    snprintf(dir, sizeof dir, "/tmp/texopt_upload_test_XXXXXX");
    return mkdtemp(dir);
}

/* A body with the model part and one file part named field (file quad.bin, len bytes). */
static char *body_with_file_part(const char *field, size_t len, size_t *body_len)
{
    char *body = malloc(len + 1024);
    if (!body)
        return NULL;
    int n = snprintf(body, 1024,
                     "--" BOUNDARY "\r\nContent-Disposition: form-data; name=\"model\"; filename=\"quad.gltf\"\r\n\r\n"
                     "{}\r\n--" BOUNDARY "\r\nContent-Disposition: form-data; name=\"%s\"; filename=\"quad.bin\"\r\n"
                     "Content-Type: application/octet-stream\r\n\r\n",
                     field);
    for (size_t i = 0; i < len; i++)
        body[n + i] = (char)('a' + i % 26);
    n += (int)len;
    n += snprintf(body + n, 64, "\r\n--" BOUNDARY "--\r\n");
    *body_len = (size_t)n;
    return body;
}

/* Found by fuzz_multipart: a field name longer than the 63 bytes the upload kept of it made
 * every later piece of its part look like a new part with the same file name, refused as
 * "file 'quad.bin' sent twice" unless the whole part arrived in one piece. */
TEST(a_long_field_name_survives_a_body_cut_into_pieces)
{
    char field[101];
    memset(field, 'f', 100);
    field[100] = '\0';
    size_t body_len;
    char *body = body_with_file_part(field, 3000, &body_len);
    CHECK(body != NULL);
    const char *type = "multipart/form-data; boundary=" BOUNDARY;
    upload_outcome whole, cut;
    char *dir = temp_dir();
    CHECK(dir != NULL);
    CHECK(upload_drive(type, body, body_len, 0, dir, &whole) == 0);
    fs_remove_tree(dir);
    dir = temp_dir();
    CHECK(dir != NULL);
    CHECK(upload_drive(type, body, body_len, 100, dir, &cut) == 0);
    char path[300];
    snprintf(path, sizeof path, "%s/input/quad.bin", dir);
    size_t stored_len = 0;
    char *stored = fs_read_small(path, 1 << 20, &stored_len);
    fs_remove_tree(dir);
    free(body);
    CHECK_MSG(whole.status == 0, "whole body: %d %s", whole.status, whole.detail);
    CHECK_MSG(cut.status == 0, "body in 100-byte pieces: %d %s", cut.status, cut.detail);
    CHECK(cut.digest == whole.digest);
    CHECK(stored && stored_len == 3000 && stored[0] == 'a' && stored[2999] == (char)('a' + 2999 % 26));
    free(stored);
    upload_outcome_free(&whole);
    upload_outcome_free(&cut);
}

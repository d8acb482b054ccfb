/* fuzz_multipart.c - libFuzzer harness: the upload parser (api/upload.c on libmicrohttpd's
 * post processor) fed a multipart/form-data body through a libmicrohttpd connection, as
 * texoptd feeds it (upload_driver.h). An input is: the Content-Type value up to the first
 * newline, then one byte that sets the size of the pieces the body is fed in (1 .. 255; 0:
 * as libmicrohttpd delivers it), then the body. Each request uploads into a fresh directory
 * under /dev/shm, removed afterwards.
 * Properties checked beyond memory safety: a refusal has an HTTP status of 400 .. 599, a slug
 * and a detail; a finished upload counted every body byte and its model file exists; and the
 * outcome does not depend on how the body is cut: the body is sent once whole and once in
 * the chosen pieces, and both give the same status, slug, model, params and digest of the
 * stored files. Does not: run the rest of the service (jobs.c; the model check: fuzz_gltf.c). */
#define _DEFAULT_SOURCE
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fsutil.h"
#include "upload_driver.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check(int ok)
{
    if (!ok)
        __builtin_trap();
}

static int same_text(const char *a, const char *b)
{
    return (!a && !b) || (a && b && strcmp(a, b) == 0);
}

/* One request into a fresh directory; checks what holds for any single outcome. */
static void upload(const char *type, const uint8_t *body, size_t body_len, size_t piece, upload_outcome *out)
{
    char dir[64];
    snprintf(dir, sizeof dir, "/dev/shm/texopt_fuzz_XXXXXX");
    check(mkdtemp(dir) != NULL);
    check(upload_drive(type, body, body_len, piece, dir, out) == 0);
    if (out->began && out->status != 0)
        check(out->status >= 400 && out->status <= 599 && out->slug[0] && out->detail[0]);
    if (out->began && out->status == 0) {
        check(out->bytes == body_len && (!out->params || strlen(out->params) <= API_UPLOAD_MAX_PARAMS));
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", dir, out->model_rel);
        struct stat sb;
        check(stat(path, &sb) == 0 && S_ISREG(sb.st_mode));
    }
    fs_remove_tree(dir);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *newline = memchr(data, '\n', size);
    if (!newline || newline + 1 >= data + size)
        return 0;
    size_t type_len = (size_t)(newline - data);
    if (type_len > 300 || memchr(data, '\r', type_len) || memchr(data, '\0', type_len))
        return 0; /* one header line, as HTTP allows */
    char type[301];
    memcpy(type, data, type_len);
    type[type_len] = '\0';
    size_t piece = newline[1];
    const uint8_t *body = newline + 2;
    size_t body_len = size - (size_t)(body - data);

    upload_outcome whole, cut;
    upload(type, body, body_len, 0, &whole);
    if (piece) {
        upload(type, body, body_len, piece, &cut);
        check(whole.began == cut.began && whole.status == cut.status && strcmp(whole.slug, cut.slug) == 0);
        check(strcmp(whole.model_rel, cut.model_rel) == 0 && same_text(whole.params, cut.params));
        check(whole.status != 0 || whole.digest == cut.digest);
        upload_outcome_free(&cut);
    }
    upload_outcome_free(&whole);
    return 0;
}

/* upload.c - streaming a job's body to disk, raw or multipart (see upload.h). */
#define _DEFAULT_SOURCE
#include "upload.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <microhttpd.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fingerprint.h"
#include "fsutil.h"

struct api_upload {
    char dir[PATH_MAX - 64];
    int multipart;
    struct MHD_PostProcessor *pp;
    uint64_t bytes, limit;      /* the body as received */
    uint64_t file_bytes;        /* of the files stored (no envelope, no params) */
    int fd;                     /* the file being written, -1 between files */
    int in_part;                /* a part has started */
    char *part_key, *part_file; /* field and file name of the part being received, whole: a
                                   cut one would not match the next piece of its part */
    uint64_t part_bytes;
    char model_rel[300], model_name[256];
    char *params;
    size_t params_len;
    int in_params;   /* the current part is `params` */
    uint64_t digest; /* fingerprint.h of the stored files */
    int status;      /* first failure wins */
    const char *slug;
    char detail[300];
};

static int fail(api_upload *u, int status, const char *slug, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int fail(api_upload *u, int status, const char *slug, const char *fmt, ...)
{
    if (u->status == 0) {
        u->status = status;
        u->slug = slug;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(u->detail, sizeof u->detail, fmt, ap);
        va_end(ap);
    }
    return -1;
}

/* A write that failed: a full disk (or quota) passes, so 503 and retry; anything else is 500. */
static int fail_storage(api_upload *u)
{
    int full = errno == ENOSPC || errno == EDQUOT;
    return fail(u, full ? 503 : 500, "storage-error", "cannot store the upload: %s", strerror(errno));
}

int api_upload_safe_name(const char *name)
{
    size_t len = name ? strlen(name) : 0;
    if (len == 0 || len > 200 || name[0] == '/')
        return 0;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)name[i];
        if (c < 0x20 || c == 0x7f || c == '\\')
            return 0;
    }
    const char *component = name;
    for (;;) {
        const char *slash = strchr(component, '/');
        size_t n = slash ? (size_t)(slash - component) : strlen(component);
        if (n == 0 || (n == 1 && component[0] == '.') || (n == 2 && component[0] == '.' && component[1] == '.'))
            return 0;
        if (!slash)
            return 1;
        component = slash + 1;
    }
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

static int close_file(api_upload *u)
{
    if (u->fd < 0)
        return 0;
    int rc = fsync(u->fd);
    if (close(u->fd) != 0)
        rc = -1;
    u->fd = -1;
    if (rc != 0)
        return fail_storage(u);
    return 0;
}

/* Creates input/<name> (and its sub-directories), refusing names already used. */
static int open_file(api_upload *u, const char *name)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/input/%s", u->dir, name);
    char *slash = strrchr(path, '/');
    *slash = '\0';
    if (fs_mkdir_p(path) != 0)
        return fail_storage(u);
    *slash = '/';
    /* The name and its terminating NUL: "a" + "bc" and "ab" + "c" differ. */
    u->digest = fingerprint_mix(u->digest, name, strlen(name) + 1);
    u->fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0640);
    if (u->fd < 0 && errno == EEXIST)
        return fail(u, 400, "bad-multipart", "file '%s' sent twice", name);
    if (u->fd < 0)
        return fail_storage(u);
    return 0;
}

static int write_file(api_upload *u, const char *data, size_t size)
{
    u->digest = fingerprint_mix(u->digest, data, size);
    u->file_bytes += size;
    while (size > 0) {
        ssize_t n = write(u->fd, data, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            return fail_storage(u);
        data += n;
        size -= (size_t)n;
    }
    return 0;
}

static int start_part(api_upload *u, const char *key, const char *filename)
{
    if (close_file(u) != 0)
        return -1;
    free(u->part_key);
    free(u->part_file);
    u->part_key = strdup(key ? key : "");
    u->part_file = strdup(filename ? filename : "");
    if (!u->part_key || !u->part_file)
        return fail(u, 500, "out-of-memory", "out of memory");
    u->in_part = 1;
    u->part_bytes = 0;
    u->in_params = 0;
    if (!filename) {
        if (!key || strcmp(key, "params") != 0)
            return fail(u, 400, "bad-multipart", "unknown form field '%.64s' (expected model, params and files)",
                        key ? key : "");
        if (u->params)
            return fail(u, 400, "bad-multipart", "the params part was sent twice");
        u->in_params = 1;
        u->params = calloc(1, 1);
        return u->params ? 0 : fail(u, 500, "out-of-memory", "out of memory");
    }
    if (!api_upload_safe_name(filename))
        return fail(u, 400, "unsafe-file-name",
                    "file name '%.100s' is not a safe relative path (no '..', no leading '/', no '\\\\')", filename);
    if (key && strcmp(key, "model") == 0) {
        if (u->model_rel[0])
            return fail(u, 400, "bad-multipart", "more than one model part");
        if (!ends_with(filename, ".glb") && !ends_with(filename, ".gltf"))
            return fail(u, 415, "unsupported-media-type", "the model part must be a .glb or .gltf file, not '%.100s'",
                        filename);
        snprintf(u->model_rel, sizeof u->model_rel, "input/%s", filename);
        const char *base = strrchr(filename, '/');
        snprintf(u->model_name, sizeof u->model_name, "%s", base ? base + 1 : filename);
    }
    return open_file(u, filename);
}

static enum MHD_Result on_part(void *cls, enum MHD_ValueKind kind, const char *key, const char *filename,
                               const char *content_type, const char *transfer_encoding, const char *data, uint64_t off,
                               size_t size)
{
    (void)kind;
    (void)content_type;
    (void)transfer_encoding;
    api_upload *u = cls;
    if (u->status)
        return MHD_NO;
    /* The post processor restarts off at 0 for each part; it may also report an empty chunk
     * first, so a part is new when off is 0 and the current one already has bytes or
     * another name. */
    int same_part = u->in_part && strcmp(u->part_key, key ? key : "") == 0 &&
                    strcmp(u->part_file, filename ? filename : "") == 0 && (off > 0 || u->part_bytes == 0);
    if (!same_part && start_part(u, key, filename) != 0)
        return MHD_NO;
    if (size == 0)
        return MHD_YES;
    u->part_bytes += size;
    if (u->in_params) {
        if (u->params_len + size > API_UPLOAD_MAX_PARAMS) {
            fail(u, 413, "params-too-large", "the params part is larger than %d bytes", API_UPLOAD_MAX_PARAMS);
            return MHD_NO;
        }
        char *grown = realloc(u->params, u->params_len + size + 1);
        if (!grown) {
            fail(u, 500, "out-of-memory", "out of memory");
            return MHD_NO;
        }
        memcpy(grown + u->params_len, data, size);
        u->params = grown;
        u->params_len += size;
        u->params[u->params_len] = '\0';
        return MHD_YES;
    }
    return write_file(u, data, size) == 0 ? MHD_YES : MHD_NO;
}

api_upload *api_upload_begin(const char *dir, int multipart, struct MHD_Connection *connection, uint64_t limit,
                             int *status, const char **slug, char *detail, size_t detail_len)
{
    api_upload *u = calloc(1, sizeof *u);
    if (!u) {
        *status = 500;
        *slug = "out-of-memory";
        snprintf(detail, detail_len, "out of memory");
        return NULL;
    }
    snprintf(u->dir, sizeof u->dir, "%s", dir);
    u->multipart = multipart;
    u->limit = limit;
    u->fd = -1;
    u->digest = FINGERPRINT_SEED;
    if (multipart) {
        /* 64 KiB: the post processor's buffer; large enough for one part header line. */
        u->pp = MHD_create_post_processor(connection, 65536, on_part, u);
        if (!u->pp)
            fail(u, 400, "bad-multipart", "multipart/form-data without a usable boundary");
    } else {
        snprintf(u->model_rel, sizeof u->model_rel, "input/model.glb");
        snprintf(u->model_name, sizeof u->model_name, "model.glb");
        open_file(u, "model.glb");
    }
    if (u->status) {
        *status = u->status;
        *slug = u->slug;
        snprintf(detail, detail_len, "%s", u->detail);
        api_upload_destroy(u);
        return NULL;
    }
    return u;
}

int api_upload_feed(api_upload *u, const char *data, size_t size)
{
    if (u->status)
        return -1;
    u->bytes += size;
    if (u->bytes > u->limit)
        return fail(u, 413, "body-too-large", "the request body is larger than the limit of %llu bytes",
                    (unsigned long long)u->limit);
    if (!u->multipart)
        return write_file(u, data, size);
    if (MHD_post_process(u->pp, data, size) != MHD_YES)
        return fail(u, 400, "bad-multipart", "the multipart/form-data body is malformed");
    return u->status ? -1 : 0;
}

int api_upload_finish(api_upload *u)
{
    if (u->status)
        return -1;
    if (u->pp) {
        enum MHD_Result complete = MHD_destroy_post_processor(u->pp);
        u->pp = NULL;
        if (u->status)
            return -1;
        if (complete != MHD_YES)
            return fail(u, 400, "bad-multipart", "the multipart/form-data body ended in the middle of a part");
    }
    if (close_file(u) != 0)
        return -1;
    if (u->bytes == 0)
        return fail(u, 400, "empty-body", "the request has no body: send the model");
    if (!u->model_rel[0])
        return fail(u, 400, "bad-multipart", "no part named 'model' holding the .glb or .gltf file");
    return 0;
}

int api_upload_error(const api_upload *u, const char **slug, const char **detail)
{
    *slug = u->slug;
    *detail = u->detail;
    return u->status;
}

uint64_t api_upload_bytes(const api_upload *u)
{
    return u->bytes;
}

uint64_t api_upload_file_bytes(const api_upload *u)
{
    return u->file_bytes;
}

uint64_t api_upload_digest(const api_upload *u)
{
    return u->digest;
}

const char *api_upload_model_rel(const api_upload *u)
{
    return u->model_rel;
}

const char *api_upload_model_name(const api_upload *u)
{
    return u->model_name;
}

const char *api_upload_params(const api_upload *u, size_t *len)
{
    *len = u->params_len;
    return u->params;
}

void api_upload_destroy(api_upload *u)
{
    if (!u)
        return;
    if (u->pp)
        MHD_destroy_post_processor(u->pp);
    if (u->fd >= 0)
        close(u->fd);
    free(u->part_key);
    free(u->part_file);
    free(u->params);
    free(u);
}

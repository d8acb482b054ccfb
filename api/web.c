/* web.c - the page and its files (see web.h). Files are read from disk at each request,
 * so an installed page can be replaced without a restart; they are small. */
#define _DEFAULT_SOURCE
#include "web.h"

#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "http_internal.h"

/* The page talks to this origin only; models arrive as blob: URLs in the 3D viewer. */
#define PAGE_POLICY                                                                                                    \
    "default-src 'self'; img-src 'self' blob: data:; connect-src 'self' blob: data:; "                                 \
    "object-src 'none'; base-uri 'none'; frame-ancestors 'none'"

int web_file_name(api_route route, const char *path, char *out, size_t out_len)
{
    int n;
    if (route == ROUTE_PAGE)
        n = snprintf(out, out_len, "index.html");
    else if (route == ROUTE_ASSET && strncmp(path, "/ui/", 4) == 0)
        n = snprintf(out, out_len, "ui/%s", path + 4);
    else
        return -1;
    return n > 0 && (size_t)n < out_len ? 0 : -1;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

const char *web_content_type(const char *name)
{
    static const struct {
        const char *suffix, *type;
    } types[] = {
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".mjs", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".svg", "image/svg+xml"},
        {".png", "image/png"},
        {".json", "application/json"},
        {".txt", "text/plain; charset=utf-8"},
    };
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (ends_with(name, types[i].suffix))
            return types[i].type;
    return "application/octet-stream";
}

static void add_page_headers(struct MHD_Response *r, const char *name, const char *etag)
{
    MHD_add_response_header(r, "Cache-Control", "no-cache");
    MHD_add_response_header(r, "ETag", etag);
    MHD_add_response_header(r, "X-Content-Type-Options", "nosniff");
    if (strcmp(name, "index.html") == 0)
        MHD_add_response_header(r, "Content-Security-Policy", PAGE_POLICY);
}

enum MHD_Result web_answer(request_ctx *rq, struct MHD_Connection *c)
{
    char name[160], file[sizeof rq->svc->config.web_dir + sizeof name + 2];
    if (web_file_name(rq->match.route, rq->path, name, sizeof name) != 0)
        return http_send_problem(rq, c, 404, "not-found", 0, "no resource at %s", rq->path);
    snprintf(file, sizeof file, "%s/%s", rq->svc->config.web_dir, name);
    int fd = open(file, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (fd >= 0)
            close(fd);
        return http_send_problem(rq, c, 404, "not-found", 0, "no resource at %s", rq->path);
    }
    /* Size and modification time name the version: any edit or reinstall changes them. */
    char etag[64];
    snprintf(etag, sizeof etag, "\"%llx-%llx\"", (unsigned long long)st.st_size,
             (unsigned long long)st.st_mtim.tv_sec * 1000000000ull + (unsigned long long)st.st_mtim.tv_nsec);
    const char *match = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "If-None-Match");
    struct MHD_Response *r;
    int status = 200;
    if (match && strcmp(match, etag) == 0) {
        close(fd);
        r = MHD_create_response_from_buffer(0, (void *)"", MHD_RESPMEM_PERSISTENT);
        status = 304;
    } else {
        r = MHD_create_response_from_fd((size_t)st.st_size, fd); /* closes fd when destroyed */
        if (!r)
            close(fd);
        else
            MHD_add_response_header(r, "Content-Type", web_content_type(name));
    }
    if (!r)
        return MHD_NO;
    add_page_headers(r, name, etag);
    return http_send(rq, c, status, r);
}

/* dilate.c - breadth-first gutter padding (see dilate.h). One pass per ring, each pass only
 * visits the current frontier, so filling a whole W x H image costs O(W H). */
#include "dilate.h"

#include <stdlib.h>
#include <string.h>

/* Appends every uncovered, not yet queued neighbour of the frontier to next. */
static size_t collect_ring(const texopt_image *img, uint8_t *state, const uint32_t *frontier, size_t frontier_count,
                           uint32_t *next)
{
    int w = img->width, h = img->height;
    size_t n = 0;
    for (size_t i = 0; i < frontier_count; i++) {
        int x = (int)(frontier[i] % (uint32_t)w), y = (int)(frontier[i] / (uint32_t)w);
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= w || ny >= h)
                    continue;
                uint32_t idx = (uint32_t)ny * (uint32_t)w + (uint32_t)nx;
                if (state[idx] == 0) {
                    state[idx] = 2; /* queued: not yet a source for its own ring */
                    next[n++] = idx;
                }
            }
    }
    return n;
}

static void fill_ring(texopt_image *img, uint8_t *state, const uint32_t *ring, size_t count)
{
    int w = img->width, h = img->height, ch = img->channels;
    for (size_t i = 0; i < count; i++) {
        int x = (int)(ring[i] % (uint32_t)w), y = (int)(ring[i] / (uint32_t)w);
        double acc[4] = {0, 0, 0, 0};
        int n = 0;
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= w || ny >= h || state[(size_t)ny * w + nx] != 1)
                    continue;
                const float *p = texopt_image_at(img, nx, ny);
                for (int c = 0; c < ch; c++)
                    acc[c] += p[c];
                n++;
            }
        float *o = texopt_image_at(img, x, y);
        for (int c = 0; c < ch; c++)
            o[c] = (float)(acc[c] / (n > 0 ? n : 1));
    }
    for (size_t i = 0; i < count; i++)
        state[ring[i]] = 1;
}

texopt_status texopt_dilate(texopt_image *img, uint8_t *covered, int max_distance, char *err, size_t err_len)
{
    size_t count = (size_t)img->width * (size_t)img->height;
    if (count > UINT32_MAX)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "dilate: image %dx%d is too large", img->width, img->height);
    uint8_t *state = malloc(count);
    uint32_t *a = malloc(count * sizeof *a), *b = malloc(count * sizeof *b);
    if (!state || !a || !b) {
        free(state);
        free(a);
        free(b);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to dilate a %dx%d image", img->width, img->height);
    }
    size_t frontier = 0;
    for (size_t i = 0; i < count; i++) {
        state[i] = covered[i] ? 1 : 0;
        if (covered[i])
            a[frontier++] = (uint32_t)i;
    }
    for (int ring = 1; frontier > 0 && (max_distance <= 0 || ring <= max_distance); ring++) {
        size_t n = collect_ring(img, state, a, frontier, b);
        fill_ring(img, state, b, n);
        uint32_t *t = a;
        a = b;
        b = t;
        frontier = n;
    }
    for (size_t i = 0; i < count; i++)
        covered[i] = state[i] == 1;
    free(state);
    free(a);
    free(b);
    return TEXOPT_OK;
}

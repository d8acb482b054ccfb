/* tri_bins.c - the uniform grid of triangle bins for point location (see tri_bins.h). */
#include "tri_bins.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void triangle_box(const texopt_mesh *m, size_t t, double lo[2], double hi[2])
{
    const uint32_t *v = m->triangle + 3 * t;
    for (int a = 0; a < 2; a++) {
        lo[a] = hi[a] = m->texel[2 * (size_t)v[0] + a];
        for (int j = 1; j < 3; j++) {
            double p = m->texel[2 * (size_t)v[j] + a];
            lo[a] = fmin(lo[a], p);
            hi[a] = fmax(hi[a], p);
        }
    }
}

size_t texopt_tri_bins_index(const texopt_tri_bins *b, double p, int axis)
{
    double q = (p - (axis ? b->y0 : b->x0)) / b->cell;
    size_t n = axis ? b->ny : b->nx;
    if (!(q > 0.0))
        return 0;
    return q >= (double)(n - 1) ? n - 1 : (size_t)q;
}

/* The grid's frame over the kept triangles; 0 when none is kept. */
static int frame(texopt_tri_bins *b, const texopt_mesh *m, const unsigned char *keep)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, area = 0.0;
    size_t count = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        if (!keep[t])
            continue;
        double a[2], c[2];
        triangle_box(m, t, a, c);
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], a[k]);
            hi[k] = fmax(hi[k], c[k]);
        }
        area += fabs(m->area_texel[t]);
        count++;
    }
    if (count == 0)
        return 0;
    b->cell = sqrt(2.0 * area / (double)count);
    if (!(b->cell > 0.0))
        b->cell = 1.0;
    double max_bins = fmax(1024.0, 4.0 * (double)count);
    while (((hi[0] - lo[0]) / b->cell + 1.0) * ((hi[1] - lo[1]) / b->cell + 1.0) > max_bins)
        b->cell *= 1.5;
    b->x0 = lo[0];
    b->y0 = lo[1];
    b->nx = (size_t)((hi[0] - lo[0]) / b->cell) + 1;
    b->ny = (size_t)((hi[1] - lo[1]) / b->cell) + 1;
    return 1;
}

texopt_status texopt_tri_bins_build(texopt_tri_bins *b, const texopt_mesh *m, const unsigned char *keep, char *err,
                                    size_t err_len)
{
    memset(b, 0, sizeof *b);
    if (!frame(b, m, keep))
        return TEXOPT_OK;
    size_t bins = b->nx * b->ny;
    b->start = calloc(bins + 1, sizeof *b->start);
    if (!b->start)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu triangle bins", bins);
    for (int pass = 0; pass < 2; pass++) {
        for (size_t t = 0; t < m->triangle_count; t++) {
            if (!keep[t])
                continue;
            double lo[2], hi[2];
            triangle_box(m, t, lo, hi);
            for (size_t j = texopt_tri_bins_index(b, lo[1], 1); j <= texopt_tri_bins_index(b, hi[1], 1); j++)
                for (size_t i = texopt_tri_bins_index(b, lo[0], 0); i <= texopt_tri_bins_index(b, hi[0], 0); i++) {
                    if (pass == 0)
                        b->start[j * b->nx + i + 1]++;
                    else
                        b->tri[b->start[j * b->nx + i]++] = (uint32_t)t;
                }
        }
        if (pass == 0) {
            for (size_t k = 0; k < bins; k++)
                b->start[k + 1] += b->start[k];
            b->tri = malloc((b->start[bins] ? b->start[bins] : 1) * sizeof *b->tri);
            if (!b->tri)
                return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %u binned triangles", b->start[bins]);
        }
    }
    for (size_t k = bins; k > 0; k--) /* the fill advanced each start to the next bin's */
        b->start[k] = b->start[k - 1];
    b->start[0] = 0;
    return TEXOPT_OK;
}

void texopt_tri_bins_free(texopt_tri_bins *b)
{
    if (!b)
        return;
    free(b->start);
    free(b->tri);
    b->start = NULL;
    b->tri = NULL;
}

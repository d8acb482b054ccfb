/* coverage.c - unique covered texels, overlap texels and packing efficiency of a layout.
 *
 * Implements the texel cost of Sun et al. 2022, "Efficient Texture Parameterization Driven
 * by Perceptual-Loss-on-Screen" (eq. 20) on the texel grid, as coverage.h specifies: a
 * scanline fill with a half-open rule into two bit masks (covered once, covered again).
 *
 * Why scanlines and not the sum of areas: real layouts overlap (mirrored halves, REPEAT
 * tiling), and the texture memory is the union of texels, not the sum. Why the half-open
 * rule and canonical edges: a shared edge must split its texels between its two triangles
 * bit-exactly, or every chart's interior would look like a thin overlap. The crossing of an
 * edge with a row centre is computed from its endpoints in one canonical order (sorted by
 * y, then x), so both triangles of an edge get the same double.
 *
 * Does not: rasterise attributes, pick a texture size, or pack (see the packer). */
#include "coverage.h"
#include "vec2.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Texel positions beyond this magnitude cannot be wrapped exactly in int64 arithmetic. */
#define MAX_COORDINATE 1e12
/* A triangle spanning more repeats of the frame than this is refused rather than filled. */
#define MAX_REPEATS 4096.0
/* Texel area of all triangles together past which a layout is refused rather than filled:
 * filling costs about a second per 10^10 texels, and a layout that repeats its texture so
 * often (UVs, or a texture transform, with a scale in the thousands) would take minutes. */
#define MAX_TOTAL_AREA 68719476736.0 /* 2^36 */

typedef enum span_op { SPAN_MARK, SPAN_MARK_ONCE, SPAN_QUERY } span_op;

typedef struct masks {
    int width, height;
    size_t words_per_row;
    uint64_t *covered; /* some triangle's centre-rule covers the texel */
    uint64_t *multi;   /* ... and a second one (or the same one again, wrapped) */
    uint64_t *clamped; /* read from outside a CLAMP frame; NULL without CLAMP */
    texopt_wrap wrap_s, wrap_t;
} masks;

static uint64_t word_bits(int64_t first, int64_t last, int64_t word)
{
    int lo = first > word * 64 ? (int)(first - word * 64) : 0;
    int hi = last < word * 64 + 63 ? (int)(last - word * 64) : 63;
    uint64_t upper = hi == 63 ? ~0ull : ((1ull << (hi + 1)) - 1);
    return upper & ~((1ull << lo) - 1);
}

/* Applies op to texels [x0, x1] (inside the frame) of wrapped row y. For SPAN_QUERY returns 1
 * when one of them is an overlap texel. */
static int apply_span(masks *m, int64_t y, int64_t x0, int64_t x1, span_op op)
{
    uint64_t *c = (op == SPAN_MARK_ONCE ? m->clamped : m->covered) + (size_t)y * m->words_per_row;
    uint64_t *mu = m->multi + (size_t)y * m->words_per_row;
    for (int64_t w = x0 >> 6; w <= x1 >> 6; w++) {
        uint64_t bits = word_bits(x0, x1, w);
        if (op == SPAN_QUERY) {
            if (mu[w] & bits)
                return 1;
        } else {
            if (op == SPAN_MARK)
                mu[w] |= c[w] & bits;
            c[w] |= bits;
        }
    }
    return 0;
}

static int64_t floor_div(int64_t a, int64_t n)
{
    int64_t q = a / n;
    return (a % n != 0 && a < 0) ? q - 1 : q;
}

/* Maps unwrapped columns [a, b] through wrap_s into frame chunks of frame row `row`, calling
 * apply_span for each. Parts that come from outside a CLAMP frame (row_clamped, or columns
 * clamped here) mark without counting overlaps. Returns 1 as soon as a query hits. */
static int wrap_columns(masks *m, int64_t row, int64_t a, int64_t b, span_op op, int row_clamped)
{
    int64_t n = m->width;
    span_op clamped = op == SPAN_MARK ? SPAN_MARK_ONCE : op;
    span_op normal = row_clamped ? clamped : op;
    if (m->wrap_s == TEXOPT_WRAP_CLAMP) {
        if (a < 0 && apply_span(m, row, 0, 0, clamped))
            return 1;
        if (b >= n && apply_span(m, row, n - 1, n - 1, clamped))
            return 1;
        int64_t s = a < 0 ? 0 : a, e = b >= n ? n - 1 : b;
        return s <= e ? apply_span(m, row, s, e, normal) : 0;
    }
    for (int64_t k = floor_div(a, n);; k++) {
        int64_t s = a > k * n ? a : k * n, e = b < k * n + n - 1 ? b : k * n + n - 1;
        if (s > e)
            break;
        int hit;
        if (m->wrap_s == TEXOPT_WRAP_MIRROR && (k & 1))
            hit = apply_span(m, row, k * n + n - 1 - e, k * n + n - 1 - s, normal);
        else
            hit = apply_span(m, row, s - k * n, e - k * n, normal);
        if (hit)
            return 1;
    }
    return 0;
}

/* The frame row of unwrapped row y; *clamped says it came from outside a CLAMP frame. */
static int64_t wrap_row(const masks *m, int64_t y, int *clamped)
{
    int64_t n = m->height;
    *clamped = 0;
    if (m->wrap_t == TEXOPT_WRAP_CLAMP) {
        if (y < 0 || y >= n)
            *clamped = 1;
        return y < 0 ? 0 : y >= n ? n - 1 : y;
    }
    int64_t k = floor_div(y, n), r = y - k * n;
    if (m->wrap_t == TEXOPT_WRAP_MIRROR && (k & 1))
        return n - 1 - r;
    return r;
}

/* Edge endpoints in canonical order (by y, then x). */
static void canonical_edge(const double *a, const double *b, const double **lo, const double **hi)
{
    int a_first = a[1] < b[1] || (a[1] == b[1] && a[0] <= b[0]);
    *lo = a_first ? a : b;
    *hi = a_first ? b : a;
}

/* Runs op over every texel whose centre the triangle covers. Returns 1 when a query hits. */
static int fill_triangle(masks *m, const double *p[3], span_op op)
{
    const double *lo[3], *hi[3];
    double ymin = p[0][1], ymax = p[0][1];
    for (int e = 0; e < 3; e++) {
        canonical_edge(p[e], p[(e + 1) % 3], &lo[e], &hi[e]);
        ymin = fmin(ymin, p[e][1]);
        ymax = fmax(ymax, p[e][1]);
    }
    /* rows whose centre y + 0.5 lies in [ymin, ymax) */
    int64_t y0 = (int64_t)ceil(ymin - 0.5), y1 = (int64_t)ceil(ymax - 0.5) - 1;
    for (int64_t y = y0; y <= y1; y++) {
        double yc = (double)y + 0.5, xs[3];
        int n = 0;
        for (int e = 0; e < 3; e++)
            if (lo[e][1] <= yc && yc < hi[e][1])
                xs[n++] = lo[e][0] + (yc - lo[e][1]) * (hi[e][0] - lo[e][0]) / (hi[e][1] - lo[e][1]);
        if (n != 2)
            continue;
        double left = fmin(xs[0], xs[1]), right = fmax(xs[0], xs[1]);
        /* columns whose centre x + 0.5 lies in [left, right) */
        int64_t x0 = (int64_t)ceil(left - 0.5), x1 = (int64_t)ceil(right - 0.5) - 1;
        if (x1 < x0)
            continue;
        int clamped;
        int64_t row = wrap_row(m, y, &clamped);
        if (wrap_columns(m, row, x0, x1, op, clamped))
            return 1;
    }
    return 0;
}

static uint64_t popcount_all(const uint64_t *words, size_t count)
{
    uint64_t n = 0;
    for (size_t i = 0; i < count; i++)
        n += (uint64_t)__builtin_popcountll(words[i]);
    return n;
}

static texopt_status check_triangle(const double *p[3], int width, int height, size_t t, char *err, size_t err_len)
{
    double xmin = p[0][0], xmax = p[0][0], ymin = p[0][1], ymax = p[0][1];
    for (int k = 0; k < 3; k++) {
        if (!isfinite(p[k][0]) || !isfinite(p[k][1]))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "coverage: triangle %zu has a non-finite texel position", t);
        if (fabs(p[k][0]) > MAX_COORDINATE || fabs(p[k][1]) > MAX_COORDINATE)
            return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "coverage: triangle %zu has a texel position beyond %g", t,
                               MAX_COORDINATE);
        xmin = fmin(xmin, p[k][0]);
        xmax = fmax(xmax, p[k][0]);
        ymin = fmin(ymin, p[k][1]);
        ymax = fmax(ymax, p[k][1]);
    }
    if (xmax - xmin > MAX_REPEATS * width || ymax - ymin > MAX_REPEATS * height)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                           "coverage: triangle %zu spans more than %g repeats of the %dx%d texture", t, MAX_REPEATS,
                           width, height);
    return TEXOPT_OK;
}

static void triangle_points(const texopt_mesh *mesh, const double *texel, size_t t, const double *p[3])
{
    for (int k = 0; k < 3; k++)
        p[k] = texel + 2 * (size_t)mesh->triangle[3 * t + (size_t)k];
}

/* Whether triangle t covers nothing: degenerate in the layout measured (mesh.h's test), so
 * that a layout is measured alike from any mesh of it, the one a file of it loads as too. */
static int covers_nothing(const texopt_mesh *mesh, const double *texel, size_t t)
{
    const double *p[3];
    triangle_points(mesh, texel, t, p);
    return texopt_texel_triangle_degenerate(p[0], p[1], p[2]);
}

texopt_status texopt_coverage_measure(const texopt_mesh *mesh, const texopt_coverage_options *opt, texopt_coverage *out,
                                      char *err, size_t err_len)
{
    texopt_coverage_options o = {0};
    if (opt)
        o = *opt;
    if (!mesh || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "coverage: no mesh or output");
    masks m = {.width = o.width > 0 ? o.width : mesh->width,
               .height = o.height > 0 ? o.height : mesh->height,
               .wrap_s = o.use_wraps ? o.wrap_s : mesh->wrap_s,
               .wrap_t = o.use_wraps ? o.wrap_t : mesh->wrap_t};
    const double *texel = o.texel ? o.texel : mesh->texel;
    if (o.width < 0 || o.height < 0 || m.width <= 0 || m.height <= 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "coverage: frame %dx%d is not valid", m.width,
                           m.height);
    if ((uint64_t)m.width * (uint64_t)m.height > TEXOPT_COVERAGE_MAX_TEXELS)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "coverage: frame %dx%d exceeds %llu texels", m.width, m.height,
                           (unsigned long long)TEXOPT_COVERAGE_MAX_TEXELS);
    double total_area = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const double *p[3];
        triangle_points(mesh, texel, t, p);
        texopt_status st = check_triangle(p, m.width, m.height, t, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        total_area += fabs(texopt_signed_area(p[0], p[1], p[2]));
    }
    if (total_area > MAX_TOTAL_AREA)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                           "coverage: the triangles cover %.3g texels, %.0f times the %dx%d texture (more than "
                           "2^36 to fill): the UVs repeat it that often (a texture transform or UVs scaled by "
                           "thousands?)",
                           total_area, total_area / ((double)m.width * m.height), m.width, m.height);
    m.words_per_row = ((size_t)m.width + 63) / 64;
    size_t words = m.words_per_row * (size_t)m.height;
    m.covered = calloc(words, sizeof(uint64_t));
    m.multi = calloc(words, sizeof(uint64_t));
    int clamps = m.wrap_s == TEXOPT_WRAP_CLAMP || m.wrap_t == TEXOPT_WRAP_CLAMP;
    if (clamps)
        m.clamped = calloc(words, sizeof(uint64_t));
    if (!m.covered || !m.multi || (clamps && !m.clamped)) {
        free(m.covered);
        free(m.multi);
        free(m.clamped);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "coverage: no memory for a %dx%d mask", m.width, m.height);
    }
    texopt_coverage res = {.width = m.width, .height = m.height};
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (covers_nothing(mesh, texel, t))
            continue;
        const double *p[3];
        triangle_points(mesh, texel, t, p);
        res.texel_area += fabs(texopt_signed_area(p[0], p[1], p[2]));
        fill_triangle(&m, p, SPAN_MARK);
    }
    if (m.clamped)
        for (size_t i = 0; i < words; i++)
            m.covered[i] |= m.clamped[i];
    res.covered_texels = popcount_all(m.covered, words);
    res.overlap_texels = popcount_all(m.multi, words);
    res.packing_efficiency = (double)res.covered_texels / ((double)m.width * (double)m.height);
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        int overlaps = 0;
        if (res.overlap_texels > 0 && !covers_nothing(mesh, texel, t)) {
            const double *p[3];
            triangle_points(mesh, texel, t, p);
            overlaps = fill_triangle(&m, p, SPAN_QUERY);
        }
        res.overlapping_triangles += (size_t)overlaps;
        if (o.triangle_flags)
            o.triangle_flags[t] = (uint8_t)(overlaps ? (o.triangle_flags[t] | TEXOPT_TRI_OVERLAPS)
                                                     : (o.triangle_flags[t] & ~TEXOPT_TRI_OVERLAPS));
    }
    free(m.covered);
    free(m.multi);
    free(m.clamped);
    *out = res;
    return TEXOPT_OK;
}

texopt_status texopt_coverage_model_texels(const texopt_model *model, uint64_t *texels, char *err, size_t err_len)
{
    if (!model || !texels)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "coverage: no model or output");
    uint64_t sum = 0;
    for (int d = 0; d < model->domain_count; d++) {
        texopt_mesh *mesh = NULL;
        texopt_status st = texopt_mesh_create(&mesh, model, d, err, err_len);
        texopt_coverage cov;
        if (st == TEXOPT_OK)
            st = texopt_coverage_measure(mesh, NULL, &cov, err, err_len);
        texopt_mesh_destroy(mesh);
        if (st != TEXOPT_OK)
            return st;
        sum += cov.covered_texels;
    }
    *texels = sum;
    return TEXOPT_OK;
}

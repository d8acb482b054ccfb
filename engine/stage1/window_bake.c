/* window_bake.c - least-squares bake of the texels a candidate parameterization shows on screen
 * (Sun et al. 2022, "Efficient Texture Parameterization Driven by Perceptual-Loss-on-
 * Screen", eq. 11; DESIGN.md 3.1). Solves the ridge-regularised normal equations
 * (A^T A + r I) x = A^T ref + r mean(ref) with banded Cholesky, all channels at once.
 * (GCC/Clang vector extensions are used for the narrow-band factorisation.)
 * Does not render, convert colour or measure the loss.
 *
 * Why banded: the footprints of a 64x64 screen window mapped by one linear J form a dense
 * patch of texels. Numbered in texture row-major order (column-major for a patch wider than
 * tall), a footprint's four texels are at most about one patch row (column) apart, so A^T A
 * has a band of that width and Cholesky costs n kd^2 instead of n^3 / 3. Texels are
 * numbered through a dense map over the patch's bounding box (no hashing, no sorting) when
 * the box is small, which is the normal case; footprints that straddle a wrap seam or
 * scatter over a huge texture go through a hash map and a sort instead. When a minified
 * patch has more touched texels than pixels, the pixel-side system A A^T + r I (push-through
 * identity, see solve notes below) is factored instead when its band is cheaper: same
 * minimiser, smaller and narrower system. */
#include "window_bake.h"

#include <lapacke.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sample.h"

typedef double bake_v2 __attribute__((vector_size(16)));

/* The dense map may be this many times larger than the footprint entries. */
#define BAKE_BOX_FACTOR 16
#define BAKE_LANE_SLACK 4

struct texopt_bake_workspace {
    int max_pixels, max_channels;
    texopt_bake_solver solver;
    int *rc;           /* 4 per pixel: wrapped columns c0, c1 and rows r0, r1 */
    int *cell;         /* 4 per pixel: local unknown of each footprint texel */
    double *weight;    /* 4 per pixel */
    int *texel;        /* per unknown: its box slot or texel index, ascending */
    int *first, *last; /* per unknown: envelope of A^T A (see envelope()) */
    int last_unknowns;
    /* the last successful fit's factored system, which texopt_bake_refit solves again */
    int last_pixel_count, last_kd;
    double last_ridge;
    /* dense map over a bounding box: a mark per touched slot (all clear between fits; 8 bytes
     * of slack for the scan's last load), and each touched slot's local unknown (stale
     * elsewhere: only touched slots are read) */
    unsigned char *box_marks;
    int *box;
    size_t box_capacity;
    /* hash map for the scattered case: texel -> unknown, open addressing */
    int *hash_key, *hash_value;
    size_t hash_mask;
    /* normal equations */
    double *band; /* (kd + 1) x n, LAPACK upper band storage */
    size_t band_capacity;
    double *rhs;    /* n x channels, row-major: a texel's channels side by side */
    double *column; /* two columns of the factor below their diagonal (2 (kd + 1) doubles) */
    int column_capacity;
    /* the pixel-side system (see solve_pixel_side) */
    texopt_bake_side side;
    int last_side;                 /* TEXOPT_BAKE_SIDE_TEXEL or _PIXEL of the last fit */
    int *unknown_start;            /* per unknown + 1: its footprint entries in unknown_entry */
    int *unknown_entry;            /* footprint entries grouped by unknown */
    int *pixel_first, *pixel_last; /* envelope of A A^T */
    double *pixel_rhs;             /* max_pixels x channels, row-major */
};

texopt_bake_workspace *texopt_bake_workspace_create(int max_pixels, int max_channels)
{
    if (max_pixels <= 0 || max_pixels > (1 << 24) || max_channels < 1 || max_channels > TEXOPT_BAKE_MAX_CHANNELS)
        return NULL;
    texopt_bake_workspace *ws = calloc(1, sizeof *ws);
    if (!ws)
        return NULL;
    size_t entries = 4 * (size_t)max_pixels;
    size_t hash_size = 1;
    while (hash_size < 2 * entries)
        hash_size <<= 1;
    ws->max_pixels = max_pixels;
    ws->max_channels = max_channels;
    ws->box_capacity = BAKE_BOX_FACTOR * entries + 1024;
    ws->hash_mask = hash_size - 1;
    ws->rc = malloc(entries * sizeof *ws->rc);
    ws->cell = malloc(entries * sizeof *ws->cell);
    ws->weight = malloc(entries * sizeof *ws->weight);
    ws->texel = malloc(entries * sizeof *ws->texel);
    ws->first = malloc(entries * sizeof *ws->first);
    ws->last = malloc(entries * sizeof *ws->last);
    ws->box = malloc(ws->box_capacity * sizeof *ws->box);
    ws->box_marks = calloc(ws->box_capacity + 8, 1);
    ws->hash_key = malloc(hash_size * sizeof *ws->hash_key);
    ws->hash_value = malloc(hash_size * sizeof *ws->hash_value);
    /* + BAKE_LANE_SLACK: the four-lane solve reads (and discards) up to 3 values past the
     * last row; calloc keeps them finite. */
    ws->rhs = calloc(entries * (size_t)max_channels + BAKE_LANE_SLACK, sizeof *ws->rhs);
    ws->unknown_start = malloc((entries + 1) * sizeof *ws->unknown_start);
    ws->unknown_entry = malloc(entries * sizeof *ws->unknown_entry);
    ws->pixel_first = malloc((size_t)max_pixels * sizeof *ws->pixel_first);
    ws->pixel_last = malloc((size_t)max_pixels * sizeof *ws->pixel_last);
    ws->pixel_rhs = calloc((size_t)max_pixels * (size_t)max_channels + BAKE_LANE_SLACK, sizeof *ws->pixel_rhs);
    if (!ws->rc || !ws->cell || !ws->weight || !ws->texel || !ws->first || !ws->last || !ws->box || !ws->box_marks ||
        !ws->hash_key || !ws->hash_value || !ws->rhs || !ws->unknown_start || !ws->unknown_entry || !ws->pixel_first ||
        !ws->pixel_last || !ws->pixel_rhs) {
        texopt_bake_workspace_destroy(ws);
        return NULL;
    }
    memset(ws->hash_key, 0xff, hash_size * sizeof *ws->hash_key); /* all -1: empty */
    return ws;
}

void texopt_bake_workspace_destroy(texopt_bake_workspace *ws)
{
    if (!ws)
        return;
    free(ws->rc);
    free(ws->cell);
    free(ws->weight);
    free(ws->texel);
    free(ws->first);
    free(ws->last);
    free(ws->box);
    free(ws->box_marks);
    free(ws->hash_key);
    free(ws->hash_value);
    free(ws->band);
    free(ws->column);
    free(ws->rhs);
    free(ws->unknown_start);
    free(ws->unknown_entry);
    free(ws->pixel_first);
    free(ws->pixel_last);
    free(ws->pixel_rhs);
    free(ws);
}

int texopt_bake_last_texel_count(const texopt_bake_workspace *ws)
{
    return ws ? ws->last_unknowns : 0;
}

int texopt_bake_last_bandwidth(const texopt_bake_workspace *ws)
{
    return ws && ws->last_unknowns > 0 ? ws->last_kd : 0;
}

texopt_bake_side texopt_bake_last_side(const texopt_bake_workspace *ws)
{
    return ws ? (texopt_bake_side)ws->last_side : TEXOPT_BAKE_SIDE_AUTO;
}

void texopt_bake_workspace_set_side(texopt_bake_workspace *ws, texopt_bake_side side)
{
    if (ws && side >= TEXOPT_BAKE_SIDE_AUTO && side <= TEXOPT_BAKE_SIDE_PIXEL)
        ws->side = side;
}

typedef struct cell_box {
    int col0, row0, cols, rows;
} cell_box;

/* texopt_bilinear_cells for a footprint whose four texels are inside the grid (the usual
 * case: the caller centres the patch), inlined, with the same arithmetic and so the same
 * weights; returns 0 (and writes nothing) otherwise. Saves a call and four wrap tests per
 * pixel. */
static inline int footprint_inside(int width, int height, double x, double y, int rc[4], double w[4])
{
    /* Also false for NaN: such positions take the general path. */
    if (!(x >= 0.5 && y >= 0.5 && x < width - 0.5 && y < height - 0.5))
        return 0;
    double xs = x - 0.5, ys = y - 0.5;
    int x0 = (int)xs, y0 = (int)ys; /* xs, ys >= 0.5: truncation is floor */
    double fx = xs - x0, fy = ys - y0;
    rc[0] = x0;
    rc[1] = x0 + 1;
    rc[2] = y0;
    rc[3] = y0 + 1;
    w[0] = (1.0 - fx) * (1.0 - fy);
    w[1] = fx * (1.0 - fy);
    w[2] = (1.0 - fx) * fy;
    w[3] = fx * fy;
    return 1;
}

/* Footprints of every pixel as wrapped columns and rows (ws->rc: c0, c1, r0, r1 per pixel);
 * returns the bounding box of their cells. No division anywhere in the per-pixel work. */
static cell_box gather_footprints(texopt_bake_workspace *ws, int pixel_count, const double *texel_pos, int width,
                                  int height, texopt_wrap wrap_s, texopt_wrap wrap_t)
{
    int cmin = width, cmax = -1, rmin = height, rmax = -1;
    for (int q = 0; q < pixel_count; q++) {
        int *rc = ws->rc + 4 * (size_t)q;
        double *w = ws->weight + 4 * (size_t)q;
        if (!footprint_inside(width, height, texel_pos[2 * q], texel_pos[2 * q + 1], rc, w))
            texopt_bilinear_cells(width, height, wrap_s, wrap_t, texel_pos[2 * q], texel_pos[2 * q + 1], rc, rc + 2, w);
        for (int k = 0; k < 2; k++) {
            cmin = rc[k] < cmin ? rc[k] : cmin;
            cmax = rc[k] > cmax ? rc[k] : cmax;
            rmin = rc[2 + k] < rmin ? rc[2 + k] : rmin;
            rmax = rc[2 + k] > rmax ? rc[2 + k] : rmax;
        }
    }
    cell_box box = {cmin, rmin, cmax - cmin + 1, rmax - rmin + 1};
    return box;
}

/* Numbers the touched texels through a dense map over the box, row by row when the box is
 * at least as tall as wide and column by column when it is wider. A footprint couples a
 * texel with the next row (column), so A^T A's band is about one row (column) of the patch;
 * for an elliptic patch the chord along the box's shorter side is the shorter one, and
 * Cholesky costs n kd^2 (squeezed candidates lying along the texture's x axis had bands
 * as wide as the patch: BENCHMARKS.md@9f788a8, "Stage 1"). In column order the footprint's
 * entries 1 and 2 (and their weights) swap, so its four unknowns stay ascending. Touched
 * slots are marked with a byte (plain stores), so the scan reads 8 slots a load
 * and the marks take a quarter of the cache an int per slot did (the box may hold up to
 * BAKE_BOX_FACTOR x entries slots, and a minified or rotated patch touches only part of it;
 * numbering through an int per slot was ~9% of a DamagedHelmet triangle's CPU). The scan
 * clears the marks it reads; box[] is read only at touched slots, which it rewrites. */
static int number_through_box(texopt_bake_workspace *ws, int pixel_count, cell_box b)
{
    unsigned char *marks = ws->box_marks;
    int *box = ws->box;
    static const int row_order[4] = {0, 1, 2, 3}, column_order[4] = {0, 2, 1, 3};
    int by_column = b.cols > b.rows;
    int row_step = by_column ? 1 : b.cols, col_step = by_column ? b.rows : 1;
    const int *order = by_column ? column_order : row_order;
    for (int q = 0; q < pixel_count; q++) {
        const int *rc = ws->rc + 4 * (size_t)q;
        int *cell = ws->cell + 4 * (size_t)q;
        for (int k = 0; k < 4; k++) {
            int e = order[k];
            int slot = (rc[2 + (e >> 1)] - b.row0) * row_step + (rc[e & 1] - b.col0) * col_step;
            marks[slot] = 1;
            cell[k] = slot;
        }
        if (by_column) {
            double *w = ws->weight + 4 * (size_t)q, w1 = w[1];
            w[1] = w[2];
            w[2] = w1;
        }
    }
    int n = 0;
    size_t area = (size_t)b.rows * (size_t)b.cols;
    for (size_t at = 0; at < area; at += 8) {
        uint64_t word;
        memcpy(&word, marks + at, sizeof word);
        if (!word)
            continue;
        for (int k = 0; k < 8; k++) {
            if (marks[at + k]) {
                int slot = (int)at + k;
                ws->texel[n] = slot;
                box[slot] = n++;
            }
        }
        memset(marks + at, 0, sizeof word);
    }
    for (int e = 0; e < 4 * pixel_count; e++)
        ws->cell[e] = box[ws->cell[e]];
    return n;
}

static size_t hash_slot(const texopt_bake_workspace *ws, int key)
{
    size_t h = ((uint32_t)key * 2654435761u) & ws->hash_mask;
    while (ws->hash_key[h] != -1 && ws->hash_key[h] != key)
        h = (h + 1) & ws->hash_mask;
    return h;
}

static int compare_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* The scattered case: unique texels through a hash map, sorted into row-major order. */
static int number_through_hash(texopt_bake_workspace *ws, int pixel_count, int width)
{
    int n = 0, entries = 4 * pixel_count;
    for (int q = 0; q < pixel_count; q++) {
        const int *rc = ws->rc + 4 * (size_t)q;
        for (int k = 0; k < 4; k++)
            ws->cell[4 * q + k] = rc[2 + (k >> 1)] * width + rc[k & 1];
    }
    for (int e = 0; e < entries; e++) {
        size_t h = hash_slot(ws, ws->cell[e]);
        if (ws->hash_key[h] == -1) {
            ws->hash_key[h] = ws->cell[e];
            ws->texel[n++] = ws->cell[e];
        }
    }
    qsort(ws->texel, (size_t)n, sizeof *ws->texel, compare_int);
    for (int i = 0; i < n; i++)
        ws->hash_value[hash_slot(ws, ws->texel[i])] = i;
    for (int e = 0; e < entries; e++)
        ws->cell[e] = ws->hash_value[hash_slot(ws, ws->cell[e])];
    /* Empty the table again: every key sits in the run of occupied slots that starts at its
     * home slot, and the table held only our keys, so wiping those runs empties it. */
    for (int i = 0; i < n; i++) {
        size_t h = ((uint32_t)ws->texel[i] * 2654435761u) & ws->hash_mask;
        while (ws->hash_key[h] != -1) {
            ws->hash_key[h] = -1;
            h = (h + 1) & ws->hash_mask;
        }
    }
    return n;
}

/* Closes an envelope: makes first[] non-decreasing (a suffix minimum) so that the rows
 * reaching back to column j are exactly j+1 .. last[j], fills last[] and returns the
 * bandwidth kd = max(i - first[i]). */
static int close_envelope(int *first, int *last, int n)
{
    int kd = 0;
    for (int i = n - 1; i >= 0; i--) {
        if (i + 1 < n && first[i + 1] < first[i])
            first[i] = first[i + 1];
        kd = i - first[i] > kd ? i - first[i] : kd;
    }
    for (int j = 0, i = 0; j < n; j++) {
        while (i + 1 < n && first[i + 1] <= j)
            i++;
        last[j] = i > j ? i : j;
    }
    return kd;
}

/* The envelope of A^T A: first[i] = the smallest unknown coupled to unknown i. Cholesky
 * fill stays inside the envelope, so the factorisation and the solves skip the band's zeros
 * outside it (~1/3 of the work for a round patch). Returns the bandwidth. */
static int envelope(texopt_bake_workspace *ws, int pixel_count, int n)
{
    int *first = ws->first, *last = ws->last;
    for (int i = 0; i < n; i++)
        first[i] = i;
    for (int q = 0; q < pixel_count; q++) {
        const int *c = ws->cell + 4 * (size_t)q;
        int lo = c[0];
        for (int k = 1; k < 4; k++)
            lo = c[k] < lo ? c[k] : lo;
        for (int k = 0; k < 4; k++)
            first[c[k]] = lo < first[c[k]] ? lo : first[c[k]];
    }
    return close_envelope(first, last, n);
}

static int reserve_band(texopt_bake_workspace *ws, size_t needed, int kd)
{
    if (2 * (kd + 1) > ws->column_capacity) { /* two columns: band_cholesky_avx2 */
        double *column = realloc(ws->column, (size_t)(2 * (kd + 1)) * sizeof *column);
        if (!column)
            return 0;
        ws->column = column;
        ws->column_capacity = 2 * (kd + 1);
    }
    if (needed <= ws->band_capacity)
        return 1;
    double *band = realloc(ws->band, needed * sizeof *band);
    if (!band)
        return 0;
    ws->band = band;
    ws->band_capacity = needed;
    return 1;
}

/* row[u] -= f * column[u] for u in [0, count): two lanes at a time (SSE2, baseline x86-64;
 * GCC and Clang vector extensions elsewhere), unaligned through memcpy. */
static inline void subtract_scaled(double *restrict row, const double *restrict column, double f, int count)
{
    bake_v2 fv = {f, f};
    int u = 0;
    for (; u + 4 <= count; u += 4) {
        bake_v2 a, b, c, d;
        memcpy(&a, row + u, sizeof a);
        memcpy(&b, row + u + 2, sizeof b);
        memcpy(&c, column + u, sizeof c);
        memcpy(&d, column + u + 2, sizeof d);
        a -= fv * c;
        b -= fv * d;
        memcpy(row + u, &a, sizeof a);
        memcpy(row + u + 2, &b, sizeof b);
    }
    for (; u < count; u++)
        row[u] -= f * column[u];
}

/* A^T ref + ridge mean as right-hand sides (ws->rhs, n x channels). A pixel's reference is
 * widened to doubles once for its four texels (the per-texel float conversions and the
 * scalar channel loop were 8% of the DamagedHelmet stage-1 bench's samples). */
static void assemble_texel_rhs(texopt_bake_workspace *ws, int pixel_count, int n, const float *reference, int channels,
                               double ridge)
{
    double *rhs = ws->rhs;
    memset(rhs, 0, (size_t)n * (size_t)channels * sizeof *rhs);
    double mean[TEXOPT_BAKE_MAX_CHANNELS] = {0};
    for (int q = 0; q < pixel_count; q++) {
        const int *c = ws->cell + 4 * (size_t)q;
        const double *w = ws->weight + 4 * (size_t)q;
        const float *ref = reference + (size_t)q * channels;
        double wide[TEXOPT_BAKE_MAX_CHANNELS];
        for (int ch = 0; ch < channels; ch++) {
            wide[ch] = ref[ch];
            mean[ch] += wide[ch];
        }
        for (int k = 0; k < 4; k++) /* += w v, as -= (-w) v: the same bits */
            subtract_scaled(rhs + (size_t)c[k] * channels, wide, -w[k], channels);
    }
    for (int ch = 0; ch < channels; ch++) {
        double m = mean[ch] / pixel_count;
        for (int i = 0; i < n; i++)
            rhs[(size_t)i * channels + ch] += ridge * m;
    }
}

/* A^T A + ridge I in upper band storage. */
static void assemble_normal_equations(texopt_bake_workspace *ws, int pixel_count, int n, int kd, double ridge)
{
    int ld = kd + 1;
    double *band = ws->band;
    memset(band, 0, (size_t)ld * (size_t)n * sizeof *band);
    for (int q = 0; q < pixel_count; q++) {
        const int *c = ws->cell + 4 * (size_t)q;
        const double *w = ws->weight + 4 * (size_t)q;
        if (c[0] < c[1] && c[1] < c[2] && c[2] < c[3]) {
            /* The usual footprint (no wrap, no clamp): four distinct texels in ascending
             * order, so the ten upper entries are known without tests. */
            for (int b = 0; b < 4; b++) {
                double *col = band + (size_t)kd + (size_t)c[b] * ld - c[b];
                for (int a = 0; a <= b; a++)
                    col[c[a]] += w[a] * w[b];
            }
        } else {
            for (int a = 0; a < 4; a++)
                for (int b = 0; b < 4; b++)
                    if (c[a] <= c[b])
                        band[(size_t)(kd + c[a] - c[b]) + (size_t)c[b] * ld] += w[a] * w[b];
        }
    }
    for (int i = 0; i < n; i++)
        band[(size_t)kd + (size_t)i * ld] += ridge;
}

/* Gathers column j of L below the diagonal into `column` after scaling it by the pivot.
 * Returns the number of rows below j in the envelope, or -1 when A is not positive
 * definite. Storage: row i of L holds columns i-kd..i contiguously, L(i, j) =
 * band[i * (kd + 1) + kd - (i - j)] -- the same bytes as LAPACK's column-major upper band
 * of A (U = L^T), so assembly fills it directly and either factorisation can be used. */
static inline int scale_column(double *band, int j, int kd, const int *last, double *column)
{
    int ld = kd + 1;
    double *lj = band + (size_t)j * ld + kd - j; /* lj[k] = L(j, k) */
    double d = lj[j];
    if (!(d > 0.0))
        return -1;
    double pivot = sqrt(d), inv = 1.0 / pivot;
    lj[j] = pivot;
    int m = last[j] - j;
    for (int t = 0; t < m; t++) {
        double *li = band + (size_t)(j + 1 + t) * ld + kd - (j + 1 + t);
        li[j] *= inv;
        column[t] = li[j];
    }
    return m;
}

/* In-place banded Cholesky, right-looking: each scaled column's outer product is subtracted
 * from the triangle below it, rows j+1+t, columns j+1 .. j+1+t. Returns 0 when A is not
 * positive definite. */
static int band_cholesky_sse2(double *band, int n, int kd, const int *last, double *column)
{
    int ld = kd + 1;
    for (int j = 0; j < n; j++) {
        int m = scale_column(band, j, kd, last, column);
        if (m < 0)
            return 0;
        for (int t = 0; t < m; t++)
            subtract_scaled(band + (size_t)(j + 1 + t) * ld + kd - t, column, column[t], t + 1);
    }
    return 1;
}

#if defined(__GNUC__) && defined(__x86_64__)
#define BAKE_HAVE_AVX2 1
typedef double bake_v4 __attribute__((vector_size(32)));

/* subtract_scaled with four lanes: row[u] -= f * column[u] for u in [0, count). */
__attribute__((target("avx2,fma"), always_inline)) static inline void subtract_scaled_avx2(
    double *restrict row, const double *restrict column, double f, int count)
{
    bake_v4 fv = {f, f, f, f};
    int u = 0;
    for (; u + 4 <= count; u += 4) {
        bake_v4 a, c;
        memcpy(&a, row + u, sizeof a);
        memcpy(&c, column + u, sizeof c);
        a -= fv * c;
        memcpy(row + u, &a, sizeof a);
    }
    for (; u < count; u++)
        row[u] -= f * column[u];
}

/* row[u] -= f0 * c0[u] + f1 * c1[u] for u in [0, count). */
__attribute__((target("avx2,fma"), always_inline)) static inline void subtract_scaled2_avx2(
    double *restrict row, const double *restrict c0, double f0, const double *restrict c1, double f1, int count)
{
    bake_v4 f0v = {f0, f0, f0, f0}, f1v = {f1, f1, f1, f1};
    int u = 0;
    for (; u + 4 <= count; u += 4) {
        bake_v4 a, x, y;
        memcpy(&a, row + u, sizeof a);
        memcpy(&x, c0 + u, sizeof x);
        memcpy(&y, c1 + u, sizeof y);
        a -= f0v * x;
        a -= f1v * y;
        memcpy(row + u, &a, sizeof a);
    }
    for (; u < count; u++)
        row[u] -= f0 * c0[u] + f1 * c1[u];
}

/* The same with four lanes and fused multiply-adds, for CPUs that have them (checked at
 * run time): 1.5x the two-lane loop. Columns are taken two at a time (a rank-2 update), so
 * the triangle below is loaded and stored once per pair: column j is scaled and applied to
 * column j+1 only, column j+1 is scaled, then both update the rows below (8-20% less
 * Cholesky time on the stage-1 bench; `column` holds 2 (kd + 1) doubles). Rows past
 * last[j] have L(i, j) = 0 and take column j+1 alone. */
__attribute__((target("avx2,fma"))) static int band_cholesky_avx2(double *band, int n, int kd, const int *last,
                                                                  double *column)
{
    int ld = kd + 1, j = 0;
    double *next = column + kd + 1;
    for (; j + 1 < n; j += 2) {
        int m0 = scale_column(band, j, kd, last, column);
        if (m0 < 0)
            return 0;
        for (int t = 0; t < m0; t++) /* the first entry of row j+1+t's segment: column j+1 */
            band[(size_t)(j + 1 + t) * ld + kd - t] -= column[t] * column[0];
        int m1 = scale_column(band, j + 1, kd, last, next);
        if (m1 < 0)
            return 0;
        for (int t = 0; t < m1; t++) {
            double *row = band + (size_t)(j + 2 + t) * ld + kd - t;
            if (t + 1 < m0)
                subtract_scaled2_avx2(row, column + 1, column[t + 1], next, next[t], t + 1);
            else
                subtract_scaled_avx2(row, next, next[t], t + 1);
        }
    }
    for (; j < n; j++) {
        int m = scale_column(band, j, kd, last, column);
        if (m < 0)
            return 0;
        for (int t = 0; t < m; t++)
            subtract_scaled_avx2(band + (size_t)(j + 1 + t) * ld + kd - t, column, column[t], t + 1);
    }
    return 1;
}
#endif

/* Below these bandwidths the loops above beat LAPACK dpbtrf, which runs its unblocked path
 * with a BLAS call per column there (two lanes: 1.3-2.5x at kd 8..45, equal at 56-64; four
 * lanes with FMA: ahead up to kd ~ 96); above them dpbtrf's blocked path wins
 * (kd 120: 2.4 ms against 3.2 ms). */
#define BAKE_SSE2_CHOLESKY_MAX_KD 56
#define BAKE_AVX2_CHOLESKY_MAX_KD 96

static int cpu_has_avx2_fma(void)
{
#ifdef BAKE_HAVE_AVX2
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return 0;
#endif
}

static int band_cholesky(texopt_bake_solver solver, double *band, int n, int kd, const int *last, double *column)
{
    int avx2 = cpu_has_avx2_fma();
    if (solver == TEXOPT_BAKE_SOLVER_AUTO)
        solver = avx2 && kd < BAKE_AVX2_CHOLESKY_MAX_KD ? TEXOPT_BAKE_SOLVER_VECTOR4
                 : kd < BAKE_SSE2_CHOLESKY_MAX_KD       ? TEXOPT_BAKE_SOLVER_VECTOR2
                                                        : TEXOPT_BAKE_SOLVER_LAPACK;
#ifdef BAKE_HAVE_AVX2
    if (solver == TEXOPT_BAKE_SOLVER_VECTOR4 && avx2)
        return band_cholesky_avx2(band, n, kd, last, column);
#endif
    if (solver == TEXOPT_BAKE_SOLVER_LAPACK)
        return LAPACKE_dpbtrf_work(LAPACK_COL_MAJOR, 'U', n, kd, band, kd + 1) == 0;
    return band_cholesky_sse2(band, n, kd, last, column);
}

void texopt_bake_workspace_set_solver(texopt_bake_workspace *ws, texopt_bake_solver solver)
{
    if (ws && solver >= TEXOPT_BAKE_SOLVER_AUTO && solver <= TEXOPT_BAKE_SOLVER_LAPACK)
        ws->solver = solver;
}

/* Dot product two lanes at a time (independent partial sums shorten the dependency chain). */
static double dot2(const double *a, const double *b, int count)
{
    bake_v2 acc0 = {0.0, 0.0}, acc1 = {0.0, 0.0};
    int k = 0;
    for (; k + 4 <= count; k += 4) {
        bake_v2 a0, a1, b0, b1;
        memcpy(&a0, a + k, sizeof a0);
        memcpy(&a1, a + k + 2, sizeof a1);
        memcpy(&b0, b + k, sizeof b0);
        memcpy(&b1, b + k + 2, sizeof b1);
        acc0 += a0 * b0;
        acc1 += a1 * b1;
    }
    double s = (acc0[0] + acc1[0]) + (acc0[1] + acc1[1]);
    for (; k < count; k++)
        s += a[k] * b[k];
    return s;
}

/* Several channels: every row of L is read once per triangular solve for all of them (the
 * channels of a texel are the vector lanes), instead of once per channel. */
static void band_solve_channels(const double *band, int n, int kd, const int *envelope_first, double *rhs, int channels)
{
    int ld = kd + 1;
    for (int i = 0; i < n; i++) {
        const double *li = band + (size_t)i * ld + kd - i;
        double *xi = rhs + (size_t)i * channels;
        for (int k = envelope_first[i]; k < i; k++)
            subtract_scaled(xi, rhs + (size_t)k * channels, li[k], channels);
        for (int c = 0; c < channels; c++)
            xi[c] /= li[i];
    }
    for (int i = n - 1; i >= 0; i--) {
        const double *li = band + (size_t)i * ld + kd - i;
        double *xi = rhs + (size_t)i * channels;
        for (int c = 0; c < channels; c++)
            xi[c] /= li[i];
        for (int k = envelope_first[i]; k < i; k++)
            subtract_scaled(rhs + (size_t)k * channels, xi, li[k], channels);
    }
}

#ifdef BAKE_HAVE_AVX2
/* One right-hand side with four lanes and fused multiply-adds (the two-lane loops below were
 * 16% of a DamagedHelmet triangle, most search evaluations bake one signal). */
__attribute__((target("avx2,fma"))) static void band_solve_one_avx2(const double *band, int n, int kd,
                                                                    const int *envelope_first, double *x)
{
    int ld = kd + 1;
    for (int i = 0; i < n; i++) {
        const double *li = band + (size_t)i * ld + kd - i;
        int k = envelope_first[i];
        bake_v4 acc = {0.0, 0.0, 0.0, 0.0};
        for (; k + 4 <= i; k += 4) {
            bake_v4 a, b;
            memcpy(&a, li + k, sizeof a);
            memcpy(&b, x + k, sizeof b);
            acc += a * b;
        }
        double dot = (acc[0] + acc[2]) + (acc[1] + acc[3]);
        for (; k < i; k++)
            dot += li[k] * x[k];
        x[i] = (x[i] - dot) / li[i];
    }
    for (int i = n - 1; i >= 0; i--) {
        const double *li = band + (size_t)i * ld + kd - i;
        double xi = x[i] / li[i];
        x[i] = xi;
        int k = envelope_first[i];
        subtract_scaled_avx2(x + k, li + k, xi, i - k);
    }
}
#endif

#ifdef BAKE_HAVE_AVX2
/* acc[0..vecs) += f * the row at x, four channels a vector (lanes past the row's channels
 * read the next row and are discarded by finish_row). */
__attribute__((target("avx2,fma"), always_inline)) static inline void accumulate_row(bake_v4 acc[4], double f,
                                                                                     const double *x, const int vecs)
{
    bake_v4 fv = {f, f, f, f}, v;
    memcpy(&v, x, sizeof v);
    acc[0] += fv * v;
    if (vecs > 1) {
        memcpy(&v, x + 4, sizeof v);
        acc[1] += fv * v;
    }
    if (vecs > 2) {
        memcpy(&v, x + 8, sizeof v);
        acc[2] += fv * v;
    }
    if (vecs > 3) {
        memcpy(&v, x + 12, sizeof v);
        acc[3] += fv * v;
    }
}

static inline void finish_row(double *x, const bake_v4 acc[4], double pivot, int channels)
{
    for (int c = 0; c < channels; c++)
        x[c] = (x[c] - acc[c >> 2][c & 3]) / pivot;
}

/* Several channels, both triangular solves in gather form: row i's sum over the rows it
 * depends on stays in registers and row i is written once (the scatter loop of
 * band_solve_channels rewrote it per coupled row: 14% of a DamagedHelmet triangle). The
 * backward solve reads column i of L, rows i+1 .. last[i], L(k, i) at a stride of kd. */
__attribute__((target("avx2,fma"), always_inline)) static inline void solve_channels_avx2_vecs(
    const double *band, int n, int kd, const int *first, const int *last, double *rhs, int channels, const int vecs)
{
    int ld = kd + 1;
    for (int i = 0; i < n; i++) {
        const double *li = band + (size_t)i * ld + kd - i;
        bake_v4 acc[4] = {{0.0, 0.0, 0.0, 0.0}};
        for (int k = first[i]; k < i; k++)
            accumulate_row(acc, li[k], rhs + (size_t)k * channels, vecs);
        finish_row(rhs + (size_t)i * channels, acc, li[i], channels);
    }
    for (int i = n - 1; i >= 0; i--) {
        bake_v4 acc[4] = {{0.0, 0.0, 0.0, 0.0}};
        for (int k = i + 1; k <= last[i]; k++)
            accumulate_row(acc, band[(size_t)k * kd + (size_t)kd + (size_t)i], rhs + (size_t)k * channels, vecs);
        finish_row(rhs + (size_t)i * channels, acc, band[(size_t)i * ld + kd], channels);
    }
}

__attribute__((target("avx2,fma"))) static void band_solve_channels_avx2(const double *band, int n, int kd,
                                                                         const int *first, const int *last, double *rhs,
                                                                         int channels)
{
    switch ((channels + 3) / 4) {
    case 1: solve_channels_avx2_vecs(band, n, kd, first, last, rhs, channels, 1); break;
    case 2: solve_channels_avx2_vecs(band, n, kd, first, last, rhs, channels, 2); break;
    case 3: solve_channels_avx2_vecs(band, n, kd, first, last, rhs, channels, 3); break;
    default: solve_channels_avx2_vecs(band, n, kd, first, last, rhs, channels, 4); break;
    }
}
#endif

/* Solves L L^T X = B in place, B row-major n x channels; first/last: the envelope. */
static void band_solve(const double *band, int n, int kd, const int *envelope_first, const int *envelope_last,
                       double *rhs, int channels)
{
#ifdef BAKE_HAVE_AVX2
    if (channels > 1 && cpu_has_avx2_fma()) {
        band_solve_channels_avx2(band, n, kd, envelope_first, envelope_last, rhs, channels);
        return;
    }
#endif
    if (channels > 1) {
        band_solve_channels(band, n, kd, envelope_first, rhs, channels);
        return;
    }
#ifdef BAKE_HAVE_AVX2
    if (cpu_has_avx2_fma()) {
        band_solve_one_avx2(band, n, kd, envelope_first, rhs);
        return;
    }
#endif
    int ld = kd + 1;
    double *x = rhs;
    for (int i = 0; i < n; i++) {
        const double *li = band + (size_t)i * ld + kd - i;
        int first = envelope_first[i];
        x[i] = (x[i] - dot2(li + first, x + first, i - first)) / li[i];
    }
    for (int i = n - 1; i >= 0; i--) {
        const double *li = band + (size_t)i * ld + kd - i;
        int first = envelope_first[i];
        double xi = x[i] / li[i];
        x[i] = xi;
        subtract_scaled(x + first, li + first, xi, i - first);
    }
}

static void reconstruct(const texopt_bake_workspace *ws, int pixel_count, int channels, float *out)
{
    for (int q = 0; q < pixel_count; q++) {
        const int *c = ws->cell + 4 * (size_t)q;
        const double *w = ws->weight + 4 * (size_t)q;
        const double *x0 = ws->rhs + (size_t)c[0] * channels;
        const double *x1 = ws->rhs + (size_t)c[1] * channels;
        const double *x2 = ws->rhs + (size_t)c[2] * channels;
        const double *x3 = ws->rhs + (size_t)c[3] * channels;
        for (int ch = 0; ch < channels; ch++)
            out[(size_t)q * channels + ch] = (float)(w[0] * x0[ch] + w[1] * x1[ch] + w[2] * x2[ch] + w[3] * x3[ch]);
    }
}

/* The pixel side. When the footprints spread over more texels than there are pixels (a
 * one-ring minified on screen), the texel system is large and, numbered by rows or columns
 * over a wide patch, has a wide band. With y = x - m (m the mean reference, per channel) the
 * fit is min |A y - b'|^2 + r |y|^2 with b' = b - m A 1, whose minimiser is, by the
 * push-through identity (A^T A + r I)^-1 A^T = A^T (A A^T + r I)^-1,
 *     y = A^T z,   (A A^T + r I) z = b'.
 * A A^T is pixels x pixels, couples only pixels that share a texel (screen neighbours when
 * minified) and, in the caller's pixel order (row-major on screen), has a narrow band. The
 * same banded Cholesky solves it; x = m + A^T z is then the same texel solution. */

/* Footprint entries grouped by unknown (a counting sort): unknown_entry[unknown_start[u] ..
 * unknown_start[u + 1]) are the entries e (pixel e / 4) on texel u, ascending. ws->texel,
 * free once the texels are numbered, serves as the fill cursor. */
static void group_entries_by_unknown(texopt_bake_workspace *ws, int pixel_count, int n)
{
    int *start = ws->unknown_start, *cursor = ws->texel, entries = 4 * pixel_count;
    memset(start, 0, (size_t)(n + 1) * sizeof *start);
    for (int e = 0; e < entries; e++)
        start[ws->cell[e] + 1]++;
    for (int u = 0; u < n; u++)
        start[u + 1] += start[u];
    memcpy(cursor, start, (size_t)n * sizeof *cursor);
    for (int e = 0; e < entries; e++)
        ws->unknown_entry[cursor[ws->cell[e]]++] = e;
}

/* The envelope of A A^T: pixel q reaches back to the smallest pixel sharing one of its
 * texels, which is the first entry of that texel's group. */
static int pixel_envelope(texopt_bake_workspace *ws, int pixel_count)
{
    int *first = ws->pixel_first;
    for (int q = 0; q < pixel_count; q++) {
        int lo = q;
        for (int k = 0; k < 4; k++) {
            int u = ws->cell[4 * q + k];
            int p = ws->unknown_entry[ws->unknown_start[u]] >> 2;
            lo = p < lo ? p : lo;
        }
        first[q] = lo;
    }
    return close_envelope(first, ws->pixel_last, pixel_count);
}

/* b - m (A 1) as right-hand sides (pixel_rhs, pixels x channels). */
static void assemble_pixel_rhs(texopt_bake_workspace *ws, int pixel_count, const float *reference, int channels,
                               const double *mean)
{
    for (int q = 0; q < pixel_count; q++) {
        const double *w = ws->weight + 4 * (size_t)q;
        double row_sum = w[0] + w[1] + w[2] + w[3];
        for (int ch = 0; ch < channels; ch++)
            ws->pixel_rhs[(size_t)q * channels + ch] =
                (double)reference[(size_t)q * channels + ch] - mean[ch] * row_sum;
    }
}

/* A A^T + r I in upper band storage. */
static void assemble_pixel_system(texopt_bake_workspace *ws, int pixel_count, int n, int kd, double ridge)
{
    int ld = kd + 1;
    double *band = ws->band;
    memset(band, 0, (size_t)ld * (size_t)pixel_count * sizeof *band);
    for (int u = 0; u < n; u++) {
        for (int i = ws->unknown_start[u]; i < ws->unknown_start[u + 1]; i++) {
            int e1 = ws->unknown_entry[i], q1 = e1 >> 2;
            double w1 = ws->weight[e1];
            /* Entries ascend, so q2 >= q1: the upper triangle. Two entries of one pixel on
             * the same texel (a clamped footprint) meet in both orders on the diagonal. */
            band[(size_t)kd + (size_t)q1 * ld] += w1 * w1;
            for (int j = i + 1; j < ws->unknown_start[u + 1]; j++) {
                int e2 = ws->unknown_entry[j], q2 = e2 >> 2;
                double v = w1 * ws->weight[e2];
                band[(size_t)(kd + q1 - q2) + (size_t)q2 * ld] += q1 == q2 ? 2.0 * v : v;
            }
        }
    }
    for (int q = 0; q < pixel_count; q++)
        band[(size_t)kd + (size_t)q * ld] += ridge;
}

/* x = m + A^T z, per channel, into ws->rhs (n x channels) for reconstruct(). */
static void texels_from_pixel_solution(texopt_bake_workspace *ws, int pixel_count, int n, int channels,
                                       const double *mean)
{
    for (int i = 0; i < n; i++)
        for (int ch = 0; ch < channels; ch++)
            ws->rhs[(size_t)i * channels + ch] = mean[ch];
    for (int e = 0; e < 4 * pixel_count; e++) {
        double *x = ws->rhs + (size_t)ws->cell[e] * channels;
        const double *z = ws->pixel_rhs + (size_t)(e >> 2) * channels;
        for (int ch = 0; ch < channels; ch++)
            x[ch] += ws->weight[e] * z[ch];
    }
}

/* Whether to solve on the pixel side: forced, or when it has more unknowns than pixels and
 * the banded factorisation (n kd^2) of the pixel system is cheaper. */
static int choose_pixel_side(const texopt_bake_workspace *ws, int pixel_count, int n, int kd, int pixel_kd)
{
    if (ws->side == TEXOPT_BAKE_SIDE_PIXEL)
        return 1;
    double texel_cost = (double)n * (kd + 1.0) * (kd + 1.0);
    double pixel_cost = (double)pixel_count * (pixel_kd + 1.0) * (pixel_kd + 1.0);
    return pixel_cost < texel_cost;
}

static void reference_mean(const float *reference, int pixel_count, int channels, double *mean)
{
    for (int ch = 0; ch < channels; ch++)
        mean[ch] = 0.0;
    for (int q = 0; q < pixel_count; q++)
        for (int ch = 0; ch < channels; ch++)
            mean[ch] += reference[(size_t)q * channels + ch];
    for (int ch = 0; ch < channels; ch++)
        mean[ch] /= pixel_count;
}

static texopt_status fit_pixel_side(texopt_bake_workspace *ws, int pixel_count, int n, int pixel_kd,
                                    const float *reference, int channels, double ridge, float *reconstruction,
                                    char *err, size_t err_len)
{
    if (!reserve_band(ws, (size_t)(pixel_kd + 1) * (size_t)pixel_count, pixel_kd))
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "bake: band of %d x %d", pixel_kd + 1, pixel_count);
    double mean[TEXOPT_BAKE_MAX_CHANNELS];
    reference_mean(reference, pixel_count, channels, mean);
    assemble_pixel_system(ws, pixel_count, n, pixel_kd, ridge);
    assemble_pixel_rhs(ws, pixel_count, reference, channels, mean);
    if (!band_cholesky(ws->solver, ws->band, pixel_count, pixel_kd, ws->pixel_last, ws->column))
        return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "bake: pixel system of %d pixels is not positive definite",
                           pixel_count);
    band_solve(ws->band, pixel_count, pixel_kd, ws->pixel_first, ws->pixel_last, ws->pixel_rhs, channels);
    texels_from_pixel_solution(ws, pixel_count, n, channels, mean);
    reconstruct(ws, pixel_count, channels, reconstruction);
    ws->last_unknowns = n;
    ws->last_side = TEXOPT_BAKE_SIDE_PIXEL;
    ws->last_pixel_count = pixel_count;
    ws->last_kd = pixel_kd;
    ws->last_ridge = ridge;
    return TEXOPT_OK;
}

texopt_status texopt_bake_fit(texopt_bake_workspace *ws, int pixel_count, const double *texel_pos,
                              const float *reference, int channels, int width, int height, texopt_wrap wrap_s,
                              texopt_wrap wrap_t, double ridge, float *reconstruction, char *err, size_t err_len)
{
    if (!ws)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bake: no workspace");
    if (pixel_count < 0 || pixel_count > ws->max_pixels)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bake: %d pixels, workspace holds %d", pixel_count,
                           ws->max_pixels);
    if (channels < 1 || channels > ws->max_channels)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bake: %d channels, workspace holds 1..%d",
                           channels, ws->max_channels);
    if (width <= 0 || height <= 0 || (long long)width * height > 0x7fffffffLL)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bake: texture %dx%d", width, height);
    if (!(ridge > 0.0) || !isfinite(ridge))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bake: ridge %g must be positive", ridge);
    ws->last_unknowns = 0;
    if (pixel_count == 0)
        return TEXOPT_OK;
    if (!texel_pos || !reference || !reconstruction)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bake: NULL buffer");

    cell_box box = gather_footprints(ws, pixel_count, texel_pos, width, height, wrap_s, wrap_t);
    int n = (size_t)box.rows * (size_t)box.cols <= ws->box_capacity ? number_through_box(ws, pixel_count, box)
                                                                    : number_through_hash(ws, pixel_count, width);
    int kd = envelope(ws, pixel_count, n);
    if (ws->side != TEXOPT_BAKE_SIDE_TEXEL && (ws->side == TEXOPT_BAKE_SIDE_PIXEL || n > pixel_count)) {
        group_entries_by_unknown(ws, pixel_count, n);
        int pixel_kd = pixel_envelope(ws, pixel_count);
        if (choose_pixel_side(ws, pixel_count, n, kd, pixel_kd))
            return fit_pixel_side(ws, pixel_count, n, pixel_kd, reference, channels, ridge, reconstruction, err,
                                  err_len);
    }
    if (!reserve_band(ws, (size_t)(kd + 1) * (size_t)n, kd))
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "bake: band of %d x %d", kd + 1, n);
    assemble_normal_equations(ws, pixel_count, n, kd, ridge);
    assemble_texel_rhs(ws, pixel_count, n, reference, channels, ridge);
    if (!band_cholesky(ws->solver, ws->band, n, kd, ws->last, ws->column))
        return texopt_fail(err, err_len, TEXOPT_E_NUMERIC,
                           "bake: normal equations of %d texels are not positive definite", n);
    band_solve(ws->band, n, kd, ws->first, ws->last, ws->rhs, channels);
    reconstruct(ws, pixel_count, channels, reconstruction);
    ws->last_unknowns = n;
    ws->last_side = TEXOPT_BAKE_SIDE_TEXEL;
    ws->last_pixel_count = pixel_count;
    ws->last_kd = kd;
    ws->last_ridge = ridge;
    return TEXOPT_OK;
}

texopt_status texopt_bake_refit(texopt_bake_workspace *ws, const float *reference, int channels, float *reconstruction,
                                char *err, size_t err_len)
{
    if (!ws || ws->last_unknowns == 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "bake: no successful fit with pixels to solve again");
    if (channels < 1 || channels > ws->max_channels)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bake: %d channels, workspace holds 1..%d",
                           channels, ws->max_channels);
    if (!reference || !reconstruction)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bake: NULL buffer");
    int pixel_count = ws->last_pixel_count, n = ws->last_unknowns;
    if (ws->last_side == TEXOPT_BAKE_SIDE_PIXEL) {
        double mean[TEXOPT_BAKE_MAX_CHANNELS];
        reference_mean(reference, pixel_count, channels, mean);
        assemble_pixel_rhs(ws, pixel_count, reference, channels, mean);
        band_solve(ws->band, pixel_count, ws->last_kd, ws->pixel_first, ws->pixel_last, ws->pixel_rhs, channels);
        texels_from_pixel_solution(ws, pixel_count, n, channels, mean);
    } else {
        assemble_texel_rhs(ws, pixel_count, n, reference, channels, ws->last_ridge);
        band_solve(ws->band, n, ws->last_kd, ws->first, ws->last, ws->rhs, channels);
    }
    reconstruct(ws, pixel_count, channels, reconstruction);
    return TEXOPT_OK;
}

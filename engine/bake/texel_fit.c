/* texel_fit.c - conjugate-gradient least-squares fit of texels to sub-texel references (see
 * texel_fit.h).
 *
 * A sample at offset -1/4 from a texel centre lies between the previous centre (weight 1/4)
 * and its own (3/4); at +1/4 between its own (3/4) and the next (1/4). Each sample's four
 * bilinear taps are within one texel of its texel, so the normal matrix K = A^T A couples
 * only 3x3 neighbourhoods. Where every sample around a texel counts (the inside of a chart,
 * nearly all texels) its row of K is the constant stencil T x T, T = (3/8, 5/4, 3/8), so
 * K is not stored for them: the rows of texels near chart borders are gathered from the
 * samples once and kept per row block, in the order the passes visit them.
 * Every pass gathers (a texel writes only itself), so threads never conflict. The unknown
 * is the change from x0: fixed texels simply stay at zero change and x0 enters through the
 * starting residual A^T (ref - A x0), computed per row block from references asked for
 * that block only. */
#include "texel_fit.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "parallel.h"

#define BLOCK_ROWS 16
#define MAX_THREADS 64
#define MAX_SUMS 2
/* Rounds of holding texels at their bounds and solving again for the others. */
#define HOLD_ROUNDS 3

enum { NOT_FREE = 0, FREE_BORDER = 1, FREE_INSIDE = 2 };

/* 1-D bilinear weight of the sample with side sigma (0: -1/4, 1: +1/4) of texel u on the
 * texel u + d, d in {-1, 0, 1}. */
static const float W1[2][3] = {{0.25f, 0.75f, 0.0f}, {0.0f, 0.75f, 0.25f}};
/* Row of K of a texel all of whose 16 touching samples count: T[dy] T[dx]. */
static const float T1[3] = {0.375f, 1.25f, 0.375f};

typedef struct fit_ctx {
    const texopt_texel_fit_problem *pb;
    int w, h, ch;
    uint8_t *is_free;     /* per texel: NOT_FREE, FREE_BORDER or FREE_INSIDE */
    uint8_t *held;        /* per texel: 1 once a bound holds it (a free texel the solve no longer moves) */
    uint8_t *bounds;      /* per texel: ch lower then ch upper bounds, 8-bit code values */
    float *inv_diag;      /* per free texel: 1 / (K_tt + ridge), the Jacobi preconditioner */
    float *r, *p, *q;     /* ch per texel */
    float **border_k9;    /* per row block: the K rows of its FREE_BORDER texels, 9 floats each */
    size_t *border_count; /* per row block */
    double alpha, beta;
    size_t scratch_floats; /* per worker, for the pass that needs one */
    atomic_int no_memory;
} fit_ctx;

typedef void (*block_fn)(fit_ctx *c, int y0, int y1, double *sums, float *scratch);

typedef struct block_worker {
    fit_ctx *c;
    block_fn fn;
    int first, step, blocks;
    double *sums; /* MAX_SUMS per block */
} block_worker;

static void *run_worker(void *arg)
{
    block_worker *bw = arg;
    float *scratch = NULL;
    if (bw->c->scratch_floats > 0 && !(scratch = malloc(bw->c->scratch_floats * sizeof *scratch))) {
        atomic_store(&bw->c->no_memory, 1);
        return NULL;
    }
    for (int b = bw->first; b < bw->blocks; b += bw->step) {
        int y0 = b * BLOCK_ROWS, y1 = y0 + BLOCK_ROWS < bw->c->h ? y0 + BLOCK_ROWS : bw->c->h;
        bw->fn(bw->c, y0, y1, bw->sums + (size_t)b * MAX_SUMS, scratch);
    }
    free(scratch);
    return NULL;
}

/* Runs fn over all row blocks on `threads` workers and adds the blocks' sums in block order,
 * so totals do not depend on the thread count. */
static void run_blocks(fit_ctx *c, block_fn fn, double *block_sums, double totals[MAX_SUMS])
{
    int threads = c->pb->threads < 1 ? 1 : (c->pb->threads > MAX_THREADS ? MAX_THREADS : c->pb->threads);
    int blocks = (c->h + BLOCK_ROWS - 1) / BLOCK_ROWS;
    memset(block_sums, 0, sizeof(double) * MAX_SUMS * (size_t)blocks);
    block_worker bw[MAX_THREADS];
    for (int k = 0; k < threads; k++)
        bw[k] = (block_worker){.c = c, .fn = fn, .first = k, .step = threads, .blocks = blocks, .sums = block_sums};
    texopt_parallel_run(run_worker, bw, sizeof *bw, threads);
    for (int s = 0; s < MAX_SUMS; s++)
        totals[s] = 0;
    for (int b = 0; b < blocks; b++)
        for (int s = 0; s < MAX_SUMS; s++)
            totals[s] += block_sums[(size_t)b * MAX_SUMS + s];
}

/* Whether sample (sx, sy) of texel (ux, uy) counts: its texel is sampled and all four taps
 * are inside the image. */
static int sample_counts(const fit_ctx *c, int ux, int uy, int sx, int sy)
{
    if (!c->pb->sampled[(size_t)uy * c->w + ux])
        return 0;
    int x0 = ux + sx - 1, y0 = uy + sy - 1;
    return x0 >= 0 && y0 >= 0 && x0 + 1 < c->w && y0 + 1 < c->h;
}

/* Runs the body with (wt, ux, uy, s, sx, sy) for every counted sample s of texel (ux, uy)
 * that touches texel (x, y) with weight wt > 0 (16 candidates: 1, 2 or 4 samples from each
 * of the 3x3 neighbours). */
#define FOR_TOUCHING_SAMPLES(c, x, y, ...)                                                                             \
    for (int uy = (y)-1; uy <= (y) + 1; uy++)                                                                          \
        for (int ux = (x)-1; ux <= (x) + 1; ux++) {                                                                    \
            if (ux < 0 || uy < 0 || ux >= (c)->w || uy >= (c)->h)                                                      \
                continue;                                                                                              \
            for (int s = 0; s < TEXOPT_TEXEL_FIT_SAMPLES; s++) {                                                       \
                int sx = s & 1, sy = s >> 1;                                                                           \
                float wt = W1[sx][(x)-ux + 1] * W1[sy][(y)-uy + 1];                                                    \
                if (wt > 0 && sample_counts((c), ux, uy, sx, sy)) {                                                    \
                    __VA_ARGS__                                                                                        \
                }                                                                                                      \
            }                                                                                                          \
        }

/* Row of K of texel (x, y), gathered from its touching samples: k9[(oy + 1) * 3 + ox + 1]. */
static void gather_stencil(const fit_ctx *c, int x, int y, float k9[9])
{
    memset(k9, 0, 9 * sizeof *k9);
    FOR_TOUCHING_SAMPLES(c, x, y, {
        for (int dy = sy - 1; dy <= sy; dy++)
            for (int dx = sx - 1; dx <= sx; dx++) {
                int ox = ux + dx - x, oy = uy + dy - y; /* in -1..1 */
                k9[(oy + 1) * 3 + ox + 1] += wt * W1[sx][dx + 1] * W1[sy][dy + 1];
            }
    })
}

/* Whether every sample touching (x, y) counts: all 3x3 neighbours sampled and their taps,
 * up to two texels away, inside the image. */
static int inside_stencil(const fit_ctx *c, int x, int y)
{
    if (x < 2 || y < 2 || x + 2 >= c->w || y + 2 >= c->h)
        return 0;
    for (int uy = y - 1; uy <= y + 1; uy++)
        for (int ux = x - 1; ux <= x + 1; ux++)
            if (!c->pb->sampled[(size_t)uy * c->w + ux])
                return 0;
    return 1;
}

/* Appends the K row of the block's next border texel; 0 when out of memory. */
static int keep_border_row(fit_ctx *c, int block, size_t *capacity, const float k9[9])
{
    size_t n = c->border_count[block];
    if (n == *capacity) {
        size_t grown = *capacity ? 2 * *capacity : 256;
        float *more = realloc(c->border_k9[block], grown * 9 * sizeof *more);
        if (!more)
            return 0;
        c->border_k9[block] = more;
        *capacity = grown;
    }
    memcpy(c->border_k9[block] + 9 * n, k9, 9 * sizeof *k9);
    c->border_count[block] = n + 1;
    return 1;
}

/* Marks the free texels (touched by a counted sample, not fixed), their preconditioner and
 * the K rows of the border ones. */
static void mark_free(fit_ctx *c, int y0, int y1, double *sums, float *scratch)
{
    (void)scratch;
    int block = y0 / BLOCK_ROWS;
    size_t capacity = 0;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            c->is_free[t] = NOT_FREE;
            c->inv_diag[t] = 0;
            if (c->pb->fixed && c->pb->fixed[t])
                continue;
            float k9[9];
            if (inside_stencil(c, x, y)) {
                c->is_free[t] = FREE_INSIDE;
                k9[4] = T1[1] * T1[1];
            } else {
                gather_stencil(c, x, y, k9);
                if (!(k9[4] > 0))
                    continue;
                if (!keep_border_row(c, block, &capacity, k9)) {
                    atomic_store(&c->no_memory, 1);
                    continue;
                }
                c->is_free[t] = FREE_BORDER;
            }
            c->inv_diag[t] = (float)(1.0 / (k9[4] + c->pb->ridge));
            sums[0] += 1;
        }
}

/* The residuals ref - A x0 of the counted samples of rows [r0, r1) into scratch (4 * ch
 * floats per texel of those rows), and each sampled texel's range into ranges (ch lows then
 * ch highs per texel; [0, 1] without a range callback). */
static void block_residuals(fit_ctx *c, int r0, int r1, float *scratch, float *ranges)
{
    size_t per_texel = TEXOPT_TEXEL_FIT_SAMPLES * (size_t)c->ch;
    for (int uy = r0; uy < r1; uy++)
        for (int ux = 0; ux < c->w; ux++) {
            if (!c->pb->sampled[(size_t)uy * c->w + ux])
                continue;
            float *ref = scratch + ((size_t)(uy - r0) * c->w + ux) * per_texel;
            c->pb->reference(c->pb->user, ux, uy, ref);
            float *lo = ranges + ((size_t)(uy - r0) * c->w + ux) * 2 * (size_t)c->ch, *hi = lo + c->ch;
            if (c->pb->range) {
                c->pb->range(c->pb->user, ux, uy, lo, hi);
            } else {
                for (int k = 0; k < c->ch; k++)
                    lo[k] = 0.0f, hi[k] = 1.0f;
            }
            for (int s = 0; s < TEXOPT_TEXEL_FIT_SAMPLES; s++) {
                int sx = s & 1, sy = s >> 1;
                if (!sample_counts(c, ux, uy, sx, sy))
                    continue;
                float *e = ref + (size_t)s * c->ch;
                for (int dy = sy - 1; dy <= sy; dy++)
                    for (int dx = sx - 1; dx <= sx; dx++) {
                        float wgt = W1[sx][dx + 1] * W1[sy][dy + 1];
                        const float *v = texopt_image_at(c->pb->image, ux + dx, uy + dy);
                        for (int k = 0; k < c->ch; k++)
                            e[k] -= wgt * v[k];
                    }
            }
        }
}

static uint8_t code_value(float v)
{
    return (uint8_t)(v > 0.0f ? (v < 255.0f ? v : 255.0f) : 0.0f);
}

/* Starting residual A^T (ref - A x0) of the free texels of rows [y0, y1), from the sample
 * residuals of rows y0 - 1 .. y1 (the block and one row on each side), and each free texel's
 * bounds (code values, widened outward): a sampled texel's own range, another's the union of
 * the ranges of the sampled texels whose samples it takes part in. */
static void start_residual(fit_ctx *c, int y0, int y1, double *sums, float *scratch)
{
    (void)sums;
    int r0 = y0 > 0 ? y0 - 1 : 0, r1 = y1 < c->h ? y1 + 1 : c->h;
    size_t per_texel = TEXOPT_TEXEL_FIT_SAMPLES * (size_t)c->ch;
    float *ranges = scratch + (size_t)(BLOCK_ROWS + 2) * c->w * per_texel;
    block_residuals(c, r0, r1, scratch, ranges);
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            float *rt = c->r + t * c->ch;
            double acc[4] = {0, 0, 0, 0};
            float lo[4] = {1, 1, 1, 1}, hi[4] = {0, 0, 0, 0};
            if (c->is_free[t] != NOT_FREE) {
                int own = c->pb->sampled[t] != 0;
                FOR_TOUCHING_SAMPLES(c, x, y, {
                    size_t at = ((size_t)(uy - r0) * c->w + ux) * per_texel + (size_t)s * c->ch;
                    const float *rl = ranges + ((size_t)(uy - r0) * c->w + ux) * 2 * (size_t)c->ch;
                    int counts = !own || (ux == x && uy == y);
                    for (int k = 0; k < c->ch; k++) {
                        acc[k] += (double)wt * scratch[at + k];
                        lo[k] = counts && rl[k] < lo[k] ? rl[k] : lo[k];
                        hi[k] = counts && rl[c->ch + k] > hi[k] ? rl[c->ch + k] : hi[k];
                    }
                })
            }
            for (int k = 0; k < c->ch; k++) {
                rt[k] = (float)acc[k];
                c->bounds[2 * t * c->ch + k] = code_value(floorf(255.0f * (lo[k] < hi[k] ? lo[k] : hi[k])));
                c->bounds[(2 * t + 1) * c->ch + k] = code_value(ceilf(255.0f * (hi[k] > lo[k] ? hi[k] : lo[k])));
            }
        }
}

/* p = M^-1 r + beta p, on free texels (beta = 0 starts). sums[0] = r . M^-1 r. */
static void update_direction(fit_ctx *c, int y0, int y1, double *sums, float *scratch)
{
    (void)scratch;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            float *pt = c->p + t * c->ch;
            if (c->is_free[t] == NOT_FREE || c->held[t]) {
                memset(pt, 0, (size_t)c->ch * sizeof *pt);
                continue;
            }
            float inv = c->inv_diag[t];
            const float *rt = c->r + t * c->ch;
            for (int k = 0; k < c->ch; k++) {
                pt[k] = (float)(rt[k] * inv + c->beta * pt[k]);
                sums[0] += (double)rt[k] * rt[k] * inv;
            }
        }
}

/* acc = (T x T + ridge) p at an inside texel (p at pt, rows w texels apart): the generic
 * loop below in the same order of operations (same bits), unrolled for a channel count the
 * compiler knows. */
static inline void apply_inside(const float *pt, size_t w, int ch, float ridge, float *acc)
{
    for (int k = 0; k < ch; k++)
        acc[k] = ridge * pt[k];
    for (int oy = -1; oy <= 1; oy++) {
        const float *row = pt + (ptrdiff_t)oy * (ptrdiff_t)w * ch;
        for (int ox = -1; ox <= 1; ox++) {
            float kv = T1[oy + 1] * T1[ox + 1];
            const float *pn = row + ox * ch;
            for (int k = 0; k < ch; k++)
                acc[k] += kv * pn[k];
        }
    }
}

static void accumulate_q(float *qt, const float *pt, const float *acc, int ch, double *sums)
{
    for (int k = 0; k < ch; k++) {
        qt[k] = acc[k];
        sums[0] += (double)pt[k] * acc[k];
    }
}

static void apply_inside_any(const float *pt, size_t w, int ch, float ridge, float *acc)
{
    switch (ch) {
    case 1: apply_inside(pt, w, 1, ridge, acc); break;
    case 3: apply_inside(pt, w, 3, ridge, acc); break;
    case 4: apply_inside(pt, w, 4, ridge, acc); break;
    default: apply_inside(pt, w, ch, ridge, acc);
    }
}

/* q = (K + ridge I) p on free texels not held. sums[0] = p . q. p is zero wherever the fit
 * may not change a texel (but once, when held texels' clamps are passed on: release_held),
 * so inside texels run the constant stencil without tests. */
static void apply_matrix(fit_ctx *c, int y0, int y1, double *sums, float *scratch)
{
    (void)scratch;
    int ch = c->ch;
    float ridge = (float)c->pb->ridge;
    const float *border = c->border_k9[y0 / BLOCK_ROWS];
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            if (c->is_free[t] == NOT_FREE)
                continue;
            const float *pt = c->p + t * ch;
            float acc[4];
            if (c->held[t]) {
                border += c->is_free[t] == FREE_BORDER ? 9 : 0;
                continue;
            }
            if (c->is_free[t] == FREE_INSIDE) {
                apply_inside_any(pt, (size_t)c->w, ch, ridge, acc);
                accumulate_q(c->q + t * ch, pt, acc, ch, sums);
                continue;
            }
            const float *k9 = border;
            border += 9;
            for (int k = 0; k < ch; k++)
                acc[k] = ridge * pt[k];
            for (int oy = -1; oy <= 1; oy++) {
                if (y + oy < 0 || y + oy >= c->h)
                    continue;
                const float *row = c->p + ((size_t)(y + oy) * c->w + (size_t)x) * ch;
                for (int ox = -1; ox <= 1; ox++) {
                    float kv = k9[(oy + 1) * 3 + ox + 1];
                    if (kv == 0.0f)
                        continue; /* also every neighbour outside the image */
                    const float *pn = row + ox * ch;
                    for (int k = 0; k < ch; k++)
                        acc[k] += kv * pn[k];
                }
            }
            accumulate_q(c->q + t * ch, pt, acc, ch, sums);
        }
}

/* x += alpha p, r -= alpha q on free texels. sums[0] = r . M^-1 r of the new residual. */
static void step(fit_ctx *c, int y0, int y1, double *sums, float *scratch)
{
    (void)scratch;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            if (c->is_free[t] == NOT_FREE || c->held[t])
                continue;
            float *xt = texopt_image_at(c->pb->image, x, y), *rt = c->r + t * c->ch;
            const float *pt = c->p + t * c->ch, *qt = c->q + t * c->ch;
            float inv = c->inv_diag[t];
            for (int k = 0; k < c->ch; k++) {
                xt[k] = (float)(xt[k] + c->alpha * pt[k]);
                rt[k] = (float)(rt[k] - c->alpha * qt[k]);
                sums[0] += (double)rt[k] * rt[k] * inv;
            }
        }
}

/* Clamps the free texels to their bounds. The change of each texel not yet held goes to p
 * (0 where none), and a texel that changed is held from now on. sums[0] counts those. */
static void clamp_to_bounds(fit_ctx *c, int y0, int y1, double *sums, float *scratch)
{
    (void)scratch;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            float *pt = c->p + t * c->ch;
            memset(pt, 0, (size_t)c->ch * sizeof *pt);
            if (c->is_free[t] == NOT_FREE)
                continue;
            float *xt = texopt_image_at(c->pb->image, x, y);
            const uint8_t *lo = c->bounds + 2 * t * c->ch, *hi = lo + c->ch;
            int moved = 0;
            for (int k = 0; k < c->ch; k++) {
                float l = lo[k] / 255.0f, h = hi[k] / 255.0f;
                float v = xt[k] > l ? (xt[k] < h ? xt[k] : h) : l;
                pt[k] = v - xt[k];
                moved |= v != xt[k];
                xt[k] = v;
            }
            if (moved && !c->held[t]) {
                c->held[t] = 1;
                sums[0] += 1;
            } else if (c->held[t]) {
                memset(pt, 0, (size_t)c->ch * sizeof *pt);
            }
        }
}

/* r -= q on the free texels not held (q = K times the latest clamps: their effect on the
 * others' residual), 0 on held ones. */
static void pass_on_clamps(fit_ctx *c, int y0, int y1, double *sums, float *scratch)
{
    (void)sums;
    (void)scratch;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            if (c->is_free[t] == NOT_FREE)
                continue;
            float *rt = c->r + t * c->ch;
            const float *qt = c->q + t * c->ch;
            for (int k = 0; k < c->ch; k++)
                rt[k] = c->held[t] ? 0.0f : rt[k] - qt[k];
        }
}

static texopt_status check_problem(const texopt_texel_fit_problem *pb, char *err, size_t err_len)
{
    if (!pb || !pb->image || !pb->image->pixels || !pb->sampled || !pb->reference)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "texel fit: missing image, mask or references");
    if (pb->image->channels < 1 || pb->image->channels > 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "texel fit: %d channels (1..4)",
                           pb->image->channels);
    if (!(pb->ridge > 0) || !(pb->tolerance > 0) || pb->max_iterations < 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "texel fit: ridge and tolerance must be > 0 and max_iterations >= 1");
    return TEXOPT_OK;
}

/* Preconditioned conjugate gradients from the residual in c->r; adds its iterations to rep's. */
static void solve(fit_ctx *c, double *block_sums, texopt_texel_fit_report *rep)
{
    double sums[MAX_SUMS];
    c->beta = 0;
    run_blocks(c, update_direction, block_sums, sums);
    double rz = sums[0], rz0 = sums[0];
    int iterations = 0;
    rep->residual_ratio = 0;
    while (rz > 0 && iterations < c->pb->max_iterations) {
        run_blocks(c, apply_matrix, block_sums, sums);
        if (!(sums[0] > 0))
            break;
        c->alpha = rz / sums[0];
        run_blocks(c, step, block_sums, sums);
        iterations++;
        rep->iterations++;
        double rz_new = sums[0];
        rep->residual_ratio = sqrt(rz_new / rz0);
        if (rep->residual_ratio < c->pb->tolerance)
            break;
        c->beta = rz_new / rz;
        run_blocks(c, update_direction, block_sums, sums);
        rz = rz_new;
    }
}

/* The fit with every texel inside its bounds: solve, clamp the texels that left them and hold
 * them there, pass the clamps on to the others' residual and solve again for those, up to
 * HOLD_ROUNDS times; the last clamp then holds whatever is still outside. */
static void solve_within_bounds(fit_ctx *c, double *block_sums, texopt_texel_fit_report *rep)
{
    double sums[MAX_SUMS];
    solve(c, block_sums, rep);
    for (int round = 0; round < HOLD_ROUNDS; round++) {
        run_blocks(c, clamp_to_bounds, block_sums, sums);
        if (!(sums[0] > 0))
            return;
        run_blocks(c, apply_matrix, block_sums, sums);
        run_blocks(c, pass_on_clamps, block_sums, sums);
        solve(c, block_sums, rep);
    }
    run_blocks(c, clamp_to_bounds, block_sums, sums);
}

texopt_status texopt_texel_fit(const texopt_texel_fit_problem *problem, uint8_t *changed,
                               texopt_texel_fit_report *report, char *err, size_t err_len)
{
    texopt_status st = check_problem(problem, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    fit_ctx c = {
        .pb = problem, .w = problem->image->width, .h = problem->image->height, .ch = problem->image->channels};
    atomic_init(&c.no_memory, 0);
    size_t n = (size_t)c.w * (size_t)c.h;
    int blocks = (c.h + BLOCK_ROWS - 1) / BLOCK_ROWS;
    c.is_free = malloc(n);
    c.held = calloc(n, 1);
    c.bounds = malloc(2 * n * (size_t)c.ch);
    c.inv_diag = malloc(n * sizeof *c.inv_diag);
    c.r = malloc(n * (size_t)c.ch * sizeof *c.r);
    /* Zeroed: the first direction update reads p times beta = 0, and 0 times leftover
     * garbage (NaN, Inf) from an earlier allocation is not 0. */
    c.p = calloc(n * (size_t)c.ch, sizeof *c.p);
    c.q = malloc(n * (size_t)c.ch * sizeof *c.q);
    double *block_sums = malloc((size_t)blocks * MAX_SUMS * sizeof *block_sums);
    c.border_k9 = calloc((size_t)blocks, sizeof *c.border_k9);
    c.border_count = calloc((size_t)blocks, sizeof *c.border_count);
    texopt_texel_fit_report rep = {0};
    if (!c.is_free || !c.held || !c.bounds || !c.inv_diag || !c.r || !c.p || !c.q || !block_sums || !c.border_k9 ||
        !c.border_count) {
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d texel fit", c.w, c.h);
    } else {
        double sums[MAX_SUMS];
        run_blocks(&c, mark_free, block_sums, sums);
        rep.unknowns = (size_t)sums[0];
        c.scratch_floats = 2 * (size_t)(BLOCK_ROWS + 2) * (size_t)c.w * TEXOPT_TEXEL_FIT_SAMPLES * (size_t)c.ch;
        run_blocks(&c, start_residual, block_sums, sums);
        c.scratch_floats = 0;
        if (atomic_load(&c.no_memory)) {
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d texel fit", c.w, c.h);
        } else {
            solve_within_bounds(&c, block_sums, &rep);
            if (changed)
                for (size_t t = 0; t < n; t++)
                    if (c.is_free[t] != NOT_FREE)
                        changed[t] = 1;
        }
    }
    if (report)
        *report = rep;
    free(c.is_free);
    free(c.held);
    free(c.bounds);
    free(c.inv_diag);
    free(c.r);
    free(c.p);
    free(c.q);
    free(block_sums);
    for (int b = 0; c.border_k9 && b < blocks; b++)
        free(c.border_k9[b]);
    free(c.border_k9);
    free(c.border_count);
    return st;
}

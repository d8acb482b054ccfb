/* texel_fit.c - conjugate-gradient least-squares fit of texels to sub-texel references (see
 * texel_fit.h).
 *
 * A sample at offset -1/4 from a texel centre lies between the previous centre (weight 1/4)
 * and its own (3/4); at +1/4 between its own (3/4) and the next (1/4). Each sample's four
 * bilinear taps are within one texel of its texel, so the normal matrix K = A^T A couples
 * only 3x3 neighbourhoods: it is stored as nine coefficients per free texel, built once by
 * gathering, which keeps every pass free of write conflicts between threads. The unknown is
 * the change from x0, so fixed texels simply stay at zero change and x0 enters through the
 * starting residual A^T (ref - A x0). */
#include "texel_fit.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define BLOCK_ROWS 16
#define MAX_THREADS 64
#define MAX_SUMS 2

/* 1-D bilinear weight of the sample with side sigma (0: -1/4, 1: +1/4) of texel u on the
 * texel u + d, d in {-1, 0, 1}. */
static const float W1[2][3] = {{0.25f, 0.75f, 0.0f}, {0.0f, 0.75f, 0.25f}};

typedef struct fit_ctx {
    const texopt_texel_fit_problem *pb;
    int w, h, ch;
    uint8_t *is_free; /* per texel */
    float *coef;      /* 9 per texel: K[t][t + (dx, dy)] at (dy + 1) * 3 + dx + 1 */
    float *r, *p, *q; /* ch per texel */
    double alpha, beta;
} fit_ctx;

typedef void (*block_fn)(fit_ctx *c, int y0, int y1, double *sums);

typedef struct block_worker {
    fit_ctx *c;
    block_fn fn;
    int first, step, blocks;
    double *sums; /* MAX_SUMS per block */
    int started;
    pthread_t thread;
} block_worker;

static void *run_worker(void *arg)
{
    block_worker *bw = arg;
    for (int b = bw->first; b < bw->blocks; b += bw->step) {
        int y0 = b * BLOCK_ROWS, y1 = y0 + BLOCK_ROWS < bw->c->h ? y0 + BLOCK_ROWS : bw->c->h;
        bw->fn(bw->c, y0, y1, bw->sums + (size_t)b * MAX_SUMS);
    }
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
    for (int k = 1; k < threads; k++)
        bw[k].started = pthread_create(&bw[k].thread, NULL, run_worker, &bw[k]) == 0;
    run_worker(&bw[0]);
    for (int k = 1; k < threads; k++) {
        if (bw[k].started)
            pthread_join(bw[k].thread, NULL);
        else
            run_worker(&bw[k]); /* a thread that could not start: its blocks run here */
    }
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

/* Turns the references of sampled texels into residuals against x0 (the image):
 * ref - bilinear(x0), per channel; each texel rewrites only its own four samples. */
static void subtract_prediction(fit_ctx *c, int y0, int y1, double *sums)
{
    (void)sums;
    for (int uy = y0; uy < y1; uy++)
        for (int ux = 0; ux < c->w; ux++) {
            float *ref = c->pb->reference + ((size_t)uy * c->w + ux) * TEXOPT_TEXEL_FIT_SAMPLES * (size_t)c->ch;
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

/* Marks the free texels: touched by a counted sample and not fixed. */
static void mark_free(fit_ctx *c, int y0, int y1, double *sums)
{
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            int touched = 0;
            for (int uy = y - 1; uy <= y + 1 && !touched; uy++)
                for (int ux = x - 1; ux <= x + 1 && !touched; ux++) {
                    if (ux < 0 || uy < 0 || ux >= c->w || uy >= c->h)
                        continue;
                    for (int s = 0; s < TEXOPT_TEXEL_FIT_SAMPLES && !touched; s++) {
                        int sx = s & 1, sy = s >> 1;
                        touched = W1[sx][x - ux + 1] > 0 && W1[sy][y - uy + 1] > 0 &&
                                  sample_counts(c, ux, uy, sx, sy);
                    }
                }
            c->is_free[t] = touched && !(c->pb->fixed && c->pb->fixed[t]);
            sums[0] += c->is_free[t];
        }
}

/* For each free texel: its nine coefficients of K and the starting residual
 * A^T (ref - A x0), by gathering over the samples that touch it. */
static void build_system(fit_ctx *c, int y0, int y1, double *sums)
{
    (void)sums;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            float *k9 = c->coef + 9 * t, *rt = c->r + t * c->ch;
            memset(k9, 0, 9 * sizeof *k9);
            memset(rt, 0, (size_t)c->ch * sizeof *rt);
            if (!c->is_free[t])
                continue;
            double acc[4] = {0, 0, 0, 0};
            for (int uy = y - 1; uy <= y + 1; uy++)
                for (int ux = x - 1; ux <= x + 1; ux++) {
                    if (ux < 0 || uy < 0 || ux >= c->w || uy >= c->h)
                        continue;
                    for (int s = 0; s < TEXOPT_TEXEL_FIT_SAMPLES; s++) {
                        int sx = s & 1, sy = s >> 1;
                        double wt = (double)W1[sx][x - ux + 1] * W1[sy][y - uy + 1];
                        if (!(wt > 0) || !sample_counts(c, ux, uy, sx, sy))
                            continue;
                        for (int dy = sy - 1; dy <= sy; dy++)
                            for (int dx = sx - 1; dx <= sx; dx++) {
                                int ox = ux + dx - x, oy = uy + dy - y; /* in -1..1 */
                                k9[(oy + 1) * 3 + ox + 1] += (float)(wt * W1[sx][dx + 1] * W1[sy][dy + 1]);
                            }
                        const float *e = c->pb->reference +
                                         ((size_t)uy * c->w + ux) * TEXOPT_TEXEL_FIT_SAMPLES * (size_t)c->ch +
                                         (size_t)s * c->ch;
                        for (int k = 0; k < c->ch; k++)
                            acc[k] += wt * e[k];
                    }
                }
            for (int k = 0; k < c->ch; k++)
                rt[k] = (float)acc[k];
        }
}

static double diagonal(const fit_ctx *c, size_t t)
{
    return c->coef[9 * t + 4] + c->pb->ridge;
}

/* p = M^-1 r + beta p, on free texels (beta = 0 starts). sums[0] = r . M^-1 r. */
static void update_direction(fit_ctx *c, int y0, int y1, double *sums)
{
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            float *pt = c->p + t * c->ch;
            if (!c->is_free[t]) {
                memset(pt, 0, (size_t)c->ch * sizeof *pt);
                continue;
            }
            double inv = 1.0 / diagonal(c, t);
            const float *rt = c->r + t * c->ch;
            for (int k = 0; k < c->ch; k++) {
                pt[k] = (float)(rt[k] * inv + c->beta * pt[k]);
                sums[0] += (double)rt[k] * rt[k] * inv;
            }
        }
}

/* q = (K + ridge I) p on free texels. sums[0] = p . q. Away from the image border all nine
 * neighbours exist (p is zero wherever the fit may not change a texel), so the stencil runs
 * without tests there. */
static void apply_matrix(fit_ctx *c, int y0, int y1, double *sums)
{
    int ch = c->ch;
    float ridge = (float)c->pb->ridge;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            if (!c->is_free[t])
                continue;
            const float *k9 = c->coef + 9 * t, *pt = c->p + t * ch;
            float *qt = c->q + t * ch;
            float acc[4];
            for (int k = 0; k < ch; k++)
                acc[k] = ridge * pt[k];
            int interior = x > 0 && y > 0 && x + 1 < c->w && y + 1 < c->h;
            for (int oy = -1; oy <= 1; oy++) {
                if (!interior && (y + oy < 0 || y + oy >= c->h))
                    continue;
                const float *row = c->p + ((size_t)(y + oy) * c->w + (size_t)x) * ch;
                for (int ox = -1; ox <= 1; ox++) {
                    if (!interior && (x + ox < 0 || x + ox >= c->w))
                        continue;
                    float kv = k9[(oy + 1) * 3 + ox + 1];
                    const float *pn = row + ox * ch;
                    for (int k = 0; k < ch; k++)
                        acc[k] += kv * pn[k];
                }
            }
            for (int k = 0; k < ch; k++) {
                qt[k] = acc[k];
                sums[0] += (double)pt[k] * acc[k];
            }
        }
}

/* x += alpha p, r -= alpha q on free texels. sums[0] = r . M^-1 r of the new residual. */
static void step(fit_ctx *c, int y0, int y1, double *sums)
{
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            size_t t = (size_t)y * c->w + x;
            if (!c->is_free[t])
                continue;
            float *xt = texopt_image_at(c->pb->image, x, y), *rt = c->r + t * c->ch;
            const float *pt = c->p + t * c->ch, *qt = c->q + t * c->ch;
            double inv = 1.0 / diagonal(c, t);
            for (int k = 0; k < c->ch; k++) {
                xt[k] = (float)(xt[k] + c->alpha * pt[k]);
                rt[k] = (float)(rt[k] - c->alpha * qt[k]);
                sums[0] += (double)rt[k] * rt[k] * inv;
            }
        }
}

static void clamp_free(fit_ctx *c, int y0, int y1, double *sums)
{
    (void)sums;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < c->w; x++) {
            if (!c->is_free[(size_t)y * c->w + x])
                continue;
            float *xt = texopt_image_at(c->pb->image, x, y);
            for (int k = 0; k < c->ch; k++)
                xt[k] = xt[k] > 0.0f ? (xt[k] < 1.0f ? xt[k] : 1.0f) : 0.0f;
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

/* Preconditioned conjugate gradients from the residual in c->r. */
static void solve(fit_ctx *c, double *block_sums, texopt_texel_fit_report *rep)
{
    double sums[MAX_SUMS];
    c->beta = 0;
    run_blocks(c, update_direction, block_sums, sums);
    double rz = sums[0], rz0 = sums[0];
    rep->iterations = 0;
    rep->residual_ratio = 0;
    while (rz > 0 && rep->iterations < c->pb->max_iterations) {
        run_blocks(c, apply_matrix, block_sums, sums);
        if (!(sums[0] > 0))
            break;
        c->alpha = rz / sums[0];
        run_blocks(c, step, block_sums, sums);
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

texopt_status texopt_texel_fit(const texopt_texel_fit_problem *problem, uint8_t *changed,
                               texopt_texel_fit_report *report, char *err, size_t err_len)
{
    texopt_status st = check_problem(problem, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    fit_ctx c = {.pb = problem, .w = problem->image->width, .h = problem->image->height,
                 .ch = problem->image->channels};
    size_t n = (size_t)c.w * (size_t)c.h;
    int blocks = (c.h + BLOCK_ROWS - 1) / BLOCK_ROWS;
    c.is_free = malloc(n);
    c.coef = malloc(9 * n * sizeof *c.coef);
    c.r = malloc(n * (size_t)c.ch * sizeof *c.r);
    c.p = malloc(n * (size_t)c.ch * sizeof *c.p);
    c.q = malloc(n * (size_t)c.ch * sizeof *c.q);
    double *block_sums = malloc((size_t)blocks * MAX_SUMS * sizeof *block_sums);
    texopt_texel_fit_report rep = {0};
    if (!c.is_free || !c.coef || !c.r || !c.p || !c.q || !block_sums) {
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d texel fit", c.w, c.h);
    } else {
        double sums[MAX_SUMS];
        run_blocks(&c, mark_free, block_sums, sums);
        rep.unknowns = (size_t)sums[0];
        run_blocks(&c, subtract_prediction, block_sums, sums);
        run_blocks(&c, build_system, block_sums, sums);
        solve(&c, block_sums, &rep);
        run_blocks(&c, clamp_free, block_sums, sums);
        if (changed)
            for (size_t t = 0; t < n; t++)
                if (c.is_free[t])
                    changed[t] = 1;
    }
    if (report)
        *report = rep;
    free(c.is_free);
    free(c.coef);
    free(c.r);
    free(c.p);
    free(c.q);
    free(block_sums);
    return st;
}

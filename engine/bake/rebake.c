/* rebake.c - texel-centre rasterisation of the new layout, affine map back to the input,
 * prefiltered lookup, least-squares fit, chart rim, dilation (see rebake.h for the contract
 * and the normal-map rule).
 *
 * Two rasterisation passes over the triangles decide which triangle owns each texel: the
 * first takes texels whose centre is inside a triangle (first triangle wins on shared
 * edges; both sides of an interior edge agree there), the second gives each still-empty
 * texel within half a texel diagonal of a triangle to that triangle, to be sampled at the
 * clamped barycentric point, so bilinear lookups just inside a chart border read the chart,
 * not the gutter. Then the owned texels are sampled (prefiltered lookups), rows interleaved
 * over `threads` workers; the fit (texel_fit.h) then refines them and their one-texel ring
 * from four sub-texel lookups per owned texel, and the gutter is dilated. */
#include "rebake.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dilate.h"
#include "parallel.h"
#include "texel_fit.h"
#include "texel_map.h"
#include "texture_filter.h"

#define RIM_DISTANCE 0.7072 /* half the diagonal of a texel, slightly rounded up */
#define CHECK_EVERY 4096
#define MAX_THREADS 64
/* The fit: ridge toward the prefiltered bake (tiny against the 1.56 a fully sampled texel
 * gets, but it holds texels that only a corner sample sees), and CG stopping rule (a
 * residual fall of 1e-2 took 6 iterations on spot and gave the same q to 0.5% as 1e-3 with
 * 11). */
#define FIT_RIDGE 1e-3
#define FIT_TOLERANCE 1e-2
#define FIT_MAX_ITERATIONS 60
/* Least squares everywhere: whole-mesh q (evaluate.h) against the prefilter, baseline
 * layouts on four models, fell by 4-69% (median about 45%; BENCHMARKS.md@9f788a8 "Re-bake"), while
 * fitting only magnified triangles gained little except where everything is magnified. */
#define DEFAULT_FIT TEXOPT_REBAKE_FIT_LEAST_SQUARES
/* The fit's references are looked up through half an output texel's footprint, the spacing
 * of the four sub-texel points: a whole texel's footprint averages each reference over its
 * neighbours' too, and where the layout shrinks, the fit then matched a box-blurred input and
 * gave back the prefiltered bake, blurrier than a Lanczos-3 resize (docs/benchmarks.md "The
 * re-bake's reduction against a Lanczos-3 resize"). The cost: detail finer than the output
 * can hold (above its Nyquist frequency) is no longer averaged away but may alias. */
#define REFERENCE_FOOTPRINT 0.5

enum { TEXEL_EMPTY = 0, TEXEL_INSIDE = 1, TEXEL_RIM = 2 };

/* One triangle of the new layout, in output texel units, with its map to the input. */
typedef struct mapped_triangle {
    double q[3][2];      /* output texel positions */
    double p0[2];        /* input texel position of vertex 0 */
    double m[4];         /* d input / d output, row-major */
    double area2;        /* twice the signed output area */
    double edge_len[3];  /* |q[(i+2)%3] - q[(i+1)%3]|: length of the edge opposite vertex i */
    double rot_c, rot_s; /* rotation part of the map, for normal maps */
    int valid;           /* non-zero output area: owns texels */
    int magnifies;       /* an output texel covers at most one input texel */
} mapped_triangle;

typedef struct bake_context {
    const texopt_texture_filter *filter;
    texopt_image *out;
    uint8_t *state; /* per texel: TEXEL_EMPTY / INSIDE / RIM */
    int32_t *owner; /* per texel: owning triangle, -1 when empty */
    const mapped_triangle *tris;
    int normal_map;
    int channels;
    texopt_rebake_fit fit; /* resolved: never DEFAULT */
} bake_context;

static int map_triangle(const texopt_rebake_layout *layout, size_t t, const texopt_image *in, const texopt_image *out,
                        mapped_triangle *tri)
{
    const uint32_t *v = layout->triangles + 3 * t;
    double p[3][2];
    for (int i = 0; i < 3; i++) {
        tri->q[i][0] = layout->uv_out[2 * v[i]] * out->width;
        tri->q[i][1] = layout->uv_out[2 * v[i] + 1] * out->height;
        p[i][0] = layout->uv_in[2 * v[i]] * in->width;
        p[i][1] = layout->uv_in[2 * v[i] + 1] * in->height;
    }
    tri->valid = texopt_texel_map((const double(*)[2])p, (const double(*)[2])tri->q, tri->m, &tri->area2);
    if (!tri->valid)
        return 0;
    tri->p0[0] = p[0][0];
    tri->p0[1] = p[0][1];
    for (int i = 0; i < 3; i++) {
        const double *a = tri->q[(i + 1) % 3], *b = tri->q[(i + 2) % 3];
        tri->edge_len[i] = hypot(b[0] - a[0], b[1] - a[1]);
    }
    texopt_texel_map_rotation(tri->m, &tri->rot_c, &tri->rot_s);
    /* Largest singular value of m <= 1, from the eigenvalues of m m^T. */
    double a = tri->m[0] * tri->m[0] + tri->m[1] * tri->m[1];
    double d = tri->m[2] * tri->m[2] + tri->m[3] * tri->m[3];
    double b = tri->m[0] * tri->m[2] + tri->m[1] * tri->m[3];
    tri->magnifies = 0.5 * (a + d) + sqrt(0.25 * (a - d) * (a - d) + b * b) <= 1.0 + 1e-9;
    return 1;
}

/* Barycentric coordinates of point (x, y), each normalised so that inside means >= 0. */
static void barycentrics(const mapped_triangle *tri, double x, double y, double w[3])
{
    for (int i = 0; i < 3; i++) {
        const double *a = tri->q[(i + 1) % 3], *b = tri->q[(i + 2) % 3];
        w[i] = ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) / tri->area2;
    }
}

/* The input value seen at barycentric point w of tri, through a footprint of `scale` output
 * texels, with a normal map's XY turned by the triangle's rotation. */
/* The input texel position of barycentric point w of tri. */
static void input_position(const mapped_triangle *tri, const double w[3], double *ix, double *iy)
{
    double ox = w[0] * tri->q[0][0] + w[1] * tri->q[1][0] + w[2] * tri->q[2][0];
    double oy = w[0] * tri->q[0][1] + w[1] * tri->q[1][1] + w[2] * tri->q[2][1];
    double dx = ox - tri->q[0][0], dy = oy - tri->q[0][1];
    *ix = tri->p0[0] + tri->m[0] * dx + tri->m[1] * dy;
    *iy = tri->p0[1] + tri->m[2] * dx + tri->m[3] * dy;
}

static void lookup(const bake_context *ctx, const mapped_triangle *tri, const double w[3], double scale, float *o)
{
    double ix, iy;
    input_position(tri, w, &ix, &iy);
    double foot[4] = {tri->m[0] * scale, tri->m[1] * scale, tri->m[2] * scale, tri->m[3] * scale};
    texopt_texture_filter_sample(ctx->filter, ix, iy, foot, o);
    if (ctx->normal_map && ctx->channels >= 2)
        texopt_normal_turn(tri->rot_c, tri->rot_s, o);
}

static void bake_texel(const bake_context *ctx, const mapped_triangle *tri, int x, int y, const double w[3])
{
    lookup(ctx, tri, w, 1.0, texopt_image_at(ctx->out, x, y));
}

/* The texel range [x0, x1] x [y0, y1] of a triangle's bounding box grown by `grow` texels. */
static void texel_box(const mapped_triangle *tri, const texopt_image *out, double grow, int box[4])
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], tri->q[i][k]);
            hi[k] = fmax(hi[k], tri->q[i][k]);
        }
    box[0] = (int)fmax(0, floor(lo[0] - grow - 0.5));
    box[1] = (int)fmax(0, floor(lo[1] - grow - 0.5));
    box[2] = (int)fmin(out->width - 1, ceil(hi[0] + grow - 0.5));
    box[3] = (int)fmin(out->height - 1, ceil(hi[1] + grow - 0.5));
}

static void claim_inside(const bake_context *ctx, const mapped_triangle *tri, int32_t t)
{
    int box[4];
    texel_box(tri, ctx->out, 0, box);
    for (int y = box[1]; y <= box[3]; y++)
        for (int x = box[0]; x <= box[2]; x++) {
            size_t i = (size_t)y * ctx->out->width + x;
            if (ctx->state[i] != TEXEL_EMPTY)
                continue;
            double w[3];
            barycentrics(tri, x + 0.5, y + 0.5, w);
            if (w[0] < 0 || w[1] < 0 || w[2] < 0)
                continue;
            ctx->state[i] = TEXEL_INSIDE;
            ctx->owner[i] = t;
        }
}

/* Clamps barycentrics to the triangle (approximately its nearest point: negative weights
 * to zero, renormalised); 0 when nothing is left. */
static int clamp_barycentrics(double w[3])
{
    double sum = 0;
    for (int i = 0; i < 3; i++) {
        w[i] = w[i] > 0 ? w[i] : 0;
        sum += w[i];
    }
    if (!(sum > 0))
        return 0;
    for (int i = 0; i < 3; i++)
        w[i] /= sum;
    return 1;
}

/* Barycentrics of the point of the triangle nearest (approximately: clamped and
 * renormalised) to (x, y); 0 when (x, y) is farther than RIM_DISTANCE from it. */
static int rim_point(const mapped_triangle *tri, double x, double y, double w[3])
{
    double twice_area = fabs(tri->area2);
    barycentrics(tri, x, y, w);
    for (int i = 0; i < 3; i++) /* w_i * 2A / |edge_i| = signed edge distance */
        if (w[i] * twice_area / fmax(tri->edge_len[i], 1e-12) < -RIM_DISTANCE)
            return 0;
    return clamp_barycentrics(w);
}

static void claim_rim(const bake_context *ctx, const mapped_triangle *tri, int32_t t)
{
    int box[4];
    texel_box(tri, ctx->out, 1, box);
    for (int y = box[1]; y <= box[3]; y++)
        for (int x = box[0]; x <= box[2]; x++) {
            size_t i = (size_t)y * ctx->out->width + x;
            double w[3];
            if (ctx->state[i] != TEXEL_EMPTY || !rim_point(tri, x + 0.5, y + 0.5, w))
                continue;
            ctx->state[i] = TEXEL_RIM;
            ctx->owner[i] = t;
        }
}

static void report(const texopt_monitor *monitor, double stage_fraction)
{
    texopt_progress p = {.stage = "bake", .stage_fraction = stage_fraction, .eta_seconds = -1};
    texopt_monitor_report(monitor, &p);
}

static texopt_status claim_pass(const bake_context *ctx, size_t n, int rim, const texopt_monitor *monitor, char *err,
                                size_t err_len)
{
    for (size_t t = 0; t < n; t++) {
        if (t % CHECK_EVERY == 0) {
            if (texopt_monitor_canceled(monitor))
                return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "bake canceled");
            report(monitor, 0.1 * (rim + (double)t / (double)n));
        }
        if (!ctx->tris[t].valid)
            continue;
        if (rim)
            claim_rim(ctx, &ctx->tris[t], (int32_t)t);
        else
            claim_inside(ctx, &ctx->tris[t], (int32_t)t);
    }
    return TEXOPT_OK;
}

/* The four sub-texel references of owned texel (x, y) for the least-squares fit (texel_fit.h
 * order). Each point is looked up through the triangle that contains it: the texel's owner
 * or the owner of the neighbour on the point's side (a point may cross an edge between
 * triangles of one chart); a point no candidate contains (past a chart border) takes the
 * nearest point of the owner, as the rim does. */
static void sample_references(const bake_context *ctx, int x, int y, float *ref)
{
    int width = ctx->out->width, height = ctx->out->height, ch = ctx->channels;
    const mapped_triangle *own = &ctx->tris[ctx->owner[(size_t)y * width + x]];
    for (int s = 0; s < TEXOPT_TEXEL_FIT_SAMPLES; s++) {
        int sx = s & 1, sy = s >> 1;
        double px = x + 0.25 + 0.5 * sx, py = y + 0.25 + 0.5 * sy;
        int nx[4] = {x, x + 2 * sx - 1, x, x + 2 * sx - 1};
        int ny[4] = {y, y, y + 2 * sy - 1, y + 2 * sy - 1};
        const mapped_triangle *tri = NULL;
        double w[3];
        for (int k = 0; k < 4 && !tri; k++) {
            if (nx[k] < 0 || ny[k] < 0 || nx[k] >= width || ny[k] >= height)
                continue;
            size_t i = (size_t)ny[k] * width + nx[k];
            if (ctx->state[i] == TEXEL_EMPTY)
                continue;
            const mapped_triangle *c = &ctx->tris[ctx->owner[i]];
            barycentrics(c, px, py, w);
            if (w[0] >= -1e-12 && w[1] >= -1e-12 && w[2] >= -1e-12)
                tri = c;
        }
        if (!tri) {
            tri = own;
            barycentrics(tri, px, py, w);
            clamp_barycentrics(w);
        }
        lookup(ctx, tri, w, REFERENCE_FOOTPRINT, ref + (size_t)s * ch);
    }
}

/* Whether owned texel i takes part in the fit. */
static int fits_texel(const bake_context *ctx, size_t i)
{
    if (ctx->state[i] == TEXEL_EMPTY)
        return 0;
    return ctx->fit == TEXOPT_REBAKE_FIT_LEAST_SQUARES || ctx->tris[ctx->owner[i]].magnifies;
}

/* texel_fit's reference callback. */
static void fit_reference(void *user, int x, int y, float *out)
{
    sample_references(user, x, y, out);
}

/* The owner of owned texel (x, y) and the barycentrics its value is taken at: its centre,
 * or for a rim texel the nearest point of the owner. */
static const mapped_triangle *texel_point(const bake_context *ctx, int x, int y, double w[3])
{
    size_t i = (size_t)y * ctx->out->width + x;
    const mapped_triangle *tri = &ctx->tris[ctx->owner[i]];
    if (ctx->state[i] == TEXEL_RIM)
        rim_point(tri, x + 0.5, y + 0.5, w);
    else
        barycentrics(tri, x + 0.5, y + 0.5, w);
    return tri;
}

/* c times the interval [lo, hi]. */
static void scale_interval(double c, double lo, double hi, double out[2])
{
    out[0] = c >= 0 ? c * lo : c * hi;
    out[1] = c >= 0 ? c * hi : c * lo;
}

/* A normal map's XY range turned as its texels are (texopt_normal_turn on the decoded
 * components, interval arithmetic: a box that holds every turned value). */
static void turn_range(double c, double s, float *lo, float *hi)
{
    double a[2] = {2.0 * lo[0] - 1.0, 2.0 * hi[0] - 1.0}, b[2] = {2.0 * lo[1] - 1.0, 2.0 * hi[1] - 1.0};
    double ca[2], sb[2], sa[2], cb[2];
    scale_interval(c, a[0], a[1], ca);
    scale_interval(-s, b[0], b[1], sb);
    scale_interval(s, a[0], a[1], sa);
    scale_interval(c, b[0], b[1], cb);
    lo[0] = (float)(0.5 + 0.5 * (ca[0] + sb[0]));
    hi[0] = (float)(0.5 + 0.5 * (ca[1] + sb[1]));
    lo[1] = (float)(0.5 + 0.5 * (sa[0] + cb[0]));
    hi[1] = (float)(0.5 + 0.5 * (sa[1] + cb[1]));
}

/* texel_fit's range callback: the input a bilinear lookup anywhere in the owned texel's square
 * (mapped back through its triangle) can read, so the fit cannot take a texel beyond what
 * the input holds around it: the least-squares solution of a sharp edge rings, like any
 * sharpening, and a bound there is what keeps it from overshooting. */
static void fit_range(void *user, int x, int y, float *lo, float *hi)
{
    const bake_context *ctx = user;
    double w[3], ix, iy;
    const mapped_triangle *tri = texel_point(ctx, x, y, w);
    input_position(tri, w, &ix, &iy);
    double hx = 0.5 * (fabs(tri->m[0]) + fabs(tri->m[1])), hy = 0.5 * (fabs(tri->m[2]) + fabs(tri->m[3]));
    texopt_texture_filter_range(ctx->filter, ix, iy, hx, hy, lo, hi);
    if (ctx->normal_map && ctx->channels >= 2)
        turn_range(tri->rot_c, tri->rot_s, lo, hi);
}

typedef struct sample_worker {
    const bake_context *ctx;
    int first_row, step;
    const texopt_monitor *monitor; /* only worker 0 reports; every worker checks cancel */
    int canceled;
} sample_worker;

static void sample_row(const bake_context *ctx, int y)
{
    int width = ctx->out->width;
    for (int x = 0; x < width; x++) {
        size_t i = (size_t)y * width + x;
        if (ctx->state[i] == TEXEL_EMPTY)
            continue;
        double w[3];
        const mapped_triangle *tri = texel_point(ctx, x, y, w);
        bake_texel(ctx, tri, x, y, w);
    }
}

static void *sample_rows(void *arg)
{
    sample_worker *wk = arg;
    const bake_context *ctx = wk->ctx;
    int height = ctx->out->height;
    for (int y = wk->first_row; y < height; y += wk->step) {
        if (texopt_monitor_canceled(wk->monitor)) {
            wk->canceled = 1;
            return NULL;
        }
        if (wk->first_row == 0 && y % 64 == 0)
            report(wk->monitor, 0.2 + 0.3 * (double)y / height);
        sample_row(ctx, y);
    }
    return NULL;
}

/* Samples every owned texel at its centre, rows interleaved over `threads` workers. */
static texopt_status sample_owned(const bake_context *ctx, int threads, const texopt_monitor *monitor, char *err,
                                  size_t err_len)
{
    if (threads < 1)
        threads = 1;
    if (threads > MAX_THREADS)
        threads = MAX_THREADS;
    sample_worker wk[MAX_THREADS];
    for (int k = 0; k < threads; k++)
        wk[k] = (sample_worker){.ctx = ctx, .first_row = k, .step = threads, .monitor = monitor};
    texopt_parallel_run(sample_rows, wk, sizeof *wk, threads);
    int canceled = 0;
    for (int k = 0; k < threads; k++)
        canceled |= wk[k].canceled;
    if (canceled)
        return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "bake canceled");
    return TEXOPT_OK;
}

/* The least-squares fit over the prefiltered bake (texel_fit.h). The one-texel ring around
 * the owned texels is first dilated, because the fit starts from it and may change it;
 * `covered` then marks the owned texels and every texel the fit set, for the final dilation.
 * The fit itself is not interruptible: cancellation is checked before it. */
static texopt_status fit_texels(bake_context *ctx, uint8_t *covered, int threads, const texopt_monitor *monitor,
                                char *err, size_t err_len)
{
    size_t count = (size_t)ctx->out->width * (size_t)ctx->out->height;
    texopt_status st = texopt_dilate(ctx->out, covered, 1, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    if (texopt_monitor_canceled(monitor))
        return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "bake canceled");
    report(monitor, 0.5);
    uint8_t *sampled = malloc(count), *fixed = malloc(count);
    if (!sampled || !fixed)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to fit a %dx%d bake", ctx->out->width,
                         ctx->out->height);
    if (st == TEXOPT_OK) {
        for (size_t i = 0; i < count; i++) {
            sampled[i] = (uint8_t)fits_texel(ctx, i);
            fixed[i] = ctx->state[i] != TEXEL_EMPTY && !sampled[i];
            covered[i] = ctx->state[i] != TEXEL_EMPTY;
        }
        texopt_texel_fit_problem pb = {.image = ctx->out,
                                       .sampled = sampled,
                                       .reference = fit_reference,
                                       .range = fit_range,
                                       .user = ctx,
                                       .fixed = fixed,
                                       .ridge = FIT_RIDGE,
                                       .tolerance = FIT_TOLERANCE,
                                       .max_iterations = FIT_MAX_ITERATIONS,
                                       .threads = threads};
        st = texopt_texel_fit(&pb, covered, NULL, err, err_len);
    }
    free(sampled);
    free(fixed);
    return st;
}

static texopt_status check_layout(const texopt_image *input, const texopt_rebake_layout *layout,
                                  const texopt_image *output, char *err, size_t err_len)
{
    if (!input || !input->pixels || !output || !output->pixels || !layout)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rebake: missing image or layout");
    if (output->channels != input->channels)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rebake: output has %d channels, input %d",
                           output->channels, input->channels);
    if (layout->triangle_count > 0 && (!layout->triangles || !layout->uv_in || !layout->uv_out))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rebake: layout arrays missing");
    return TEXOPT_OK;
}

texopt_status texopt_rebake_image(const texopt_image *input, texopt_wrap wrap_s, texopt_wrap wrap_t, int normal_map,
                                  const texopt_rebake_layout *layout, texopt_image *output, size_t *covered_texels,
                                  const texopt_monitor *monitor, char *err, size_t err_len)
{
    return texopt_rebake_image_fit(input, wrap_s, wrap_t, normal_map, layout, TEXOPT_REBAKE_FIT_DEFAULT, output,
                                   covered_texels, monitor, err, err_len);
}

texopt_status texopt_rebake_image_fit(const texopt_image *input, texopt_wrap wrap_s, texopt_wrap wrap_t, int normal_map,
                                      const texopt_rebake_layout *layout, texopt_rebake_fit fit, texopt_image *output,
                                      size_t *covered_texels, const texopt_monitor *monitor, char *err, size_t err_len)
{
    texopt_status st = check_layout(input, layout, output, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    size_t count = (size_t)output->width * (size_t)output->height, n = layout->triangle_count;
    uint8_t *state = calloc(count, 1);
    int32_t *owner = malloc(count * sizeof *owner);
    mapped_triangle *tris = malloc((n ? n : 1) * sizeof *tris);
    if (!state || !owner || !tris) {
        free(state);
        free(owner);
        free(tris);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d bake", output->width, output->height);
    }
    for (size_t t = 0; t < n; t++)
        map_triangle(layout, t, input, output, &tris[t]);
    texopt_texture_filter *filter = NULL;
    st = texopt_texture_filter_create(&filter, input, wrap_s, wrap_t, err, err_len);
    bake_context ctx = {.filter = filter,
                        .out = output,
                        .state = state,
                        .owner = owner,
                        .tris = tris,
                        .normal_map = normal_map,
                        .channels = output->channels,
                        .fit = fit == TEXOPT_REBAKE_FIT_DEFAULT ? DEFAULT_FIT : fit};
    if (st == TEXOPT_OK)
        st = claim_pass(&ctx, n, 0, monitor, err, err_len);
    if (st == TEXOPT_OK)
        st = claim_pass(&ctx, n, 1, monitor, err, err_len);
    if (st == TEXOPT_OK)
        st = sample_owned(&ctx, layout->threads, monitor, err, err_len);
    if (st == TEXOPT_OK && covered_texels) {
        size_t inside = 0;
        for (size_t i = 0; i < count; i++)
            inside += state[i] == TEXEL_INSIDE;
        *covered_texels = inside;
    }
    uint8_t *covered = st == TEXOPT_OK ? malloc(count) : NULL;
    if (st == TEXOPT_OK && !covered)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d bake", output->width, output->height);
    if (st == TEXOPT_OK) {
        for (size_t i = 0; i < count; i++)
            covered[i] = state[i] != TEXEL_EMPTY;
        if (ctx.fit != TEXOPT_REBAKE_FIT_PREFILTER)
            st = fit_texels(&ctx, covered, layout->threads, monitor, err, err_len);
    }
    if (st == TEXOPT_OK)
        st = texopt_dilate(output, covered, 0, err, err_len);
    if (st == TEXOPT_OK)
        report(monitor, 1.0);
    texopt_texture_filter_destroy(filter);
    free(covered);
    free(state);
    free(owner);
    free(tris);
    return st;
}

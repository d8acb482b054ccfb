/* rebake.c - texel-centre rasterisation of the new layout, affine map back to the input,
 * prefiltered lookup, chart rim, dilation (see rebake.h for the contract and the normal-map
 * rule).
 *
 * Two passes over the triangles: the first bakes texels whose centre is inside a triangle
 * (first triangle wins on shared edges; both sides of an interior edge agree there), the
 * second gives each still-empty texel within half a texel diagonal of a triangle the value
 * at the clamped barycentric point, so bilinear lookups just inside a chart border read the
 * chart, not the gutter. Then the gutter is dilated. */
#include "rebake.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dilate.h"
#include "texture_filter.h"

#define RIM_DISTANCE 0.7072 /* half the diagonal of a texel, slightly rounded up */
#define CHECK_EVERY 4096

enum { TEXEL_EMPTY = 0, TEXEL_INSIDE = 1, TEXEL_RIM = 2 };

/* One triangle of the new layout, in output texel units, with its map to the input. */
typedef struct mapped_triangle {
    double q[3][2];   /* output texel positions */
    double p0[2];     /* input texel position of vertex 0 */
    double m[4];      /* d input / d output, row-major */
    double area2;     /* twice the signed output area */
    double edge_len[3]; /* |q[(i+2)%3] - q[(i+1)%3]|: length of the edge opposite vertex i */
    double rot_c, rot_s; /* rotation part of the map, for normal maps */
} mapped_triangle;

typedef struct bake_context {
    const texopt_texture_filter *filter;
    texopt_image *out;
    uint8_t *state;
    int normal_map;
    int channels;
} bake_context;

static int map_triangle(const texopt_rebake_layout *layout, size_t t, const texopt_image *in,
                        const texopt_image *out, mapped_triangle *tri)
{
    const uint32_t *v = layout->triangles + 3 * t;
    double p[3][2];
    for (int i = 0; i < 3; i++) {
        tri->q[i][0] = layout->uv_out[2 * v[i]] * out->width;
        tri->q[i][1] = layout->uv_out[2 * v[i] + 1] * out->height;
        p[i][0] = layout->uv_in[2 * v[i]] * in->width;
        p[i][1] = layout->uv_in[2 * v[i] + 1] * in->height;
    }
    double e1x = tri->q[1][0] - tri->q[0][0], e1y = tri->q[1][1] - tri->q[0][1];
    double e2x = tri->q[2][0] - tri->q[0][0], e2y = tri->q[2][1] - tri->q[0][1];
    tri->area2 = e1x * e2y - e2x * e1y;
    if (!(fabs(tri->area2) > 1e-12) || !isfinite(tri->area2))
        return 0;
    double f1x = p[1][0] - p[0][0], f1y = p[1][1] - p[0][1];
    double f2x = p[2][0] - p[0][0], f2y = p[2][1] - p[0][1];
    /* M = [f1 f2] [e1 e2]^-1 */
    double inv = 1.0 / tri->area2;
    double i00 = e2y * inv, i01 = -e2x * inv, i10 = -e1y * inv, i11 = e1x * inv;
    tri->m[0] = f1x * i00 + f2x * i10;
    tri->m[1] = f1x * i01 + f2x * i11;
    tri->m[2] = f1y * i00 + f2y * i10;
    tri->m[3] = f1y * i01 + f2y * i11;
    tri->p0[0] = p[0][0];
    tri->p0[1] = p[0][1];
    for (int i = 0; i < 3; i++) {
        const double *a = tri->q[(i + 1) % 3], *b = tri->q[(i + 2) % 3];
        tri->edge_len[i] = hypot(b[0] - a[0], b[1] - a[1]);
    }
    double theta = atan2(tri->m[2] - tri->m[1], tri->m[0] + tri->m[3]);
    tri->rot_c = cos(theta);
    tri->rot_s = sin(theta);
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

static void bake_texel(const bake_context *ctx, const mapped_triangle *tri, int x, int y,
                       const double w[3])
{
    double ox = w[0] * tri->q[0][0] + w[1] * tri->q[1][0] + w[2] * tri->q[2][0];
    double oy = w[0] * tri->q[0][1] + w[1] * tri->q[1][1] + w[2] * tri->q[2][1];
    double dx = ox - tri->q[0][0], dy = oy - tri->q[0][1];
    double ix = tri->p0[0] + tri->m[0] * dx + tri->m[1] * dy;
    double iy = tri->p0[1] + tri->m[2] * dx + tri->m[3] * dy;
    float *o = texopt_image_at(ctx->out, x, y);
    texopt_texture_filter_sample(ctx->filter, ix, iy, tri->m, o);
    if (ctx->normal_map && ctx->channels >= 2) {
        double a = 2.0 * o[0] - 1.0, b = 2.0 * o[1] - 1.0;
        o[0] = (float)(0.5 * (tri->rot_c * a - tri->rot_s * b + 1.0));
        o[1] = (float)(0.5 * (tri->rot_s * a + tri->rot_c * b + 1.0));
    }
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

static void bake_inside(const bake_context *ctx, const mapped_triangle *tri)
{
    int box[4];
    texel_box(tri, ctx->out, 0, box);
    for (int y = box[1]; y <= box[3]; y++)
        for (int x = box[0]; x <= box[2]; x++) {
            uint8_t *s = &ctx->state[(size_t)y * ctx->out->width + x];
            if (*s != TEXEL_EMPTY)
                continue;
            double w[3];
            barycentrics(tri, x + 0.5, y + 0.5, w);
            if (w[0] < 0 || w[1] < 0 || w[2] < 0)
                continue;
            bake_texel(ctx, tri, x, y, w);
            *s = TEXEL_INSIDE;
        }
}

static void bake_rim(const bake_context *ctx, const mapped_triangle *tri)
{
    int box[4];
    texel_box(tri, ctx->out, 1, box);
    double twice_area = fabs(tri->area2);
    for (int y = box[1]; y <= box[3]; y++)
        for (int x = box[0]; x <= box[2]; x++) {
            uint8_t *s = &ctx->state[(size_t)y * ctx->out->width + x];
            if (*s != TEXEL_EMPTY)
                continue;
            double w[3], sum = 0;
            barycentrics(tri, x + 0.5, y + 0.5, w);
            int near = 1;
            for (int i = 0; i < 3 && near; i++) /* w_i * 2A / |edge_i| = signed edge distance */
                near = w[i] * twice_area / fmax(tri->edge_len[i], 1e-12) >= -RIM_DISTANCE;
            if (!near)
                continue;
            for (int i = 0; i < 3; i++) {
                w[i] = w[i] > 0 ? w[i] : 0;
                sum += w[i];
            }
            if (!(sum > 0))
                continue;
            for (int i = 0; i < 3; i++)
                w[i] /= sum;
            bake_texel(ctx, tri, x, y, w);
            *s = TEXEL_RIM;
        }
}

static void report(const texopt_monitor *monitor, double stage_fraction)
{
    texopt_progress p = {.stage = "bake", .stage_fraction = stage_fraction, .eta_seconds = -1};
    texopt_monitor_report(monitor, &p);
}

static texopt_status bake_pass(const bake_context *ctx, const texopt_rebake_layout *layout,
                               const texopt_image *in, int rim, const texopt_monitor *monitor,
                               char *err, size_t err_len)
{
    size_t n = layout->triangle_count;
    for (size_t t = 0; t < n; t++) {
        if (t % CHECK_EVERY == 0) {
            if (texopt_monitor_canceled(monitor))
                return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "bake canceled");
            report(monitor, (rim ? 0.5 : 0.0) + 0.5 * (double)t / (double)n);
        }
        mapped_triangle tri;
        if (!map_triangle(layout, t, in, ctx->out, &tri))
            continue;
        if (rim)
            bake_rim(ctx, &tri);
        else
            bake_inside(ctx, &tri);
    }
    return TEXOPT_OK;
}

static texopt_status check_layout(const texopt_image *input, const texopt_rebake_layout *layout,
                                  const texopt_image *output, char *err, size_t err_len)
{
    if (!input || !input->pixels || !output || !output->pixels || !layout)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rebake: missing image or layout");
    if (output->channels != input->channels)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "rebake: output has %d channels, input %d", output->channels,
                           input->channels);
    if (layout->triangle_count > 0 && (!layout->triangles || !layout->uv_in || !layout->uv_out))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rebake: layout arrays missing");
    return TEXOPT_OK;
}

texopt_status texopt_rebake_image(const texopt_image *input, texopt_wrap wrap_s,
                                  texopt_wrap wrap_t, int normal_map,
                                  const texopt_rebake_layout *layout, texopt_image *output,
                                  size_t *covered_texels, const texopt_monitor *monitor,
                                  char *err, size_t err_len)
{
    texopt_status st = check_layout(input, layout, output, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    size_t count = (size_t)output->width * (size_t)output->height;
    uint8_t *state = calloc(count, 1);
    if (!state)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d bake mask",
                           output->width, output->height);
    texopt_texture_filter *filter = NULL;
    st = texopt_texture_filter_create(&filter, input, wrap_s, wrap_t, err, err_len);
    if (st == TEXOPT_OK) {
        bake_context ctx = {filter, output, state, normal_map, output->channels};
        st = bake_pass(&ctx, layout, input, 0, monitor, err, err_len);
        if (st == TEXOPT_OK)
            st = bake_pass(&ctx, layout, input, 1, monitor, err, err_len);
    }
    if (st == TEXOPT_OK && covered_texels) {
        size_t inside = 0;
        for (size_t i = 0; i < count; i++)
            inside += state[i] == TEXEL_INSIDE;
        *covered_texels = inside;
    }
    if (st == TEXOPT_OK)
        st = texopt_dilate(output, state, 0, err, err_len);
    if (st == TEXOPT_OK)
        report(monitor, 1.0);
    texopt_texture_filter_destroy(filter);
    free(state);
    return st;
}

/* ssp.c - signal-stretch metric targets (Sander, Gortler, Snyder, Hoppe 2002), the "SSPOP"
 * baseline of Sun et al. 2022, section 5, fed to the same mesh-wise solver with wR = 0.
 *
 * The integral of grad s grad s^T over a triangle is estimated as the mean over the
 * centroids of its regular n x n subdivision (n = longest edge in texels, 1..32), which
 * samples about once per texel; the gradient is the central difference of the bilinear
 * texture with a one-texel step, per channel, summed over channels.
 * Does not: solve, pack or bake; the Hessian variant lives in tewari.c. */
#include "ssp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metric_maps.h"
#include "sample.h"

#define MAX_SUBDIVISION 32
/* lambda ~ eig(M)^(1/2) (ssp.h). */
#define STRETCH_EXPONENT 0.5
/* A reference scale below this: the signal is flat to float precision, every triangle
 * equally simple. */
#define FLAT_SCALE 1e-9

const texopt_image *texopt_domain_signal_image(const texopt_model *model, const texopt_mesh *mesh)
{
    if (!model || !mesh || mesh->domain < 0 || mesh->domain >= model->domain_count)
        return NULL;
    const texopt_domain *dom = &model->domains[mesh->domain];
    if (dom->image_count < 1)
        return NULL;
    const texopt_image *img = &model->images[dom->images[0]];
    return img->pixels ? img : NULL;
}

static int signal_channels(const texopt_image *img)
{
    return img->channels >= 3 ? 3 : 1;
}

static void probe_gradient(const texopt_image *img, texopt_wrap ws, texopt_wrap wt, double x, double y, double sx,
                           double sy, double m[3])
{
    float l[4], r[4], u[4], d[4];
    texopt_sample_bilinear(img, ws, wt, x - 1, y, l);
    texopt_sample_bilinear(img, ws, wt, x + 1, y, r);
    texopt_sample_bilinear(img, ws, wt, x, y - 1, u);
    texopt_sample_bilinear(img, ws, wt, x, y + 1, d);
    for (int c = 0; c < signal_channels(img); c++) {
        /* d/d(domain texel) = d/d(image texel) * image texels per domain texel. */
        double gx = 0.5 * (r[c] - l[c]) / sx, gy = 0.5 * (d[c] - u[c]) / sy;
        m[0] += gx * gx;
        m[1] += gx * gy;
        m[2] += gy * gy;
    }
}

texopt_status texopt_signal_metric(const texopt_model *model, const texopt_mesh *mesh, texopt_signal_probe probe,
                                   double *metric, char *err, size_t err_len)
{
    if (!model || !mesh || !probe || !metric)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "signal metric: missing argument");
    const texopt_image *img = texopt_domain_signal_image(model, mesh);
    if (!img)
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "domain %d has no decoded base colour image to measure",
                           mesh->domain);
    return texopt_signal_metric_of(model, mesh, img, probe, metric);
}

texopt_status texopt_signal_metric_of(const texopt_model *model, const texopt_mesh *mesh, const texopt_image *img,
                                      texopt_signal_probe probe, double *metric)
{
    const texopt_domain *dom = &model->domains[mesh->domain];
    double sx = (double)mesh->width / img->width, sy = (double)mesh->height / img->height;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        double *m = metric + 3 * t;
        m[0] = m[1] = m[2] = 0;
        if (mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV))
            continue;
        const double *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = mesh->texel + 2 * (size_t)mesh->triangle[3 * t + k];
        double longest = 0;
        for (int k = 0; k < 3; k++)
            longest = fmax(longest, hypot(p[(k + 1) % 3][0] - p[k][0], p[(k + 1) % 3][1] - p[k][1]));
        int n = (int)fmin(MAX_SUBDIVISION, fmax(1, ceil(longest)));
        int samples = 0;
        /* Centroids of the n^2 congruent sub-triangles: the upward ones at (i + 1/3, j + 1/3)/n,
         * the downward ones at (i + 2/3, j + 2/3)/n, in barycentrics of corners 1 and 2. */
        for (int i = 0; i < n; i++)
            for (int j = 0; i + j < n; j++)
                for (int down = 0; down < 2; down++) {
                    if (down && i + j >= n - 1)
                        continue;
                    double off = down ? 2.0 / 3.0 : 1.0 / 3.0;
                    double b1 = (i + off) / n, b2 = (j + off) / n, b0 = 1 - b1 - b2;
                    double x = b0 * p[0][0] + b1 * p[1][0] + b2 * p[2][0];
                    double y = b0 * p[0][1] + b1 * p[1][1] + b2 * p[2][1];
                    probe(img, dom->wrap_s, dom->wrap_t, x / sx, y / sy, sx, sy, m);
                    samples++;
                }
        for (int k = 0; k < 3; k++)
            m[k] /= samples;
    }
    return TEXOPT_OK;
}

texopt_status texopt_ssp_metric(const texopt_model *model, const texopt_mesh *mesh, double *metric, char *err,
                                size_t err_len)
{
    return texopt_signal_metric(model, mesh, probe_gradient, metric, err, err_len);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int counted(const texopt_mesh *mesh, size_t t)
{
    return !(mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV));
}

/* The scale mapped to lambda = 1: the 98th percentile of the larger per-direction scale. */
static texopt_status reference_scale(const texopt_mesh *mesh, const double *metric, double exponent, double *out,
                                     char *err, size_t err_len)
{
    double *s = malloc((mesh->triangle_count ? mesh->triangle_count : 1) * sizeof *s);
    if (!s)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for metric scales");
    size_t n = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (!counted(mesh, t))
            continue;
        double mu1, mu2, theta;
        texopt_sym2_eigen(metric + 3 * t, &mu1, &mu2, &theta);
        s[n++] = pow(mu1, exponent);
    }
    *out = 0;
    if (n > 0) {
        qsort(s, n, sizeof *s, cmp_double);
        *out = s[(size_t)floor(0.98 * (double)(n - 1))];
    }
    free(s);
    return TEXOPT_OK;
}

static double clamp(double x, double lo, double hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

texopt_status texopt_targets_from_metric(const texopt_mesh *mesh, const double *metric, double exponent,
                                         double lambda_min, texopt_triangle_target *targets, char *err, size_t err_len)
{
    if (!mesh || !metric || !targets)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "metric targets: missing argument");
    if (lambda_min == 0)
        lambda_min = 0.1;
    if (!(lambda_min > 0 && lambda_min <= 1) || !(exponent > 0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "lambda_min %g must be in (0, 1] and exponent %g positive", lambda_min, exponent);
    for (size_t t = 0; t < 3 * mesh->triangle_count; t++)
        if (!isfinite(metric[t]))
            return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "metric of triangle %zu is not finite", t / 3);
    double ref = 0;
    texopt_status st = reference_scale(mesh, metric, exponent, &ref, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    int flat = !(ref > FLAT_SCALE);
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        texopt_triangle_target *g = &targets[t];
        memset(g, 0, sizeof *g);
        g->lambda1 = g->lambda2 = 1;
        if (!counted(mesh, t))
            continue;
        g->w_stretch = 1;
        if (flat)
            continue;
        double mu1, mu2, theta;
        texopt_sym2_eigen(metric + 3 * t, &mu1, &mu2, &theta);
        double along = clamp(pow(mu1, exponent) / ref, lambda_min, 1);
        double across = clamp(pow(mu2, exponent) / ref, lambda_min, 1);
        texopt_target_set_stretch(g, theta, along, across);
    }
    return TEXOPT_OK;
}

texopt_status texopt_ssp_targets(const texopt_model *model, const texopt_mesh *mesh, double lambda_min,
                                 texopt_triangle_target *targets, char *err, size_t err_len)
{
    if (!mesh)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "ssp: missing mesh");
    double *metric = malloc(3 * (mesh->triangle_count ? mesh->triangle_count : 1) * sizeof *metric);
    if (!metric)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the signal metric");
    texopt_status st = texopt_ssp_metric(model, mesh, metric, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_targets_from_metric(mesh, metric, STRETCH_EXPONENT, lambda_min, targets, err, err_len);
    free(metric);
    return st;
}

texopt_status texopt_ssp_targets_every_map(const texopt_model *model, const texopt_mesh *mesh, double lambda_min,
                                           const double *signal_weights, int threads, texopt_triangle_target *targets,
                                           char *err, size_t err_len)
{
    return texopt_metric_targets_every_map(model, mesh, probe_gradient, STRETCH_EXPONENT, lambda_min, signal_weights,
                                           threads, targets, err, err_len);
}

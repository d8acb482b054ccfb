/* tewari.c - Hessian-metric targets (Tewari et al. 2004), a baseline of Sun et al. 2022.
 *
 * The Hessian is estimated by central second differences of the bilinear texture with a
 * one-texel step (s_xx, s_yy with the 1 -2 1 stencil, s_xy with the 4-corner stencil), at
 * the same per-texel sample points as the signal-stretch metric (ssp.c), and converted to
 * domain texels. Does not: solve, pack or bake. */
#include "tewari.h"

#include <stdlib.h>

#include "metric_maps.h"
#include "sample.h"
#include "ssp.h"

/* lambda ~ eig(M)^(1/4) (tewari.h). */
#define HESSIAN_EXPONENT 0.25

static void probe_hessian(const texopt_image *img, texopt_wrap ws, texopt_wrap wt, double x, double y, double sx,
                          double sy, double m[3])
{
    /* s[dy + 1][dx + 1] = the texture at (x + dx, y + dy). */
    float s[3][3][4];
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
            texopt_sample_bilinear(img, ws, wt, x + dx, y + dy, s[dy + 1][dx + 1]);
    int channels = img->channels >= 3 ? 3 : 1;
    for (int c = 0; c < channels; c++) {
        double hxx = (s[1][2][c] - 2.0 * s[1][1][c] + s[1][0][c]) / (sx * sx);
        double hyy = (s[2][1][c] - 2.0 * s[1][1][c] + s[0][1][c]) / (sy * sy);
        double hxy = 0.25 * (s[2][2][c] - s[0][2][c] - s[2][0][c] + s[0][0][c]) / (sx * sy);
        /* H^2 for symmetric H = [[hxx, hxy], [hxy, hyy]]. */
        m[0] += hxx * hxx + hxy * hxy;
        m[1] += hxy * (hxx + hyy);
        m[2] += hxy * hxy + hyy * hyy;
    }
}

texopt_status texopt_tewari_metric(const texopt_model *model, const texopt_mesh *mesh, double *metric, char *err,
                                   size_t err_len)
{
    return texopt_signal_metric(model, mesh, probe_hessian, metric, err, err_len);
}

texopt_status texopt_tewari_targets(const texopt_model *model, const texopt_mesh *mesh, double lambda_min,
                                    texopt_triangle_target *targets, char *err, size_t err_len)
{
    if (!mesh)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "tewari: missing mesh");
    double *metric = malloc(3 * (mesh->triangle_count ? mesh->triangle_count : 1) * sizeof *metric);
    if (!metric)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the Hessian metric");
    texopt_status st = texopt_tewari_metric(model, mesh, metric, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_targets_from_metric(mesh, metric, HESSIAN_EXPONENT, lambda_min, targets, err, err_len);
    free(metric);
    return st;
}

texopt_status texopt_tewari_targets_every_map(const texopt_model *model, const texopt_mesh *mesh, double lambda_min,
                                              const double *signal_weights, int threads,
                                              texopt_triangle_target *targets, char *err, size_t err_len)
{
    return texopt_metric_targets_every_map(model, mesh, probe_hessian, HESSIAN_EXPONENT, lambda_min, signal_weights,
                                           threads, targets, err, err_len);
}

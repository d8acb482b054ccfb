/* distortion.c - symmetric Dirichlet distortion of a layout and flip counting.
 *
 * Implements the distortion measure of Sun et al. 2022 (eq. 24), the symmetric Dirichlet
 * energy of Smith and Schaefer 2015, "Bijective parameterization with free boundaries":
 * |J|_F^2 + |J^-1|_F^2 per triangle, area-weighted over the surface, and the other metrics of
 * the parameterization lecture (distortion.h) from the same Jacobian. It does not optimise
 * anything; meshwise.c and the evaluation call it on finished layouts. */
#include "distortion.h"

#include <cjson/cJSON.h>
#include <math.h>

static int is_counted(const texopt_mesh *mesh, size_t t)
{
    return !(mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV));
}

/* Twice the signed texel area of triangle t in `texel`. */
static double doubled_signed_area(const double *texel, const uint32_t *tri)
{
    const double *p0 = texel + 2 * (size_t)tri[0];
    const double *p1 = texel + 2 * (size_t)tri[1];
    const double *p2 = texel + 2 * (size_t)tri[2];
    return (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]);
}

size_t texopt_count_flipped(const texopt_mesh *mesh, const double *texel)
{
    if (!mesh)
        return 0;
    if (!texel)
        texel = mesh->texel;
    size_t flipped = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (!is_counted(mesh, t))
            continue;
        const uint32_t *tri = mesh->triangle + 3 * t;
        double before = doubled_signed_area(mesh->texel, tri);
        double after = doubled_signed_area(texel, tri);
        /* det grad_phi = after / before; a NaN position also counts as a flip. */
        if (!(after / before > 0.0))
            flipped++;
    }
    return flipped;
}

void texopt_layout_edges(const double *layout, const uint32_t tri[3], double T[2][2])
{
    const double *p0 = layout + 2 * (size_t)tri[0];
    const double *p1 = layout + 2 * (size_t)tri[1];
    const double *p2 = layout + 2 * (size_t)tri[2];
    for (int r = 0; r < 2; r++) {
        T[r][0] = p1[r] - p0[r];
        T[r][1] = p2[r] - p0[r];
    }
}

void texopt_jacobian(const double T[2][2], const double P[2][2], double scale, double J[2][2])
{
    double det_p = P[0][0] * P[1][1] - P[0][1] * P[1][0];
    double inv[2][2] = {{P[1][1] / det_p, -P[0][1] / det_p}, {-P[1][0] / det_p, P[0][0] / det_p}};
    for (int r = 0; r < 2; r++)
        for (int c = 0; c < 2; c++)
            J[r][c] = scale * (T[r][0] * inv[0][c] + T[r][1] * inv[1][c]);
}

void texopt_triangle_distortion_of(const double J[2][2], texopt_triangle_distortion *out)
{
    double frob = J[0][0] * J[0][0] + J[0][1] * J[0][1] + J[1][0] * J[1][0] + J[1][1] * J[1][1];
    double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    if (!(det > 0.0)) {
        double inf = INFINITY;
        *out = (texopt_triangle_distortion){inf, 0.0, inf, inf, inf, inf, inf, inf, inf, inf};
        return;
    }
    /* 2x2 singular values: smax^2 + smin^2 = |J|_F^2 and smax * smin = det. */
    double root = sqrt(fmax(0.0, frob * frob - 4.0 * det * det));
    double smax = sqrt(0.5 * (frob + root)), smin = det / smax;
    out->sigma_max = smax;
    out->sigma_min = smin;
    out->conformal = smax / smin;
    out->mips = smax / smin + smin / smax;
    out->isometric = sqrt(smax * smax + 1.0 / (smin * smin));
    out->max_isometric = fmax(smax, 1.0 / smin);
    out->area = fmax(det, 1.0 / det);
    /* For 2x2, |J^-1|_F^2 = |J|_F^2 / det^2. */
    out->symmetric_dirichlet = frob + frob / (det * det);
    out->l2_stretch = sqrt(0.5 * (1.0 / (smin * smin) + 1.0 / (smax * smax)));
    out->linf_stretch = 1.0 / smin;
}

/* The metrics and their accumulation over a layout, in one place. */
enum { METRICS = 8 };

static void metric_values(const texopt_triangle_distortion *d, double v[METRICS])
{
    double all[METRICS] = {
        d->symmetric_dirichlet,        d->conformal,   d->mips, d->isometric, d->max_isometric, d->area,
        d->l2_stretch * d->l2_stretch, d->linf_stretch};
    for (int k = 0; k < METRICS; k++)
        v[k] = all[k];
}

static void store_metrics(texopt_distortion *out, const double mean[METRICS], const double max[METRICS])
{
    texopt_distortion_stat *stat[METRICS] = {
        NULL,       &out->conformal,  &out->mips,        &out->isometric, &out->max_isometric,
        &out->area, &out->l2_stretch, &out->linf_stretch};
    out->symmetric_dirichlet = mean[0];
    out->max_symmetric_dirichlet = max[0];
    for (int k = 1; k < METRICS; k++)
        *stat[k] = (texopt_distortion_stat){mean[k], max[k]};
    /* Sander's L2 norm is the root of the mean squared stretch. */
    out->l2_stretch.mean = sqrt(mean[6]);
    out->l2_stretch.max = sqrt(max[6]);
}

texopt_status texopt_distortion_measure(const texopt_mesh *mesh, const double *texel, texopt_distortion *out, char *err,
                                        size_t err_len)
{
    if (!mesh || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "distortion: NULL mesh or output");
    if (!texel)
        texel = mesh->texel;
    for (size_t i = 0; i < 2 * mesh->vertex_count; i++)
        if (!isfinite(texel[i]))
            return texopt_fail(err, err_len, TEXOPT_E_NUMERIC,
                               "distortion: texel coordinate of vertex %zu is not finite", i / 2);

    double area_3d = 0.0, area_texel = 0.0;
    size_t counted = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (!is_counted(mesh, t))
            continue;
        area_3d += mesh->area_3d[t];
        area_texel += 0.5 * fabs(doubled_signed_area(texel, mesh->triangle + 3 * t));
        counted++;
    }
    if (counted == 0 || !(area_3d > 0.0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "distortion: the mesh has no non-degenerate triangle");
    if (!(area_texel > 0.0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "distortion: the layout has zero texel area");

    /* Uniform scale making total texel area equal total 3D area: resolution is not distortion. */
    double scale = sqrt(area_3d / area_texel);
    double mean[METRICS] = {0}, max[METRICS] = {0};
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (!is_counted(mesh, t))
            continue;
        const uint32_t *tri = mesh->triangle + 3 * t;
        double T[2][2], P[2][2], J[2][2];
        texopt_layout_edges(texel, tri, T);
        texopt_mesh_plane_edges(mesh, t, P);
        texopt_jacobian(T, P, scale, J);
        if (J[0][0] * J[1][1] - J[0][1] * J[1][0] < 0.0) {
            /* The plane frame has no orientation relative to texel space: mirror it. */
            J[1][0] = -J[1][0];
            J[1][1] = -J[1][1];
        }
        texopt_triangle_distortion d;
        texopt_triangle_distortion_of(J, &d);
        double v[METRICS];
        metric_values(&d, v);
        for (int k = 0; k < METRICS; k++) {
            mean[k] += mesh->area_3d[t] * v[k] / area_3d;
            max[k] = fmax(max[k], v[k]);
        }
    }
    out->counted = counted;
    out->flipped = texopt_count_flipped(mesh, texel);
    if (out->flipped)
        for (int k = 0; k < METRICS; k++)
            mean[k] = max[k] = INFINITY;
    store_metrics(out, mean, max);
    return TEXOPT_OK;
}

static void add_stat(cJSON *o, const char *name, texopt_distortion_stat s)
{
    cJSON *m = cJSON_AddObjectToObject(o, name);
    if (!m)
        return;
    /* JSON has no infinity: a flipped layout's metrics are null. */
    if (isfinite(s.mean))
        cJSON_AddNumberToObject(m, "mean", s.mean);
    else
        cJSON_AddNullToObject(m, "mean");
    if (isfinite(s.max))
        cJSON_AddNumberToObject(m, "max", s.max);
    else
        cJSON_AddNullToObject(m, "max");
}

cJSON *texopt_distortion_json(const texopt_distortion *d)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddNumberToObject(o, "counted", (double)d->counted);
    cJSON_AddNumberToObject(o, "flipped", (double)d->flipped);
    add_stat(o, "symmetric_dirichlet", (texopt_distortion_stat){d->symmetric_dirichlet, d->max_symmetric_dirichlet});
    add_stat(o, "conformal", d->conformal);
    add_stat(o, "mips", d->mips);
    add_stat(o, "isometric", d->isometric);
    add_stat(o, "max_isometric", d->max_isometric);
    add_stat(o, "area", d->area);
    add_stat(o, "l2_stretch", d->l2_stretch);
    add_stat(o, "linf_stretch", d->linf_stretch);
    return o;
}

/* distortion.c - symmetric Dirichlet distortion of a layout and flip counting.
 *
 * Implements the distortion measure of Sun et al. 2022 (eq. 24), the symmetric Dirichlet
 * energy of Smith and Schaefer 2015, "Bijective parameterization with free boundaries":
 * |J|_F^2 + |J^-1|_F^2 per triangle, area-weighted over the surface. It does not optimise
 * anything; meshwise.c and the evaluation call it on finished layouts. */
#include "distortion.h"

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

/* |J|^2 + |J^-1|^2 for J = scale * T P^-1; +inf when the texel triangle collapsed. The
 * frame of P has an arbitrary orientation, so only |det J| matters here (flips are judged
 * against the input layout by texopt_count_flipped). */
static double symmetric_dirichlet(const double T[2][2], const double P[2][2], double scale)
{
    double det_p = P[0][0] * P[1][1] - P[0][1] * P[1][0];
    double inv[2][2] = {{P[1][1] / det_p, -P[0][1] / det_p}, {-P[1][0] / det_p, P[0][0] / det_p}};
    double J[2][2];
    for (int r = 0; r < 2; r++)
        for (int c = 0; c < 2; c++)
            J[r][c] = scale * (T[r][0] * inv[0][c] + T[r][1] * inv[1][c]);
    double frob = J[0][0] * J[0][0] + J[0][1] * J[0][1] + J[1][0] * J[1][0] + J[1][1] * J[1][1];
    double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    if (det == 0.0)
        return INFINITY;
    /* For 2x2, |J^-1|_F^2 = |J|_F^2 / det^2. */
    return frob + frob / (det * det);
}

static void texel_edges(const double *texel, const uint32_t *tri, double T[2][2])
{
    const double *p0 = texel + 2 * (size_t)tri[0];
    const double *p1 = texel + 2 * (size_t)tri[1];
    const double *p2 = texel + 2 * (size_t)tri[2];
    for (int r = 0; r < 2; r++) {
        T[r][0] = p1[r] - p0[r];
        T[r][1] = p2[r] - p0[r];
    }
}

texopt_status texopt_distortion_measure(const texopt_mesh *mesh, const double *texel,
                                        texopt_distortion *out, char *err, size_t err_len)
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
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "distortion: the layout has zero texel area");

    /* Uniform scale making total texel area equal total 3D area: resolution is not distortion. */
    double scale = sqrt(area_3d / area_texel);
    double weighted = 0.0, worst = 0.0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (!is_counted(mesh, t))
            continue;
        const uint32_t *tri = mesh->triangle + 3 * t;
        double T[2][2], P[2][2];
        texel_edges(texel, tri, T);
        texopt_mesh_plane_edges(mesh, t, P);
        double e = symmetric_dirichlet(T, P, scale);
        weighted += mesh->area_3d[t] * e;
        if (e > worst)
            worst = e;
    }
    out->counted = counted;
    out->flipped = texopt_count_flipped(mesh, texel);
    out->symmetric_dirichlet = out->flipped ? INFINITY : weighted / area_3d;
    out->max_symmetric_dirichlet = out->flipped ? INFINITY : worst;
    return TEXOPT_OK;
}

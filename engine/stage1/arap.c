/* arap.c - isometric (ARAP, Liu et al. 2008) targets for the mesh-wise solver; see arap.h.
 *
 * Per triangle: the 3D edges in a 2D frame of the triangle's plane, the input texel edges,
 * J = s P T^-1, S = sqrt(J^T J) by the closed-form 2x2 symmetric eigen-decomposition.
 * Does not: solve (meshwise.c does, with these targets and wR = 0). */
#include "arap.h"

#include <math.h>
#include <string.h>

static int counted(const texopt_mesh *mesh, size_t t)
{
    return !(mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV));
}

static void isometric_target(const texopt_mesh *mesh, size_t t, double scale, texopt_triangle_target *g)
{
    const uint32_t *v = mesh->triangle + 3 * t;
    const double *p0 = mesh->texel + 2 * (size_t)v[0], *p1 = mesh->texel + 2 * (size_t)v[1],
                 *p2 = mesh->texel + 2 * (size_t)v[2];
    double T[2][2] = {{p1[0] - p0[0], p2[0] - p0[0]}, {p1[1] - p0[1], p2[1] - p0[1]}};
    double det = T[0][0] * T[1][1] - T[0][1] * T[1][0];
    double P[2][2];
    if (!(fabs(det) > 0) || texopt_mesh_plane_edges(mesh, t, P) != 0)
        return;
    P[1][1] *= det < 0 ? -1.0 : 1.0; /* mirrored like the texel triangle */
    double Ti[2][2] = {{T[1][1] / det, -T[0][1] / det}, {-T[1][0] / det, T[0][0] / det}};
    double J[2][2];
    for (int r = 0; r < 2; r++)
        for (int c = 0; c < 2; c++)
            J[r][c] = scale * (P[r][0] * Ti[0][c] + P[r][1] * Ti[1][c]);
    /* S = sqrt(J^T J): the eigenvectors of J^T J and the square roots of its eigenvalues. */
    double JtJ[3] = {J[0][0] * J[0][0] + J[1][0] * J[1][0], J[0][0] * J[0][1] + J[1][0] * J[1][1],
                     J[0][1] * J[0][1] + J[1][1] * J[1][1]};
    double mu1, mu2, theta;
    texopt_sym2_eigen(JtJ, &mu1, &mu2, &theta);
    texopt_target_set_stretch(g, theta, sqrt(mu1), sqrt(mu2));
    g->w_stretch = 1;
}

texopt_status texopt_arap_targets(const texopt_mesh *mesh, texopt_triangle_target *targets, char *err, size_t err_len)
{
    if (!mesh || !targets)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "arap: missing argument");
    double texel_area = 0, area_3d = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (counted(mesh, t)) {
            texel_area += fabs(mesh->area_texel[t]);
            area_3d += mesh->area_3d[t];
        }
    if (!(texel_area > 0 && area_3d > 0) || !isfinite(texel_area) || !isfinite(area_3d))
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "domain %d has no triangle with both 3D and texel area",
                           mesh->domain);
    double scale = sqrt(texel_area / area_3d);
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        texopt_triangle_target *g = &targets[t];
        memset(g, 0, sizeof *g);
        g->lambda1 = g->lambda2 = 1;
        if (counted(mesh, t))
            isometric_target(mesh, t, scale, g);
    }
    return TEXOPT_OK;
}

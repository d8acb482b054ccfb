/* target_restate.c - targets restated for another layout (target_restate.h). */
#include "target_restate.h"

#include <math.h>
#include <string.h>

#include "texel_map.h"
#include "triloss.h"

#define QUARTER_TURN 1.57079632679489661923

/* The texel triangle t of mesh (rows: corners). */
static void texel_triangle(const texopt_mesh *mesh, size_t t, double tri[3][2])
{
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 2; a++)
            tri[k][a] = mesh->texel[2 * (size_t)mesh->triangle[3 * t + (size_t)k] + (size_t)a];
}

/* g's rotation and stretch from M = R S (polar; S = sqrt(M^T M) when M mirrors, rotation
 * weight dropped). */
static void set_target(texopt_triangle_target *g, const double M[4])
{
    double det = M[0] * M[3] - M[1] * M[2];
    double c = 1, s = 0;
    if (det > 0) {
        c = M[0] + M[3];
        s = M[2] - M[1];
        double len = hypot(c, s);
        c /= len;
        s /= len;
    } else
        g->w_rotation = 0;
    /* S = R^T M when det > 0; else M^T M's square root through its eigen-decomposition. */
    double mu1, mu2, theta;
    if (det > 0) {
        double S[3] = {c * M[0] + s * M[2], c * M[1] + s * M[3], -s * M[1] + c * M[3]};
        texopt_sym2_eigen(S, &mu1, &mu2, &theta);
    } else {
        double MtM[3] = {M[0] * M[0] + M[2] * M[2], M[0] * M[1] + M[2] * M[3], M[1] * M[1] + M[3] * M[3]};
        texopt_sym2_eigen(MtM, &mu1, &mu2, &theta);
        mu1 = sqrt(mu1);
        mu2 = sqrt(mu2);
    }
    double alpha = fmod(atan2(s, c), QUARTER_TURN);
    g->alpha = alpha < 0 ? alpha + QUARTER_TURN : alpha;
    texopt_target_set_stretch(g, theta, fmax(mu1, 1e-9), fmax(mu2, 1e-9));
}

/* Whether triangle t has the same corners in both layouts. */
static int unmoved(const double from[3][2], const double to[3][2])
{
    return memcmp(from, to, 6 * sizeof(double)) == 0;
}

void texopt_targets_restate(const texopt_mesh *in, const texopt_mesh *out, texopt_triangle_target *targets)
{
    const uint8_t degenerate = TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV;
    for (size_t t = 0; targets && t < in->triangle_count; t++) {
        if ((in->flags[t] & degenerate) || (out->flags[t] & degenerate))
            continue;
        double from[3][2], to[3][2], m[4], J[4], M[4];
        texel_triangle(in, t, from);
        texel_triangle(out, t, to);
        if (unmoved(from, to) || !texopt_texel_map(from, to, m, NULL))
            continue;
        texopt_jacobian_from_params(targets[t].alpha, targets[t].lambda1, targets[t].lambda2, targets[t].beta, J);
        M[0] = J[0] * m[0] + J[1] * m[2];
        M[1] = J[0] * m[1] + J[1] * m[3];
        M[2] = J[2] * m[0] + J[3] * m[2];
        M[3] = J[2] * m[1] + J[3] * m[3];
        set_target(&targets[t], M);
    }
}

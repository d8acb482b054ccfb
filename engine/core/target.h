/* target.h - what a per-triangle stage hands the mesh-wise stage.
 *
 * For each triangle a target Jacobian J = R(alpha) V(beta) diag(lambda1, lambda2) V(beta)^T
 * of the deformation from input texels to output texels, and how much the triangle's loss
 * cares about rotation (w_rotation, wR of the paper's eq. 17) and about stretch (w_stretch,
 * wS). The perceptual stage (triopt) fills every field; the baselines (ssp, tewari, arap)
 * fill the Jacobian with w_rotation = 0. Degenerate triangles get J = I and zero weights. */
#ifndef TEXOPT_TARGET_H
#define TEXOPT_TARGET_H

#include <stddef.h>

typedef struct texopt_triangle_target {
    double alpha;   /* rotation, [0, pi/2) */
    double lambda1; /* singular values, (lambda_min, 1] for the perceptual stage */
    double lambda2;
    double beta; /* orientation of the stretch axes, [0, pi/2) */
    double loss; /* perceptual loss E at the optimum (0 where not computed) */
    double w_rotation;
    double w_stretch;
    int evaluations; /* loss evaluations spent on this triangle */
} texopt_triangle_target;

/* Eigen-decomposition of the symmetric 2x2 matrix [[m0, m1], [m1, m2]]: eigenvalues
 * mu1 >= mu2 (clamped at 0) and the direction theta in [0, pi) of mu1's eigenvector. */
void texopt_sym2_eigen(const double m[3], double *mu1, double *mu2, double *theta);

/* Sets beta, lambda1, lambda2 of g for the scale `along` in direction theta in [0, pi) and
 * `across` perpendicular to it (beta folded into [0, pi/2), the scales swapped past it). */
void texopt_target_set_stretch(texopt_triangle_target *g, double theta, double along, double across);

/* Raises the targets whose area scale lambda1 lambda2 is below k^2 times floor_targets' to k
 * times their singular values along their axes (beta), keeping their rotation and weights; k in
 * (0, 1]. Returns how many were raised. */
size_t texopt_targets_raise_to_floor(texopt_triangle_target *targets, const texopt_triangle_target *floor_targets,
                                     size_t count, double k);

#endif

/* arap.h - isometric baseline targets: the as-rigid-as-possible layout of Liu, Zhang, Xu,
 * Gotsman and Gortler 2008, "A Local/Global Approach to Mesh Parameterization", expressed as
 * targets for the mesh-wise solver (meshwise.h) so that no second solver exists.
 *
 * ARAP asks every triangle's layout to be a rotation of its 3D shape (at one global scale).
 * In the solver's terms the Jacobian G_i from the input texel triangle to the new one should
 * be R_i S_i with R_i free (wR = 0) and S_i the symmetric stretch that turns the input texel
 * triangle into a copy of the 3D triangle: with J_i = s P_i T_i^-1 (P_i the 3D edges in the
 * triangle's own plane, T_i the input texel edges, s^2 = total texel area / total 3D area so
 * the cost stays the input's), S_i = (J_i^T J_i)^(1/2) = V(beta) diag(l1, l2) V(beta)^T.
 * Mirrored input triangles use the mirrored plane frame, so J_i keeps det > 0 like the
 * solver's G. The mesh-wise local step then picks R_i by polar decomposition and the global
 * step is the ARAP solve: the stand-in for isometric methods such as OptCuts (Sun et al.
 * 2022, section 5), with the input's cuts.
 *
 * Does not: solve, pack or bake; know about the texture (it is geometry only). */
#ifndef TEXOPT_ARAP_H
#define TEXOPT_ARAP_H

#include "mesh.h"
#include "status.h"
#include "target.h"

/* Isometric targets for every triangle of mesh (alpha = 0, w_rotation = 0, w_stretch = 1;
 * degenerate triangles J = I with zero weights). lambda1, lambda2 are not clamped: a region
 * the input squeezed gets lambda > 1. Fails when no triangle has both 3D and texel area. */
texopt_status texopt_arap_targets(const texopt_mesh *mesh, texopt_triangle_target *targets, char *err, size_t err_len);

#endif

/* meshwise.h - stage 2: the mesh-wise local-global solve for new texel positions.
 *
 * Implements the mesh-wise optimisation of Sun et al. 2022, "Efficient Texture
 * Parameterization Driven by Perceptual-Loss-on-Screen" (section 4.2, eq. 19 and 28,
 * appendix B), with the locally injective barrier of Schueller, Kavan, Panozzo and
 * Sorkine-Hornung 2013. It turns the per-triangle targets of stage 1 (target.h) into one
 * conforming layout: same cuts, same charts, seams stay split.
 *
 * The energy, for the Jacobian G_i = grad phi_i of triangle i relative to its INPUT texel
 * triangle (so the unchanged layout has G_i = I and det G_i = +1 everywhere, mirrored input
 * charts included), summed with the input texel area a_i of each triangle:
 *
 *   E = sum_i a_i ( w_rs |G_i - R_i S_i|^2 + w_R,i |R_i - Rbar_i R(k_i pi/2)|^2
 *                   + w_S,i |S_i - Sbar_i|^2 ) + w_b sum_i a_i B(det G_i)
 *
 * with Rbar = R(alpha), Sbar = V(beta) diag(lambda1, lambda2) V(beta)^T from the target.
 * Local step (per triangle, exact block minimisation, so E never increases): k_i from the
 * closest of Rbar R(k pi/2) to R_i; R_i = closest rotation (2x2 polar) of
 * w_R Rbar R^k + w_rs G_i S_i; S_i = (w_S Sbar + w_rs sym(R_i^T G_i)) / (w_S + w_rs).
 * Global step: one damped Newton step on the new texel positions, a line search whose
 * largest step keeps every determinant > 0; w_b /= 20 whenever the fitting part falls below
 * the barrier part (eq. 28). The Newton matrix is the constant fitting Hessian plus the u
 * and v blocks of the barrier's Gauss-Newton term: two n x n sparse systems (CHOLMOD:
 * symbolic analysis once, numeric factorisation only while a barrier is active).
 * B(d) = 1/g(d/s) - 1 below the threshold s = 0.5 lambda1 lambda2 (at most 0.5), 0 above,
 * g(t) = t^3 - 3t^2 + 3t (Schueller et al.): it costs nothing until a triangle is squeezed
 * to half the area its target asks for.
 *
 * Choices the paper leaves open (documented in meshwise.c):
 *  - Translation: one vertex per chart (the first vertex of its first triangle with a texel
 *    area) is pinned at its starting position: exact, no bias. Vertices used only by
 *    degenerate-UV triangles stay where they start.
 *  - Weights: w_R and w_S are divided by the mean w_S of the counted triangles (or mean w_R
 *    when every w_S is 0), so their ratios follow stage 1 while their absolute size (a
 *    variance of a loss, ~1e-4) does not vanish against w_rs; all-ones weights stay ones.
 *    The normalised w_S is at least 1 (the mean), so a triangle whose loss ignores its
 *    stretch (flat colour, variance 0) still moves toward its (area-driven) target; lower
 *    floors measured worse (meshwise.c, BENCHMARKS.md@9f788a8). w_R has no floor.
 *  - Degenerate triangles (TEXOPT_TRI_DEGENERATE_3D/UV) add no fitting energy; those with a
 *    non-zero input texel area still carry the barrier, so they never flip either. Their
 *    vertices move with their neighbours. A COLLAPSED triangle (degenerate in UV, not in
 *    3D: a face an exporter mapped to one texel line) has a singular input Jacobian, so
 *    nothing above holds its shape: it is tied (like a fold's minority vertex, same
 *    stiffness) to stay on a line, the corner opposite its longest input edge held at its
 *    fraction along that edge. Its corners are unknowns (never a chart's pin), so a line
 *    between two parts of a chart follows them as one, and its image stays (near) zero
 *    area inside its chart instead of opening over other texels.
 *
 * Overlapping / mirrored input charts (Duck, DamagedHelmet):
 *  - Separate charts that overlap (mirrored or repeated parts cut apart): kept shared when
 *    the caller passes their sharing groups (opt->share, texel_share.h: a chart whose texels
 *    lie mostly on a larger one's). The group is pinned once, coincident vertices share an
 *    unknown, and every vertex of a secondary is tied like a fold's minority vertex to the
 *    point of the primary triangle it lay on in the input, whatever the orientations and
 *    tessellations: one compromise deformation for both surface places, paid for once.
 *    Without opt->share each chart is solved on its own.
 *  - Folded charts (mirrored halves joined along a fold line inside one chart; Duck has 2,
 *    DamagedHelmet 25): kept shared. Vertices of one chart at bit-identical input (and
 *    starting) texel positions share one unknown, so the halves keep lying exactly on each
 *    other with one compromise deformation. Where the halves are tessellated differently
 *    (Duck), every vertex used only by the minority-orientation side is tied (stiff
 *    quadratic penalty, 100x the mean fitting curvature) to the point of the majority-side
 *    triangle it lay on in the input. Otherwise the halves would drift apart while still
 *    overlapping near the fold, and one output texel would have to show two different
 *    input texels (the packer cannot separate the halves of one chart).
 *
 * Not here: the perceptual targets (stage 1), packing and scaling to the budget (the
 * output layout is in texel units of the input frame, not yet packed), re-baking, the loss
 * of each triangle under the result (meshwise_loss.h: share with E <= eps, paper Fig. 16). */
#ifndef TEXOPT_MESHWISE_H
#define TEXOPT_MESHWISE_H

#include <stddef.h>

#include "mesh.h"
#include "monitor.h"
#include "status.h"
#include "target.h"
#include "texel_share.h"

#define TEXOPT_MESHWISE_MAX_REPORTED 256

typedef struct texopt_meshwise_options {
    int max_iterations;    /* local-global iterations; 0 -> 50 */
    double tolerance;      /* stop when the relative energy change falls below; 0 -> 1e-4 */
    double barrier_weight; /* initial w_b; 0 -> 1.0 (barrier is 0 above its threshold) */
    int threads;           /* >= 2: the u and v Newton systems factorise in parallel; 0 -> 1 */
    double fit_weight;     /* w_rs of eq. 19; 0 -> 1.0 */
    /* Optional sharing groups of this mesh (texel_share.h): each group is pinned once (on
     * its primary), its coincident vertices share unknowns and the secondaries' vertices
     * are tied to their primary's triangles like a fold's minority side. NULL: every chart
     * alone. */
    const texopt_texel_share *share;
    /* Optional scaffold (layout/scaffold.h): triangles filling the space around charts, so
     * that the barrier keeps charts from crossing one another or themselves. NULL: none. */
    const struct texopt_meshwise_scaffold *scaffold;
} texopt_meshwise_options;

/* Extra triangles solved with the mesh's: corners are mesh vertices (index < mesh
 * vertex_count) or extra vertices (index mesh vertex_count + i), which stay at position[].
 * Each is fitted to its rest shape as-rigidly-as-possible (w_R 0, w_S 1, target I) with
 * the barrier, its energy scaled by weight, relative to the rest shape rest[6 t .. 6 t + 6)
 * (the corners' positions when the scaffold was built: det G starts at 1). */
typedef struct texopt_meshwise_scaffold {
    size_t vertex_count;
    const double *position; /* 2 per extra vertex */
    size_t triangle_count;
    const uint32_t *triangle; /* 3 per triangle */
    const double *rest;       /* 6 per triangle */
    double weight;            /* > 0 */
} texopt_meshwise_scaffold;

typedef struct texopt_meshwise_report {
    int iterations;        /* local-global iterations run */
    double energy_initial; /* E after the first local step on the initial layout */
    double energy_final;
    double seconds;                              /* wall clock of the whole solve */
    int flipped;                                 /* triangles with det G <= 0 after the solve: always 0 on success */
    double energy[TEXOPT_MESHWISE_MAX_REPORTED]; /* E after iteration i + 1 (non-increasing),
                                                    the first 256 iterations */
    int energy_count;
    double barrier_weight_final; /* w_b after the eq. 28 reductions */
    int factorizations;          /* numeric CHOLMOD factorisations done */
    int merged_vertices;         /* vertices sharing the unknown of a coincident one (folds) */
    int fold_ties;               /* minority-side fold vertices tied to the majority side */
    int shared_ties;             /* secondary vertices tied to their primary (opt->share) */
    int collapse_ties;           /* ties holding collapsed triangles on a line (see above) */
} texopt_meshwise_report;

/* Computes new texel positions of every mesh vertex (2 per vertex, texel units of the input
 * frame) into texel_out[0 .. 2 * mesh->vertex_count). targets has mesh->triangle_count
 * entries. initial_texel: the starting layout (NULL = mesh->texel); it must have no
 * triangle with det G <= 0 relative to mesh->texel (else TEXOPT_E_INVALID_ARGUMENT).
 * opt and report may be NULL. The monitor gets stage "stage2" progress per iteration and is
 * checked for cancellation between iterations. Returns TEXOPT_E_NUMERIC when CHOLMOD fails
 * or values become non-finite. texel_out is written only on success. */
texopt_status texopt_meshwise_solve(const texopt_mesh *mesh, const texopt_triangle_target *targets,
                                    const double *initial_texel, const texopt_meshwise_options *opt, double *texel_out,
                                    texopt_meshwise_report *report, const texopt_monitor *monitor, char *err,
                                    size_t err_len);

#endif

/* target_allocation.h - spends a texel budget over the triangles before the mesh-wise stage.
 *
 * Stage 1 (and the baselines) give each triangle a target Jacobian whose singular values say
 * how much it may shrink at one fixed loss threshold; their total area is whatever it is
 * (on Fox about 3% of the input). Scaling the solved layout uniformly to the budget would
 * then magnify triangles that were already at input density far above it, which buys
 * nothing: the input texture has no detail beyond its own texels. Here the targets are
 * rescaled before stage 2 instead ("water-filling"): every singular value is multiplied by
 * one factor s and capped at 1 (input density), with s chosen so that the targets' total
 * texel area, sum a_i lambda1' lambda2', equals the requested area (cap: 1 unless the
 * options say otherwise). Triangles at the cap
 * keep the input's density; the budget that a uniform scale would have wasted on them goes
 * to the others. When the request is at least the whole input area, every target is the
 * identity scale (J's rotation is kept).
 *
 * Option slow_lossless (perceptual targets): triangles whose stage-1 optimum lost nothing
 * (loss <= lossless_loss, e.g. flat colour at lambda_min) grow by s^lossless_growth instead
 * of s: more texels cannot improve a look that is already exact, so the budget goes where
 * the loss is (a step towards equal marginal loss, DESIGN.md 3.2). Growth 0 keeps them as
 * they are; that measured worse at large budgets (BENCHMARKS.md@9f788a8 "Quality"): stage 1 judges
 * a triangle with its whole one-ring shrunk alike, not next to neighbours at full density.
 *
 * The allocation fixes areas only approximately: stage 2 trades the targets against one
 * conforming layout and packing adds its own loss, so budget.h still scales the solved
 * layout to the exact cost; that factor is reported to show how small it has become.
 * Does not: solve the layout (meshwise.h), pack (budget.h), or change rotations and weights. */
#ifndef TEXOPT_ALLOCATE_H
#define TEXOPT_ALLOCATE_H

#include "mesh.h"
#include "status.h"
#include "target.h"

typedef struct texopt_allocate_options {
    int slow_lossless;      /* non-zero: targets with loss <= lossless_loss grow slower */
    double lossless_loss;   /* with slow_lossless; e.g. 1e-6 */
    double cap;             /* largest singular value allowed; 0 -> 1 (input density) */
    double lossless_growth; /* with slow_lossless: lossless targets are scaled by
                               s^lossless_growth (0: kept as they are) */
    /* May be NULL (every triangle pays for its texels): per triangle, the share of its texel
     * area it pays for, a_i above becoming paid[i] a_i. Triangles lying on texels that others
     * pay for (a fold's minority side, a sharing group's secondaries: texel_share.h) pay 0,
     * so that the areas add up to covered texels, which is what the budget counts. They are
     * still scaled like the others. */
    const double *paid;
} texopt_allocate_options;

typedef struct texopt_allocation {
    double scale;          /* the common factor s on the singular values */
    double area_requested; /* texels asked for */
    double area_allocated; /* sum of a_i lambda1' lambda2' (equals the request unless it is
                              past what the caps allow) */
    double area_input;     /* sum of a_i over the counted triangles */
    size_t capped;         /* triangles with at least one singular value at the cap */
    size_t lossless;       /* triangles scaled as lossless (slow_lossless) */
} texopt_allocation;

/* Writes to out (mesh->triangle_count entries; may equal in) the targets in rescaled to a
 * total texel area of area_requested (> 0). a_i is |mesh->area_texel| (times opt->paid[i]
 * when given); degenerate triangles are copied unchanged. opt and report may be NULL. */
texopt_status texopt_allocate_targets(const texopt_mesh *mesh, const texopt_triangle_target *in, double area_requested,
                                      const texopt_allocate_options *opt, texopt_triangle_target *out,
                                      texopt_allocation *report, char *err, size_t err_len);

/* The targets' total texel area as allocated above: sum a_i lambda1 lambda2 over the counted
 * triangles, a_i times paid[i] when paid is not NULL. */
double texopt_targets_area(const texopt_mesh *mesh, const texopt_triangle_target *targets, const double *paid);

/* Closed-loop reallocation from what the screen shows (Sun et al. 2022's principle, the
 * perceptual loss on screen, applied to the whole mesh; job_refine.c iterates it). error[t]
 * (mesh->triangle_count entries, >= 0) is triangle t's on-screen error under the layout that
 * the targets in produced (evaluate.h triangle_error; the base-colour refinement reads
 * its triangle_error_edges measure). Each triangle's target area is
 * multiplied by ((e_t + f) / (e_mean + f))^gamma, clamped to [step_min, step_max], where
 * e_mean is the mean error weighted by 3D area (pixels seen) and f = 0.05 e_mean keeps an
 * error-free triangle from vanishing in one step; singular values are scaled by the square
 * root (anisotropy, orientation and rotation kept); then everything is rescaled to
 * area_requested with singular values capped at cap (texopt_allocate_targets): triangles
 * the screen shows as lossy may go above input density, where the re-bake and the
 * renderer's bilinear lookups blur less. With all errors 0 the targets are only rescaled. */
typedef struct texopt_reallocate_options {
    double gamma;              /* > 0 */
    double step_min, step_max; /* 0 < step_min <= 1 <= step_max */
    double cap;                /* > 0 */
    const double *paid;        /* as texopt_allocate_options.paid; may be NULL */
} texopt_reallocate_options;

texopt_status texopt_reallocate_by_error(const texopt_mesh *mesh, const texopt_triangle_target *in, const double *error,
                                         double area_requested, const texopt_reallocate_options *opt,
                                         texopt_triangle_target *out, texopt_allocation *report, char *err,
                                         size_t err_len);

#endif

/* distortion_reduce.h - a packed atlas's charts pulled back toward a reference layout's
 * shapes inside a fixed box (Liu et al. 2019, "Atlas Refinement with Bounded Packing
 * Efficiency", section 3.3, Algorithm 2).
 *
 * The refinement (atlas_refine.h) bends charts toward axis-aligned shapes, cuts and packs
 * them; this step lets them return toward the shapes of the unrefined layout (the
 * reference, which carries stage 2's texel allocation: the paper's 3.4 "distortion relative
 * to the input atlas") without giving the packing back. Algorithm 2: the atlas is scaled by
 * s = sqrt(min over charts of reference area / chart area), so every chart holds at most
 * its reference area and may grow; a box delta times the atlas's bounding box (centred on
 * it) is fixed; then rounds of stage 2 (meshwise.h, each triangle's target its reference
 * Jacobian relative to the mesh's input texels, w_stretch 1, w_rotation 0: a rotation
 * target fights the turns the refinement gave the charts, which the box does not let
 * them undo) with scaffold triangles filling that box (scaffold.h, one fixed
 * box: no triangle flips, no chart crosses another or leaves the box), the box grown by
 * delta_step of its size after each round, until the distortion changes by less than
 * `tolerance` relatively or reaches the reference's (1). The energy minimised is stage 2's
 * fit to the reference Jacobians (as-rigid-as-possible to the reference shape, a
 * customised energy as 3.4 allows, with the anti-flip barrier), the distortion reported and
 * tested the symmetric Dirichlet energy relative to the reference up to scale. A round whose packing
 * efficiency (chart area over the atlas's bounding box) falls below min_efficiency, and
 * below the round before's, is undone and ends the reduction: the paper's bound, as a stop
 * rather than a barrier (a start short of the bound, which the paper's never is, may gain
 * but not lose).
 * Charts one box cannot hold without overlap at the start (a chart over itself, a fold,
 * mirrored halves) are left out of it: moved right of the box and solved without scaffold
 * (report->charts_unboxed; the box, the scale and the efficiencies are the other charts').
 * Refused (out = start, report->refused): a start the box still cannot scaffold (charts
 * over one another, not manifold), a start with a triangle reversed relative to the mesh's
 * input texels, no chart to box. Charts pressed together until a re-mesh makes a
 * scaffold triangle without area end the reduction at the last round (stage 2 refuses
 * such a start, or its factorisation fails).
 * With a gap, each chart first gets the paper's gap layer ("Gaps between charts",
 * gap_layer.h), solved as part of it and dropped at the end, so charts stay apart (the
 * layers are squeezed as the charts are: measure the gap, chart_gap.h); without, charts may
 * come to touch, and a caller that needs gutters packs again.
 * Does not: cut, or pack into a texture. */
#ifndef TEXOPT_DISTORTION_REDUCE_H
#define TEXOPT_DISTORTION_REDUCE_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "monitor.h"
#include "status.h"

/* The paper's delta, Delta delta and stop tolerance. */
#define TEXOPT_REDUCE_DELTA 1.005
#define TEXOPT_REDUCE_DELTA_STEP 0.005
#define TEXOPT_REDUCE_TOLERANCE 1e-4

typedef struct texopt_distortion_reduce_options {
    double delta;          /* 0 -> TEXOPT_REDUCE_DELTA */
    double delta_step;     /* 0 -> TEXOPT_REDUCE_DELTA_STEP */
    double tolerance;      /* 0 -> TEXOPT_REDUCE_TOLERANCE */
    int max_rounds;        /* 0 -> 30 */
    int round_iterations;  /* stage-2 iterations per round; 0 -> 20 */
    double min_efficiency; /* 0: no bound */
    int threads;           /* stage 2's; 0 -> 1 */
    double gap_layer;      /* > 0: the width of a gap layer around each chart (gap_layer.h),
                              in the start's units: charts stay up to twice it apart, less
                              what pressure squeezes out of the layers */
} texopt_distortion_reduce_options;

typedef struct texopt_distortion_reduce_report {
    int refused;               /* 1: out = start (see above) */
    size_t charts_unboxed;     /* charts left out of the box (see above) */
    size_t charts_without_gap; /* with a gap: charts whose boundary took no layer */
    int rounds;                /* rounds kept */
    double scale;              /* Algorithm 2's initial scale of lengths */
    double distortion_start;   /* area-weighted mean symmetric Dirichlet relative to the reference
                                (1 = its shapes), of the start */
    double distortion;         /* of out */
    double efficiency_start;   /* chart area over the bounding box area, of the start */
    double efficiency;         /* of out */
    double box[4];             /* the last box, x0 y0 x1 y1: out lies inside it */
    double seconds;
} texopt_distortion_reduce_report;

/* mesh: triangles, charts and input texels (mesh->texel, the frame of the reference's
 * Jacobians); reference and start: 2 per vertex, start without overlap (a packed atlas),
 * reference at the scale the start's charts should return to, any placement. out (2 per
 * vertex) gets the reduced atlas. opt and report may be NULL. Fails on no memory or
 * cancellation. */
texopt_status texopt_distortion_reduce(const texopt_mesh *mesh, const double *reference, const double *start,
                                       const texopt_distortion_reduce_options *opt, double *out,
                                       texopt_distortion_reduce_report *report, const texopt_monitor *monitor,
                                       char *err, size_t err_len);

/* Area-weighted (reference area) mean symmetric Dirichlet energy of the map from the
 * reference to x, up to scale (the reference first scaled to x's total area: the budget
 * scales a layout as a whole), 1 where every triangle keeps its reference shape; +inf when a
 * triangle reverses. Triangles without reference area are left out. */
double texopt_distortion_relative(const texopt_mesh *mesh, const double *reference, const double *x);

#endif

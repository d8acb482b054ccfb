/* chart_reshape.h - deforms charts that fill little of their bounding box toward it, so
 * the atlas packs tighter (atlas refinement in the spirit of Liu, Fu, Ye, Chai and Liu 2019,
 * "Atlas Refinement with Bounded Packing Efficiency").
 *
 * Does: per chart, its box fill (texel area / area of its axis-aligned bounding box: the
 * packer only translates and makes quarter turns, so that is the box it sees). A chart
 * below the goal fill has each vertex of its outer boundary pulled, along the axis its
 * outward normal mostly points in, toward that side of a box around the chart shrunk to
 * hold the chart's area at the goal fill (meshwise.h's soft positional term; pulling to
 * the chart's own box would inflate it, and at a fixed cost the other charts would pay),
 * while every triangle is held to the Jacobian it has now, weighted by the caller's
 * rotation and stretch weights: the stage-2 solve with its flip barrier, so no triangle
 * flips. The pull is bounded per chart (Liu's point: reshape only as much as the goal
 * needs): a geometric ladder of pull weights, then two bisections, and each chart keeps
 * the weakest pull that reaches the goal, or the best fill it got. A pull that makes the
 * chart overlap itself (a notch filled from two sides sweeps them into each other; the
 * barrier prevents flips, not that) ends the chart's climb at the last result kept.
 * Charts are independent in the solve, so one solve serves every chart's rung.
 * Does not: cut (same charts, same connectivity, seams stay seams), reshape folded charts
 * (a chart holding both input orientations: its halves must stay on each other) or the
 * charts the caller keeps (opt->keep: sharing groups), or inner
 * boundaries (holes), scale to a budget or pack (budget.h, pack.h). Deterministic. */
#ifndef TEXOPT_CHART_RESHAPE_H
#define TEXOPT_CHART_RESHAPE_H

#include <stddef.h>

#include "mesh.h"
#include "status.h"
#include "target.h"

typedef struct texopt_reshape_options {
    double box_fill;     /* goal box fill in (0, 1]: charts below it are reshaped */
    int threads;         /* for the solves; 0 -> 1 */
    const uint8_t *keep; /* may be NULL: per chart, nonzero = not reshaped, like a folded
                            chart (a sharing group, texel_share.h: the solve here does not
                            hold its charts on each other) */
} texopt_reshape_options;

typedef struct texopt_reshape_report {
    int charts_below; /* charts below the goal before (folded ones included) */
    int charts_reshaped;
    int charts_reaching;    /* reshaped charts that reached the goal */
    int charts_overlapping; /* reshaped charts held back at a weaker pull because a stronger
                               one made them overlap themselves */
    double fill_before;     /* sum of chart areas / sum of their box areas */
    double fill_after;
    int solves;
} texopt_reshape_report;

/* Writes the layout `texel` (2 per mesh vertex, in any frame in which the mesh's triangles
 * keep their input orientation, e.g. a stage-2 layout) with its low-fill charts reshaped
 * to texel_out (must not alias texel). targets (may be NULL: weights 1) gives each
 * triangle's w_rotation and w_stretch, how much its rotation and stretch may give. report
 * may be NULL. */
texopt_status texopt_chart_reshape(const texopt_mesh *mesh, const double *texel, const texopt_triangle_target *targets,
                                   const texopt_reshape_options *opt, double *texel_out, texopt_reshape_report *report,
                                   char *err, size_t err_len);

#endif

/* layout_check.h - the validity check a new layout passes before anything is written
 * (issue 37): no new overlap, no new fold-over, no triangle far above its target area.
 *
 * Given a domain's input mesh and its new layout (texel positions in the output frame):
 *  - overlap: a triangle with a texel centre that a triangle of another sharing group
 *    (texel_share.h: mirrored twins laid on one region, a chart with its folds) also covers
 *    in the new layout: what shared texels in the input may keep sharing them, nothing
 *    else (centres on an edge belong to neither side; frames past 2^26 texels unchecked);
 *  - overlap within a chart, counted and not failed: a triangle on a texel centre that a
 *    triangle of its own chart with the same orientation also covers (a chart over itself;
 *    the two sides of a fold may share), in a chart that does not do so in the input (the
 *    input rastered the same way over its whole extent, past the frame too; past 2^26
 *    texels every chart counts). Stage 2's barrier does not prevent it, and `bijective`
 *    prevents it only in the charts its scaffold covers (scaffold.h; chart_unfold.h says
 *    which it cannot), so it is measured, not failed;
 *  - fold-over: a triangle with an area in both layouts whose orientation the new one
 *    reverses, and that was not FLIPPED (mesh.h) in the input;
 *  - area: a triangle whose new texel area is above TEXOPT_LAYOUT_CHECK_AREA_FACTOR times
 *    the larger of its target area and its input area scaled as the whole layout was, plus
 *    the layout's mean triangle area; the target areas are lambda1 lambda2 |input area| of
 *    the targets it was solved from, scaled together to the new layout's total. A collapsed
 *    triangle (no input texel area) may so cover one mean triangle at most (the blow-ups of
 *    issue 37 were 35 times it); small targets in flat regions, which stage 2 cannot always
 *    meet beside large ones, are no failure.
 * The check of the first offending triangle names the result; the counts of all three are
 * given, and the first TEXOPT_LAYOUT_CHECK_LISTED offending triangles (model triangle
 * indices) of the failed check.
 * Does not: fix a layout (the pipeline keeps the input layout resized) or read files. */
#ifndef TEXOPT_LAYOUT_CHECK_H
#define TEXOPT_LAYOUT_CHECK_H

#include <cjson/cJSON.h>
#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "status.h"
#include "target.h"

#define TEXOPT_LAYOUT_CHECK_LISTED 16
#define TEXOPT_LAYOUT_CHECK_AREA_FACTOR 8.0

typedef enum texopt_layout_failure {
    TEXOPT_LAYOUT_PASSED = 0,
    TEXOPT_LAYOUT_OVERLAP,
    TEXOPT_LAYOUT_FOLDOVER,
    TEXOPT_LAYOUT_AREA,
} texopt_layout_failure;

typedef struct texopt_layout_check {
    texopt_layout_failure failed;
    size_t overlapping;           /* triangles on texels of another sharing group */
    size_t overlapping_within;    /* triangles on texels of their own chart (below) */
    size_t overlap_within_texels; /* texel centres they cover a second time */
    uint32_t first_within;        /* the first of them (model triangle) */
    size_t folded;                /* new fold-overs */
    size_t oversized;             /* triangles far above their target area */
    size_t listed;
    uint32_t triangles[TEXOPT_LAYOUT_CHECK_LISTED]; /* model triangles of the failed check */
} texopt_layout_check;

/* "overlap", "foldover", "area", or NULL when passed. */
const char *texopt_layout_failure_name(texopt_layout_failure failure);

/* Checks the layout `texel` (2 per vertex of `input`, texel units of a width x height frame)
 * against the input mesh. group_of_chart: per chart of the input, its sharing group (NULL:
 * every chart its own). targets (per triangle; NULL: the area check without its target
 * term) are those the layout was solved from. */
texopt_status texopt_layout_check_run(const texopt_mesh *input, const double *texel, int width, int height,
                                      const uint32_t *group_of_chart, const texopt_triangle_target *targets,
                                      texopt_layout_check *out, char *err, size_t err_len);

/* The check on a file's own layout, for `texopt info`, which has no input to compare with:
 * overlaps between its sharing groups (texel_share.h, as the pipeline groups them), every
 * chart over itself in the frame (overlap within a chart, counted, not failed) and its
 * fold-overs (FLIPPED, mesh.h); no area check. */
texopt_status texopt_layout_check_own(const texopt_mesh *mesh, texopt_layout_check *out, char *err, size_t err_len);

/* {"passed", "failed" (a name or null), "triangles": [...], "overlapping_triangles",
 * "overlapping_within_chart_triangles", "overlap_within_chart_texels",
 * "foldover_triangles", "oversized_triangles"}, as the statistics and `texopt info` give it. */
cJSON *texopt_layout_check_json(const texopt_layout_check *check);

#endif

/* chart_unfold.h - a bijective start for the charts that overlap themselves in a layout, so
 * that the scaffold (scaffold.h) can box them.
 *
 * A chart holding fold-overs (mesh.h TEXOPT_TRI_FLIPPED) or whose boundary crosses itself
 * cannot be tiled with scaffold triangles, and no stage-2 step undoes an overlap its start
 * holds. Such a chart (the scaffold's own test, texopt_scaffold_overlapping_charts) is laid
 * out anew here as the disk it is in 3D, on its own vertices (the chart keeps its seams, so
 * the model needs no vertex split): linear ABF (param_abf.h) when its layout has no flip and
 * no boundary crossing, else Tutte with mean-value weights (param_tutte.h), which is a
 * bijection. The layout takes the chart's input texel area (the sum of its triangles'), the
 * chart's orientation (chart_sign), and the rotation and place that fit the input best (a
 * least-squares rigid fit), so most triangles keep the frame their targets were found in.
 *
 * Left as they are, and counted: charts the caller keeps (a sharing group's, texel_share.h:
 * they share texels with another chart by design, unless texopt_unfold_groups can lay the
 * group out as one), clean mirrors (a side of the opposite
 * orientation that is not FLIPPED, i.e. a patch holding 20% or more of the chart's texel
 * area, and no texel centre covered twice with one orientation: halves laid on one another
 * on purpose, whose texels the budget pays once, and whose overlap the within-chart count
 * does not count; the scaffold boxes most of them half by half, so they reach here only
 * when a half cannot be boxed), and charts that are no disk (a handle, a non-manifold vertex or edge, a
 * triangle without 3D area). A mirror that also covers centres twice with one orientation
 * (folds inside it) is unfolded and so loses its sharing. Holes and pinched vertices (a
 * boundary through a vertex twice) are no obstacle: every boundary loop but the longest is
 * filled with a fan for the layout (by Tutte then), and the fans dropped. A chart whose
 * triangles fall into parts that meet only at vertices (a strip joined corner to corner) is
 * laid out part by part, each part moved to the vertex it shares with those before it and
 * turned about it, shrunk if it must be, until neither crosses or holds the other (a part
 * meeting them at two vertices is no disk; one that never comes clear is left overlapping,
 * and its sharing group, if any, left alone).
 * Does not: restate the targets for the new layout (target_restate.h), or solve. */
#ifndef TEXOPT_CHART_UNFOLD_H
#define TEXOPT_CHART_UNFOLD_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "status.h"
#include "texel_share.h"

typedef struct texopt_unfold_report {
    size_t overlapping; /* charts overlapping themselves in the input layout */
    size_t unfolded;    /* of them, laid out anew */
    size_t tutte;       /* of those, by Tutte (ABF's layout failed, flipped or crossed itself) */
    size_t kept;        /* left alone: the caller's */
    size_t mirrored;    /* left alone: clean mirrors */
    size_t not_disks;   /* left alone: no disk (or, job level, welded otherwise) */
    size_t followed;    /* sharing groups' secondaries laid on their primary's new layout */
} texopt_unfold_report;

/* Copies mesh->texel into texel_out (2 per vertex) with the charts that overlap themselves
 * laid out anew as above; keep (per chart, may be NULL) marks charts to leave alone.
 * unfolded (per chart, may be NULL) receives 1 for the charts laid out anew. */
texopt_status texopt_unfold_charts(const texopt_mesh *mesh, const uint8_t *keep, double *texel_out, uint8_t *unfolded,
                                   texopt_unfold_report *report, char *err, size_t err_len);

/* texopt_unfold_charts for a mesh with sharing groups (share may be NULL: none). A group
 * whose secondaries have a tie (texel_share.h) at every vertex is laid out as one: its
 * primary as any chart above, and, when the primary was laid out anew or some secondary
 * overlaps itself while the primary does not, each secondary vertex put on its tie's point
 * of the primary's layout: mirrored or repeated twins then start as the primary does,
 * without overlap, and still on its texels (counted in followed, and no longer in kept). A
 * secondary that overlaps itself in the input where its primary does not (no twin: it covers
 * the primary's texels twice) is taken out of its group (texopt_texel_share_release) and laid
 * out on its own, paying for its texels. A group with an untied secondary vertex, or that
 * would still overlap, is left alone whole (kept). */
texopt_status texopt_unfold_groups(const texopt_mesh *mesh, texopt_texel_share *share, double *texel_out,
                                   texopt_unfold_report *report, char *err, size_t err_len);

#endif

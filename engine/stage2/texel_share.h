/* texel_share.h - separate charts that read the same texels, so that a layout keeps them
 * sharing.
 *
 * Mirrored and repeated parts of game and product assets are often separate charts laid on
 * one texel region (DamagedHelmet's halves: half of its texel area is read twice). A layout
 * that solves and packs such charts apart pays for the texture twice. Here a SHARING GROUP
 * is a primary chart and the charts whose input texel footprint lies mostly on it; stage 2
 * lays the primary out and ties every vertex of the others to the point of the primary
 * triangle it lay on in the input (meshwise.h), and the later per-chart stages (orient,
 * reshape, pack) move the group as one chart through `view`, so the others land on the
 * primary's new texels and share them as in the input.
 *
 * Footprints are counted on the texel grid of the input frame, unwrapped (a texel is a
 * centre inside a triangle; a chart's texels are counted once however often it covers them,
 * so a folded chart is not its own secondary). Charts are visited from the most covered
 * texels down; a chart becomes a secondary of the primary whose texels hold at least
 * TEXOPT_TEXEL_SHARE_FRACTION of its own, else a primary that claims its texels no
 * primary claimed yet. Whatever the orientations (mirrored or repeated) and tessellations
 * (Duck's halves are different triangulations of one region): only footprints are compared.
 *
 * Ties: a vertex of a secondary's triangle with an input texel area is tied to the nearest
 * point of its primary's triangles when that is at most TEXOPT_TEXEL_SHARE_TOLERANCE texels
 * away (inside one: distance 0); farther vertices (a boundary that sticks out of the
 * primary) are left to their neighbours.
 *
 * Not here: the solve (meshwise.h), the check that the layout is worth it (coverage.h counts
 * a shared texel once). Frames whose unwrapped footprint spans more than
 * TEXOPT_TEXEL_SHARE_MAX_CELLS texels get no groups. */
#ifndef TEXOPT_TEXEL_SHARE_H
#define TEXOPT_TEXEL_SHARE_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "status.h"

/* A secondary's texels that must lie on its primary's: near-complete overlaps only, so
 * that a secondary's untied part cannot fold over other texels of the primary.
 * BENCHMARKS.md@9f788a8 "Shared texels kept" for the measured overlaps. */
#define TEXOPT_TEXEL_SHARE_FRACTION 0.9
#define TEXOPT_TEXEL_SHARE_TOLERANCE 0.5 /* texels */
#define TEXOPT_TEXEL_SHARE_MAX_CELLS (1u << 25)

/* Vertex `vertex` held on sum_j weight[j] * corner[j] (a point of a primary triangle). */
typedef struct texopt_texel_tie {
    uint32_t vertex;
    uint32_t corner[3];
    double weight[3];
} texopt_texel_tie;

typedef struct texopt_texel_share {
    size_t chart_count;
    uint32_t *primary_of;   /* per chart of the mesh: the chart whose texels it shares,
                                itself for a primary (a chart sharing none is one) */
    size_t secondary_count; /* charts with primary_of[c] != c */
    texopt_texel_tie *ties;
    size_t tie_count;
    /* The mesh with every group as one chart, numbered in order of first triangle, its
     * sign the primary's: chart_count, chart_of and chart_sign are its own, every other
     * field is the mesh's (the view must not outlive the mesh). */
    texopt_mesh view;
    uint8_t *grouped; /* per chart of the view: 1 when it holds secondaries */
} texopt_texel_share;

/* Finds the sharing groups of `mesh` and the ties. The caller frees *out with
 * texopt_texel_share_destroy. */
texopt_status texopt_texel_share_create(texopt_texel_share **out, const texopt_mesh *mesh, char *err, size_t err_len);

void texopt_texel_share_destroy(texopt_texel_share *share);

/* Takes chart `chart`, a secondary, out of its group (a chart that overlaps itself where its
 * primary does not cannot lie on the primary without overlap, chart_unfold.h): it becomes a
 * primary of its own, its ties are dropped and the view is rebuilt on `mesh`, the mesh
 * `share` was made from. */
texopt_status texopt_texel_share_release(texopt_texel_share *share, const texopt_mesh *mesh, uint32_t chart, char *err,
                                         size_t err_len);

/* Re-bases the view on `layout`: a mesh of the same vertices, triangles and charts as the
 * one `share` was made from, in another layout (chart_unfold.h), which must outlive it. */
void texopt_texel_share_rebase(texopt_texel_share *share, const texopt_mesh *layout);

/* Per triangle of the mesh `share` was made from, the share of its texel area that it pays
 * for in a budget of covered texels (target_allocation.h `paid`): 0 for the triangles of a
 * secondary, which lie on their primary's texels, and for a chart's triangles of the
 * orientation opposite to its sign (chart_sign: a fold's minority side lies on the
 * majority's texels), 1 for the others. Returns how many pay 0 (none: every weight is 1). */
size_t texopt_texel_share_paid(const texopt_texel_share *share, const texopt_mesh *mesh, double *paid);

#endif

/* chart_gap.h - the smallest distance between two charts of a layout: whether a layout can
 * be written with the gutters the packer would give it (pack.h: two charts at least
 * `gutter` texels apart).
 *
 * The distance is Euclidean, between the boundary edges (edges used by one triangle) of two
 * different charts; charts that touch or cross are 0 apart. A chart inside another's hole
 * is measured to that hole's boundary. Every pair of boundary edges is compared: for
 * measurement and checks of a few thousand boundary edges, not for a solver's loop.
 * The boundary edges themselves are given too (gap_layer.h builds on them).
 * Does not: measure a chart's distance to itself, or to the texture's border. */
#ifndef TEXOPT_CHART_GAP_H
#define TEXOPT_CHART_GAP_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "status.h"

/* An edge used by one triangle, directed as in that triangle. */
typedef struct texopt_boundary_edge {
    uint32_t from, to, triangle;
} texopt_boundary_edge;

/* The boundary edges of mesh into *out (caller frees; NULL out of memory): their count. */
size_t texopt_boundary_edges(const texopt_mesh *mesh, texopt_boundary_edge **out);

/* *gap: the smallest distance between boundary edges of two different charts of mesh in
 * the layout x (2 per vertex), leaving out the charts with skip[c] nonzero (skip may be
 * NULL); INFINITY when fewer than two charts are left. Fails on no memory. */
texopt_status texopt_chart_gap(const texopt_mesh *mesh, const double *x, const uint8_t *skip, double *gap, char *err,
                               size_t err_len);

#endif

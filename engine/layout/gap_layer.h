/* gap_layer.h - a thin layer of triangles around each chart, so that charts solved in one
 * box keep a gap between them (Liu et al. 2019, section 3.3, "Gaps between charts", Fig. 11).
 *
 * Every boundary edge of a chart gets a quad of two triangles on its outer side, of width
 * `width` in the packed start layout (output texels), the chart's own orientation, and the
 * chart's number: the layer is part of the chart for the solve (distortion_reduce.h), so two
 * charts' layers keep them about twice the width apart. The layer's outer vertex of a
 * boundary vertex lies the width out along its edges' mean outward normal (not mitred: the
 * layer stays within the width of its chart, so charts packed more than twice the width
 * apart start with layers clear of one another); in the input texels and the reference its offset is scaled as the adjacent
 * boundary edges are, so its target (the reference's Jacobian) is the chart's own stretch
 * continued outward. A chart whose boundary is not simple loops (a vertex on more than two
 * boundary edges), has a spike or an edge without length, or whose layer would collapse or
 * turn between the three layouts (a concave corner sharper than the width allows: stage 2
 * refuses a start turned against the input texels) gets no layer (charts_without).
 * Does not: check that a layer stays off its own chart at sharp concave corners (the
 * caller's scaffold finds such a chart over itself and leaves it out of its box). */
#ifndef TEXOPT_GAP_LAYER_H
#define TEXOPT_GAP_LAYER_H

#include <stddef.h>

#include "mesh.h"
#include "status.h"

typedef struct texopt_gap_layer {
    texopt_mesh mesh;          /* the charts' vertices and triangles first (same numbers), then the
                         layer's; fields set: width, height, vertex_count, texel,
                         triangle_count, triangle, area_texel, flags, chart_count, chart_of,
                         chart_sign (the others NULL) */
    double *start, *reference; /* 2 per vertex of mesh */
    size_t charts_layered, charts_without;
} texopt_gap_layer;

/* mesh, reference and start as texopt_distortion_reduce takes them; width > 0. */
texopt_status texopt_gap_layer_create(const texopt_mesh *mesh, const double *reference, const double *start,
                                      double width, texopt_gap_layer *out, char *err, size_t err_len);

void texopt_gap_layer_destroy(texopt_gap_layer *layer);

#endif

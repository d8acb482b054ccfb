/* atlas_quality.h - the atlas measures of Liu et al. 2019, "Atlas Refinement with Bounded
 * Packing Efficiency" (section 4, "Quality metrics"), so texopt's layouts can be set beside
 * the paper's Table 1.
 *
 * PE: the atlas's area (the texel areas of its non-degenerate triangles; mirrored or
 * overlapping charts count each time) over the area of its bounding box (of every
 * triangle's corners), with no frame and no gutter around it: unlike coverage.h's packing
 * efficiency, which counts covered texels of the whole texture frame.
 * BL: the length of the cut on the surface (each 3D edge of the mesh along which the layout
 * is split, counted once, whatever the number of charts it separates; the surface's own
 * border is no cut) over the diagonal of the surface's bounding box. CN: charts.
 * The paper's distortion E_d is distortion.h's symmetric Dirichlet divided by 4.
 *
 * Does not: look at the texel grid, the frame or the textures. */
#ifndef TEXOPT_ATLAS_QUALITY_H
#define TEXOPT_ATLAS_QUALITY_H

#include <stddef.h>

#include "mesh.h"
#include "status.h"

typedef struct texopt_atlas_quality {
    double packing_efficiency; /* PE, in (0, 1] for a layout without overlap */
    double boundary_length;    /* BL */
    size_t charts;             /* CN: mesh->chart_count */
} texopt_atlas_quality;

/* Measures the layout `texel` (2 per mesh vertex; NULL = mesh->texel) of `mesh`. Fails with
 * TEXOPT_E_INVALID_ARGUMENT when the layout or the surface has no extent (no triangle, zero
 * bounding box) and with TEXOPT_E_NOMEM. */
texopt_status texopt_atlas_quality_measure(const texopt_mesh *mesh, const double *texel, texopt_atlas_quality *out,
                                           char *err, size_t err_len);

/* {"packing_efficiency", "boundary_length", "charts"}; NULL when out of memory. */
struct cJSON *texopt_atlas_quality_json(const texopt_atlas_quality *q);

#endif

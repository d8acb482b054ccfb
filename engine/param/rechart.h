/* rechart.h - new disk charts for a texture domain, each laid out by a parameterization
 * method (param_*.h): the engine half of `--charts new` (issue 41).
 *
 * Triangles are grouped by region growing over shared 3D edges (through UV seams): a chart
 * never crosses a crease (normals more than crease_degrees apart) nor holds a triangle whose
 * normal is more than cone_degrees from its seed's (nor, with density_ratio, one whose input
 * texel density is that factor from the seed's, nor, with may_cross, across an input seam
 * it refuses), nor grows past max_triangles, and only
 * takes a triangle that keeps it a disk (no vertex reached twice, no surface closed). A
 * region that is still no disk (param_chart.h: a non-manifold or inconsistently oriented
 * mesh) is split in two along its growth order until every part is one. Each chart is laid out by the chosen method at 3D scale (1 unit = 1 world unit);
 * when the method fails or flips a triangle (LSCM may fold; the square refuses ears it cannot peel, param_ears.h) the
 * chart falls back to the mean-value Tutte map, which cannot flip; when its layout overlaps
 * itself (the boundary loop crosses itself: ABF and LSCM are only locally injective) the
 * region is split in two along its growth order, as a region that is no disk. Degenerate (zero 3D area)
 * triangles get a chart of their own with all corners at (0, 0). It does not pack the charts
 * nor write them into the model. */
#ifndef TEXOPT_RECHART_H
#define TEXOPT_RECHART_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "params.h"
#include "status.h"

typedef struct texopt_rechart_options {
    texopt_parameterizer method;
    double crease_degrees; /* 0 = 60 */
    double cone_degrees;   /* 0 = 75 */
    size_t max_triangles;  /* 0 = 5000: bounds one chart's solve */
    double density_ratio;  /* > 0: no triangle whose input texel density (texels per world
                              unit) is more than this factor from the seed's joins it; 0 = any */
    /* non-NULL: a region grows across an input seam (t and u share a 3D edge but not its
     * texel corners) only where may_cross(cross_context, t, u) is non-zero */
    int (*may_cross)(const void *cross_context, uint32_t t, uint32_t u);
    const void *cross_context;
} texopt_rechart_options;

typedef struct texopt_rechart {
    size_t triangle_count, chart_count;
    uint32_t *chart_of;     /* per mesh triangle */
    double *corner_uv;      /* 6 per mesh triangle: its corners' layout, world units, each
                            chart's box starting at (0, 0) */
    size_t fallback_charts; /* charts laid out by Tutte because the method failed or flipped */
    size_t overlap_splits;  /* regions split in two because the method's layout overlapped itself */
} texopt_rechart;

/* On success the caller owns *out and frees it with texopt_rechart_destroy. */
texopt_status texopt_rechart_create(texopt_rechart **out, const texopt_mesh *mesh,
                                    const texopt_rechart_options *options, char *err, size_t err_len);
void texopt_rechart_destroy(texopt_rechart *rechart);

#endif

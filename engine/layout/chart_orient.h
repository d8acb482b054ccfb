/* chart_orient.h - turns charts to the angle of their smallest bounding rectangle before
 * packing.
 *
 * Does: per chart, the convex hull of its texel positions and, over the hull's edge
 * directions (rotating calipers: the smallest-area enclosing rectangle has a side on a hull
 * edge, Freeman and Shapira 1975), the rectangle of least area; the chart is turned rigidly
 * about its centroid so that rectangle is axis-aligned, by at most 45 degrees either way
 * (the packer's quarter turns do the rest). A chart stays as it is unless the turn shrinks
 * its box by more than KEEP_MARGIN (chart_orient.c): a turn resamples the texture at an
 * angle, so it must pay.
 * Only for layouts whose objective does not see a chart's rotation: the baselines' stage 2
 * (ssp, tewari, arap: rotation weight wR = 0) is defined up to one rotation per chart, so
 * turning a chart changes nothing they optimise. Stage 2 of the perceptual method weighs
 * each triangle's alignment with the texel grid (Sun et al. 2022, eq. 17-19: wR), so its
 * charts must keep their angle up to quarter turns; the caller decides per chart.
 * Does not: mirror (rotations only: every triangle keeps its orientation), scale, move a
 * chart's centroid, or pack (pack.h). */
#ifndef TEXOPT_CHART_ORIENT_H
#define TEXOPT_CHART_ORIENT_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "status.h"

/* Writes the layout `texel` (2 per mesh vertex) with every chart c for which turnable is
 * NULL or turnable[c] != 0 turned as above to texel_out (2 per vertex, must not alias
 * texel); other charts and vertices of no triangle are copied. angle_out (per chart,
 * radians counter-clockwise in (x, y), 0 for charts left alone) may be NULL. */
texopt_status texopt_chart_orient(const texopt_mesh *mesh, const double *texel, const uint8_t *turnable,
                                  double *texel_out, double *angle_out, char *err, size_t err_len);

#endif

/* param_ears.h - a disk chart laid out with its ears peeled off and put back.
 *
 * A layout method that maps the boundary onto straight sides (param_square.h) flattens
 * every ear (a triangle with all three vertices on the boundary) that lands on one side.
 * Region-grown charts have many (param/rechart.h). Here the ears whose apex belongs to no
 * other triangle are taken off, layer by layer, the rest of the chart is laid out by the
 * caller's method, and each apex is put back by its triangle's 3D shape, scaled like its
 * base edge, on the side of the base edge away from the chart: the chart keeps its square
 * with the ears outside it.
 * Does not: peel an ear whose apex has other triangles (that would cut the chart in two),
 * or check the result for overlap (ears at a corner can touch; rechart.h checks and
 * splits). */
#ifndef TEXOPT_PARAM_EARS_H
#define TEXOPT_PARAM_EARS_H

#include <stddef.h>

#include "param_chart.h"
#include "status.h"

/* A layout method: 2 doubles per vertex of `chart` into uv. */
typedef texopt_status (*texopt_param_layout_fn)(const texopt_param_chart *chart, void *context, double *uv, char *err,
                                                size_t err_len);

/* Lays out `chart` (a disk) with `layout` after peeling up to `max_layers` layers of ears,
 * then puts them back: 2 doubles per vertex into uv (caller-owned). *peeled (may be NULL)
 * gets the number of triangles peeled. Fails as texopt_param_boundary_create does on a
 * chart that is not a disk, or as `layout` does on the rest. */
texopt_status texopt_param_without_ears(const texopt_param_chart *chart, texopt_param_layout_fn layout, void *context,
                                        int max_layers, double *uv, size_t *peeled, char *err, size_t err_len);

#endif

/* tri_bins.h - a uniform grid of bins over the input texel plane holding chosen triangles
 * of a mesh, for point location: the triangles that may hold or lie near a point are those
 * of its bin (and of the bins a small box around it touches).
 *
 * Each triangle is listed in every bin its texel box touches, in triangle order. Bins are
 * about two triangles' area a side where the triangles are, and never more than 4 per
 * triangle (or 1024) in all: triangles far apart must not make a huge empty grid.
 * Not here: the containment test (the callers have their own barycentrics). */
#ifndef TEXOPT_TRI_BINS_H
#define TEXOPT_TRI_BINS_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "status.h"

typedef struct texopt_tri_bins {
    double x0, y0, cell; /* lower corner of bin (0, 0), bin side in texels */
    size_t nx, ny;
    uint32_t *start; /* nx * ny + 1 offsets into tri; NULL when no triangle was kept */
    uint32_t *tri;
} texopt_tri_bins;

/* Bins the triangles t of `mesh` with keep[t] nonzero by their boxes in mesh->texel.
 * On TEXOPT_E_NOMEM *bins may hold a part: free it with texopt_tri_bins_free either way. */
texopt_status texopt_tri_bins_build(texopt_tri_bins *bins, const texopt_mesh *mesh, const unsigned char *keep,
                                    char *err, size_t err_len);

/* The bin column (axis 0) or row (axis 1) of coordinate p, clamped to the grid. */
size_t texopt_tri_bins_index(const texopt_tri_bins *bins, double p, int axis);

void texopt_tri_bins_free(texopt_tri_bins *bins);

#endif

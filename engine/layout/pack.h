/* pack.h - places the charts of a layout in one texture, by translations and 90-degree
 * rotations only.
 *
 * Does: take a layout already at its final texel density (texel positions per mesh vertex,
 * any origin), rasterise each chart's footprint grown by half the gutter onto a grid of
 * cells, and place the charts in a given order (largest first by default), each rotation
 * at its lowest then leftmost free position, holes under placed charts included, and the
 * rotation chosen by a rule (texopt_pack_rule) (bottom-left placement on the real footprints, in the
 * spirit of the brute-force mode of xatlas: concave charts interlock, which bounding-box
 * shelves cannot do). Charts are never mirrored and never turned by other angles: the
 * orientation the mesh-wise stage chose for each triangle (Sun et al. 2022, "Efficient
 * Texture Parameterization Driven by Perceptual-Loss-on-Screen", section 4.2: the pixel grid
 * orientation matters for the perceived quality) survives up to the texture grid's own
 * symmetry.
 * Does not: scale the layout to a budget (budget.h does, calling this), count covered texels
 * (coverage is the cost of the paper's eq. 20, measured by the caller), or rebake.
 *
 * Gutter: two charts end up at least `gutter` texels apart (Chebyshev distance between
 * their triangles), and every chart at least gutter / 2 from the texture border, so with
 * REPEAT wrapping the distance across the border is the gutter too. */
#ifndef TEXOPT_PACK_H
#define TEXOPT_PACK_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "status.h"

/* How a chart's four rotations, each at its lowest-leftmost free position, are compared
 * (then by top, then leftmost). No rule wins everywhere; budget.h tries all three. */
typedef enum texopt_pack_rule {
    TEXOPT_PACK_LOWEST_TOP = 0,    /* keeps the strip's top low */
    TEXOPT_PACK_LOWEST_BOTTOM = 1, /* fills the lowest holes first */
    TEXOPT_PACK_LOWEST_CENTRE = 2  /* between the two (a "lowest gravity centre" rule) */
} texopt_pack_rule;

typedef struct texopt_pack_options {
    int gutter;               /* texels between charts; 0 -> 4 (bilinear plus two mip levels) */
    int cell;                 /* placement grid cell in texels; 0 -> chosen from the texture size
                      (1 up to 1024, then so the grid stays <= 1024 cells a side) */
    int order;                /* placement order: 0 largest triangle area first, 1 largest bounding
                      box first (better for elongated charts; budget.h tries both) */
    const uint32_t *sequence; /* optional: the placement order itself, every chart index
                                 0..chart_count-1 once (budget.h searches orders this way);
                                 NULL = by `order` */
    int rule;                 /* texopt_pack_rule; 0 = lowest top */
} texopt_pack_options;

typedef struct texopt_pack_result {
    int width, height;      /* texture size the charts were packed into */
    int used_height;        /* rows actually used (the top of the highest chart + gutter/2) */
    int used_width;         /* columns actually used (the right of the rightmost chart +
                              gutter/2): the texture may be cut to it, rounded up to 4 */
    double area_efficiency; /* sum of |texel area| of the triangles / (width * height) */
    size_t chart_count;
    uint8_t *rotation; /* per chart: quarter turns 0..3 (counter-clockwise in (x, y)) */
} texopt_pack_result;

/* Packs the charts of mesh (mesh->chart_of, mesh->triangle) laid out at `texel` (2 per mesh
 * vertex) into a width x height texture. height 0 means "as tall as needed": the charts are
 * packed into width columns and result->height = result->used_height (rounded up to a
 * multiple of 4). On success texel_out (2 per vertex) holds the placed positions, inside
 * [0, width] x [0, height], and *fits is 1. When the charts do not fit in a fixed height,
 * *fits is 0 and TEXOPT_OK is returned (texel_out is then undefined). result->rotation is
 * allocated by the call; free it with texopt_pack_result_destroy. opt may be NULL. */
texopt_status texopt_pack_charts(const texopt_mesh *mesh, const double *texel, int width, int height,
                                 const texopt_pack_options *opt, double *texel_out, texopt_pack_result *result,
                                 int *fits, char *err, size_t err_len);

void texopt_pack_result_destroy(texopt_pack_result *result);

/* A packer keeps the footprints of one layout (every chart in its four quarter turns) so
 * that many packings of it (other widths, other orders: budget.h's search) cost only the
 * placement. The layout (mesh, texel) must stay alive and unchanged while the packer is.
 * The grid cell is opt->cell, or chosen for a texture of `side` texels a side. */
typedef struct texopt_packer texopt_packer;

texopt_status texopt_packer_create(texopt_packer **out, const texopt_mesh *mesh, const double *texel,
                                   const texopt_pack_options *opt, int side, char *err, size_t err_len);

/* As texopt_pack_charts with the packer's layout, gutter and cell; of opt (may be NULL)
 * only order, sequence and rule are read. */
texopt_status texopt_packer_run(const texopt_packer *packer, int width, int height, const texopt_pack_options *opt,
                                double *texel_out, texopt_pack_result *result, int *fits, char *err, size_t err_len);

void texopt_packer_destroy(texopt_packer *packer);

#endif

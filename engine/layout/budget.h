/* budget.h - scales a layout to the requested pixel budget and picks the texture size.
 *
 * The budget of Sun et al. 2022, "Efficient Texture Parameterization Driven by
 * Perceptual-Loss-on-Screen": cost c = covered texels (eq. 20, counted by coverage.h on the
 * packed layout), relative cost c_r = c(output) / c(input) (eq. 21).
 *  - relative cost: the layout is scaled so that its packed cost is c_r c(input) (within
 *    0.5%, by a few multiplicative corrections: cost grows as scale squared), and the texture
 *    is the smallest we find that holds it: several strip widths around sqrt(area /
 *    efficiency * aspect of the input frame) and placement orders are packed "as tall as
 *    needed" (the width then cut to the columns used), for small atlases followed by a
 *    seeded local search over the order, and the packing with the fewest texels wins (a
 *    fixed number of packings: deterministic, on any number of threads). Both sides are multiples of 4 (block compression and mip levels two deep
 *    stay aligned); the aspect is therefore close to, not exactly, the input's: we choose
 *    the texture memory over the aspect.
 *  - texture size W x H: the largest scale whose packing fits in exactly W x H, by
 *    bisection on the scale (to 0.2%).
 * Does not: choose the layout's shape (stage 2 does) or rebake.
 * Packing is pack.h (translations and quarter turns, gutters); charts whose rotation is free
 * (see `targets`) are turned by chart_orient.h first (any angle, rigid), so their output is
 * that turn followed by the packer's quarter turn and translation. */
#ifndef TEXOPT_BUDGET_H
#define TEXOPT_BUDGET_H

#include "mesh.h"
#include "monitor.h"
#include "pack.h"
#include "params.h"
#include "status.h"
#include "target.h"

typedef struct texopt_budget_request {
    texopt_budget kind;                    /* RELATIVE_COST or TEXTURE_SIZE */
    double relative_cost;                  /* with RELATIVE_COST, > 0 */
    int texture_width, texture_height;     /* with TEXTURE_SIZE */
    double input_cost;                     /* covered texels of the input layout, > 0 */
    int input_width, input_height;         /* input frame, for the aspect */
    texopt_pack_options pack;              /* gutter, cell; zero = defaults */
    const texopt_triangle_target *targets; /* may be NULL: the per-triangle targets the
                                            layout was solved for. A chart none of whose
                                            triangles cares about rotation (w_rotation 0: every
                                            chart of the baselines, flat charts of the
                                            perceptual method) is first turned to its
                                            smallest bounding rectangle (chart_orient.h);
                                            the others, and all with NULL, keep their angle
                                            up to the packer's quarter turns */
    double efficiency_bound;               /* not read here: the job's refinement (packing
                                            refine) holds its packing efficiency to it (Liu
                                            et al. 2019's PE_bound, texopt_params
                                            packing_efficiency) */
    const uint8_t *keep_shape;             /* may be NULL: per chart, nonzero = a sharing group's
                                            (texel_share.h: its charts must stay on each
                                            other). Not read here: for the job's refinement
                                            (atlas_refine.h), which leaves them as they are */
    const double *paid;                    /* may be NULL: per triangle, the share of its texel
                                            area it pays for (texel_share.h
                                            texopt_texel_share_paid); the scale estimates
                                            count a texel shared by a sharing group once */
    int threads;                           /* for the packing search; 0 -> 1. The result does
                                            not depend on it */
    const texopt_monitor *monitor;         /* may be NULL; checked for cancellation between
                                            packings (TEXOPT_E_CANCELED) */
} texopt_budget_request;

typedef struct texopt_budget_result {
    int width, height;         /* output texture */
    double scale;              /* applied to the layout before packing */
    double cost;               /* covered texels of the packed layout */
    double relative_cost;      /* cost / input_cost */
    double packing_efficiency; /* cost / (width * height) */
    int packings;              /* pack runs spent */
    int no_fit;                /* texture size: the charts fit it at no scale (with
                                   TEXOPT_E_LIMIT; the other fields are then 0) */
} texopt_budget_result;

/* Scales `texel` (2 per mesh vertex, any scale, e.g. the stage-2 layout in input texels),
 * packs it and writes the packed positions (output texels, 2 per vertex) to texel_out.
 * TEXOPT_E_LIMIT when the budget needs a texture past 16384 a side (relative cost) or the
 * charts cannot fit at any useful scale (texture size). */
texopt_status texopt_budget_fit(const texopt_mesh *mesh, const double *texel, const texopt_budget_request *req,
                                double *texel_out, texopt_budget_result *res, char *err, size_t err_len);

#endif

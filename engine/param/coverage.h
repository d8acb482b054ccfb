/* coverage.h - which texels a UV layout uses: unique covered texels, overlaps, packing.
 *
 * The cost of Sun et al. 2022, "Efficient Texture Parameterization Driven by
 * Perceptual-Loss-on-Screen" (eq. 20, DESIGN.md 3.4), counted on the texel grid: a texel is
 * covered when its centre lies inside a (non-degenerate) triangle of the layout, with a
 * half-open fill rule (a centre on an edge shared by two triangles belongs to exactly one),
 * so two triangles that merely touch never share a texel. Each texel counts once however
 * many triangles cover it: mirrored halves and REPEAT copies are paid for once, which is
 * what the texture's memory costs. For a layout without overlaps covered_texels tracks the
 * sum of texel areas to within the boundary texels of each chart.
 *
 * Texel positions outside the frame are taken with the wrap modes: REPEAT modulo the frame,
 * MIRROR reflected, CLAMP onto the edge texel (the clamped part covers the edge texel but is
 * never called an overlap: clamping shares no texel with another surface place on purpose).
 *
 * An overlap texel is a texel whose centre lies inside two triangles, or twice inside one
 * triangle that spans more than one REPEAT period: two surface places read it. Triangles
 * covering an overlap texel are "overlapping" (TEXOPT_TRI_OVERLAPS). A fold-over (flipped
 * triangle) overlaps its neighbours and is counted too.
 *
 * Cost: one scanline pass per triangle over two bit masks of width x height bits (2 MB each
 * for 4096^2), word-wide on long spans; a second pass finds the overlapping triangles. */
#ifndef TEXOPT_COVERAGE_H
#define TEXOPT_COVERAGE_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "model.h"
#include "status.h"

/* Frames past this many texels are refused (TEXOPT_E_LIMIT): 2 x 32 MB of masks. */
#define TEXOPT_COVERAGE_MAX_TEXELS (1ull << 28)

/* What to measure. A zero-initialised struct (or NULL) measures the mesh's own layout
 * (mesh->texel) in its own frame with its own wrap modes. */
typedef struct texopt_coverage_options {
    const double *texel; /* 2 per mesh vertex, texel units of the frame below;
                                 NULL = mesh->texel */
    int width, height;   /* frame; 0 = the mesh's */
    int use_wraps;       /* nonzero: wrap_s/wrap_t below; 0: the mesh's */
    texopt_wrap wrap_s, wrap_t;
    uint8_t *triangle_flags; /* when not NULL (mesh->triangle_count entries, e.g. mesh->flags):
                                 TEXOPT_TRI_OVERLAPS is set on overlapping triangles and cleared
                                 on the others; other bits untouched */
} texopt_coverage_options;

typedef struct texopt_coverage {
    int width, height;            /* the frame measured */
    uint64_t covered_texels;      /* unique texels with a triangle over their centre */
    uint64_t overlap_texels;      /* covered texels read by two surface places */
    size_t overlapping_triangles; /* triangles covering an overlap texel */
    double packing_efficiency;    /* covered_texels / (width * height) */
    double texel_area;            /* sum of |signed texel area| of non-degenerate triangles */
} texopt_coverage;

/* Measures the layout. Triangles degenerate in the layout measured (mesh.h's relative test:
 * TEXOPT_TRI_DEGENERATE_UV of the mesh's own layout) cover nothing; a triangle degenerate in
 * the input but not in a new layout is counted, as on the file written with it. Fails with
 * TEXOPT_E_INVALID_ARGUMENT for a bad frame or non-finite positions, TEXOPT_E_LIMIT for a
 * frame past TEXOPT_COVERAGE_MAX_TEXELS, a triangle spanning more than 4096 repeats of it or
 * triangles covering more than 2^36 texels together (a layout that repeats its texture that
 * often takes minutes to fill), TEXOPT_E_NOMEM. *out is written only on success. */
texopt_status texopt_coverage_measure(const texopt_mesh *mesh, const texopt_coverage_options *opt, texopt_coverage *out,
                                      char *err, size_t err_len);

/* Covered texels summed over every texture domain of the model (each domain in its own frame,
 * each texel of a domain counted once), for the relative cost c_r and the evaluation's
 * default resolution. */
texopt_status texopt_coverage_model_texels(const texopt_model *model, uint64_t *texels, char *err, size_t err_len);

#endif

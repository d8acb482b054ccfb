/* chart_cut.h - an axis-aligned chart cut into rectangle-like pieces along mesh edges (Liu
 * et al. 2019, "Atlas Refinement with Bounded Packing Efficiency", section 3.2 with the
 * variant "cutting along the existing edges").
 *
 * For one chart whose boundary is nearly axis-aligned (atlas_refine.h's output) and the
 * target polar angle of each boundary edge (axis_angles.h):
 *  1. its axis-aligned polygon: each run of boundary edges with one target direction is one
 *     side, at the run's length-weighted mean coordinate; a corner where the direction
 *     changes, at the loop vertex where it does;
 *  2. a rectangle decomposition of that polygon by motorcycle graphs (rect_decompose.h:
 *     random candidates scored by eq. 11, packing-efficiency bound; when no candidate
 *     reaches the bound, the best-scoring one regardless);
 *  3. each trail cut along mesh edges: a shortest path over interior edges from the trail's
 *     corner vertex to a vertex of the boundary or of an earlier path, an edge costing its
 *     length times 1 + PATH_OFF_TRAIL times its midpoint's distance from the straight trail
 *     (in mean edge lengths), the end vertex PATH_END_MISS times its distance from the
 *     trail's stop point; trails ending on another trail are cut after it. The triangles
 *     then fall into pieces by flood fill across edges that are on no path.
 * The pieces keep the chart's coordinates (no Tutte map onto the rectangles): the texel
 * allocation of the layout they come from is kept.
 * texopt_mesh_cut_create turns pieces into a mesh whose vertices are split where a piece
 * boundary runs through them, for packing (pack.h) and re-baking.
 * Not here: the deformation (axis_deform.h), packing, the model's vertex split for the
 * written file, distortion reduction (3.3). */
#ifndef TEXOPT_CHART_CUT_H
#define TEXOPT_CHART_CUT_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "status.h"

#define TEXOPT_CHART_CUT_CANDIDATES 500 /* N_motor of the paper */
#define TEXOPT_CHART_CUT_BOUND 0.8      /* PE_bound of the paper */

typedef struct texopt_chart_cut_options {
    int candidates;          /* decompositions drawn; 0 -> TEXOPT_CHART_CUT_CANDIDATES */
    double efficiency_bound; /* 0 -> TEXOPT_CHART_CUT_BOUND */
    double padding;          /* added to each rectangle's right and top when scoring */
    uint64_t seed;
} texopt_chart_cut_options;

typedef struct texopt_chart_cut {
    size_t piece_count;
    uint32_t *piece_of;        /* per triangle, 0..piece_count-1 */
    size_t corner_count;       /* polygon corners */
    size_t rect_count;         /* rectangles of the chosen decomposition */
    size_t trail_count;        /* trails cut along edges */
    size_t path_edges;         /* mesh edges on the cuts */
    double rect_efficiency;    /* the chosen rectangles' packing efficiency alone */
    double polygon_area_ratio; /* the polygon's area over the chart's */
} texopt_chart_cut;

/* Cuts the chart (vertex_count points xy, 2 each; triangle_count counter-clockwise
 * triangles, 3 local indices each) whose counter-clockwise boundary loop is loop[0..n) with
 * target angle theta[i] (quarter turns) for the edge loop[i] -> loop[i + 1]. opt may be
 * NULL. A chart already a rectangle comes out as one piece. Fails (E_INVALID_ARGUMENT, the
 * chart left uncut by the caller) when the runs do not alternate between the axes or the
 * polygon is not simple; out is the caller's to destroy on success. */
texopt_status texopt_chart_cut_compute(size_t vertex_count, const double *xy, size_t triangle_count,
                                       const uint32_t *triangle, const uint32_t *loop, const int *theta, size_t n,
                                       const texopt_chart_cut_options *opt, texopt_chart_cut *out, char *err,
                                       size_t err_len);

void texopt_chart_cut_destroy(texopt_chart_cut *cut);

/* A copy of mesh whose charts are the pieces (piece_of: per triangle, piece_count of them;
 * a piece lies within one chart) and whose vertices are split where pieces meet: a vertex
 * keeps its index in the piece of its first triangle, each further piece gets a copy
 * appended (same point, model vertex and texel). chart_sign is the source chart's,
 * vertex_on_boundary recomputed; vertex_of_model_vertex still names the original vertices.
 * *source (per vertex of the copy, caller frees; may be NULL) gets the vertex each one
 * repeats. */
texopt_status texopt_mesh_cut_create(const texopt_mesh *mesh, const uint32_t *piece_of, size_t piece_count,
                                     texopt_mesh **out, uint32_t **source, char *err, size_t err_len);

#endif

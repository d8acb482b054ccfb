/* atlas_refine.h - a layout's charts deformed toward axis-aligned shapes before packing
 * (Liu et al. 2019, "Atlas Refinement with Bounded Packing Efficiency", section 3.1).
 *
 * For each chart of a finished layout (stage 2's or a baseline's, any scale): its boundary
 * loop, the loop's target polar angles (axis_angles.h) and the angle-driven deformation
 * relative to that layout (axis_deform.h: symmetric Dirichlet to the given layout plus
 * boundary alignment, no triangle flips), so the texel allocation of the layout is kept
 * while the chart comes to fill more of its axis-aligned box and packs tighter (pack.h).
 * Charts free to turn are turned by the angles' rotation (any angle); the others (keep_angle:
 * perceptual charts, whose angle on the texel grid the mesh-wise stage chose) are refined
 * only when that rotation is at most TEXOPT_ATLAS_REFINE_MAX_TURN (the deformation's energy
 * is blind to rotations, so snapping their edges without the turn would turn them all the
 * same). A chart laid out clockwise (texel space has v down) is mirrored for the solve and
 * back.
 * Left as they are: charts in keep_shape (sharing groups must stay on each other), charts
 * that are not disks (param_chart.h: holes, handles, non-manifold edges), charts with a triangle
 * without area or against the chart's orientation (folds), and charts the angles or the
 * deformation refuse, and charts the deformation distorts past max_distortion (their mean
 * symmetric Dirichlet energy relative to the given layout, 1 = unchanged): a chart bent far
 * from the layout stage 2 solved loses the texel allocation the refinement is to keep.
 * texopt_atlas_cut then cuts the refined charts into rectangle-like pieces (chart_cut.h).
 * Not here: distortion reduction with the packing bound (3.3), packing. */
#ifndef TEXOPT_ATLAS_REFINE_H
#define TEXOPT_ATLAS_REFINE_H

#include <stddef.h>
#include <stdint.h>

#include "chart_cut.h"
#include "mesh.h"
#include "monitor.h"
#include "status.h"

/* The default max_distortion: about a quarter stretch one way and shrink the other. */
#define TEXOPT_ATLAS_REFINE_MAX_DISTORTION 1.1
/* Radians a keep_angle chart may be turned (about 3 degrees). */
#define TEXOPT_ATLAS_REFINE_MAX_TURN 0.05

typedef struct texopt_atlas_refine_report {
    size_t charts_refined, charts_skipped;
    size_t charts_too_distorted; /* of the skipped, those past max_distortion */
    size_t charts_kept_angle;    /* of the skipped, keep_angle charts past the largest turn */
    double distortion;           /* symmetric Dirichlet energy relative to the given layout, mean
                               weighted by texel area over all triangles (1: unchanged) */
    double boundary_before;      /* chart boundary length (texels of the given layout) */
    double boundary_after;
    double max_angle_error; /* radians, the largest boundary edge's miss of its target */
    double seconds;
    /* texopt_atlas_cut's, when it ran */
    size_t charts_cut;     /* charts cut into more than one piece */
    size_t pieces;         /* charts after the cut: pieces of the cut ones, the others whole */
    size_t cuts;           /* trails cut along mesh edges */
    size_t vertices_split; /* vertex copies the pieces need (texopt_mesh_cut_create) */
    double boundary_cut;   /* boundary length after the cut (texels) */
    double cut_seconds;
} texopt_atlas_refine_report;

/* Refines the layout `texel` (2 per mesh vertex) of `mesh`'s charts into texel_out (2 per
 * vertex; vertices of skipped charts and of no chart are copied). keep_shape (per chart,
 * nonzero: left as it is), keep_angle (per chart, nonzero: not turned) and report may be
 * NULL; max_distortion <= 0: no bound. Fails only on no memory or cancellation. */
texopt_status texopt_atlas_refine(const texopt_mesh *mesh, const double *texel, const uint8_t *keep_shape,
                                  const uint8_t *keep_angle, double max_distortion, double *texel_out,
                                  texopt_atlas_refine_report *report, const texopt_monitor *monitor, char *err,
                                  size_t err_len);

/* Largest polygon area over chart area (or its inverse) a chart may have to be cut: its
 * boundary runs must follow the polygon closely for the cuts to land on the trails. */
#define TEXOPT_ATLAS_CUT_AREA_RATIO 1.1

/* Cuts the charts of the layout `texel` (refined: texopt_atlas_refine's output) whose
 * boundary is nearly axis-aligned (axis_angles.h turns them by at most
 * TEXOPT_ATLAS_REFINE_MAX_TURN; polygon within TEXOPT_ATLAS_CUT_AREA_RATIO of the chart)
 * into pieces (chart_cut.h); the other charts, and those in keep_shape, stay whole.
 * piece_of (per triangle) gets the pieces numbered over the mesh, *piece_count their
 * number; the cut's fields of report (may be NULL) are filled. opt may be NULL. */
texopt_status texopt_atlas_cut(const texopt_mesh *mesh, const double *texel, const uint8_t *keep_shape,
                               const texopt_chart_cut_options *opt, uint32_t *piece_of, size_t *piece_count,
                               texopt_atlas_refine_report *report, const texopt_monitor *monitor, char *err,
                               size_t err_len);

/* Total length of the chart boundary edges (edges used by one triangle of a chart) of the
 * layout texel. */
double texopt_atlas_boundary_length(const texopt_mesh *mesh, const double *texel);

#endif

/* scaffold.h - bijective stage 2: the mesh-wise solve with scaffold triangles.
 *
 * Jiang, Schaefer and Panozzo 2017, "Simplicial complex augmentation framework for
 * bijective maps", as Sun et al. 2022 prescribe it (section 4.2, "Bijectivity", Fig. 19):
 * the space between and around charts inside a box is triangulated (triangulate.h: a
 * constrained triangulation of the chart boundaries and the box), those scaffold triangles
 * are solved with the charts' by stage 2 (meshwise.h, the scaffold option) under the same
 * anti-flip barrier with a small as-rigid-as-possible energy, re-meshed every few
 * iterations as they degrade, and dropped. The box corners stay put and no triangle of the
 * charts or the scaffold ever flips (the line search keeps every determinant positive along
 * the whole step), so a layout that starts without overlap ends without overlap: no chart
 * boundary crosses another or itself.
 *
 * Boxes: one per chart by default (stage 2 solves in the input frame and the packer places
 * the charts afterwards, so only a chart's overlap with itself needs the scaffold), or one
 * around all charts (one_box: they also keep clear of one another). A box is three times
 * its charts' extent and is rebuilt around them at every re-mesh, so charts can grow; or,
 * with one_box and a given box, that box at every re-mesh (Liu et al. 2019, section 3.3:
 * a fixed box slightly larger than a packed atlas bounds its packing efficiency).
 * A clean mirror (halves of opposite orientation welded at their mirror line, no fold-over:
 * mesh.h) is boxed half by half, so each half stays off itself while the halves keep lying
 * on one another. A chart that otherwise overlaps itself at the start (a fold, a boundary
 * through a vertex) cannot be made bijective by a scaffold: it is solved without one and
 * counted in charts_skipped. The job gives such charts a bijective start first under
 * `bijective` (chart_unfold.h: laid out anew as disks, a sharing group as one, their
 * targets restated), so only those it leaves alone stay skipped: sharing groups that would
 * still overlap, no disks. With one_box, charts
 * overlapping one another at the start skip the whole box.
 * Does not: change stage 2's energy on the charts, pack, or repair an overlapping start. */
#ifndef TEXOPT_SCAFFOLD_H
#define TEXOPT_SCAFFOLD_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "meshwise.h"
#include "monitor.h"
#include "status.h"
#include "target.h"

typedef struct texopt_scaffold_options {
    int one_box;            /* 1: every chart in one box; 0: a box per chart */
    const double *box;      /* with one_box, may be NULL: the box {x0, y0, x1, y1}, fixed (every
                              chart must lie inside it, else the box is skipped); NULL: three
                              times the charts' extent, rebuilt around them */
    const uint8_t *unboxed; /* with one_box, may be NULL: per chart, nonzero leaves it out of
                               the box (solved without scaffold, counted in no report field) */
    double weight;          /* scaffold energy per texel relative to the charts' mean; 0 -> 0.01 */
    int remesh_iterations;  /* stage 2 iterations between re-meshes; 0 -> 10 */
} texopt_scaffold_options;

typedef struct texopt_scaffold_report {
    int rounds; /* scaffolds built: re-meshes + 1 */
    size_t charts_scaffolded;
    size_t charts_skipped;           /* overlapping at the start: solved without a scaffold */
    size_t triangles;                /* scaffold triangles of the last round */
    texopt_meshwise_report meshwise; /* of the last round, iterations and seconds of all */
} texopt_scaffold_report;

/* texopt_meshwise_solve (same arguments, opt->scaffold ignored) with scaffold triangles:
 * stage 2 from initial_texel (NULL: mesh->texel), re-meshed every remesh_iterations
 * iterations until it converges or reaches opt->max_iterations in all. sopt and report may
 * be NULL. texel_out is written only on success. */
texopt_status texopt_scaffold_solve(const texopt_mesh *mesh, const texopt_triangle_target *targets,
                                    const double *initial_texel, const texopt_meshwise_options *opt,
                                    const texopt_scaffold_options *sopt, double *texel_out,
                                    texopt_scaffold_report *report, const texopt_monitor *monitor, char *err,
                                    size_t err_len);

/* Per chart of mesh, 1 in overlapping[] (chart_count bytes) when it overlaps itself in
 * the layout texel (the charts texopt_scaffold_solve skips with a box per chart); *count
 * (may be NULL) how many. */
texopt_status texopt_scaffold_overlapping_charts(const texopt_mesh *mesh, const double *texel, uint8_t *overlapping,
                                                 size_t *count, char *err, size_t err_len);

/* Texel centres (x + 0.5, y + 0.5 of the integer lattice) covered by two triangles of one
 * chart with one orientation (within: a chart over itself; the two sides of a fold are
 * not counted) and by triangles of two different charts (between: mirrored twins count),
 * in the layout texel. Triangles without area and centres on an edge count for neither.
 * For measurement and tests; layouts spanning more than 2^26 centres are refused. */
texopt_status texopt_count_overlap(const texopt_mesh *mesh, const double *texel, size_t *within, size_t *between,
                                   char *err, size_t err_len);

/* Per chart (chart_count entries), the centres texopt_count_overlap counts within it. */
texopt_status texopt_count_overlap_per_chart(const texopt_mesh *mesh, const double *texel, size_t *chart_within,
                                             char *err, size_t err_len);

#endif

/* target_restate.h - targets found for one layout of a mesh's triangles restated for
 * another layout of the same triangles.
 *
 * A target is the deformation J from a triangle's input texels to its output (target.h).
 * When stage 2 starts from another layout (new charts, domain_rechart.h; a chart laid out
 * anew, chart_unfold.h), the same output asks J' = J (d input / d new) of the new one. A
 * triangle whose map to the new layout mirrors keeps its stretch and loses its rotation
 * target; a degenerate triangle in either layout, and one the new layout does not move,
 * keeps its target as it is. Does not: find targets or solve. */
#ifndef TEXOPT_TARGET_RESTATE_H
#define TEXOPT_TARGET_RESTATE_H

#include "mesh.h"
#include "target.h"

/* Restates targets (NULL: nothing), found for `from`'s layout, for `to`'s; both meshes hold
 * the same triangles in the same order (their vertices may differ). */
void texopt_targets_restate(const texopt_mesh *from, const texopt_mesh *to, texopt_triangle_target *targets);

#endif

/* meshwise_loss.h - the perceptual loss of every triangle under a finished layout.
 *
 * After the mesh-wise solve, how many triangles still meet the loss threshold eps that
 * stage 1 aimed for (Sun et al. 2022, Fig. 16: the share of triangles with E <= eps after
 * the mesh-wise stage)? For each non-degenerate triangle, J = grad_phi from the input texel
 * triangle to the same triangle in `texel`, and E = texopt_triloss_eval(J) (triloss.h:
 * one-ring, LS bake, GMSD, max over the domain's textures). Translating a chart or turning
 * it by a quarter turn (what packing does) does not change E, so the layout may be the
 * solved one, the budget-scaled one or the packed one (J then includes the scale).
 *
 * Not here: the solve (meshwise.h), the whole-mesh evaluation from 20 views (evaluate.h). */
#ifndef TEXOPT_MESHWISE_LOSS_H
#define TEXOPT_MESHWISE_LOSS_H

#include <stddef.h>

#include "mesh.h"
#include "model.h"
#include "monitor.h"
#include "status.h"

typedef struct texopt_loss_share {
    size_t evaluated; /* triangles with a loss (not flagged degenerate) */
    size_t within;    /* of those, E <= epsilon */
    double share;     /* within / evaluated; 0 when nothing was evaluated */
    double mean_loss; /* mean E over the evaluated triangles */
    double max_loss;
} texopt_loss_share;

/* Evaluates E for every non-degenerate triangle of `mesh` (built from `model`'s domain
 * mesh->domain, with decoded images) under the layout `texel` (2 per mesh vertex, texel
 * units), its signals scaled by signal_weights as stage 1's were (triloss.h
 * texopt_triloss_weigh_signals; NULL: none). epsilon > 0 is the threshold; threads 0 -> every
 * online core; viewport 0 -> 64.
 * loss_out (may be NULL) receives mesh->triangle_count values, NaN for degenerate
 * triangles. The result does not depend on the thread count. The monitor gets stage
 * "stage2" progress and is checked between triangles. */
texopt_status texopt_meshwise_loss_share(const texopt_model *model, const texopt_mesh *mesh, const double *texel,
                                         const double *signal_weights, double epsilon, int threads, int viewport,
                                         double *loss_out, texopt_loss_share *out, const texopt_monitor *monitor,
                                         char *err, size_t err_len);

#endif

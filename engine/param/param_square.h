/* param_square.h - square parameterization with a searched boundary mapping (Dechvijankit,
 * Nagahashi and Yoshizawa 2013).
 *
 * The boundary loop goes onto the unit square: the vertex chosen for corner P00 starts it,
 * each side takes the boundary arc nearest to a quarter of its 3D length (the paper's
 * section 3), vertices spaced by arc length. The interior is the stretch-minimising map of
 * Yoshizawa et al. 2004 (mean-value embedding, param_tutte.h, reweighted by the L2 stretch
 * of Sander et al. at each vertex, the best of a few rounds kept). Which vertex becomes P00
 * is searched over the m boundary vertices within the first quarter of the loop (later ones
 * repeat the square turned by 90 degrees; m is the paper's "total test cases"), minimising
 * the L2 stretch by: brute force (all m), step sampling (the paper's Algorithm 2: every
 * step-th candidate, then the unchecked neighbours of the best), or particle swarm
 * optimisation (the paper's Algorithm 1, one dimension: arc length from the loop's start).
 * It does not parallelise the candidates. */
#ifndef TEXOPT_PARAM_SQUARE_H
#define TEXOPT_PARAM_SQUARE_H

#include <stddef.h>
#include <stdint.h>

#include "param_chart.h"
#include "status.h"

typedef enum texopt_square_search {
    TEXOPT_SQUARE_BRUTE_FORCE,
    TEXOPT_SQUARE_STEP_SAMPLING,
    TEXOPT_SQUARE_PSO
} texopt_square_search;

typedef struct texopt_square_params {
    texopt_square_search search;
    int step;                                /* step sampling; 0 = the paper's sqrt(vertices * m / faces) */
    int particles;                           /* PSO swarm size */
    int max_iterations;                      /* PSO */
    int stall_iterations;                    /* PSO stops when its global best holds this many iterations */
    double inertia, local_pull, global_pull; /* PSO a, b_l, b_g of the paper's eq. 1 */
    uint64_t seed;                           /* PSO */
    int stretch_rounds;                      /* Yoshizawa reweightings of each candidate's interior map */
} texopt_square_params;

void texopt_square_params_default(texopt_square_params *params);

typedef struct texopt_square_report {
    size_t candidates;               /* m */
    size_t evaluations;              /* stretch-minimising parameterizations run (distinct candidates) */
    size_t corner;                   /* boundary loop index of the vertex at P00 */
    double l2_stretch, linf_stretch; /* of the layout returned */
} texopt_square_report;

/* Lays out the disk `chart` on the unit square [0,1]^2: 2 doubles per vertex into uv
 * (caller-owned, 2 * vertex_count); report may be NULL. Fails with
 * TEXOPT_E_INVALID_ARGUMENT when the boundary has fewer than 4 vertices or the parameters
 * are out of range, and with TEXOPT_E_UNSUPPORTED when every candidate puts both ends of an
 * interior edge on one side of the square (an ear whose apex is no corner, a bridge across
 * a narrow part): the map would flatten its triangles (Floater 2003). The paper's method
 * assumes charts without such edges; candidates that have them are skipped, not
 * evaluated. */
texopt_status texopt_param_square(const texopt_param_chart *chart, const texopt_square_params *params, double *uv,
                                  texopt_square_report *report, char *err, size_t err_len);

#endif

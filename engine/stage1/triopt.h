/* triopt.h - the triangle-wise stage: per triangle, the Jacobian that minimises texel area
 * under a perceptual-loss constraint, and how sensitive the loss is to rotation and stretch.
 *
 * Sun et al. 2022, section 4.1.2 (eq. 14) and eq. 17. For every non-degenerate triangle T
 * of a texture domain's mesh, minimise over (alpha, lambda1, lambda2, beta) in
 * [0, pi/2) x (lambda_min, 1]^2 x [0, pi/2)
 *     f = lambda1 lambda2 |T| + L_eps(E(J)),   L_eps(x) = -log(eps - x) for x < eps,
 * with |T| the triangle's area in texels and E the one-ring GMSD loss (triloss.h), by
 * golden-section line searches and Bayesian optimisation (bayesopt.h) on the unit box,
 * x -> (alpha, lambda1, lambda2, beta) =
 * (x0 pi/2, lmin + (1 - lmin) x1, lmin + (1 - lmin) x2, x3 pi/2). E >= eps is infeasible: the
 * objective returns +INFINITY and bayesopt.h's penalty rule applies.
 *
 * Evaluation plan per triangle (measured in BENCHMARKS.md@9f788a8, "Stage 1"):
 *  1. J = lambda_min I. If it loses nothing (f within 1e-6 of the objective's lower bound
 *     lambda_min^2 |T| - log(eps)), no J can do better: stop, with w_rotation = w_stretch = 0
 *     (E is 0 over the whole box, so eq. 17's variances are 0; sampling them confirmed it).
 *     Flat-coloured and smoothly shaded triangles end here after one evaluation.
 *  2. A golden-section search over isotropic shrinks lambda I (isotropic_steps evaluations),
 *     then up to anisotropic_passes anisotropic refinements: from the best point, probe
 *     squeezing lambda1 or lambda2 at orientations beta on a grid of anisotropic_directions
 *     (default 8: edges of real textures run at any angle; 2 would be the texel axes and
 *     diagonals of Fig. 7), and golden-section search the best probe's direction
 *     (anisotropic_steps evaluations). The first refinement probes coarse to fine (every
 *     other orientation, then the two next to the best: directions + 2 probes); later ones
 *     only the orientation found and its two neighbours (6 probes).
 *  3. A Bayesian-optimisation polish (unless iterations = -1) whose surrogate starts from
 *     every point steps 1-2 evaluated (known values, no new design) and that stops after
 *     polish_patience evaluations in a row gaining less than polish_stop of f, or at the
 *     lower bound: `iterations` (default 100, the paper's budget) is a cap the default
 *     stop rarely reaches (it adds about 1 evaluation per triangle on the benchmark models).
 * Candidates whose area term alone (E = 0) cannot beat the point a search compares them
 * with are not evaluated: the search's decisions and result are the same.
 * The `plain` option runs the paper's plan instead (J = I, the design, the iterations), the
 * reference the benchmark compares against.
 *
 * Weights (eq. 17): w_rotation = variance of E over weight_samples stratified uniform
 * alpha at (lambda1*, lambda2*, beta*); w_stretch = variance of E over weight_samples
 * uniform (lambda1, lambda2, beta) at alpha*, drawn as a Latin hypercube. Both are population
 * variances (divide by the count) of E, not clipped at eps, taken over the signals that
 * decided the search (texopt_triloss_keep_deciding: those that gave E in one of its
 * evaluations; a single-signal domain is unaffected). On DamagedHelmet that is 2.5 of 8
 * active signals per triangle for 6-10% less CPU, and the weights rank the triangles against
 * a 32-sample estimate as the full maximum does (BENCHMARKS.md@9f788a8, "Stage 1").
 *
 * Determinism: triangle t draws from seed_t = mix(seed, t) and nothing else, and threads
 * only decide who computes which triangle, so the output is identical for any thread count.
 * Degenerate triangles (flags DEGENERATE_3D/UV) get J = I, zero weights, no evaluation. */
#ifndef TEXOPT_TRIOPT_H
#define TEXOPT_TRIOPT_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "model.h"
#include "monitor.h"
#include "status.h"
#include "target.h"

/* Zero-initialised = defaults. */
typedef struct texopt_triopt_options {
    double epsilon;    /* loss threshold; 0 -> 0.01 */
    int iterations;    /* most BO iterations of the polish (plain: after the design);
                            0 -> 100, -1 -> no BO at all */
    double lambda_min; /* 0 -> 0.1; must be in (0, 1) */
    int threads;       /* 0 -> every online core */
    uint64_t seed;
    int viewport;                 /* 0 -> 64 */
    int weight_samples;           /* per weight; 0 -> 4, < 0 -> weights not computed (left 0) */
    int initial_design;           /* BO Latin-hypercube points; 0 -> none in the polish, bayesopt's
                            default in the plain plan; < 0 -> none */
    int no_lower_bound_stop;      /* non-zero: run every iteration (for benchmarks) */
    int plain;                    /* non-zero: the paper's plan for benchmarks: only J = I before the
                            design, no flat test, no isotropic search, no lower-bound stop */
    int isotropic_steps;          /* evaluations of the isotropic golden-section search; 0 -> 8,
                            < 0 -> none */
    int anisotropic_steps;        /* golden-section evaluations of one anisotropic refinement (after
                              its 2 x anisotropic_directions probes); 0 -> 8, < 0 -> none */
    int anisotropic_directions;   /* squeeze orientations probed in [0, pi/2); 0 -> 8
                                   (every 11.25 degrees) */
    int anisotropic_passes;       /* refinements repeated from the last result while they improve
                               f; 0 -> 3, < 0 -> none */
    double polish_stop;           /* the polish ends after polish_patience evaluations in a row that
                            lower the best f by less than this share of it; 0 -> 0.001,
                            < 0 -> never (all `iterations`) */
    int polish_patience;          /* 0 -> 1 */
    int paper_window;             /* non-zero: Sun et al.'s appendix A window (triloss.h
                                     texopt_triloss_use_paper_window), and eq. 17's weights over
                                     every signal, not only the deciding ones */
    uint32_t stride;              /* optimise triangles 0, stride, 2 stride, ...; 0 or 1 -> all.
                            Others are left as J = I, zero weights, 0 evaluations. */
    const double *signal_weights; /* the loss's signal scales (triloss.h
                                     texopt_triloss_weigh_signals), NULL -> 1 */
} texopt_triopt_options;

typedef struct texopt_triopt_report {
    size_t optimised;          /* triangles searched */
    size_t skipped;            /* degenerate or outside the stride */
    long long evaluations;     /* loss evaluations, searches and weights */
    size_t close_up_triangles; /* optimised triangles whose loss also took close-ups
                                  (triloss.h: seen at over 1.5 x the zoom limit, and a
                                  probe shrink shows a loss in some window inside) */
    double seconds;            /* wall clock */
    double cpu_seconds;        /* CPU time summed over the worker threads (load-independent) */
    double mean_loss;          /* mean E at the optimum over optimised triangles */
    double mean_area_scale;    /* mean lambda1 lambda2 */
    double mean_objective;     /* mean f at the optimum */
} texopt_triopt_report;

/* Runs the stage on every triangle of `mesh` (a domain mesh of `model`) and writes
 * out[mesh->triangle_count]. opt and report may be NULL; monitor may be NULL (progress with
 * stage "stage1", stage_fraction = fraction of triangles done; the callback is serialised by
 * a mutex). A raised cancel flag stops at the next triangle with TEXOPT_E_CANCELED (out is
 * then incomplete). */
texopt_status texopt_triopt_run(const texopt_model *model, const texopt_mesh *mesh, const texopt_triopt_options *opt,
                                texopt_triangle_target *out, texopt_triopt_report *report,
                                const texopt_monitor *monitor, char *err, size_t err_len);

#endif

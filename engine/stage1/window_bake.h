/* window_bake.h - the least-squares bake of a candidate texture (Sun et al. 2022, eq. 11).
 *
 * Given screen pixels that look up the candidate texture at texel positions p(q) (with
 * bilinear weights, see sample.h) and the reference colours I_hat(q) those pixels should
 * show, find the texel values x that reproduce the reference best:
 *     x = argmin |A x - I_hat|^2 + ridge |x - mean(I_hat)|^2
 * A = bilinear weight matrix (pixels x touched texels, 4 non-zeros a row). The unknowns are
 * only the texels touched by some footprint; the ridge pulls directions no pixel constrains
 * toward the mean reference colour, so the system is always positive definite. All channels
 * share one factorisation (up to TEXOPT_BAKE_MAX_CHANNELS right-hand sides: A depends only
 * on the positions, so every signal sampled through the same footprints -- colour channels,
 * normal, ORM and emissive maps of one size -- costs one Cholesky and one cheap triangular
 * solve pair each; each channel's result is the same as a fit of that channel alone).
 * Returns the reconstruction A x, i.e.
 * what the screen shows with the baked texture (DESIGN.md 3.1).
 *
 * Speed: the touched texels are numbered in texture row-major order, or column-major when
 * the patch is wider than tall, so A^T A is banded (bandwidth about one patch row or column,
 * the shorter; only its envelope is worked on) and is solved with
 * banded Cholesky: an own vectorised loop for narrow bands, LAPACK dpbtrf for wide ones
 * (window_bake.c says why).
 * The workspace owns every buffer and only grows, so the hot loop does not allocate once it
 * has seen its largest problem. A workspace is for one thread at a time.
 *
 * Not here: rendering, colour conversion, choosing the ridge (callers pass e.g. 1e-6). */
#ifndef TEXOPT_BAKE_H
#define TEXOPT_BAKE_H

#include "model.h"
#include "status.h"

typedef struct texopt_bake_workspace texopt_bake_workspace;

/* Most right-hand sides of one fit. */
#define TEXOPT_BAKE_MAX_CHANNELS 16

/* A workspace sized for up to max_pixels pixels of up to max_channels channels
 * (1..TEXOPT_BAKE_MAX_CHANNELS).
 * Returns NULL on bad arguments or out of memory. */
texopt_bake_workspace *texopt_bake_workspace_create(int max_pixels, int max_channels);

/* Accepts NULL. */
void texopt_bake_workspace_destroy(texopt_bake_workspace *ws);

/* How the normal equations are factored. AUTO (the default) picks by bandwidth and CPU; the
 * others force one path (tests and benchmarks compare them). VECTOR4 needs AVX2 and FMA and
 * falls back to VECTOR2 on CPUs without them. All give the same result to rounding. */
typedef enum texopt_bake_solver {
    TEXOPT_BAKE_SOLVER_AUTO = 0,
    TEXOPT_BAKE_SOLVER_VECTOR2, /* own right-looking loop, two lanes (SSE2) */
    TEXOPT_BAKE_SOLVER_VECTOR4, /* the same, four lanes with FMA */
    TEXOPT_BAKE_SOLVER_LAPACK   /* LAPACK dpbtrf */
} texopt_bake_solver;

/* Ignores NULL workspaces and unknown values. */
void texopt_bake_workspace_set_solver(texopt_bake_workspace *ws, texopt_bake_solver solver);

/* Which system is factored. TEXEL: the normal equations A^T A + r I (unknowns x unknowns).
 * PIXEL: A A^T + r I (pixels x pixels) and x = m + A^T z, the same minimiser by the
 * push-through identity, cheaper when a minified patch has more texels than pixels. AUTO
 * (the default) takes the pixel side when there are more unknowns than pixels and its
 * banded factorisation costs less. Both give the same result to rounding. */
typedef enum texopt_bake_side {
    TEXOPT_BAKE_SIDE_AUTO = 0,
    TEXOPT_BAKE_SIDE_TEXEL,
    TEXOPT_BAKE_SIDE_PIXEL
} texopt_bake_side;

/* Ignores NULL workspaces and unknown values. */
void texopt_bake_workspace_set_side(texopt_bake_workspace *ws, texopt_bake_side side);

/* Fits the texels and writes the reconstruction.
 *   pixel_count   number of pixels (<= max_pixels); 0 is allowed and does nothing
 *   texel_pos     2 doubles per pixel: the candidate texel position p(q) = J p_hat(q)
 *   reference     channels floats per pixel: the colour the pixel should show
 *   channels      1..max_channels
 *   width, height the candidate texture grid the positions refer to (> 0)
 *   wrap_s/wrap_t its wrap modes
 *   ridge         > 0 (tiny, e.g. 1e-6: the fit stays almost pure least squares)
 *   reconstruction channels floats per pixel (A x); may not alias reference
 * err/err_len: optional message buffer. TEXOPT_E_NUMERIC when the solve fails. */
texopt_status texopt_bake_fit(texopt_bake_workspace *ws, int pixel_count, const double *texel_pos,
                              const float *reference, int channels, int width, int height, texopt_wrap wrap_s,
                              texopt_wrap wrap_t, double ridge, float *reconstruction, char *err, size_t err_len);

/* The last successful fit (with pixels) again for other right-hand sides: same pixels,
 * positions, grid and ridge, new reference (channels floats per pixel). Reuses its
 * factorisation, so it costs only the solves; a channel gets the same values as in a fit
 * with the same channel count. Fails with TEXOPT_E_INVALID_ARGUMENT before any such fit. */
texopt_status texopt_bake_refit(texopt_bake_workspace *ws, const float *reference, int channels, float *reconstruction,
                                char *err, size_t err_len);

/* Number of unknown texels of the last successful fit (for benchmarks and tests). */
int texopt_bake_last_texel_count(const texopt_bake_workspace *ws);

/* Bandwidth kd of the system the last successful fit factored (for benchmarks and tests). */
int texopt_bake_last_bandwidth(const texopt_bake_workspace *ws);

/* The side (TEXEL or PIXEL) the last successful fit solved; AUTO before any. */
texopt_bake_side texopt_bake_last_side(const texopt_bake_workspace *ws);

#endif

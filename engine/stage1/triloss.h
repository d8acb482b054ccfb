/* triloss.h - the perceptual loss E of one candidate Jacobian for one triangle.
 *
 * Sun et al. 2022, section 4.1.1 (eqs. 9-12): render the triangle's one-ring with the input
 * texture (reference I_hat) and with the texture re-baked under the deformation J
 * (candidate I), and compare them with GMSD (Xue et al. 2013) on the covered pixels.
 * Here the one-ring is rasterised once per triangle (uvraster.h) and each candidate is:
 *   p(q) = c + J (p_hat(q) - c)        c = the texel centre nearest the triangle's centroid,
 *                                       so the triangle stays put and a quarter turn maps the
 *                                       texel lattice onto itself (the grid's 90-degree symmetry)
 *   x    = LS bake of I_hat on the bilinear footprints of p(q) (window_bake.h, eq. 11, ridge 1e-6)
 *   I(q) = A x                          what the screen shows with the baked texture
 *   E    = max over the domain's textures and their signals of GMSD(I_hat, I, covered mask),
 *          each signal scaled by its weight when the caller gives them
 *          (texopt_triloss_weigh_signals: what a lit render shows of it, lit_weight.h)
 *
 * Signals of a texture: colour textures (base colour, emissive, or an image of no known
 * role) contribute their luma (BT.601, as the GMSD reference); data textures (normal,
 * metallic-roughness, occlusion, extensions' maps) contribute each channel their binding reads
 * (model.h texopt_material_binding_channels: metallic-roughness G and B, occlusion R,
 * specular strength A) as its own signal in their stored encoding, because luma would mix
 * unrelated quantities (ORM) or cancel opposite tilts of a normal. Alpha counts where a
 * binding reads it: an extension's map, or base colour under alphaMode MASK or BLEND. An image
 * that lacks every channel its bindings read is compared on R, G and B. The bake is linear and shares
 * its matrix across channels, so baking luma equals taking the luma of the baked colour:
 * one signal per colour texture is exact, not an approximation. Signals of textures of equal
 * size share one bake call (up to 16 right-hand sides: one factorisation for all of them).
 *
 * Close-ups: the one-ring's window shows the whole triangle, so a triangle spanning more than
 * the viewport at the zoom limit (uvraster.h; WaterBottle's largest at 5-12 input texels per
 * pixel) is seen blurred, and fine detail in it counts for nothing: such triangles came out
 * of stage 1 lossless at lambda_min and lost on screen. Where the window shows the triangle,
 * at its own texel density, at over 1.5 times the limit, E is also taken on up to
 * TEXOPT_TRILOSS_CLOSE_UPS windows at the limit inside the triangle (the same camera frame
 * and pivot; 1,400 pixels each), those whose E under J = 0.25 I is largest among a grid of
 * candidates: E is the maximum over the one-ring's view and the close-ups (BENCHMARKS.md@9f788a8
 * "Close-ups").
 *
 * The candidate grid: J moves texels to a new layout whose wrap mode does not matter, so
 * positions are shifted by a whole number of texels to the middle of a grid large enough
 * that the one-ring never wraps (the sub-texel phase, which decides the bilinear weights,
 * is kept).
 *
 * A texopt_triloss holds every buffer (raster, references, bake and GMSD workspaces) and is
 * for one thread at a time; after texopt_triloss_prepare, texopt_triloss_eval does not
 * allocate (the bake workspace grows only on a larger problem than any seen before). */
#ifndef TEXOPT_TRILOSS_H
#define TEXOPT_TRILOSS_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"
#include "model.h"
#include "status.h"
#include "uvraster.h"

typedef struct texopt_triloss texopt_triloss;

/* Most close-up windows per triangle, besides the one-ring's. */
#define TEXOPT_TRILOSS_CLOSE_UPS 6

/* A loss evaluator for the triangles of `mesh` (built from `model`'s domain mesh->domain),
 * viewport x viewport pixels (paper: 64), with TEXOPT_TRILOSS_CLOSE_UPS evaluators of the same
 * size inside for the close-ups. model and mesh must outlive it. Fails with
 * TEXOPT_E_UNSUPPORTED when the domain has no decoded image. */
texopt_status texopt_triloss_create(texopt_triloss **out, const texopt_model *model, const texopt_mesh *mesh,
                                    int viewport, char *err, size_t err_len);

/* Scales each signal by its weight before it is compared: weights as texopt_lit_signal_weights
 * fills them (lit_weight.h; per image, luma then channels 0..3), NULL for none. Call before
 * texopt_triloss_prepare. A weight of 0 leaves the signal out (constant). */
void texopt_triloss_weigh_signals(texopt_triloss *loss, const double *weights);

/* Sun et al.'s window from now on (uvraster.h paper_window): the triangle's corners framed,
 * no zoom limit, no pixel cap, no close-ups, no redraw of a hidden triangle. Call before
 * texopt_triloss_prepare. */
void texopt_triloss_use_paper_window(texopt_triloss *loss);

/* Accepts NULL. */
void texopt_triloss_destroy(texopt_triloss *loss);

/* Rasterises the one-ring of `triangle` and samples the reference signals. Fails with
 * TEXOPT_E_INVALID_ARGUMENT for an index out of range or a triangle degenerate in 3D. */
texopt_status texopt_triloss_prepare(texopt_triloss *loss, uint32_t triangle, char *err, size_t err_len);

/* E for the 2x2 Jacobian J (row-major: J[0] J[1] / J[2] J[3]) of the prepared triangle.
 * Stops early and returns a value >= stop_above as soon as one signal reaches stop_above
 * (pass INFINITY for the exact maximum). With a finite stop_above, the signal of each bake
 * batch that had the largest E at the last evaluation of this triangle is solved first and
 * alone (the others, when needed, reuse its factorisation: texopt_bake_refit), so a
 * candidate that fails on that signal costs one solve; E then equals the INFINITY value to
 * rounding. Same triangle, same sequence of calls: same E, bit for bit. */
texopt_status texopt_triloss_eval(texopt_triloss *loss, const double jacobian[4], double stop_above, double *out_loss,
                                  char *err, size_t err_len);

/* Until the next texopt_triloss_prepare, compares only the deciding signals: those that gave
 * the returned E of some evaluation since the prepare (the maximum, or the signal that
 * reached stop_above). E is then the maximum over them, at most the full one. Triopt
 * evaluates eq. 17's weight samples this way after the search: on DamagedHelmet 2.5 of 8
 * active signals decide, and the weights rank the triangles as the full maximum does
 * (BENCHMARKS.md@9f788a8, "Stage 1"). Does nothing when no signal has decided (every E was 0). */
void texopt_triloss_keep_deciding(texopt_triloss *loss);

/* The raster of the prepared triangle (covered pixels, camera). */
const texopt_uvraster *texopt_triloss_raster(const texopt_triloss *loss);

/* Close-up windows the prepared triangle is also judged on (0 for a triangle its window
 * shows near the zoom limit). */
int texopt_triloss_close_up_count(const texopt_triloss *loss);

/* Number of signals compared per candidate (for reports and tests). */
int texopt_triloss_signal_count(const texopt_triloss *loss);

/* J = R(alpha) V(beta) diag(lambda1, lambda2) V(beta)^T, R and V rotations (paper eq. 13). */
void texopt_jacobian_from_params(double alpha, double lambda1, double lambda2, double beta, double jacobian[4]);

#endif

/* lit_weight.h - how much of each texture signal a lit render shows: per image and channel, the
 * mean size of the change of the lit luma (lit_shade.h) per unit change of that signal,
 * divided by the same for the base colour's luma.
 *
 * Stage 1 compares every signal of a domain's textures and keeps the worst (triloss.h). A map
 * whose channel the light barely shows (roughness of a matte paint, a metallic map that is
 * nearly all zero or all one) then holds a triangle at full density by itself, and the
 * budget's rescale takes those texels from every map. Scaled by its weight, a signal keeps
 * the contrast the render gives it: GMSD of w x against w y is GMSD with the constant T / w^2,
 * so weak variations count as weak and strong edges still count.
 *
 * Estimated by sampling: points spread over the textured surface by 3D area, each seen from
 * directions drawn about its face normal with density proportional to the cosine (an
 * orthographic view shows a face at its projected area), the light fixed to the view as
 * lit_shade.h places it, turned about the view by a random angle (the view's roll); central
 * differences of L at each point and direction, with every slot that reads the image
 * changed at once. Normal maps are read in the face's own tangent frame (x, y, z = T, B, N):
 * the light's direction about the normal is random anyway, so the model's frames are not
 * needed. Fixed seed: the same model gives the same weights.
 *
 * A model without a map the light reads besides base colour (texopt_lit_has_maps) gets 1
 * everywhere, as does an image no sampled point reads (among them one that only material
 * extensions bind, model.h, which the lit render does not shade): stage 1 is then unchanged.
 *
 * Does not: weigh per triangle (one weight per signal for the whole model), read baseColor
 * or emissive factors (lit_shade.h does not either), or decide what stage 1 does with the
 * weights (triopt.h). */
#ifndef TEXOPT_LIT_WEIGHT_H
#define TEXOPT_LIT_WEIGHT_H

#include <stddef.h>

#include "model.h"
#include "status.h"

/* Weights per image: [0] its luma (colour textures), [1..4] its channels 0..3 as stage 1
 * compares them (data textures; a one- or two-channel image has [1] only). Alpha, which the lit
 * render does not show (a cut-out or a specular strength), stays 1, as do [2..4] of an image
 * without those channels. */
#define TEXOPT_LIT_WEIGHT_STRIDE 5

/* Fills weights[TEXOPT_LIT_WEIGHT_STRIDE * model->image_count] (the caller's). */
texopt_status texopt_lit_signal_weights(const texopt_model *model, double *weights, char *err, size_t err_len);

#endif

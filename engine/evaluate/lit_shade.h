/* lit_shade.h - the luma of a textured model lit by one directional light: what a user sees
 * of all the maps a layout re-bakes at once, not of one texture's encoding.
 *
 * Per covered pixel of a raster (meshrender.h, the same pixels for reference and candidate),
 * a metallic-roughness material under one directional light and a uniform grey sky:
 *   L = min(1, occlusion * (b (1 - m) (A + (1 - A) max(0, n . l)) + f0 A + S) + e)
 *   f0 = 0.04 (1 - m) + b m,   S = (1 - A) pi D(n . h) V(n . l, n . v) F(v . h) max(0, n . l)
 * b the luma of baseColor as the evaluation's q reads it (mid grey 0.5 where the material has
 * none, no factor); m and r the material's metallic and roughness factors (model.h, glTF's
 * default 1 and 1) times the metallic-roughness texture's B and G where it has one;
 * occlusion its R (1 where none); e the emissive texture's luma (0 where none). S is Cook-Torrance's
 * specular: GGX D with alpha = max(r, 0.05)^2, Smith-Schlick V (k = alpha / 2), Schlick's F;
 * h the half vector of l and the view direction v (orthographic: the camera's direction).
 * The sky (A) lights the diffuse part and, at f0, the specular one, so a metal is not black
 * away from its highlight. The roughness map shows as the highlights' size and the metallic
 * map as the metal's darker diffuse and coloured reflection: what the other terms cannot
 * tell. The minimum with 1 is what a display without tone mapping shows. The factors are the
 * reference's (as the tangent frames): a re-baked output keeps its input's materials. The
 * emissive texture is taken at factor 1 (model.h does not load emissiveFactor), as the
 * assets with an emissive map set it (DamagedHelmet, WaterBottle).
 * n is the normal map's tangent-space normal (2 rgb - 1, renormalised) in world space, or the
 * surface normal N where the material has no normal map.
 *
 * N is the REFERENCE's vertex normal (its file's NORMAL, model.h) interpolated across the
 * triangle, as a viewer shades it; the flat face normal where the file has none (glTF's rule).
 * Flat facets would put whole faces on a highlight's steep flank and weigh the texels
 * under them far beyond what a viewer shows. Tangent frame: per triangle T = dP/du,
 * B = -dP/dv (glTF's +Y is up in the image) from the reference's positions and UVs; per pixel
 * T Gram-Schmidt against N and B = +-N x T with the triangle's UV winding; where the UV map
 * is degenerate n = N. Stored TANGENT is not used: both renders shade the same geometry in
 * the same frame (the reference's), and the candidate's map is turned back into that frame
 * by the caller (normal_turn, exactly as the evaluation's normal slot, evaluate.h), so an
 * unchanged layout shades bit for bit the same.
 *
 * Light: one directional light per view, fixed to that view's camera,
 * l = normalize(0.5 right + 0.5 up + 0.7 direction) (texopt_view; direction points at the
 * camera): faces towards the camera and the upper right are lit, so relief shows as shading
 * on every visible face instead of vanishing under a head-on light.
 *
 * Does not: light with an environment map or image-based lighting (one light and a uniform
 * sky), shade colour (luma only: f0 of a metal is its base colour's luma), use
 * baseColorFactor or vertex colours, or compare images (evaluate.h). */
#ifndef TEXOPT_LIT_SHADE_H
#define TEXOPT_LIT_SHADE_H

#include <stddef.h>

#include "meshrender.h"
#include "model.h"
#include "status.h"

/* Share of the light that does not depend on n: with none, faces turned from the light are
 * black in both renders and their maps' detail would count for nothing; 0.3 keeps it
 * visible at a third of the contrast of lit faces, as a sky/fill light does. */
#define TEXOPT_LIT_AMBIENT 0.3

/* Reflectance at normal incidence of a dielectric (glTF's 0.04, an index of refraction of
 * 1.5), and the smallest roughness shaded: below it GGX's highlight is narrower than a
 * pixel of the evaluation and would alias. */
#define TEXOPT_LIT_DIELECTRIC_F0 0.04
#define TEXOPT_LIT_MIN_ROUGHNESS 0.05

/* Floats per pixel of texopt_lit_shade's scratch. */
#define TEXOPT_LIT_SCRATCH_FLOATS 5

struct texopt_texture_filter;

/* Per triangle tangent frames of the reference (see the top). */
typedef struct texopt_lit_frames texopt_lit_frames;

texopt_status texopt_lit_frames_create(const texopt_model *reference, texopt_lit_frames **out, char *err,
                                       size_t err_len);
void texopt_lit_frames_destroy(texopt_lit_frames *frames);

/* Nonzero when the model has a texture that lighting reads besides base colour
 * (metallic-roughness, normal, occlusion, emissive): without one, the lit luma is base
 * colour's luma under a shading both renders share. */
int texopt_lit_has_maps(const texopt_model *model);

/* The view's light direction l (unit). */
void texopt_lit_light(const texopt_view *view, double l[3]);

/* L at one point (the formula at the top): b the base-colour luma, metallic and roughness with
 * their factors applied, n the shading normal and l, v the light and view directions (unit,
 * in any one frame), occlusion and the emissive luma. Clamped to 1 as texopt_lit_shade's. */
double texopt_lit_point(double b, double metallic, double roughness, const double n[3], const double l[3],
                        const double v[3], double occlusion, double emission);

/* The lit luma of `model` (same triangles as the frames' reference) over `raster` into
 * luma[side * side] (background 0). filters: per image pyramid, or NULL (bilinear);
 * normal_turn: per triangle (cos, sin) for the normal map's XY (meshrender.h), or NULL;
 * scratch: TEXOPT_LIT_SCRATCH_FLOATS floats per pixel, the caller's. */
texopt_status texopt_lit_shade(const texopt_model *model, const texopt_raster *raster, const texopt_lit_frames *frames,
                               struct texopt_texture_filter *const *filters, const double *normal_turn, float *scratch,
                               float *luma, char *err, size_t err_len);

#endif

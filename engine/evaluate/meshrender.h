/* meshrender.h - renders a whole textured model from the evaluation's cameras.
 *
 * Sun et al. 2022, "Efficient Texture Parameterization Driven by Perceptual-Loss-on-Screen",
 * section 5.1: the whole-mesh loss looks at the model from 20 cameras on the vertices of a
 * regular dodecahedron around its bounding sphere, all looking at the centre. The cameras
 * here are orthographic (the window is the bounding sphere's diameter), so screen-space
 * interpolation of texture coordinates is exact and needs no perspective division.
 *
 * Rendering is split in two so that a reference and a candidate with the same geometry are
 * seen through exactly the same pixels: texopt_meshrender_rasterize depth-tests the geometry
 * once and keeps, per pixel, the model triangle and its barycentrics; texopt_meshrender_shade
 * then looks each pixel up in any model with those triangles (its own UVs and images). This
 * header does not compare images (evaluate.h does). */
#ifndef TEXOPT_MESHRENDER_H
#define TEXOPT_MESHRENDER_H

#include <stdint.h>

#include "image.h"
#include "model.h"
#include "status.h"

#define TEXOPT_VIEW_COUNT 20

/* An orthographic view of the model: the camera looks along -direction at `centre`;
 * right/up span the screen; the window is [-half_extent, half_extent]^2 around the centre. */
typedef struct texopt_view {
    double centre[3];
    double direction[3]; /* unit, from the centre towards the camera */
    double right[3];     /* unit */
    double up[3];        /* unit */
    double half_extent;  /* world units, > 0 */
} texopt_view;

/* Per pixel of a side x side screen: the model triangle covering it (-1: background) and the
 * barycentric weights of the triangle's second and third corners (the first's is 1 - b1 - b2). */
typedef struct texopt_raster {
    texopt_view view; /* the view it was rasterised from */
    int side;
    int32_t *triangle; /* side * side, row 0 on top */
    float *bary;       /* 2 per pixel */
    size_t covered;    /* pixels with a triangle */
} texopt_raster;

/* Fills views[0..TEXOPT_VIEW_COUNT) with the 20 dodecahedron cameras around the bounding
 * sphere of the model's vertices (centre = bounding-box centre). Fails on a model with no
 * triangles, or (TEXOPT_E_UNSUPPORTED, valid input with nothing to see) every vertex at one
 * point. */
texopt_status texopt_meshrender_views(const texopt_model *model, texopt_view *views, char *err, size_t err_len);

/* Camera sets. The dodecahedron's 20 are the evaluation's (the paper's, what q and the
 * benchmark report). The icosahedron's 12 look from the dodecahedron's face centres, between
 * those 20: a layout tuned on what one set sees (the pipeline's closed-loop refinement) is
 * then graded on views it was not tuned on. */
typedef enum texopt_camera_set { TEXOPT_CAMERAS_DODECAHEDRON = 0, TEXOPT_CAMERAS_ICOSAHEDRON } texopt_camera_set;

/* As texopt_meshrender_views for any set: views[0..*count) (room for TEXOPT_VIEW_COUNT). */
texopt_status texopt_meshrender_camera_set(const texopt_model *model, texopt_camera_set set, texopt_view *views,
                                           int *count, char *err, size_t err_len);

/* Rasterises every triangle of the model into *out (allocated here; free with
 * texopt_raster_destroy), depth-tested, pixel centres sampled. side in [8, 16384]. */
texopt_status texopt_meshrender_rasterize(const texopt_model *model, const texopt_view *view, int side,
                                          texopt_raster *out, char *err, size_t err_len);

void texopt_raster_destroy(texopt_raster *raster);

/* Shades a raster made from a model with the same triangles as `model`: each covered pixel
 * gets the base colour of `model` at the interpolated TEXCOORD_0, bilinear, with the
 * texture's wrap modes; a triangle whose material has no base colour texture is mid grey;
 * background pixels are 0. *out becomes a side x side RGB image (allocated here).
 * Fails when the model's triangle count is not the raster's model's (checked by the caller
 * through texopt_meshrender_same_geometry) or it has no UVs. */
texopt_status texopt_meshrender_shade(const texopt_model *model, const texopt_raster *raster, texopt_image *out,
                                      char *err, size_t err_len);

struct texopt_texture_filter;

/* As texopt_meshrender_shade, with prefiltered (mip-mapped, anisotropic) lookups as a GPU's
 * trilinear/anisotropic sampler would do: the footprint of a pixel in the texture is the
 * triangle's screen-to-texel Jacobian (constant per triangle under an orthographic camera).
 * filters[i] is the texture_filter.h pyramid of model->images[i] (NULL entries fall back to
 * bilinear); the raster must come from texopt_meshrender_rasterize of the same geometry. */
texopt_status texopt_meshrender_shade_filtered(const texopt_model *model, const texopt_raster *raster,
                                               struct texopt_texture_filter *const *filters, texopt_image *out,
                                               char *err, size_t err_len);

/* As texopt_meshrender_shade_filtered (filters may be NULL: bilinear), writing only each
 * pixel's grey into the caller's side x side floats: what the evaluation compares, without
 * an RGB image. The texture read is the material's `texture`, a key of texture_keys.h (a
 * texopt_slot, or an extension texture such as clearcoatTexture). TEXOPT_SLOT_BASE_COLOR
 * gives texopt_luma of the RGB the shading functions above write, the same bits. Any other
 * texture read in R, G and B is shaded exactly the same way, its RGB encoding as if it were a
 * colour image (a normal map's XYZ as RGB); one read in fewer channels shows the mean of those
 * (occlusion's R, metallic-roughness's G and B, specular's A). Triangles whose material has no
 * such texture are mid grey. Base colour of a material whose alphaMode is MASK or BLEND is cut
 * or blended by its alpha over mid grey (meshrender.c); other textures ignore alpha unless
 * they are read in it. normal_turn (NULL: none) holds per model triangle a rotation (cos, sin)
 * by which each looked-up texel's first two channels, an encoded tangent-space XY, are turned
 * (texopt_normal_turn) before the grey: how the evaluation brings a re-baked normal map back
 * to the reference's tangent frame. */
texopt_status texopt_meshrender_shade_luma(const texopt_model *model, const texopt_raster *raster, int texture,
                                           struct texopt_texture_filter *const *filters, const double *normal_turn,
                                           float *luma, char *err, size_t err_len);

/* As texopt_meshrender_shade_luma, writing each pixel's RGB (3 floats, a one-channel texture
 * repeated) into the caller's side x side x 3 floats: what a shading that decodes the texels
 * itself (lit_shade.h) reads. Where the material has no such texture the pixel is mid grey,
 * as there. */
texopt_status texopt_meshrender_shade_rgb(const texopt_model *model, const texopt_raster *raster, int texture,
                                          struct texopt_texture_filter *const *filters, const double *normal_turn,
                                          float *rgb, char *err, size_t err_len);

/* The binding of `texture` (a texture_keys.h key) that shades primitive's triangles: its
 * material's, when it names a decoded image through TEXCOORD_0; NULL otherwise (mid grey). */
const texopt_texture_ref *texopt_meshrender_binding(const texopt_model *model, int primitive, int texture);

/* Per model triangle, the binding of `texture` that shades it (texopt_meshrender_binding of
 * its primitive; NULL: mid grey), in *out (triangle_count entries, allocated here; the caller
 * frees it). */
texopt_status texopt_meshrender_triangle_bindings(const texopt_model *model, int texture,
                                                  const texopt_texture_ref ***out, char *err, size_t err_len);

/* Nonzero when some primitive of the model is shaded from its material's `texture`. */
int texopt_meshrender_has_texture(const texopt_model *model, int texture);

/* Succeeds when candidate has the same triangles as reference: equal triangle count and every
 * corner at the same position (within 1e-5 of the bounding-box diagonal). The message names
 * the first triangle that differs. */
texopt_status texopt_meshrender_same_geometry(const texopt_model *reference, const texopt_model *candidate, char *err,
                                              size_t err_len);

#endif

/* evaluate.h - the whole-mesh perceptual loss q of a candidate layout against the input.
 *
 * Sun et al. 2022, "Efficient Texture Parameterization Driven by Perceptual-Loss-on-Screen",
 * section 5.1: render the reference (input UVs, input textures) and the candidate (new UVs,
 * new textures) from the 20 dodecahedron cameras of meshrender.h (or, on request, its 12
 * icosahedron cameras) with bilinear lookups,
 * compute GMSD (gmsd.h) on the luma of the pixels covered in both, and average over the
 * views. q(input, input) is exactly 0; larger is worse.
 *
 * Resolution: rendered far smaller than the texture, every layout looks perfect. The
 * default screen side is 1.25 sqrt(covered texels of the reference) rounded, i.e. the input
 * texture seen at about one texel per pixel (DESIGN.md 3.5), clamped to [64, 4096].
 *
 * Lookups are bilinear by default (the paper's setting); with `mipmapped` both renders use
 * the prefiltered lookups of texture_filter.h, reported separately.
 *
 * Texture: base colour by default (the paper's q, what every benchmark reports). `texture`
 * measures another texture of the material instead (texture_keys.h: normal,
 * metallic-roughness, occlusion, emissive, or a material extension's such as
 * clearcoatTexture), as stage 1 treats each signal "in its own encoding": a texture read in
 * R, G and B is rendered and compared as if it were a colour image (luma, GMSD), not lit; one
 * read in fewer channels as the grey mean of those (occlusion R, metallic-roughness G and B,
 * specular A), so the other channels of an image it shares do not count. (Stage 1 compares a
 * data texture per channel; one grey mixes them, so metallic-roughness detail where roughness
 * and metalness change in opposite directions counts less here.)
 *
 * Normal maps are compared in one tangent frame, the reference's. A renderer derives the
 * tangents of a primitive without TANGENT from its UVs, so a layout that rotates a triangle
 * rotates its frame, and the re-bake (rebake.h) turns the map's XY with it: correct for
 * lighting, but a different image. So on every candidate triangle whose primitive stores no
 * TANGENT (a candidate without a file, as the pipeline's in memory, counts as having the
 * reference's attributes), the looked-up XY is turned back by the rotation of that
 * triangle's map reference texel -> candidate texel (the two normal images' sizes and UVs;
 * texel_map.h, the re-bake's own function), before the luma. With stored tangents nothing
 * is turned, as the re-bake turned nothing. Normal-map q (normal, clearcoatNormalTexture) then
 * says how much of the map's detail survived as a renderer would shade it, up to lighting; a
 * map that was not turned where it had to be scores worse. Other textures are not turned.
 * Triangles whose material has no such texture are mid grey in both renders, as
 * untextured triangles are for base colour. A reference with no such texture
 * at all, for any texture but base colour, is refused (TEXOPT_E_UNSUPPORTED, naming the
 * texture): q would be 0 and look like a perfect result. (Base colour keeps its old rule, q of
 * grey against grey, because the pipeline evaluates every model by it.) A candidate without
 * the texture is measured: mid grey against the reference's map.
 *
 * Lit (option `lit`): instead of one texture, the luma of the model lit by one light and a sky
 * from every map that shades it (lit_shade.h: base colour, metallic-roughness with a specular
 * highlight, the normal map turned back to the reference's tangent frame as above, occlusion,
 * emissive): what a core slot's texture shows a user, the extensions' not lit. An option
 * beside `texture` rather than a texture of its own, because a texture key names one of a
 * material's textures and lit reads five. A reference with no texture in any of them is
 * refused (TEXOPT_E_UNSUPPORTED), as a texture without one: q would be 0 for any layout.
 *
 * Does not: optimise or bake, or look at more than one texture per call. */
#ifndef TEXOPT_EVALUATE_H
#define TEXOPT_EVALUATE_H

#include <stddef.h>
#include <stdint.h>

#include "meshrender.h"
#include "model.h"
#include "monitor.h"
#include "status.h"
#include "texture_keys.h"

/* The reference's shaded views, kept (texopt_evaluate_reference_create). */
typedef struct texopt_evaluate_reference texopt_evaluate_reference;

typedef struct texopt_evaluate_options {
    int resolution; /* screen side in pixels; 0 -> texopt_evaluate_default_resolution */
    int threads;    /* views rendered in parallel; 0 -> 1 */
    int mipmapped;  /* nonzero: prefiltered (mip-mapped, anisotropic) lookups in both renders
                       instead of bilinear, as a GPU sampler with mipmaps would show them */
    /* When not NULL: per reference triangle (triangle_count entries, caller-owned), the mean
     * absolute luma difference over the pixels it covers in all views (0 where never seen),
     * the same to the last bit on any number of threads. The report colours the UV layout by
     * it. */
    double *triangle_error;
    /* With triangle_error: non-zero makes a pixel add sqrt(|luma difference| (1 - GMS)) over
     * the pixels GMSD counts (gmsd.h texopt_gmsd_similarity_map) instead of the difference:
     * a pixel then counts as much as its value and its gradient are both wrong, so a blurred
     * edge weighs as GMSD weighs it and a faint shift on a flat region hardly at all. The
     * base-colour refinement reads this (job_refine.c); a triangle only seen where
     * GMSD does not count (a few pixels from the silhouette, gmsd.h's mask rule) gets 0. */
    int triangle_error_edges;
    const texopt_monitor *monitor; /* stage "evaluate", checked between views; may be NULL */
    /* Which cameras (meshrender.h): 0, the dodecahedron's 20, is q as the paper and the
     * benchmark define it; the icosahedron's 12 are for tuning a layout on other views. */
    texopt_camera_set cameras;
    /* The texture both renders shade, a texture_keys.h key (see the top of this file);
     * TEXOPT_SLOT_BASE_COLOR (0) is the paper's q. */
    int texture;
    /* Nonzero: the lit luma of every map (see the top of this file); `texture` is then not
     * read. */
    int lit;
    /* When not NULL: the reference's views as texopt_evaluate_reference_create shaded them,
     * read instead of shading the reference again; made from the same reference with the
     * same resolution, cameras, lookups and measure (else TEXOPT_E_INVALID_ARGUMENT). */
    const texopt_evaluate_reference *reference_views;
} texopt_evaluate_options;

typedef struct texopt_evaluation {
    double q;       /* mean of view_gmsd[0..view_count) */
    int view_count; /* 20, or 12 with the icosahedron's cameras */
    double view_gmsd[TEXOPT_VIEW_COUNT];
    size_t view_pixels[TEXOPT_VIEW_COUNT]; /* covered pixels per view */
    int resolution;                        /* screen side used */
    double seconds;                        /* wall clock */
} texopt_evaluation;

/* What a layout costs (DESIGN.md 3.4): cost c = unique covered texels summed over the
 * texture domains (coverage.h), the texture memory it sits in, and its distortion. */
typedef struct texopt_cost {
    uint64_t covered_texels;    /* c: unique covered texels, all domains */
    uint64_t frame_texels;      /* sum of the domains' frame sizes (width x height) */
    uint64_t texture_pixels;    /* sum of width x height of every image the domains use */
    double packing_efficiency;  /* covered_texels / frame_texels */
    double symmetric_dirichlet; /* eq. 24 (distortion.h), mean over domains weighted by
                                    counted triangles; +inf with a flipped triangle */
} texopt_cost;

/* The texture a user names: a glTF material field ("baseColor", "normal", "metallicRoughness",
 * "occlusion", "emissive"), an extension texture's ("clearcoatTexture", texture_keys.h), both
 * case-insensitive, or a short name ("base", "mr", "ao"); NULL or unknown -> -1. */
int texopt_evaluate_texture_from_name(const char *name);

/* What a user asks q to measure: a texture name as above, or "lit" (case-insensitive). Sets
 * opt->texture and opt->lit and returns 0; -1 for NULL or an unknown name (opt unchanged). */
int texopt_evaluate_select_measure(texopt_evaluate_options *opt, const char *name);

/* The name of what opt measures, as the JSON and the tools write it: "lit" or the texture's. */
const char *texopt_evaluate_measure_name(const texopt_evaluate_options *opt);

/* Succeeds when `texture` can be evaluated against this reference: a known key, and for any
 * but base colour a material binding it somewhere (the refusal described at the top). */
texopt_status texopt_evaluate_check_texture(const texopt_model *reference, int texture, char *err, size_t err_len);

/* Succeeds when the lit luma can be evaluated against this reference: a texture in base
 * colour, metallic-roughness, normal, occlusion or emissive somewhere (the refusal described
 * at the top). */
texopt_status texopt_evaluate_check_lit(const texopt_model *reference, char *err, size_t err_len);

/* Measures model's layout cost. */
texopt_status texopt_evaluate_cost(const texopt_model *model, texopt_cost *out, char *err, size_t err_len);

/* 1.25 sqrt(covered texels) rounded, clamped to [64, 4096]. */
texopt_status texopt_evaluate_default_resolution(const texopt_model *model, int *side, char *err, size_t err_len);

/* Shades every view of the reference once as opt says (its triangle_error and
 * reference_views are not read), for evaluations of candidates that come one after another
 * against it, as the closed-loop refinement's rounds do: a lit reference costs as much to
 * shade as a candidate. Holds one float per pixel per view (213 MB for DamagedHelmet's 12
 * views at 2106 px) and a pointer to the reference, which must outlive it. */
texopt_status texopt_evaluate_reference_create(const texopt_model *reference, const texopt_evaluate_options *opt,
                                               texopt_evaluate_reference **out, char *err, size_t err_len);
void texopt_evaluate_reference_destroy(texopt_evaluate_reference *views);

/* Whole-mesh loss of candidate against reference (same triangles: checked with
 * texopt_meshrender_same_geometry). opt may be NULL. *out is written only on success. */
texopt_status texopt_evaluate(const texopt_model *reference, const texopt_model *candidate,
                              const texopt_evaluate_options *opt, texopt_evaluation *out, char *err, size_t err_len);

/* One view of `model` (the reference or a candidate) as the measure of opt (`texture` or
 * `lit`) shows it, for a person to look at (compare's report): *out becomes a side x side RGB
 * image (allocated here; background 0) of the texture's texels as stored, base colour cut out
 * by its alpha as q sees it, a normal-kind texture (texture_keys.h) turned back to the
 * reference's tangent frame as q compares it, or the lit luma in grey. Bilinear lookups;
 * raster: texopt_meshrender_rasterize of the reference; the other options are not read. */
texopt_status texopt_evaluate_render(const texopt_model *reference, const texopt_model *model,
                                     const texopt_evaluate_options *opt, const texopt_raster *raster, texopt_image *out,
                                     char *err, size_t err_len);

/* Whole-mesh loss of several candidates (candidate_count >= 1, all with the reference's
 * triangles) against one reference, into out[0..candidate_count): each view of the reference
 * is rasterised and shaded once for all of them, so choosing among candidates costs one
 * reference render instead of one per candidate; out[c] is bit for bit what
 * texopt_evaluate returns for candidate c (seconds: the whole call's). opt->triangle_error
 * needs candidate_count == 1. */
texopt_status texopt_evaluate_many(const texopt_model *reference, const texopt_model *const *candidates,
                                   int candidate_count, const texopt_evaluate_options *opt, texopt_evaluation *out,
                                   char *err, size_t err_len);

#endif

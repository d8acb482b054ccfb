/* lit_shade.c - lit luma of a model from its maps (lit_shade.h): the reference's tangent
 * frames, the view's light, the material's diffuse and specular response, and the per-pixel
 * combination of the five shadings meshrender reads (base colour, metallic-roughness,
 * normal, occlusion, emissive). Does not: sample textures itself (every lookup, filtering
 * and normal-map turn is meshrender's shade_pixels), compare images. */
#include "lit_shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sample.h"
#include "vec3.h"

struct texopt_lit_frames {
    size_t triangle_count;
    /* Per triangle T, B, N (unit); T = B = 0 where the UV map is degenerate (n = N). */
    double *tbn;
    /* Per triangle its corners' vertex normals (9 floats), NULL when the model has none:
     * the shading normal is theirs interpolated, as a viewer draws it. */
    float *corner_normals;
    /* Per triangle its material's metallic and roughness factors (glTF's 1 and 1 without a
     * material). */
    float *factors;
};

static void sub3(const float *a, const float *b, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (double)a[k] - b[k];
}

/* Completes frame (T, B, N) from its unit N and a tangent T: T Gram-Schmidt against N and
 * B = sign N x T; T = B = 0 where T is parallel to N. */
static void complete_frame(double *frame, double sign)
{
    double *T = frame, *B = frame + 3, *N = frame + 6;
    double tn = texopt_dot3(T, N), nxt[3];
    for (int k = 0; k < 3; k++)
        T[k] -= tn * N[k];
    if (!texopt_normalize3(T)) {
        memset(frame, 0, 6 * sizeof *frame);
        return;
    }
    texopt_cross3(N, T, nxt);
    for (int k = 0; k < 3; k++)
        B[k] = sign * nxt[k];
}

/* T, B, N of triangle t; N = 0 as well when the triangle itself is degenerate (it then
 * covers no pixel: meshrender skips edge-on and zero-area triangles). */
static void triangle_frame(const texopt_model *m, size_t t, double *tbn)
{
    memset(tbn, 0, 9 * sizeof *tbn);
    const uint32_t *c = m->triangles + 3 * t;
    double e1[3], e2[3];
    sub3(m->positions + 3 * (size_t)c[1], m->positions + 3 * (size_t)c[0], e1);
    sub3(m->positions + 3 * (size_t)c[2], m->positions + 3 * (size_t)c[0], e2);
    double *T = tbn, *N = tbn + 6;
    texopt_cross3(e1, e2, N);
    if (!texopt_normalize3(N))
        return;
    const float *u0 = m->uvs + 2 * (size_t)c[0], *u1 = m->uvs + 2 * (size_t)c[1], *u2 = m->uvs + 2 * (size_t)c[2];
    double du1 = (double)u1[0] - u0[0], dv1 = (double)u1[1] - u0[1];
    double du2 = (double)u2[0] - u0[0], dv2 = (double)u2[1] - u0[1];
    double r = du1 * dv2 - du2 * dv1;
    if (!(fabs(r) > 1e-14))
        return;
    double dpdv[3];
    for (int k = 0; k < 3; k++) {
        T[k] = (e1[k] * dv2 - e2[k] * dv1) / r;
        dpdv[k] = (e2[k] * du1 - e1[k] * du2) / r;
    }
    /* glTF's +Y of a normal map is up in the image, i.e. towards -v. N x T keeps its
     * direction through the Gram-Schmidt step, so its side of dpdv decides now. */
    double NxT[3];
    texopt_cross3(N, T, NxT);
    complete_frame(tbn, texopt_dot3(NxT, dpdv) > 0 ? -1.0 : 1.0);
}

/* Per triangle of m, its material's metallic and roughness factors into factors (2 each). */
static void material_factors(const texopt_model *m, float *factors)
{
    for (size_t t = 0; t < m->triangle_count; t++)
        factors[2 * t] = factors[2 * t + 1] = 1.0f;
    for (int p = 0; p < m->primitive_count; p++) {
        const texopt_primitive *prim = &m->primitives[p];
        if (prim->material < 0 || prim->material >= m->material_count)
            continue;
        const texopt_material *mat = &m->materials[prim->material];
        for (size_t t = prim->first_triangle; t < prim->first_triangle + prim->triangle_count && t < m->triangle_count;
             t++) {
            factors[2 * t] = (float)mat->metallic_factor;
            factors[2 * t + 1] = (float)mat->roughness_factor;
        }
    }
}

/* Copies the reference's vertex normals per triangle corner; a triangle with a corner
 * without one (a primitive without NORMAL) gets zeros, so it is shaded flat. 0 on no memory. */
static int corner_normals_of(const texopt_model *m, texopt_lit_frames *f)
{
    f->corner_normals = calloc(f->triangle_count ? f->triangle_count * 9 : 1, sizeof *f->corner_normals);
    if (!f->corner_normals)
        return 0;
    for (size_t t = 0; t < f->triangle_count; t++) {
        float *out = f->corner_normals + 9 * t;
        int complete = 1;
        for (int c = 0; c < 3; c++) {
            const float *n = m->normals + 3 * (size_t)m->triangles[3 * t + (size_t)c];
            memcpy(out + 3 * c, n, 3 * sizeof *n);
            complete = complete && (n[0] != 0 || n[1] != 0 || n[2] != 0);
        }
        if (!complete)
            memset(out, 0, 9 * sizeof *out);
    }
    return 1;
}

texopt_status texopt_lit_frames_create(const texopt_model *reference, texopt_lit_frames **out, char *err,
                                       size_t err_len)
{
    *out = NULL;
    if (!reference || !reference->uvs || !reference->positions)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "lighting needs positions and TEXCOORD_0");
    texopt_lit_frames *f = calloc(1, sizeof *f);
    size_t tc = reference->triangle_count;
    if (f) {
        f->tbn = malloc((tc ? tc : 1) * 9 * sizeof *f->tbn);
        f->factors = malloc((tc ? tc : 1) * 2 * sizeof *f->factors);
    }
    if (!f || !f->tbn || !f->factors) {
        texopt_lit_frames_destroy(f);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the tangent frames");
    }
    f->triangle_count = tc;
    for (size_t t = 0; t < tc; t++) {
        for (int k = 0; k < 3; k++)
            if (reference->triangles[3 * t + k] >= reference->vertex_count) {
                texopt_lit_frames_destroy(f);
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                                   "triangle %zu names a vertex past the vertex count", t);
            }
        triangle_frame(reference, t, f->tbn + 9 * t);
    }
    material_factors(reference, f->factors);
    if (reference->normals && !corner_normals_of(reference, f)) {
        texopt_lit_frames_destroy(f);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the vertex normals");
    }
    *out = f;
    return TEXOPT_OK;
}

void texopt_lit_frames_destroy(texopt_lit_frames *frames)
{
    if (!frames)
        return;
    free(frames->tbn);
    free(frames->factors);
    free(frames->corner_normals);
    free(frames);
}

int texopt_lit_has_maps(const texopt_model *model)
{
    return texopt_meshrender_has_texture(model, TEXOPT_SLOT_METALLIC_ROUGHNESS) ||
           texopt_meshrender_has_texture(model, TEXOPT_SLOT_NORMAL) ||
           texopt_meshrender_has_texture(model, TEXOPT_SLOT_OCCLUSION) ||
           texopt_meshrender_has_texture(model, TEXOPT_SLOT_EMISSIVE);
}

void texopt_lit_light(const texopt_view *view, double l[3])
{
    for (int k = 0; k < 3; k++)
        l[k] = 0.5 * view->right[k] + 0.5 * view->up[k] + 0.7 * view->direction[k];
    texopt_normalize3(l);
}

/* The tangent frame at a pixel of a triangle with face frame tbn: N the corners' normals
 * interpolated at barycentrics bary (corners NULL or zero: the face normal), T
 * Gram-Schmidt against it and B = +-N x T with the face frame's handedness, as a renderer
 * builds the frame from a vertex normal and the UVs' tangent. */
static void pixel_frame(const double *tbn, const float *corners, const float *bary, double frame[9])
{
    memcpy(frame, tbn, 9 * sizeof *frame);
    if (!corners || (corners[0] == 0 && corners[1] == 0 && corners[2] == 0))
        return;
    double *N = frame + 6;
    double b1 = bary[0], b2 = bary[1], b0 = 1.0 - b1 - b2;
    for (int k = 0; k < 3; k++)
        N[k] = b0 * corners[k] + b1 * corners[3 + k] + b2 * corners[6 + k];
    if (!texopt_normalize3(N)) {
        memcpy(frame, tbn, 9 * sizeof *frame);
        return;
    }
    if (!(texopt_dot3(tbn, tbn) > 0))
        return; /* degenerate UVs: no tangent, n = N */
    double face_nxt[3];
    texopt_cross3(tbn + 6, tbn, face_nxt);
    complete_frame(frame, texopt_dot3(face_nxt, tbn + 3) < 0 ? -1.0 : 1.0);
}

/* The shading normal at a pixel with tangent frame `frame`, from its normal-map texel (NULL:
 * the frame's N). */
static void shading_normal(const double *frame, const float *texel, double n[3])
{
    const double *T = frame, *B = frame + 3, *N = frame + 6;
    memcpy(n, N, 3 * sizeof *n);
    if (texel && texopt_dot3(T, T) > 0) {
        double x = 2.0 * texel[0] - 1, y = 2.0 * texel[1] - 1, z = 2.0 * texel[2] - 1;
        for (int k = 0; k < 3; k++)
            n[k] = x * T[k] + y * B[k] + z * N[k];
        if (!texopt_normalize3(n))
            memcpy(n, N, 3 * sizeof *n);
    }
}

/* Schlick's form of Smith's masking for GGX, k = alpha / 2. */
static double smith_g1(double cosine, double alpha)
{
    double k = 0.5 * alpha;
    return cosine / (cosine * (1.0 - k) + k);
}

/* The directional light's specular radiance at a pixel (before occlusion): Cook-Torrance
 * with GGX distribution, Smith-Schlick visibility and Schlick's Fresnel from f0, scaled like
 * the diffuse term (a white Lambert surface facing the light returns 1 - A). */
static double specular(const double n[3], const double l[3], const double v[3], double f0, double roughness)
{
    double nl = texopt_dot3(n, l), nv = texopt_dot3(n, v);
    if (!(nl > 0) || !(nv > 0))
        return 0;
    double h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
    if (!texopt_normalize3(h))
        return 0;
    double r = roughness > TEXOPT_LIT_MIN_ROUGHNESS ? roughness : TEXOPT_LIT_MIN_ROUGHNESS;
    double alpha = r * r, a2 = alpha * alpha, nh = texopt_dot3(n, h), vh = texopt_dot3(v, h);
    double d = nh * nh * (a2 - 1.0) + 1.0;
    double pi_distribution = a2 / (d * d); /* pi D: the pi of the light's scale cancels D's */
    double visibility = smith_g1(nl, alpha) * smith_g1(nv, alpha) / (4.0 * nl * nv);
    double fresnel = f0 + (1.0 - f0) * pow(1.0 - (vh > 0 ? vh : 0), 5);
    return (1.0 - TEXOPT_LIT_AMBIENT) * pi_distribution * visibility * fresnel * nl;
}

/* L before occlusion and emission at a pixel of base-colour luma b (see the top). */
static double surface(double b, double metallic, double roughness, const double n[3], const double l[3],
                      const double v[3])
{
    double nl = texopt_dot3(n, l);
    double diffuse = TEXOPT_LIT_AMBIENT + (1.0 - TEXOPT_LIT_AMBIENT) * (nl > 0 ? nl : 0);
    double f0 = TEXOPT_LIT_DIELECTRIC_F0 * (1.0 - metallic) + b * metallic;
    return b * (1.0 - metallic) * diffuse + f0 * TEXOPT_LIT_AMBIENT + specular(n, l, v, f0, roughness);
}

double texopt_lit_point(double b, double metallic, double roughness, const double n[3], const double l[3],
                        const double v[3], double occlusion, double emission)
{
    double lum = occlusion * surface(b, metallic, roughness, n, l, v) + emission;
    return lum < 1.0 ? lum : 1.0;
}

/* The passes after base colour, in the order L applies them. */
typedef enum lit_term { LIT_MATERIAL, LIT_SURFACE, LIT_OCCLUSION, LIT_EMISSION } lit_term;

/* Applies one term to every covered pixel of luma from its texture (shaded into rgb; a
 * triangle whose material has none keeps the term's default: its metallic and roughness
 * factors alone, n = N, occlusion 1, no emission). LIT_MATERIAL stores metallic and
 * roughness per pixel in mr for LIT_SURFACE. */
static texopt_status apply_term(const texopt_model *model, const texopt_raster *raster, const texopt_lit_frames *frames,
                                struct texopt_texture_filter *const *filters, const double *normal_turn, lit_term term,
                                float *rgb, float *mr, float *luma, char *err, size_t err_len)
{
    static const texopt_slot slot[] = {TEXOPT_SLOT_METALLIC_ROUGHNESS, TEXOPT_SLOT_NORMAL, TEXOPT_SLOT_OCCLUSION,
                                       TEXOPT_SLOT_EMISSIVE};
    const texopt_texture_ref **bound = NULL;
    texopt_status st = texopt_meshrender_triangle_bindings(model, slot[term], &bound, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_meshrender_shade_rgb(model, raster, slot[term], filters, term == LIT_SURFACE ? normal_turn : NULL,
                                         rgb, err, err_len);
    double l[3];
    texopt_lit_light(&raster->view, l);
    const double *v = raster->view.direction;
    size_t n = (size_t)raster->side * (size_t)raster->side;
    for (size_t i = 0; i < n && st == TEXOPT_OK; i++) {
        int32_t t = raster->triangle[i];
        if (t < 0)
            continue;
        const float *texel = bound[t] ? rgb + 3 * i : NULL;
        if (term == LIT_MATERIAL) {
            const float *factor = frames->factors + 2 * (size_t)t; /* glTF: B metallic, G roughness */
            mr[2 * i] = factor[0] * (texel ? texel[2] : 1.0f);
            mr[2 * i + 1] = factor[1] * (texel ? texel[1] : 1.0f);
        } else if (term == LIT_SURFACE) {
            double frame[9], normal[3];
            pixel_frame(frames->tbn + 9 * (size_t)t,
                        frames->corner_normals ? frames->corner_normals + 9 * (size_t)t : NULL, raster->bary + 2 * i,
                        frame);
            shading_normal(frame, texel, normal);
            luma[i] = (float)surface(luma[i], mr[2 * i], mr[2 * i + 1], normal, l, v);
        } else if (texel && term == LIT_OCCLUSION)
            luma[i] *= texel[0];
        else if (texel)
            luma[i] += texopt_luma(texel, 3);
    }
    free(bound);
    return st;
}

/* A display shows at most white: highlights and emission saturate alike in both renders. */
static void clamp_to_display(const texopt_raster *raster, float *luma)
{
    size_t n = (size_t)raster->side * (size_t)raster->side;
    for (size_t i = 0; i < n; i++)
        if (luma[i] > 1.0f)
            luma[i] = 1.0f;
}

texopt_status texopt_lit_shade(const texopt_model *model, const texopt_raster *raster, const texopt_lit_frames *frames,
                               struct texopt_texture_filter *const *filters, const double *normal_turn, float *scratch,
                               float *luma, char *err, size_t err_len)
{
    if (!model || !raster || !frames || !scratch || !luma)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "nothing to light");
    if (model->triangle_count != frames->triangle_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "the model has %zu triangles, the tangent frames %zu", model->triangle_count,
                           frames->triangle_count);
    texopt_status st =
        texopt_meshrender_shade_luma(model, raster, TEXOPT_SLOT_BASE_COLOR, filters, NULL, luma, err, err_len);
    size_t pixels = (size_t)raster->side * (size_t)raster->side;
    for (lit_term term = LIT_MATERIAL; term <= LIT_EMISSION && st == TEXOPT_OK; term++)
        st = apply_term(model, raster, frames, filters, normal_turn, term, scratch, scratch + 3 * pixels, luma, err,
                        err_len);
    if (st == TEXOPT_OK)
        clamp_to_display(raster, luma);
    return st;
}

/* info.c - builds the `texopt info` JSON document of a model (info.h) with cJSON.
 *
 * Each texture domain is turned into a mesh (mesh.c) and its layout measured (coverage.c);
 * this file only gathers and names the numbers. The cost it reports is the unique covered
 * texel count of Sun et al. 2022, "Efficient Texture Parameterization Driven by
 * Perceptual-Loss-on-Screen" (eq. 20).
 *
 * Does not: load files, print, or judge whether a model is worth optimising. */
#include "info.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_quality.h"
#include "coverage.h"
#include "distortion.h"
#include "file_cost.h"
#include "layout_check.h"
#include "mesh.h"

const char *texopt_wrap_name(texopt_wrap wrap)
{
    switch (wrap) {
    case TEXOPT_WRAP_REPEAT: return "repeat";
    case TEXOPT_WRAP_CLAMP: return "clamp";
    case TEXOPT_WRAP_MIRROR: return "mirror";
    }
    return "unknown";
}

static const char *image_name(const texopt_model *model, int image)
{
    if (model->image_names && model->image_names[image])
        return model->image_names[image];
    return "";
}

static void add_image_fields(cJSON *o, const texopt_model *model, int image)
{
    const texopt_image *img = &model->images[image];
    cJSON_AddStringToObject(o, "name", image_name(model, image));
    cJSON_AddNumberToObject(o, "width", img->width);
    cJSON_AddNumberToObject(o, "height", img->height);
    cJSON_AddNumberToObject(o, "channels", img->channels);
}

static cJSON *images_json(const texopt_model *model)
{
    cJSON *arr = cJSON_CreateArray();
    for (int i = 0; arr && i < model->image_count; i++) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "index", i);
        add_image_fields(o, model, i);
        cJSON_AddItemToArray(arr, o);
    }
    return arr;
}

/* The entry of `list` for (slot, image), or NULL. */
static cJSON *find_texture(const cJSON *list, const char *slot, int image)
{
    cJSON *t;
    cJSON_ArrayForEach(t, list)
    {
        const cJSON *s = cJSON_GetObjectItemCaseSensitive(t, "slot");
        const cJSON *i = cJSON_GetObjectItemCaseSensitive(t, "image");
        if (cJSON_IsString(s) && strcmp(s->valuestring, slot) == 0 && cJSON_IsNumber(i) && i->valueint == image)
            return t;
    }
    return NULL;
}

/* The channels of a binding as letters, "RGBA" order ("GB" for metallic-roughness). */
static void channel_letters(unsigned channels, char out[5])
{
    int n = 0;
    for (int c = 0; c < 4; c++)
        if ((channels >> c) & 1u)
            out[n++] = "RGBA"[c];
    out[n] = '\0';
}

/* Sets a texture entry's "reads" to the channels it held plus `channels`: materials that
 * share a texture may read it differently (a MASK one its alpha, an OPAQUE one not). */
static void add_reads(cJSON *texture, unsigned channels)
{
    const cJSON *old = cJSON_GetObjectItemCaseSensitive(texture, "reads");
    for (const char *c = cJSON_IsString(old) ? old->valuestring : ""; *c; c++)
        channels |= 1u << (strchr("RGBA", *c) - "RGBA");
    char reads[5];
    channel_letters(channels, reads);
    cJSON_DeleteItemFromObjectCaseSensitive(texture, "reads");
    cJSON_AddStringToObject(texture, "reads", reads);
}

/* Adds the (slot or extension texture, image) pairs material mat reads through TEXCOORD_0 to
 * arr, once each, with the channels any material reads them in. */
static void add_material_textures(cJSON *arr, const texopt_model *model, int mat)
{
    if (mat < 0 || mat >= model->material_count)
        return;
    const texopt_material *m = &model->materials[mat];
    for (int s = 0; s < texopt_material_binding_count(m); s++) {
        const texopt_texture_ref *ref = texopt_material_binding(m, s);
        if (ref->image < 0 || ref->image >= model->image_count || ref->texcoord != 0)
            continue;
        const char *slot = texopt_material_binding_name(m, s);
        cJSON *o = find_texture(arr, slot, ref->image);
        if (!o) {
            o = cJSON_CreateObject();
            cJSON_AddStringToObject(o, "slot", slot);
            cJSON_AddNumberToObject(o, "image", ref->image);
            add_image_fields(o, model, ref->image);
            cJSON_AddStringToObject(o, "wrap_s", texopt_wrap_name(ref->wrap_s));
            cJSON_AddStringToObject(o, "wrap_t", texopt_wrap_name(ref->wrap_t));
            if (ref->magnify_nearest)
                cJSON_AddStringToObject(o, "magnify", "nearest");
            cJSON_AddItemToArray(arr, o);
        }
        add_reads(o, texopt_material_binding_channels(m, s));
    }
}

/* Every (slot or extension texture, image) a domain's materials (and their variants,
 * KHR_materials_variants) read through TEXCOORD_0, in primitive and binding order, once each,
 * with the channels any of them reads. */
static cJSON *textures_json(const texopt_model *model, const texopt_domain *dom)
{
    cJSON *arr = cJSON_CreateArray();
    for (int k = 0; arr && k < dom->primitive_count; k++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[k]];
        for (int i = 0; i <= prim->variant_count; i++)
            add_material_textures(arr, model, texopt_primitive_material(model, prim, i));
    }
    return arr;
}

typedef struct flag_counts {
    size_t degenerate, degenerate_3d, degenerate_uv, flipped, overlapping, wrapped;
    double area_3d, texel_area;
} flag_counts;

static flag_counts count_flags(const texopt_mesh *mesh)
{
    flag_counts c = {0};
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        uint8_t f = mesh->flags[t];
        c.degenerate += (f & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV)) != 0;
        c.degenerate_3d += (f & TEXOPT_TRI_DEGENERATE_3D) != 0;
        c.degenerate_uv += (f & TEXOPT_TRI_DEGENERATE_UV) != 0;
        c.flipped += (f & TEXOPT_TRI_FLIPPED) != 0;
        c.overlapping += (f & TEXOPT_TRI_OVERLAPS) != 0;
        c.wrapped += (f & TEXOPT_TRI_WRAPPED) != 0;
        c.area_3d += mesh->area_3d[t];
        if (!(f & TEXOPT_TRI_DEGENERATE_UV))
            c.texel_area += fabs(mesh->area_texel[t]);
    }
    return c;
}

/* Charts whose orientation is opposite to the domain's area-weighted majority. The sign
 * alone says little: in glTF's texel space (v down) the ordinary charts of many models are
 * negative; a mirrored half is the one that disagrees with the rest. */
static size_t mirrored_charts(const texopt_mesh *mesh)
{
    double balance = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (!(mesh->flags[t] & TEXOPT_TRI_DEGENERATE_UV))
            balance += mesh->area_texel[t];
    int majority = balance < 0 ? -1 : 1;
    size_t n = 0;
    for (size_t c = 0; c < mesh->chart_count; c++)
        n += mesh->chart_sign[c] != majority;
    return n;
}

/* Charts that hold triangles reversed against the chart but not FLIPPED: mirrored parts
 * welded to the rest at their mirror line (mesh.h). */
static size_t folded_charts(const texopt_mesh *mesh)
{
    uint8_t *folded = calloc(mesh->chart_count > 0 ? mesh->chart_count : 1, 1);
    if (!folded)
        return 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        uint8_t f = mesh->flags[t];
        if (f & (TEXOPT_TRI_DEGENERATE_UV | TEXOPT_TRI_FLIPPED))
            continue;
        if ((mesh->area_texel[t] < 0) != (mesh->chart_sign[mesh->chart_of[t]] < 0))
            folded[mesh->chart_of[t]] = 1;
    }
    size_t n = 0;
    for (size_t c = 0; c < mesh->chart_count; c++)
        n += folded[c];
    free(folded);
    return n;
}

static void add_frame_and_wrap(cJSON *o, const texopt_domain *dom)
{
    cJSON *frame = cJSON_AddObjectToObject(o, "frame");
    cJSON_AddNumberToObject(frame, "width", dom->width);
    cJSON_AddNumberToObject(frame, "height", dom->height);
    cJSON *wrap = cJSON_AddObjectToObject(o, "wrap");
    cJSON_AddStringToObject(wrap, "s", texopt_wrap_name(dom->wrap_s));
    cJSON_AddStringToObject(wrap, "t", texopt_wrap_name(dom->wrap_t));
}

/* The layout by Liu et al. 2019's measures (atlas_quality.h); null when it has no extent. */
static void add_atlas_quality(cJSON *o, const texopt_mesh *mesh)
{
    texopt_atlas_quality q;
    cJSON *qj = NULL;
    if (texopt_atlas_quality_measure(mesh, NULL, &q, NULL, 0) == TEXOPT_OK)
        qj = texopt_atlas_quality_json(&q);
    if (qj)
        cJSON_AddItemToObject(o, "atlas_quality", qj);
    else
        cJSON_AddNullToObject(o, "atlas_quality");
}

/* The input layout's distortion (distortion.h); null when no triangle can be measured. */
static void add_distortion(cJSON *o, const texopt_mesh *mesh)
{
    texopt_distortion d;
    cJSON *dj = NULL;
    if (texopt_distortion_measure(mesh, NULL, &d, NULL, 0) == TEXOPT_OK)
        dj = texopt_distortion_json(&d);
    if (dj)
        cJSON_AddItemToObject(o, "distortion", dj);
    else
        cJSON_AddNullToObject(o, "distortion");
}

static texopt_status domain_json(const texopt_model *model, int d, cJSON **out, char *err, size_t err_len)
{
    const texopt_domain *dom = &model->domains[d];
    texopt_mesh *mesh = NULL;
    texopt_status st = texopt_mesh_create(&mesh, model, d, err, err_len);
    texopt_coverage cov;
    char coverage_err[256] = "";
    texopt_status coverage_st = TEXOPT_OK;
    if (st == TEXOPT_OK) {
        texopt_coverage_options opt = {.triangle_flags = mesh->flags};
        coverage_st = texopt_coverage_measure(mesh, &opt, &cov, coverage_err, sizeof coverage_err);
        /* A layout too large to rasterise (a frame past the cap, UVs across thousands of
         * repeats) still gets every other number; only a real failure stops the document. */
        if (coverage_st != TEXOPT_OK && coverage_st != TEXOPT_E_LIMIT)
            st = texopt_fail(err, err_len, coverage_st, "%s", coverage_err);
    }
    if (st != TEXOPT_OK) {
        /* name the domain in front of the module's message */
        if (err && err_len > 0) {
            char inner[512];
            strncpy(inner, err, sizeof inner - 1);
            inner[sizeof inner - 1] = '\0';
            texopt_fail(err, err_len, st, "texture domain %d: %s", d, inner);
        }
        texopt_mesh_destroy(mesh);
        return st;
    }
    flag_counts fc = count_flags(mesh);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "index", d);
    cJSON *prims = cJSON_AddArrayToObject(o, "primitives");
    for (int k = 0; prims && k < dom->primitive_count; k++)
        cJSON_AddItemToArray(prims, cJSON_CreateNumber(dom->primitives[k]));
    cJSON_AddNumberToObject(o, "triangles", (double)mesh->triangle_count);
    cJSON_AddNumberToObject(o, "model_vertices", (double)mesh->model_vertex_count);
    cJSON_AddNumberToObject(o, "uv_vertices", (double)mesh->vertex_count);
    cJSON_AddNumberToObject(o, "points", (double)mesh->point_count);
    cJSON_AddNumberToObject(o, "charts", (double)mesh->chart_count);
    cJSON_AddNumberToObject(o, "mirrored_charts", (double)mirrored_charts(mesh));
    cJSON_AddNumberToObject(o, "folded_charts", (double)folded_charts(mesh));
    add_frame_and_wrap(o, dom);
    cJSON_AddItemToObject(o, "textures", textures_json(model, dom));
    if (coverage_st == TEXOPT_OK) {
        cJSON_AddNumberToObject(o, "covered_texels", (double)cov.covered_texels);
        cJSON_AddNumberToObject(o, "overlap_texels", (double)cov.overlap_texels);
        cJSON_AddNumberToObject(o, "packing_efficiency", cov.packing_efficiency);
    } else {
        cJSON_AddNullToObject(o, "covered_texels");
        cJSON_AddNullToObject(o, "overlap_texels");
        cJSON_AddNullToObject(o, "packing_efficiency");
        cJSON_AddStringToObject(o, "coverage_error", coverage_err);
    }
    cJSON_AddNumberToObject(o, "texel_area", fc.texel_area);
    cJSON_AddNumberToObject(o, "area_3d", fc.area_3d);
    cJSON_AddNumberToObject(o, "degenerate", (double)fc.degenerate);
    cJSON_AddNumberToObject(o, "degenerate_3d", (double)fc.degenerate_3d);
    cJSON_AddNumberToObject(o, "degenerate_uv", (double)fc.degenerate_uv);
    cJSON_AddNumberToObject(o, "flipped", (double)fc.flipped);
    cJSON_AddNumberToObject(o, "overlapping", (double)fc.overlapping);
    cJSON_AddNumberToObject(o, "wrapped", (double)fc.wrapped);
    add_distortion(o, mesh);
    add_atlas_quality(o, mesh);
    texopt_layout_check check;
    st = texopt_layout_check_own(mesh, &check, err, err_len);
    if (st == TEXOPT_OK)
        cJSON_AddItemToObject(o, "layout_check", texopt_layout_check_json(&check));
    texopt_mesh_destroy(mesh);
    if (st != TEXOPT_OK) {
        cJSON_Delete(o);
        return st;
    }
    *out = o;
    return TEXOPT_OK;
}

texopt_status texopt_info_json(const texopt_model *model, cJSON **out, char *err, size_t err_len)
{
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "info: no output pointer");
    *out = NULL;
    if (!model)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "info: no model");
    cJSON *root = cJSON_CreateObject();
    if (!root)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "info: no memory for the document");
    int untextured = 0;
    for (int p = 0; p < model->primitive_count; p++)
        untextured += model->primitives[p].domain < 0;
    cJSON_AddNumberToObject(root, "vertices", (double)model->vertex_count);
    cJSON_AddNumberToObject(root, "triangles", (double)model->triangle_count);
    cJSON_AddNumberToObject(root, "primitives", model->primitive_count);
    cJSON_AddNumberToObject(root, "materials", model->material_count);
    cJSON_AddNumberToObject(root, "untextured_primitives", untextured);
    cJSON_AddItemToObject(root, "images", images_json(model));
    texopt_file_cost fc;
    texopt_file_cost_of_model(model, &fc);
    cJSON *file = cJSON_AddObjectToObject(root, "file_cost");
    cJSON_AddNumberToObject(file, "texture_pixels", (double)fc.texture_pixels);
    cJSON_AddNumberToObject(file, "texture_bytes", (double)fc.texture_bytes);
    cJSON *domains = cJSON_AddArrayToObject(root, "domains");
    for (int d = 0; d < model->domain_count; d++) {
        cJSON *dj = NULL;
        texopt_status st = domain_json(model, d, &dj, err, err_len);
        if (st != TEXOPT_OK) {
            cJSON_Delete(root);
            return st;
        }
        cJSON_AddItemToArray(domains, dj);
    }
    *out = root;
    return TEXOPT_OK;
}

texopt_status texopt_info_string(const texopt_model *model, int pretty, char **out, char *err, size_t err_len)
{
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "info: no output pointer");
    *out = NULL;
    cJSON *doc = NULL;
    texopt_status st = texopt_info_json(model, &doc, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    *out = pretty ? cJSON_Print(doc) : cJSON_PrintUnformatted(doc);
    cJSON_Delete(doc);
    if (!*out)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "info: no memory to print the document");
    return TEXOPT_OK;
}

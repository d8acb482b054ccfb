/* gltf_load.cpp - texopt_model_load / texopt_model_load_memory (see gltf_io.h).
 *
 * Order of work, each step refusing with a message that names the element:
 *   1. The JSON's nesting is bounded (json_depth.h: tinygltf's parser recurses), then
 *      tinygltf parses the JSON / GLB container, reading files only through the confined
 *      callbacks of gltf_files.hpp (inside the model's directory, under the size limit,
 *      never from the network).
 *      Its image callback only keeps the encoded bytes (after checking the buffer view
 *      range, which tinygltf does not), so no image is decoded by stb.
 *   2. Every buffer view and accessor is checked against the real buffer sizes.
 *   3. Materials are read (texture slots, one KHR_texture_transform per material's
 *      TEXCOORD_0), then triangle primitives flattened into texopt_model (world-space
 *      positions, UVs through their material's transform).
 *   4. Image headers are probed, the total pixel count checked, then images decoded.
 *   5. Texture domains are built; a model without any is unsupported.
 * The format is the Khronos glTF 2.0 specification; the data feeds Sun et al. 2022. */
#include "gltf_io.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

#include "gltf_access.hpp"
#include "gltf_document.hpp"
#include "gltf_extension_textures.hpp"
#include "gltf_files.hpp"
#include "gltf_nodes.hpp"
#include "gltf_texture_source.hpp"
#include "image_io.h"
#include "image_jobs.hpp"
#include "json_depth.h"

namespace
{

const uint64_t DEFAULT_MAX_FILE_BYTES = 1ull << 30;
const uint64_t DEFAULT_MAX_TOTAL_PIXELS = 1ull << 28;

struct load_limits {
    uint64_t max_file_bytes;
    uint64_t max_total_pixels;
    bool skip_images;
};

load_limits limits_from(const texopt_load_options *opt)
{
    load_limits l;
    l.max_file_bytes = opt && opt->max_file_bytes ? opt->max_file_bytes : DEFAULT_MAX_FILE_BYTES;
    l.max_total_pixels = opt && opt->max_total_pixels ? opt->max_total_pixels : DEFAULT_MAX_TOTAL_PIXELS;
    l.skip_images = opt && opt->skip_images;
    return l;
}

/* Keeps the encoded bytes; decoding happens later, after the pixel budget is checked. */
bool keep_image_bytes(tinygltf::Image *image, const int index, std::string *err, std::string *, int, int,
                      const unsigned char *bytes, int size, void *user)
{
    gltf_load_context *ctx = static_cast<gltf_load_context *>(user);
    if (image->bufferView >= 0) {
        char msg[256];
        if (gltf_check_buffer_view(*ctx->model, image->bufferView, msg, sizeof msg) != TEXOPT_OK) {
            ctx->refuse(TEXOPT_E_MALFORMED, "image " + std::to_string(index) + ": " + msg);
            if (err)
                *err += msg;
            return false;
        }
    }
    if (size <= 0 || !bytes) {
        ctx->refuse(TEXOPT_E_MALFORMED, "image " + std::to_string(index) + " has no data");
        return false;
    }
    image->image.assign(bytes, bytes + size);
    image->as_is = true;
    return true;
}

std::string first_line(const std::string &s)
{
    size_t nl = s.find('\n');
    return nl == std::string::npos ? s : s.substr(0, nl);
}

texopt_status parse_document(tinygltf::Model *gltf, const unsigned char *bytes, size_t len, const std::string &base_dir,
                             const load_limits &lim, char *err, size_t err_len)
{
    if (len > lim.max_file_bytes)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "model has %zu bytes, more than the limit of %llu", len,
                           (unsigned long long)lim.max_file_bytes);
    if (len < 2)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "file is empty or truncated (%zu bytes)", len);
    if (len > UINT_MAX)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "model of %zu bytes is too large to parse", len);
    texopt_status depth = texopt_gltf_check_depth(bytes, len, TEXOPT_JSON_MAX_DEPTH, err, err_len);
    if (depth != TEXOPT_OK)
        return depth;
    gltf_load_context ctx;
    ctx.base_dir = base_dir;
    ctx.max_file_bytes = lim.max_file_bytes;
    ctx.model = gltf;
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(gltf_confined_fs(&ctx));
    loader.SetImageLoader(&keep_image_bytes, &ctx);
    std::string terr, twarn;
    bool binary = len >= 4 && memcmp(bytes, "glTF", 4) == 0;
    bool ok;
    try {
        ok = binary ? loader.LoadBinaryFromMemory(gltf, &terr, &twarn, bytes, (unsigned int)len, base_dir)
                    : loader.LoadASCIIFromString(gltf, &terr, &twarn, reinterpret_cast<const char *>(bytes),
                                                 (unsigned int)len, base_dir);
    } catch (const std::bad_alloc &) {
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to parse the model");
    } catch (const std::exception &e) {
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "cannot parse the model: %s", e.what());
    }
    if (ctx.status != TEXOPT_OK)
        return texopt_fail(err, err_len, ctx.status, "%s", ctx.message.c_str());
    if (!ok)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "not a valid %s file: %s", binary ? "glb" : "glTF",
                           terr.empty() ? "parse error" : first_line(terr).c_str());
    return TEXOPT_OK;
}

/* ---- structure checks ------------------------------------------------------------------ */

texopt_status check_required_extensions(const tinygltf::Model &g, char *err, size_t err_len)
{
    /* tinygltf drops a channel whose target has no node, which is every KHR_animation_pointer
     * channel: the saved file would lose those animations (and one could scroll a texture
     * transform that the new layout removes). */
    for (const std::string &ext : g.extensionsUsed)
        if (ext == "KHR_animation_pointer")
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "extension KHR_animation_pointer is not supported: its animations would be lost "
                               "when the model is written");
    static const char *const unsupported[] = {"KHR_draco_mesh_compression", "EXT_meshopt_compression",
                                              "KHR_meshopt_compression"};
    for (const std::string &ext : g.extensionsRequired)
        for (const char *u : unsupported)
            if (ext == u)
                return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                                   "extension %s (compressed geometry) is not supported", u);
    return TEXOPT_OK;
}

texopt_status check_all_views_and_accessors(const tinygltf::Model &g, char *err, size_t err_len)
{
    for (size_t i = 0; i < g.bufferViews.size(); i++) {
        texopt_status st = gltf_check_buffer_view(g, (int)i, err, err_len);
        if (st != TEXOPT_OK)
            return st;
    }
    for (size_t i = 0; i < g.accessors.size(); i++) {
        texopt_status st = gltf_check_accessor(g, (int)i, err, err_len);
        if (st != TEXOPT_OK)
            return st;
    }
    return TEXOPT_OK;
}

/* ---- materials ------------------------------------------------------------------------- */

texopt_wrap wrap_from_gl(int gl)
{
    switch (gl) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TEXOPT_WRAP_CLAMP;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TEXOPT_WRAP_MIRROR;
    default: return TEXOPT_WRAP_REPEAT;
    }
}

texopt_status bind_texture(const tinygltf::Model &g, int material, const char *slot_name, int texture, int texcoord,
                           texopt_texture_ref *ref, char *err, size_t err_len)
{
    ref->image = -1;
    ref->texcoord = 0;
    ref->wrap_s = ref->wrap_t = TEXOPT_WRAP_REPEAT;
    ref->magnify_nearest = 0;
    if (texture < 0)
        return TEXOPT_OK;
    if ((size_t)texture >= g.textures.size())
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "material %d: %s names texture %d of %zu", material,
                           slot_name, texture, g.textures.size());
    const tinygltf::Texture &t = g.textures[(size_t)texture];
    int image = gltf_texture_source(t);
    if (image < 0 || (size_t)image >= g.images.size())
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                           "texture %d (used by material %d %s): image %d does not exist", texture, material, slot_name,
                           image);
    if (t.sampler >= 0) {
        if ((size_t)t.sampler >= g.samplers.size())
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "texture %d: sampler %d does not exist", texture,
                               t.sampler);
        ref->wrap_s = wrap_from_gl(g.samplers[(size_t)t.sampler].wrapS);
        ref->wrap_t = wrap_from_gl(g.samplers[(size_t)t.sampler].wrapT);
        ref->magnify_nearest = g.samplers[(size_t)t.sampler].magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    }
    if (texcoord < 0)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "material %d: %s has texCoord %d", material, slot_name,
                           texcoord);
    ref->image = image;
    ref->texcoord = texcoord;
    return TEXOPT_OK;
}

const double identity_transform[6] = {1, 0, 0, 0, 1, 0};

/* Equal as numbers (a scale's -0 rotation term equals an absent transform's 0). */
bool same_transform(const double a[6], const double b[6])
{
    for (int i = 0; i < 6; i++)
        if (a[i] != b[i])
            return false;
    return true;
}

bool read_number_pair(const tinygltf::Value &v, const char *key, double pair[2])
{
    if (!v.Has(key))
        return true;
    const tinygltf::Value &a = v.Get(key);
    if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber())
        return false;
    pair[0] = a.Get(0).GetNumberAsDouble();
    pair[1] = a.Get(1).GetNumberAsDouble();
    return true;
}

/* A binding's KHR_texture_transform as texopt_material.uv_transform's m. The rotation turns
 * as the extension's example reads (offset [0, 1], rotation pi/2, scale 0.5 show the
 * lower-left quadrant), the way viewers apply it. False when the extension is malformed or
 * moves the binding to another texcoord set. */
bool read_texture_transform(const tinygltf::ExtensionMap &ext, int texcoord, double m[6])
{
    memcpy(m, identity_transform, sizeof identity_transform);
    auto it = ext.find("KHR_texture_transform");
    if (it == ext.end())
        return true;
    const tinygltf::Value &v = it->second;
    if (!v.IsObject())
        return false;
    if (v.Has("texCoord") && (!v.Get("texCoord").IsInt() || v.Get("texCoord").GetNumberAsInt() != texcoord))
        return false;
    double offset[2] = {0, 0}, scale[2] = {1, 1}, rotation = 0;
    if (v.Has("rotation")) {
        if (!v.Get("rotation").IsNumber())
            return false;
        rotation = v.Get("rotation").GetNumberAsDouble();
    }
    if (!read_number_pair(v, "offset", offset) || !read_number_pair(v, "scale", scale))
        return false;
    double c = cos(rotation), s = sin(rotation);
    double t[6] = {c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1]};
    for (int i = 0; i < 6; i++)
        if (!std::isfinite(t[i]))
            return false;
    memcpy(m, t, sizeof t);
    return true;
}

/* read_texture_transform for binding `name` of a material, refusing what it cannot apply. */
texopt_status read_binding_transform(size_t material, const char *name, const tinygltf::ExtensionMap &ext, int texcoord,
                                     double m[6], char *err, size_t err_len)
{
    if (read_texture_transform(ext, texcoord, m))
        return TEXOPT_OK;
    return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                       "material %zu: %s has a KHR_texture_transform texopt cannot apply (malformed, or moving the "
                       "binding to another texCoord)",
                       material, name);
}

/* A normal map's XY live in a frame its UVs' directions define: a transform that turns or
 * mirrors them would need the map turned too, which the loader does not do. */
bool turns_or_mirrors(const double m[6])
{
    return m[1] != 0 || m[3] != 0 || m[0] < 0 || m[4] < 0;
}

/* The binding's transform becomes the material's (the first TEXCOORD_0 binding's), or must
 * equal it: one UV set cannot serve two. */
texopt_status share_transform(size_t material, const char *binding, const double m[6], texopt_material *out,
                              const char **transformed_by, char *err, size_t err_len)
{
    if (!*transformed_by) {
        memcpy(out->uv_transform, m, 6 * sizeof *m);
        *transformed_by = binding;
        return TEXOPT_OK;
    }
    if (same_transform(out->uv_transform, m))
        return TEXOPT_OK;
    return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                       "material %zu: %s and %s have different KHR_texture_transform values; texopt lays out one "
                       "TEXCOORD_0 per material",
                       material, *transformed_by, binding);
}

/* The extensions object of a textureInfo inside a material extension, as tinygltf keeps a
 * core textureInfo's. */
tinygltf::ExtensionMap texture_info_extensions(const tinygltf::Value &info)
{
    tinygltf::ExtensionMap map;
    if (info.Has("extensions") && info.Get("extensions").IsObject()) {
        const tinygltf::Value &e = info.Get("extensions");
        for (const std::string &k : e.Keys())
            map[k] = e.Get(k);
    }
    return map;
}

/* The textures material extensions bind on TEXCOORD_0 into out->extra (those on other sets
 * are left as they are, like the core slots'); an unknown one is refused, since a new layout
 * would misplace it. */
texopt_status bind_extension_textures(const tinygltf::Model &g, size_t i, const tinygltf::Material &m,
                                      texopt_material *out, const char **transformed_by, char *err, size_t err_len)
{
    for (const auto &e : m.extensions) {
        std::string unknown;
        if (gltf_unknown_extension_texture_on_set0(e.first, e.second, &unknown))
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "material %zu: %s binds %s on TEXCOORD_0, which texopt does not re-bake", i,
                               e.first.c_str(), unknown.c_str());
        if (!e.second.IsObject())
            continue;
        for (const std::string &key : e.second.Keys()) {
            const tinygltf::Value &info = e.second.Get(key);
            int texcoord;
            texopt_texture_kind kind;
            unsigned channels;
            const char *name;
            if (!gltf_is_texture_info(key, info, &texcoord) || texcoord != 0 ||
                !gltf_known_extension_texture(e.first, key, &kind, &channels, &name))
                continue;
            if (out->extra_count == TEXOPT_EXTRA_TEXTURES_MAX)
                return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                                   "material %zu binds more than %d extension textures", i, TEXOPT_EXTRA_TEXTURES_MAX);
            texopt_extra_texture *x = &out->extra[out->extra_count];
            texopt_status st =
                bind_texture(g, (int)i, name, info.Get("index").GetNumberAsInt(), 0, &x->ref, err, err_len);
            if (st != TEXOPT_OK)
                return st;
            double t[6];
            st = read_binding_transform(i, name, texture_info_extensions(info), 0, t, err, err_len);
            if (st == TEXOPT_OK)
                st = share_transform(i, name, t, out, transformed_by, err, err_len);
            if (st != TEXOPT_OK)
                return st;
            x->kind = kind;
            x->channels = channels;
            x->name = name;
            out->extra_count++;
        }
    }
    return TEXOPT_OK;
}

texopt_status convert_materials(const tinygltf::Model &g, texopt_model *model, char *err, size_t err_len)
{
    size_t n = g.materials.size();
    model->materials = static_cast<texopt_material *>(calloc(n ? n : 1, sizeof(texopt_material)));
    if (!model->materials)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu materials", n);
    model->material_count = (int)n;
    for (size_t i = 0; i < n; i++) {
        const tinygltf::Material &m = g.materials[i];
        texopt_material *out = &model->materials[i];
        out->metallic_factor = m.pbrMetallicRoughness.metallicFactor;
        out->roughness_factor = m.pbrMetallicRoughness.roughnessFactor;
        out->alpha_mode = m.alphaMode == "MASK"    ? TEXOPT_ALPHA_MASK
                          : m.alphaMode == "BLEND" ? TEXOPT_ALPHA_BLEND
                                                   : TEXOPT_ALPHA_OPAQUE;
        out->alpha_cutoff = m.alphaCutoff;
        const tinygltf::TextureInfo &base = m.pbrMetallicRoughness.baseColorTexture;
        const tinygltf::TextureInfo &mr = m.pbrMetallicRoughness.metallicRoughnessTexture;
        struct {
            texopt_slot slot;
            const char *name;
            int index, texcoord;
            const tinygltf::ExtensionMap *ext;
        } slots[] = {
            {TEXOPT_SLOT_BASE_COLOR, "baseColorTexture", base.index, base.texCoord, &base.extensions},
            {TEXOPT_SLOT_NORMAL, "normalTexture", m.normalTexture.index, m.normalTexture.texCoord,
             &m.normalTexture.extensions},
            {TEXOPT_SLOT_METALLIC_ROUGHNESS, "metallicRoughnessTexture", mr.index, mr.texCoord, &mr.extensions},
            {TEXOPT_SLOT_OCCLUSION, "occlusionTexture", m.occlusionTexture.index, m.occlusionTexture.texCoord,
             &m.occlusionTexture.extensions},
            {TEXOPT_SLOT_EMISSIVE, "emissiveTexture", m.emissiveTexture.index, m.emissiveTexture.texCoord,
             &m.emissiveTexture.extensions},
        };
        memcpy(out->uv_transform, identity_transform, sizeof identity_transform);
        const char *transformed_by = NULL; /* the first TEXCOORD_0 binding, whose transform the others share */
        for (const auto &s : slots) {
            texopt_status st = bind_texture(g, (int)i, s.name, s.index, s.texcoord, &out->slot[s.slot], err, err_len);
            if (st != TEXOPT_OK)
                return st;
            if (s.index < 0)
                continue;
            double m[6];
            st = read_binding_transform(i, s.name, *s.ext, s.texcoord, m, err, err_len);
            if (st == TEXOPT_OK && s.texcoord == 0)
                st = share_transform(i, s.name, m, out, &transformed_by, err, err_len);
            if (st != TEXOPT_OK)
                return st;
        }
        texopt_status st = bind_extension_textures(g, i, m, out, &transformed_by, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        const double *t = out->uv_transform;
        if (t[0] * t[4] - t[1] * t[3] == 0)
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "material %zu: its KHR_texture_transform has a zero scale, which collapses TEXCOORD_0 "
                               "onto a line or a point",
                               i);
        for (int b = 0; b < texopt_material_binding_count(out); b++) {
            const texopt_texture_ref *r = texopt_material_binding(out, b);
            if (r->image >= 0 && r->texcoord == 0 && texopt_material_binding_kind(out, b) == TEXOPT_TEXTURE_NORMAL &&
                turns_or_mirrors(out->uv_transform))
                return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                                   "material %zu: its KHR_texture_transform turns or mirrors the UVs of a normal map "
                                   "(%s), which texopt does not apply",
                                   i, texopt_material_binding_name(out, b));
        }
    }
    return TEXOPT_OK;
}

bool material_uses_texcoord0(const texopt_model *model, int material)
{
    if (material < 0 || material >= model->material_count)
        return false;
    const texopt_material *mat = &model->materials[material];
    for (int b = 0; b < texopt_material_binding_count(mat); b++) {
        const texopt_texture_ref *r = texopt_material_binding(mat, b);
        if (r->image >= 0 && r->texcoord == 0)
            return true;
    }
    return false;
}

bool material_is_textured(const texopt_model *model, int material)
{
    if (material < 0 || material >= model->material_count)
        return false;
    const texopt_material *mat = &model->materials[material];
    for (int b = 0; b < texopt_material_binding_count(mat); b++)
        if (texopt_material_binding(mat, b)->image >= 0)
            return true;
    return false;
}

/* ---- geometry -------------------------------------------------------------------------- */

struct flat_geometry {
    std::vector<float> positions, uvs, normals;
    std::vector<uint32_t> triangles;
    std::vector<texopt_primitive> primitives;
    std::vector<int> variant_materials; /* texopt_primitive.first_variant indexes it */
    bool any_uvs = false;
    bool any_normals = false;
};

int attribute(const tinygltf::Primitive &p, const char *name)
{
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
}

/* The primitive's NORMAL in world space (unit), or zeros where it has none or one the
 * evaluation cannot use (glTF then asks for flat normals, and texopt_model.normals marks
 * them with zero vectors). Normals only shade the evaluation's lit render; a file whose
 * NORMAL is unreadable loses nothing by being shaded flat, so it is not refused here. */
std::vector<float> world_normals(const tinygltf::Model &g, const tinygltf::Primitive &p, size_t nv,
                                 const gltf_mat4 *world)
{
    std::vector<float> n(nv * 3, 0.0f), read;
    int acc = attribute(p, "NORMAL");
    char ignored[64];
    if (acc < 0 ||
        gltf_read_floats(g, acc, TINYGLTF_TYPE_VEC3, "NORMAL", &read, ignored, sizeof ignored) != TEXOPT_OK ||
        read.size() != nv * 3)
        return n;
    /* Normals turn by the inverse transpose of the placement's 3x3, whose columns are the
     * cross products of the matrix's columns over its determinant. */
    double cof[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, det = 1;
    if (world) {
        const gltf_mat4 &m = *world;
        const double a[3] = {m[0], m[1], m[2]}, b[3] = {m[4], m[5], m[6]}, c[3] = {m[8], m[9], m[10]};
        const double *cols[3][2] = {{b, c}, {c, a}, {a, b}};
        for (int k = 0; k < 3; k++) {
            const double *u = cols[k][0], *v = cols[k][1];
            cof[3 * k] = u[1] * v[2] - u[2] * v[1];
            cof[3 * k + 1] = u[2] * v[0] - u[0] * v[2];
            cof[3 * k + 2] = u[0] * v[1] - u[1] * v[0];
        }
        det = gltf_determinant3(m);
    }
    for (size_t v = 0; v < nv; v++) {
        double w[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
            for (int r = 0; r < 3; r++)
                w[r] += read[3 * v + (size_t)k] * cof[3 * k + r];
        double len = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (!(len > 0) || !std::isfinite(len))
            continue;
        double s = (det < 0 ? -1.0 : 1.0) / len;
        for (int r = 0; r < 3; r++)
            n[3 * v + (size_t)r] = (float)(w[r] * s);
    }
    return n;
}

/* TEXCOORD_0 through its material's uv_transform; false when a result is not finite. */
bool apply_uv_transform(const double m[6], std::vector<float> *uv)
{
    if (same_transform(m, identity_transform))
        return true;
    for (size_t i = 0; i + 1 < uv->size(); i += 2) {
        double u = (*uv)[i], v = (*uv)[i + 1];
        float tu = (float)(m[0] * u + m[1] * v + m[2]), tv = (float)(m[3] * u + m[4] * v + m[5]);
        if (!std::isfinite(tu) || !std::isfinite(tv))
            return false;
        (*uv)[i] = tu;
        (*uv)[i + 1] = tv;
    }
    return true;
}

/* The triangle list of a strip or fan, in glTF 2.0's order (section 3.7.2.1): strip
 * triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}), fan triangle i is (v_{i+1}, v_{i+2}, v_0),
 * which keeps every triangle's winding. The file keeps its strip; only UVs change. */
std::vector<uint32_t> triangles_of_strip_or_fan(int mode, const std::vector<uint32_t> &v)
{
    std::vector<uint32_t> tri;
    for (size_t i = 0; i + 2 < v.size(); i++) {
        size_t odd = i % 2;
        uint32_t t[3] = {v[i], v[i + 1 + odd], v[i + 2 - odd]};
        if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
            t[0] = v[i + 1], t[1] = v[i + 2], t[2] = v[0];
        tri.insert(tri.end(), t, t + 3);
    }
    return tri;
}

/* Whether a material's KHR_materials_anisotropy sets its direction in the tangent frame alone
 * (a strength and a rotation, or a direction map on another UV set): without TANGENT a renderer
 * derives that frame from TEXCOORD_0, which a new layout turns chart by chart, and a constant
 * cannot turn with it. A direction map on TEXCOORD_0 is re-baked and turned like a normal map. */
bool anisotropy_fixed_in_uv_frame(const tinygltf::Material &m)
{
    auto e = m.extensions.find("KHR_materials_anisotropy");
    if (e == m.extensions.end() || !e->second.IsObject())
        return false;
    const tinygltf::Value &a = e->second;
    double strength = a.Has("anisotropyStrength") && a.Get("anisotropyStrength").IsNumber()
                          ? a.Get("anisotropyStrength").GetNumberAsDouble()
                          : 0.0;
    int texcoord = 0;
    bool map_on_set0 = a.Has("anisotropyTexture") &&
                       gltf_is_texture_info("anisotropyTexture", a.Get("anisotropyTexture"), &texcoord) &&
                       texcoord == 0;
    return strength > 0 && !map_on_set0;
}

/* The materials primitive p's KHR_materials_variants mappings name, in mapping order, into
 * *out; a mapping naming no material is malformed. */
texopt_status mapped_materials(const tinygltf::Model &g, const tinygltf::Primitive &p, int mesh, int prim_index,
                               std::vector<int> *out, char *err, size_t err_len)
{
    out->clear();
    auto e = p.extensions.find("KHR_materials_variants");
    if (e == p.extensions.end() || !e->second.IsObject() || !e->second.Has("mappings"))
        return TEXOPT_OK;
    const tinygltf::Value &mappings = e->second.Get("mappings");
    for (size_t k = 0; mappings.IsArray() && k < mappings.ArrayLen(); k++) {
        const tinygltf::Value &m = mappings.Get((int)k);
        bool named = m.IsObject() && m.Has("material") && m.Get("material").IsInt();
        int material = named ? m.Get("material").GetNumberAsInt() : -1;
        if (material < 0 || (size_t)material >= g.materials.size())
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                               "mesh %d primitive %d: KHR_materials_variants mapping %zu names no material", mesh,
                               prim_index, k);
        out->push_back(material);
    }
    return TEXOPT_OK;
}

/* Of the materials primitive p's variants map to (mapped_materials), those reading
 * TEXCOORD_0 besides its own material, each once, into *out. Each reads the primitive's
 * TEXCOORD_0, which a new layout changes for all of them: it must have the primitive's
 * texture transform (the loader applies the primitive material's), and the primitive must
 * have TEXCOORD_0. */
texopt_status variant_materials(const texopt_model *model, const tinygltf::Primitive &p, const std::vector<int> &mapped,
                                int mesh, int prim_index, std::vector<int> *out, char *err, size_t err_len)
{
    out->clear();
    for (int material : mapped) {
        if (material == p.material || std::find(out->begin(), out->end(), material) != out->end() ||
            !material_uses_texcoord0(model, material))
            continue;
        if (attribute(p, "TEXCOORD_0") < 0)
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "mesh %d primitive %d: its variant material %d is textured but the primitive has no "
                               "TEXCOORD_0",
                               mesh, prim_index, material);
        const double *own = p.material >= 0 ? model->materials[p.material].uv_transform : identity_transform;
        if (memcmp(model->materials[material].uv_transform, own, sizeof identity_transform) != 0)
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "mesh %d primitive %d: its variant material %d has another KHR_texture_transform "
                               "than its material; one layout cannot serve both",
                               mesh, prim_index, material);
        out->push_back(material);
    }
    return TEXOPT_OK;
}

/* For a primitive whose TEXCOORD_0 a new layout changes: refuses when it has no TANGENT and
 * its material or a material its variants map to (`mapped`, untextured ones too) sets an
 * anisotropy direction in the tangent frame a renderer derives from those UVs
 * (anisotropy_fixed_in_uv_frame). */
texopt_status check_anisotropy_frames(const tinygltf::Model &g, const tinygltf::Primitive &p,
                                      const std::vector<int> &mapped, int mesh, int prim_index, char *err,
                                      size_t err_len)
{
    if (attribute(p, "TANGENT") >= 0)
        return TEXOPT_OK;
    std::vector<int> drawn_with = mapped;
    if (p.material >= 0)
        drawn_with.insert(drawn_with.begin(), p.material);
    for (int material : drawn_with)
        if (anisotropy_fixed_in_uv_frame(g.materials[(size_t)material]))
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "mesh %d primitive %d: %s material %d's KHR_materials_anisotropy direction is set in "
                               "the tangent frame a renderer derives from TEXCOORD_0, which a new layout turns; give "
                               "the primitive TANGENT (kept as it is) or the direction as an anisotropyTexture on "
                               "TEXCOORD_0 (turned with the layout)",
                               mesh, prim_index, material == p.material ? "its" : "its variant", material);
    return TEXOPT_OK;
}

texopt_status add_primitive(const tinygltf::Model &g, const texopt_model *model, int mesh, int prim_index,
                            const gltf_mat4 *world, flat_geometry *geo, char *err, size_t err_len)
{
    const tinygltf::Primitive &p = g.meshes[(size_t)mesh].primitives[(size_t)prim_index];
    char what[96];
    if (p.material >= 0 && (size_t)p.material >= g.materials.size())
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "mesh %d primitive %d: material %d does not exist", mesh,
                           prim_index, p.material);
    bool textured = material_is_textured(model, p.material);
    int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        if (textured)
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "mesh %d primitive %d: textured primitive has mode %d; only triangles (4), triangle "
                               "strips (5) and fans (6) are supported",
                               mesh, prim_index, mode);
        return TEXOPT_OK; /* untextured points and lines: nothing to optimise */
    }
    int pos_acc = attribute(p, "POSITION");
    int uv_acc = attribute(p, "TEXCOORD_0");
    if (pos_acc < 0)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "mesh %d primitive %d has no POSITION", mesh, prim_index);
    if (uv_acc < 0 && material_uses_texcoord0(model, p.material))
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                           "mesh %d primitive %d: material %d is textured but the primitive has no TEXCOORD_0", mesh,
                           prim_index, p.material);
    for (size_t t = 0; t < p.targets.size(); t++)
        if (p.targets[t].count("TEXCOORD_0") && material_uses_texcoord0(model, p.material))
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "mesh %d primitive %d: morph target %zu moves TEXCOORD_0, by offsets that hold for "
                               "its layout only",
                               mesh, prim_index, t);
    std::vector<int> mapped, variants;
    texopt_status st = mapped_materials(g, p, mesh, prim_index, &mapped, err, err_len);
    if (st == TEXOPT_OK)
        st = variant_materials(model, p, mapped, mesh, prim_index, &variants, err, err_len);
    if (st == TEXOPT_OK && (material_uses_texcoord0(model, p.material) || !variants.empty()))
        st = check_anisotropy_frames(g, p, mapped, mesh, prim_index, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    std::vector<float> pos, uv;
    snprintf(what, sizeof what, "mesh %d primitive %d POSITION", mesh, prim_index);
    st = gltf_read_floats(g, pos_acc, TINYGLTF_TYPE_VEC3, what, &pos, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    size_t nv = pos.size() / 3;
    if (uv_acc >= 0) {
        snprintf(what, sizeof what, "mesh %d primitive %d TEXCOORD_0", mesh, prim_index);
        st = gltf_read_floats(g, uv_acc, TINYGLTF_TYPE_VEC2, what, &uv, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        if (uv.size() / 2 != nv)
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                               "mesh %d primitive %d: TEXCOORD_0 has %zu elements but POSITION has %zu", mesh,
                               prim_index, uv.size() / 2, nv);
        geo->any_uvs = true;
        if (p.material >= 0 && !apply_uv_transform(model->materials[p.material].uv_transform, &uv))
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                               "mesh %d primitive %d: material %d's KHR_texture_transform takes TEXCOORD_0 past "
                               "float range",
                               mesh, prim_index, p.material);
    } else {
        uv.assign(nv * 2, 0.0f);
    }
    std::vector<uint32_t> idx;
    if (p.indices >= 0) {
        snprintf(what, sizeof what, "mesh %d primitive %d indices", mesh, prim_index);
        st = gltf_read_indices(g, p.indices, what, &idx, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        for (size_t i = 0; i < idx.size(); i++)
            if (idx[i] >= nv)
                return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "accessor %d: index %u past vertex count %zu",
                                   p.indices, idx[i], nv);
    } else {
        idx.resize(nv);
        for (size_t i = 0; i < nv; i++)
            idx[i] = (uint32_t)i;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES)
        idx = triangles_of_strip_or_fan(mode, idx);
    else if (idx.size() % 3 != 0)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                           "mesh %d primitive %d: %zu indices do not make whole triangles", mesh, prim_index,
                           idx.size());
    size_t first_vertex = geo->positions.size() / 3;
    if (first_vertex + nv > UINT32_MAX)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "model has more than 2^32 vertices");
    bool flip = false;
    if (world) {
        const gltf_mat4 &m = *world;
        for (size_t v = 0; v < nv; v++) {
            double x = pos[v * 3], y = pos[v * 3 + 1], z = pos[v * 3 + 2];
            for (int r = 0; r < 3; r++) {
                double w = m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r];
                if (!std::isfinite((float)w))
                    return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                                       "mesh %d: its node transform makes positions non-finite", mesh);
                pos[v * 3 + (size_t)r] = (float)w;
            }
        }
        /* A mirroring transform reverses the winding (glTF 2.0, section 3.7.4). */
        flip = gltf_determinant3(m) < 0;
    }
    texopt_primitive tp;
    memset(&tp, 0, sizeof tp);
    tp.gltf_mesh = mesh;
    tp.gltf_primitive = prim_index;
    tp.material = p.material;
    tp.domain = -1;
    tp.first_vertex = first_vertex;
    tp.vertex_count = nv;
    tp.first_triangle = geo->triangles.size() / 3;
    tp.triangle_count = idx.size() / 3;
    tp.first_variant = geo->variant_materials.size();
    tp.variant_count = (int)variants.size();
    tp.winding_flipped = flip;
    geo->variant_materials.insert(geo->variant_materials.end(), variants.begin(), variants.end());
    geo->positions.insert(geo->positions.end(), pos.begin(), pos.end());
    geo->uvs.insert(geo->uvs.end(), uv.begin(), uv.end());
    std::vector<float> normals = world_normals(g, p, nv, world);
    geo->any_normals = geo->any_normals || attribute(p, "NORMAL") >= 0;
    geo->normals.insert(geo->normals.end(), normals.begin(), normals.end());
    for (size_t t = 0; t < idx.size(); t += 3) {
        uint32_t a = idx[t], b = idx[t + 1], c = idx[t + 2];
        if (flip)
            std::swap(b, c);
        geo->triangles.push_back((uint32_t)first_vertex + a);
        geo->triangles.push_back((uint32_t)first_vertex + b);
        geo->triangles.push_back((uint32_t)first_vertex + c);
    }
    geo->primitives.push_back(tp);
    return TEXOPT_OK;
}

/* The node whose transform places each mesh: the first in node order; NULL for skinned
 * meshes (bind pose) and for meshes no node uses. */
texopt_status mesh_placements(const tinygltf::Model &g, const std::vector<gltf_mat4> &world,
                              std::vector<const gltf_mat4 *> *placement, char *err, size_t err_len)
{
    placement->assign(g.meshes.size(), nullptr);
    std::vector<char> seen(g.meshes.size(), 0);
    for (size_t i = 0; i < g.nodes.size(); i++) {
        int mesh = g.nodes[i].mesh;
        if (mesh < 0)
            continue;
        if ((size_t)mesh >= g.meshes.size())
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "node %zu: mesh %d does not exist", i, mesh);
        if (seen[(size_t)mesh])
            continue;
        seen[(size_t)mesh] = 1;
        if (g.nodes[i].skin < 0)
            (*placement)[(size_t)mesh] = &world[i];
    }
    return TEXOPT_OK;
}

template <typename T> T *copy_out(const std::vector<T> &v)
{
    T *p = static_cast<T *>(malloc(v.empty() ? 1 : v.size() * sizeof(T)));
    if (p && !v.empty())
        memcpy(p, v.data(), v.size() * sizeof(T));
    return p;
}

texopt_status convert_geometry(const tinygltf::Model &g, texopt_model *model, char *err, size_t err_len)
{
    std::vector<gltf_mat4> world;
    texopt_status st = gltf_world_transforms(g, &world, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    std::vector<const gltf_mat4 *> placement;
    st = mesh_placements(g, world, &placement, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    flat_geometry geo;
    for (size_t m = 0; m < g.meshes.size(); m++)
        for (size_t p = 0; p < g.meshes[m].primitives.size(); p++) {
            st = add_primitive(g, model, (int)m, (int)p, placement[m], &geo, err, err_len);
            if (st != TEXOPT_OK)
                return st;
        }
    if (geo.primitives.size() > INT_MAX)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "too many primitives");
    model->vertex_count = geo.positions.size() / 3;
    model->triangle_count = geo.triangles.size() / 3;
    model->primitive_count = (int)geo.primitives.size();
    model->positions = copy_out(geo.positions);
    model->uvs = geo.any_uvs ? copy_out(geo.uvs) : nullptr;
    model->normals = geo.any_normals ? copy_out(geo.normals) : nullptr;
    model->triangles = copy_out(geo.triangles);
    model->primitives = copy_out(geo.primitives);
    model->variant_materials = copy_out(geo.variant_materials);
    if (!model->positions || (geo.any_uvs && !model->uvs) || (geo.any_normals && !model->normals) ||
        !model->triangles || !model->primitives || !model->variant_materials)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu vertices", model->vertex_count);
    return TEXOPT_OK;
}

/* ---- images ---------------------------------------------------------------------------- */

std::string sniff_mime(const std::vector<unsigned char> &b, const std::string &declared)
{
    if (b.size() >= 8 && memcmp(b.data(), "\x89PNG\r\n\x1a\n", 8) == 0)
        return "image/png";
    if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF)
        return "image/jpeg";
    if (b.size() >= 12 && memcmp(b.data(), "RIFF", 4) == 0 && memcmp(b.data() + 8, "WEBP", 4) == 0)
        return "image/webp";
    if (b.size() >= 12 && memcmp(b.data(), "\xABKTX 20\xBB\r\n\x1A\n", 12) == 0)
        return "image/ktx2";
    return declared;
}

std::string image_label(const tinygltf::Image &im, size_t i)
{
    if (!im.uri.empty() && im.uri.compare(0, 5, "data:") != 0)
        return im.uri;
    if (!im.name.empty())
        return im.name;
    return "image " + std::to_string(i);
}

/* Per image, whether a texture reads it as its source (gltf_texture_source): the others (an
 * alternate such as KTX2 beside a PNG fallback, an image no texture names) are kept as bytes
 * for the saver, never decoded, so a format OpenImageIO cannot read there refuses nothing. */
std::vector<char> images_textures_read(const tinygltf::Model &g)
{
    std::vector<char> read(g.images.size(), 0);
    for (const tinygltf::Texture &t : g.textures) {
        int image = gltf_texture_source(t);
        if (image >= 0 && (size_t)image < read.size())
            read[(size_t)image] = 1;
    }
    return read;
}

texopt_status convert_images(texopt_gltf_document *doc, texopt_model *model, const load_limits &lim, char *err,
                             size_t err_len)
{
    const tinygltf::Model &g = doc->gltf;
    size_t n = g.images.size();
    std::vector<char> read = images_textures_read(g);
    model->images = static_cast<texopt_image *>(calloc(n ? n : 1, sizeof(texopt_image)));
    model->image_names = static_cast<char **>(calloc(n ? n : 1, sizeof(char *)));
    if (!model->images || !model->image_names)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu images", n);
    model->image_count = (int)n;
    doc->image_mime.assign(n, std::string());
    doc->image_bits.assign(n, 8);
    doc->image_chroma_subsampled.assign(n, 1);
    std::vector<texopt_image_info> info(n);
    uint64_t total = 0;
    for (size_t i = 0; i < n; i++) {
        const tinygltf::Image &im = g.images[i];
        std::string label = image_label(im, i);
        model->image_names[i] = strdup(label.c_str());
        if (!model->image_names[i])
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for image names");
        if (im.image.empty())
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "image %zu (%s): file not found or empty", i,
                               label.c_str());
        doc->image_mime[i] = sniff_mime(im.image, im.mimeType);
        if (!read[i])
            continue;
        /* OpenImageIO has no KTX2 reader: say what would be read instead of its PNG guess. */
        if (doc->image_mime[i] == "image/ktx2")
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                               "image %zu (%s) is KTX2 (KHR_texture_basisu), which texopt cannot decode: give its "
                               "texture a PNG or JPEG source beside it, which texopt reads instead",
                               i, label.c_str());
        char name[300];
        snprintf(name, sizeof name, "image %zu (%s)", i, label.c_str());
        texopt_status st = texopt_image_probe_memory(&info[i], im.image.data(), im.image.size(), name, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        doc->image_bits[i] = info[i].bits_per_channel;
        doc->image_chroma_subsampled[i] = (char)info[i].chroma_subsampled;
        total += (uint64_t)info[i].width * (uint64_t)info[i].height;
        if (total > lim.max_total_pixels)
            return texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                               "image %zu (%s, %dx%d) brings the total to %llu pixels, more than the limit of %llu", i,
                               label.c_str(), info[i].width, info[i].height, (unsigned long long)total,
                               (unsigned long long)lim.max_total_pixels);
    }
    if (lim.skip_images) {
        for (size_t i = 0; i < n; i++) {
            if (!read[i])
                continue;
            model->images[i].width = info[i].width;
            model->images[i].height = info[i].height;
            model->images[i].channels = info[i].channels;
        }
        return TEXOPT_OK;
    }
    /* Each job fills only its own image: the images decode on parallel threads. */
    return texopt_run_image_jobs(
        n,
        [&](size_t i, char *job_err, size_t job_err_len) {
            if (!read[i])
                return TEXOPT_OK;
            char name[300];
            snprintf(name, sizeof name, "image %zu (%s)", i, model->image_names[i]);
            const std::vector<unsigned char> &b = g.images[i].image;
            return texopt_image_decode_memory(&model->images[i], b.data(), b.size(), lim.max_total_pixels, name,
                                              job_err, job_err_len);
        },
        err, err_len);
}

void destroy_document(texopt_gltf_document *doc)
{
    delete doc;
}

texopt_status load_into(texopt_model *model, const unsigned char *bytes, size_t len, const std::string &base_dir,
                        const load_limits &lim, char *err, size_t err_len)
{
    texopt_gltf_document *doc = new (std::nothrow) texopt_gltf_document;
    if (!doc)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the document");
    model->document = doc;
    model->destroy_document = &destroy_document;
    texopt_status st = parse_document(&doc->gltf, bytes, len, base_dir, lim, err, err_len);
    if (st == TEXOPT_OK)
        st = check_required_extensions(doc->gltf, err, err_len);
    if (st == TEXOPT_OK)
        st = check_all_views_and_accessors(doc->gltf, err, err_len);
    if (st == TEXOPT_OK)
        st = convert_materials(doc->gltf, model, err, err_len);
    if (st == TEXOPT_OK)
        st = convert_geometry(doc->gltf, model, err, err_len);
    if (st == TEXOPT_OK)
        st = convert_images(doc, model, lim, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_model_build_domains(model, err, err_len);
    if (st == TEXOPT_OK && model->domain_count == 0)
        st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                         "no triangle primitive has a material with a texture read through TEXCOORD_0");
    return st;
}

texopt_status load_common(texopt_model **out, const unsigned char *bytes, size_t len, const std::string &base_dir,
                          const texopt_load_options *opt, char *err, size_t err_len)
{
    texopt_model *model = static_cast<texopt_model *>(calloc(1, sizeof(texopt_model)));
    if (!model)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a model");
    texopt_status st;
    try {
        st = load_into(model, bytes, len, base_dir, limits_from(opt), err, err_len);
    } catch (const std::bad_alloc &) {
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory while loading the model");
    } catch (const std::exception &e) {
        st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "unexpected error while loading: %s", e.what());
    }
    if (st != TEXOPT_OK) {
        texopt_model_destroy(model);
        return st;
    }
    *out = model;
    return TEXOPT_OK;
}

} // namespace

extern "C" texopt_status texopt_model_load_memory(texopt_model **out, const void *bytes, size_t len,
                                                  const char *base_dir, const texopt_load_options *opt, char *err,
                                                  size_t err_len)
{
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no place for the model");
    *out = nullptr;
    if (!bytes && len > 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no bytes to load");
    std::string dir;
    if (base_dir) {
        dir = gltf_absolute_directory(base_dir);
        if (dir.empty())
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "base directory %s does not exist or is the root directory", base_dir);
    }
    return load_common(out, static_cast<const unsigned char *>(bytes), len, dir, opt, err, err_len);
}

extern "C" texopt_status texopt_model_load(texopt_model **out, const char *path, const texopt_load_options *opt,
                                           char *err, size_t err_len)
{
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no place for the model");
    *out = nullptr;
    if (!path || !*path)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no model path");
    std::vector<unsigned char> bytes;
    std::string why;
    texopt_status st = gltf_read_file_limited(path, limits_from(opt).max_file_bytes, &bytes, &why);
    if (st != TEXOPT_OK)
        return texopt_fail(err, err_len, st, "%s", why.c_str());
    std::string p(path);
    size_t slash = p.find_last_of('/');
    std::string dir = gltf_absolute_directory(slash == std::string::npos ? "."
                                              : slash == 0               ? "/"
                                                                         : p.substr(0, slash).c_str());
    return load_common(out, bytes.data(), bytes.size(), dir, opt, err, err_len);
}

extern "C" uint64_t texopt_model_image_bytes(const texopt_model *model, int image)
{
    if (!model || !model->document || image < 0 || (size_t)image >= model->document->gltf.images.size())
        return 0;
    return (uint64_t)model->document->gltf.images[(size_t)image].image.size();
}

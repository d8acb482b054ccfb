/* gltf_save.cpp - texopt_model_save_glb (see gltf_io.h).
 *
 * Writes the loaded document back with these changes and nothing else:
 *   - a primitive whose vertices model_split.h copied gets every attribute gathered per
 *     model vertex and new unsigned-int triangle indices;
 *   - TEXCOORD_0 of each primitive that had one becomes a tightly packed float accessor with
 *     exact min/max (in place when no one else reads the old accessor, else a new one), and
 *     the KHR_texture_transform of bindings on TEXCOORD_0, which the loader applied to the
 *     UVs, is dropped;
 *   - replaced images are encoded as JPEG (quality 98) where the original was a JPEG, else as
 *     PNG (16 bits per channel where the original had more than 8, else 8); untouched images
 *     keep their original bytes (and MIME type) byte for byte; a binding through another set
 *     than TEXCOORD_0 (occlusion on TEXCOORD_1) that reads a replaced image is given a texture
 *     of its own on a copy of the original, since it reads it with the old UVs;
 *   - all bytes go into the one GLB BIN buffer, images in buffer views. Buffer views no
 *     one reads any more (the old UVs, replaced images) are dropped and the rest renumbered.
 * Each copied view keeps its offset modulo 4, so every accessor stays aligned.
 * Does not: re-encode untouched images, touch animations, skins, other extensions or extras.
 * Format: Khronos glTF 2.0 (GLB container, section 4.4); output of Sun et al. 2022. */
#include "gltf_io.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "gltf_document.hpp"
#include "gltf_extension_textures.hpp"
#include "gltf_texture_source.hpp"
#include "image_io.h"
#include "image_jobs.hpp"

namespace
{

/* One growing BIN chunk. */
struct bin_writer {
    std::vector<unsigned char> bytes;

    /* Appends data so that its offset is congruent to `phase` modulo 4; returns the offset. */
    size_t append(const unsigned char *data, size_t len, size_t phase)
    {
        while (bytes.size() % 4 != phase % 4)
            bytes.push_back(0);
        size_t at = bytes.size();
        bytes.insert(bytes.end(), data, data + len);
        return at;
    }
};

/* How many places read each accessor as anything other than one primitive's TEXCOORD_0. */
std::vector<int> accessor_readers(const tinygltf::Model &g)
{
    std::vector<int> readers(g.accessors.size(), 0);
    auto count = [&](int a) {
        if (a >= 0 && (size_t)a < readers.size())
            readers[(size_t)a]++;
    };
    for (const tinygltf::Mesh &mesh : g.meshes)
        for (const tinygltf::Primitive &p : mesh.primitives) {
            count(p.indices);
            for (const auto &kv : p.attributes)
                count(kv.second);
            for (const auto &target : p.targets)
                for (const auto &kv : target)
                    count(kv.second);
        }
    for (const tinygltf::Skin &s : g.skins)
        count(s.inverseBindMatrices);
    for (const tinygltf::Animation &an : g.animations)
        for (const tinygltf::AnimationSampler &s : an.samplers) {
            count(s.input);
            count(s.output);
        }
    return readers;
}

texopt_status check_edit(const texopt_model *model, const texopt_model_edit *edit, char *err, size_t err_len)
{
    if (!edit)
        return TEXOPT_OK;
    if (edit->uvs)
        for (size_t i = 0; i < model->vertex_count * 2; i++)
            if (!std::isfinite(edit->uvs[i]))
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "new UV of vertex %zu is not finite",
                                   i / 2);
    if (edit->images)
        for (int i = 0; i < model->image_count; i++) {
            const texopt_image *img = edit->images[i];
            if (img && (!img->pixels || img->width <= 0 || img->height <= 0 || img->channels < 1 || img->channels > 4))
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "replacement for image %d (%s) is empty", i,
                                   model->image_names && model->image_names[i] ? model->image_names[i] : "?");
        }
    return TEXOPT_OK;
}

/* Drops the KHR_texture_transform of a binding on TEXCOORD_0; notes whether another keeps one. */
void drop_transform(int index, int texcoord, tinygltf::ExtensionMap &ext, bool *kept)
{
    auto it = ext.find("KHR_texture_transform");
    if (index < 0 || it == ext.end())
        return;
    if (texcoord == 0)
        ext.erase(it);
    else
        *kept = true;
}

/* The same for the textures of material extension `extension` that the loader laid out (the
 * known ones on TEXCOORD_0: gltf_extension_textures.hpp). */
void drop_extension_texture_transforms(const std::string &extension, tinygltf::Value &v)
{
    if (!v.IsObject())
        return;
    for (auto &kv : v.Get<tinygltf::Value::Object>()) {
        int texcoord;
        texopt_texture_kind kind;
        unsigned channels;
        const char *name;
        if (!gltf_is_texture_info(kv.first, kv.second, &texcoord) || texcoord != 0 ||
            !gltf_known_extension_texture(extension, kv.first, &kind, &channels, &name) || !kv.second.Has("extensions"))
            continue;
        tinygltf::Value &exts = kv.second.Get<tinygltf::Value::Object>()["extensions"];
        if (!exts.IsObject())
            continue;
        tinygltf::Value::Object &obj = exts.Get<tinygltf::Value::Object>();
        obj.erase("KHR_texture_transform");
        if (obj.empty())
            kv.second.Get<tinygltf::Value::Object>().erase("extensions");
    }
}

bool value_names_key(const tinygltf::Value &v, const char *key)
{
    if (v.IsObject())
        for (const std::string &k : v.Keys())
            if (k == key || value_names_key(v.Get(k), key))
                return true;
    if (v.IsArray())
        for (size_t i = 0; i < v.ArrayLen(); i++)
            if (value_names_key(v.Get((int)i), key))
                return true;
    return false;
}

/* Calls f(index, texCoord, extensions) for each of material m's five core textureInfos. */
template <typename F> void for_each_core_texture(tinygltf::Material &m, F f)
{
    tinygltf::PbrMetallicRoughness &pbr = m.pbrMetallicRoughness;
    f(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions);
    f(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
      pbr.metallicRoughnessTexture.extensions);
    f(m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.extensions);
    f(m.occlusionTexture.index, m.occlusionTexture.texCoord, m.occlusionTexture.extensions);
    f(m.emissiveTexture.index, m.emissiveTexture.texCoord, m.emissiveTexture.extensions);
}

/* The loader applied every TEXCOORD_0 binding's KHR_texture_transform to the UVs
 * (model.h's uv_transform), so the new UVs read the new textures directly: those transforms
 * go, and the extension's declaration with them unless a binding on another set keeps one. */
void drop_applied_texture_transforms(tinygltf::Model &g)
{
    bool kept = false;
    for (tinygltf::Material &m : g.materials) {
        for_each_core_texture(m, [&](int &index, int texcoord, tinygltf::ExtensionMap &ext) {
            drop_transform(index, texcoord, ext, &kept);
        });
        for (auto &e : m.extensions) {
            drop_extension_texture_transforms(e.first, e.second);
            kept = kept || value_names_key(e.second, "KHR_texture_transform"); /* bindings on other sets */
        }
    }
    if (kept)
        return;
    for (std::vector<std::string> *list : {&g.extensionsUsed, &g.extensionsRequired})
        list->erase(std::remove(list->begin(), list->end(), std::string("KHR_texture_transform")), list->end());
}

/* Appends a buffer view holding data (made[view] keeps the bytes) and returns its index. */
int append_view(tinygltf::Model &g, std::vector<unsigned char> data, int target, size_t stride,
                std::vector<std::vector<unsigned char>> *made)
{
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteLength = data.size();
    view.byteStride = stride;
    view.target = target;
    g.bufferViews.push_back(view);
    made->resize(g.bufferViews.size());
    made->back() = std::move(data);
    return (int)g.bufferViews.size() - 1;
}

/* Puts acc where accessor `old` was when no one else reads it, else appends it; returns its
 * index. */
int place_accessor(tinygltf::Model &g, std::vector<int> &readers, int old, tinygltf::Accessor acc)
{
    if (old >= 0 && (size_t)old < readers.size() && readers[(size_t)old] == 1) {
        acc.name = g.accessors[(size_t)old].name;
        acc.extras = g.accessors[(size_t)old].extras;
        g.accessors[(size_t)old] = acc;
        return old;
    }
    if (old >= 0 && (size_t)old < readers.size())
        readers[(size_t)old]--;
    g.accessors.push_back(acc);
    return (int)g.accessors.size() - 1;
}

/* A vertex attribute accessor with element i copied from file vertex file_vertex[i] of
 * accessor `old` (the loader checked its bounds). Elements are padded to 4 bytes as glTF
 * asks of vertex attributes. */
int gather_attribute(tinygltf::Model &g, const tinygltf::Model &src, std::vector<int> &readers, int old,
                     const uint32_t *file_vertex, size_t n, std::vector<std::vector<unsigned char>> *made)
{
    const tinygltf::Accessor &a = src.accessors[(size_t)old];
    size_t elem = (size_t)tinygltf::GetComponentSizeInBytes((uint32_t)a.componentType) *
                  (size_t)tinygltf::GetNumComponentsInType((uint32_t)a.type);
    size_t stride = (elem + 3) / 4 * 4;
    std::vector<unsigned char> data(n * stride, 0);
    if (a.bufferView >= 0) {
        const tinygltf::BufferView &view = src.bufferViews[(size_t)a.bufferView];
        int from_stride = a.ByteStride(view);
        const unsigned char *base = src.buffers[(size_t)view.buffer].data.data() + view.byteOffset + a.byteOffset;
        for (size_t i = 0; i < n && from_stride > 0; i++)
            memcpy(data.data() + i * stride, base + (size_t)file_vertex[i] * (size_t)from_stride, elem);
    }
    tinygltf::Accessor acc = a;
    acc.bufferView = append_view(g, std::move(data), TINYGLTF_TARGET_ARRAY_BUFFER, stride == elem ? 0 : stride, made);
    acc.byteOffset = 0;
    acc.count = n;
    acc.sparse.isSparse = false;                 /* the loader refuses sparse accessors */
    return place_accessor(g, readers, old, acc); /* copies only: min and max stay exact */
}

/* Primitive tp's triangles as a new unsigned-int index accessor, in the file's winding. */
int triangle_indices(tinygltf::Model &g, std::vector<int> &readers, int old, const texopt_model *model,
                     const texopt_primitive &tp, std::vector<std::vector<unsigned char>> *made)
{
    std::vector<uint32_t> idx(3 * tp.triangle_count);
    for (size_t t = 0; t < tp.triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            int from = tp.winding_flipped && k > 0 ? 3 - k : k;
            idx[3 * t + (size_t)k] =
                model->triangles[3 * (tp.first_triangle + t) + (size_t)from] - (uint32_t)tp.first_vertex;
        }
    std::vector<unsigned char> data(idx.size() * sizeof(uint32_t));
    if (!data.empty())
        memcpy(data.data(), idx.data(), data.size());
    tinygltf::Accessor acc;
    acc.bufferView = append_view(g, std::move(data), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, 0, made);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    acc.type = TINYGLTF_TYPE_SCALAR;
    acc.count = idx.size();
    return place_accessor(g, readers, old, acc);
}

/* Whether primitive tp holds vertices model_split.h copied. */
bool primitive_was_split(const tinygltf::Model &src, const tinygltf::Primitive &p, const texopt_model *model,
                         const texopt_primitive &tp)
{
    if (!model->file_vertex)
        return false;
    auto pos = p.attributes.find("POSITION");
    if (pos != p.attributes.end() && src.accessors[(size_t)pos->second].count != tp.vertex_count)
        return true;
    for (size_t v = 0; v < tp.vertex_count; v++)
        if (model->file_vertex[tp.first_vertex + v] != v)
            return true;
    return false;
}

/* Rewrites every primitive model_split.h split: each attribute (morph targets' too) gathered
 * per model vertex, new triangle indices. */
void write_split_vertices(tinygltf::Model &g, const tinygltf::Model &src, const texopt_model *model,
                          std::vector<std::vector<unsigned char>> *made)
{
    std::vector<int> readers = accessor_readers(g);
    for (int pi = 0; pi < model->primitive_count; pi++) {
        const texopt_primitive &tp = model->primitives[pi];
        tinygltf::Primitive &p = g.meshes[(size_t)tp.gltf_mesh].primitives[(size_t)tp.gltf_primitive];
        if (!primitive_was_split(src, p, model, tp))
            continue;
        const uint32_t *fv = model->file_vertex + tp.first_vertex;
        for (auto &kv : p.attributes)
            kv.second = gather_attribute(g, src, readers, kv.second, fv, tp.vertex_count, made);
        for (auto &target : p.targets)
            for (auto &kv : target)
                kv.second = gather_attribute(g, src, readers, kv.second, fv, tp.vertex_count, made);
        p.indices = triangle_indices(g, readers, p.indices, model, tp, made);
        p.mode = TINYGLTF_MODE_TRIANGLES;
    }
}

/* Points every primitive that had TEXCOORD_0 at a float accessor holding its slice of uvs.
 * The data goes into a new buffer view appended to g; made[view] holds its bytes (the view
 * is placed in the BIN chunk later). */
void replace_texcoords(tinygltf::Model &g, const texopt_model *model, const float *uvs,
                       std::vector<std::vector<unsigned char>> *made)
{
    std::vector<int> readers = accessor_readers(g);
    for (int pi = 0; pi < model->primitive_count; pi++) {
        const texopt_primitive &tp = model->primitives[pi];
        tinygltf::Primitive &p = g.meshes[(size_t)tp.gltf_mesh].primitives[(size_t)tp.gltf_primitive];
        auto it = p.attributes.find("TEXCOORD_0");
        if (it == p.attributes.end())
            continue;
        const float *src = uvs + tp.first_vertex * 2;
        std::vector<unsigned char> data(tp.vertex_count * 2 * sizeof(float));
        if (!data.empty())
            memcpy(data.data(), src, data.size());
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteLength = data.size();
        view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
        int view_index = (int)g.bufferViews.size();
        g.bufferViews.push_back(view);
        made->resize(g.bufferViews.size());
        made->back() = std::move(data);

        tinygltf::Accessor acc;
        acc.bufferView = view_index;
        acc.byteOffset = 0;
        acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        acc.normalized = false;
        acc.type = TINYGLTF_TYPE_VEC2;
        acc.count = tp.vertex_count;
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (size_t v = 0; v < tp.vertex_count; v++)
            for (int k = 0; k < 2; k++) {
                double x = src[v * 2 + (size_t)k];
                lo[k] = x < lo[k] ? x : lo[k];
                hi[k] = x > hi[k] ? x : hi[k];
            }
        if (tp.vertex_count > 0) {
            acc.minValues = {lo[0], lo[1]};
            acc.maxValues = {hi[0], hi[1]};
        }
        int old = it->second;
        if (old >= 0 && (size_t)old < readers.size() && readers[(size_t)old] == 1) {
            acc.name = g.accessors[(size_t)old].name;
            acc.extras = g.accessors[(size_t)old].extras;
            g.accessors[(size_t)old] = acc; /* no one else reads it: replace in place */
        } else {
            if (old >= 0 && (size_t)old < readers.size())
                readers[(size_t)old]--;
            it->second = (int)g.accessors.size();
            g.accessors.push_back(acc);
        }
    }
}

/* A JPEG input's replacement is a JPEG again: as PNG, FoodApple01's three 4096x4096 JPEGs
 * (3.5 MB) resized to a tenth of their texels took 3.3 MB. At quality 98 they take 1.3 MB and
 * the file's q is 0.7% above the PNG's (95: 0.9 MB, +4.6%; 90: 0.7 MB, +10%): the encoding
 * adds next to nothing to the loss the layout was chosen for (BENCHMARKS.md@9f788a8 "What the written
 * file keeps"). */
const int JPEG_QUALITY = 98;

/* Whether replacement image i is written as a JPEG (its original was one, and the edit may
 * lose detail). */
bool replaced_as_jpeg(const texopt_model *model, const texopt_model_edit *edit, size_t i)
{
    const texopt_image *img = edit->images[i];
    return !edit->lossless && model->document->image_mime[i] == "image/jpeg" &&
           (img->channels == 1 || img->channels == 3);
}

/* Encodes every replacement image into (*encoded)[i]: a JPEG's as a JPEG (replaced_as_jpeg),
 * the others as PNG at 16 bits per channel where the original had more than 8, else 8. */
texopt_status encode_replacements(const texopt_model *model, const texopt_model_edit *edit,
                                  std::vector<std::vector<unsigned char>> *encoded, char *err, size_t err_len)
{
    encoded->assign((size_t)model->image_count, std::vector<unsigned char>());
    if (!edit || !edit->images)
        return TEXOPT_OK;
    /* Each job writes only its own vector: the images encode on parallel threads. */
    return texopt_run_image_jobs(
        (size_t)model->image_count,
        [&](size_t i, char *job_err, size_t job_err_len) {
            const texopt_image *img = edit->images[i];
            if (!img)
                return TEXOPT_OK;
            unsigned char *bytes = nullptr;
            size_t len = 0;
            int bits = model->document->image_bits[i] > 8 ? 16 : 8;
            texopt_status st =
                replaced_as_jpeg(model, edit, i)
                    ? texopt_image_encode_jpeg(img, JPEG_QUALITY, model->document->image_chroma_subsampled[i], &bytes,
                                               &len, job_err, job_err_len)
                    : texopt_image_encode_png_bits(img, bits, &bytes, &len, job_err, job_err_len);
            if (st == TEXOPT_OK)
                (*encoded)[i].assign(bytes, bytes + len);
            free(bytes);
            return st;
        },
        err, err_len);
}

/* Whether texopt replaced image (its new bytes in encoded). */
bool is_replaced(const std::vector<std::vector<unsigned char>> &encoded, int image)
{
    return image >= 0 && (size_t)image < encoded.size() && !encoded[(size_t)image].empty();
}

/* Gives bindings through another set than TEXCOORD_0 that read a replaced image (encoded[i]
 * not empty) a texture of their own on an untouched copy of that image (its MIME type appended to
 * mime, an empty entry to encoded), each copy made once. */
class other_set_bindings
{
  public:
    other_set_bindings(tinygltf::Model &g, std::vector<std::vector<unsigned char>> &encoded,
                       std::vector<std::string> &mime)
        : g_(g), encoded_(encoded), mime_(mime)
    {
    }

    void run()
    {
        for (tinygltf::Material &m : g_.materials) {
            for_each_core_texture(
                m, [&](int &index, int texcoord, tinygltf::ExtensionMap &) { retarget(&index, texcoord); });
            for (auto &e : m.extensions)
                walk(e.second);
        }
    }

  private:
    tinygltf::Model &g_;
    std::vector<std::vector<unsigned char>> &encoded_;
    std::vector<std::string> &mime_;
    std::map<int, int> image_copy_, texture_copy_;

    void retarget(int *index, int texcoord)
    {
        if (texcoord == 0 || *index < 0 || (size_t)*index >= g_.textures.size())
            return;
        /* the image texopt read for it: a WebP-only texture's is its alternate */
        if (!is_replaced(encoded_, gltf_texture_source(g_.textures[(size_t)*index])))
            return;
        auto t = texture_copy_.find(*index);
        if (t == texture_copy_.end()) {
            tinygltf::Texture copy = g_.textures[(size_t)*index];
            gltf_for_each_texture_image(copy, [&](int *image) {
                if (is_replaced(encoded_, *image))
                    *image = original_of(*image);
            });
            g_.textures.push_back(copy);
            t = texture_copy_.emplace(*index, (int)g_.textures.size() - 1).first;
        }
        *index = t->second;
    }

    int original_of(int image)
    {
        auto it = image_copy_.find(image);
        if (it != image_copy_.end())
            return it->second;
        g_.images.push_back(g_.images[(size_t)image]);
        encoded_.emplace_back();
        mime_.push_back(mime_[(size_t)image]);
        return image_copy_[image] = (int)g_.images.size() - 1;
    }

    /* Extension textureInfos at any depth (gltf_extension_textures.hpp's shape). */
    void walk(tinygltf::Value &v)
    {
        if (v.IsArray())
            for (size_t i = 0; i < v.ArrayLen(); i++)
                walk(v.Get<tinygltf::Value::Array>()[i]);
        if (!v.IsObject())
            return;
        for (auto &kv : v.Get<tinygltf::Value::Object>()) {
            int texcoord;
            if (gltf_is_texture_info(kv.first, kv.second, &texcoord) && texcoord != 0) {
                tinygltf::Value &index = kv.second.Get<tinygltf::Value::Object>()["index"];
                int i = index.GetNumberAsInt();
                retarget(&i, texcoord);
                index = tinygltf::Value(i);
            } else
                walk(kv.second);
        }
    }
};

/* A texture whose image texopt replaced reads the replacement only: without its alternate
 * sources (gltf_texture_source.hpp), which viewers knowing them would read instead. */
void point_textures_at_replacements(tinygltf::Model &g, const std::vector<std::vector<unsigned char>> &encoded)
{
    for (tinygltf::Texture &t : g.textures) {
        int image = gltf_texture_source(t);
        if (is_replaced(encoded, image))
            gltf_texture_read_only(t, image);
    }
    gltf_drop_unused_source_extensions(g);
}

/* The alternates of replaced textures, which nothing reads any more, leave the file with
 * their bytes (gltf_drop_images_made_unused); encoded and mime follow g's images. */
void drop_images_made_unused(tinygltf::Model &g, const tinygltf::Model &src,
                             std::vector<std::vector<unsigned char>> *encoded, std::vector<std::string> *mime)
{
    std::vector<int> renumber = gltf_drop_images_made_unused(g, src);
    std::vector<std::vector<unsigned char>> kept_encoded(g.images.size());
    std::vector<std::string> kept_mime(g.images.size());
    for (size_t i = 0; i < renumber.size(); i++)
        if (renumber[i] >= 0) {
            kept_encoded[(size_t)renumber[i]] = std::move((*encoded)[i]);
            kept_mime[(size_t)renumber[i]] = std::move((*mime)[i]);
        }
    *encoded = std::move(kept_encoded);
    *mime = std::move(kept_mime);
}

/* Builds the output document: new UVs, images in views, one buffer, unused views dropped. */
texopt_status build_output(const texopt_model *model, const texopt_model_edit *edit, tinygltf::Model *out, char *err,
                           size_t err_len)
{
    const texopt_gltf_document *doc = model->document;
    const tinygltf::Model &src = doc->gltf;
    *out = src;
    tinygltf::Model &g = *out;

    std::vector<std::vector<unsigned char>> encoded;
    texopt_status st = encode_replacements(model, edit, &encoded, err, err_len);
    if (st != TEXOPT_OK)
        return st;

    std::vector<std::string> mime = doc->image_mime;
    other_set_bindings(g, encoded, mime).run();
    point_textures_at_replacements(g, encoded);
    for (size_t i = 0; i < (size_t)model->image_count; i++)
        if (!encoded[i].empty())
            mime[i] = replaced_as_jpeg(model, edit, i) ? "image/jpeg" : "image/png";
    drop_images_made_unused(g, src, &encoded, &mime);

    /* Data of the views that will exist, by old index; views made here carry their bytes. */
    size_t old_views = g.bufferViews.size();
    std::vector<std::vector<unsigned char>> made(old_views);
    write_split_vertices(g, src, model, &made);
    if (edit && edit->uvs) {
        replace_texcoords(g, model, edit->uvs, &made);
        drop_applied_texture_transforms(g);
    }
    for (size_t i = 0; i < g.images.size(); i++) {
        tinygltf::Image &im = g.images[i];
        bool replaced = !encoded[i].empty();
        bool keeps_view = !replaced && im.bufferView >= 0;
        if (!keeps_view) {
            tinygltf::BufferView view;
            view.buffer = 0;
            view.byteLength = replaced ? encoded[i].size() : im.image.size();
            im.bufferView = (int)g.bufferViews.size();
            g.bufferViews.push_back(view);
            made.push_back(replaced ? std::move(encoded[i]) : im.image);
        }
        im.mimeType = mime[i];
        im.uri.clear();
        im.image.clear();
        im.as_is = false;
        im.width = im.height = im.component = im.bits = im.pixel_type = -1;
    }

    /* Keep only views someone reads, in their old order. */
    std::vector<char> used(g.bufferViews.size(), 0);
    for (const tinygltf::Accessor &a : g.accessors) {
        if (a.bufferView >= 0)
            used[(size_t)a.bufferView] = 1;
        if (a.sparse.isSparse) {
            used[(size_t)a.sparse.indices.bufferView] = 1;
            used[(size_t)a.sparse.values.bufferView] = 1;
        }
    }
    for (const tinygltf::Image &im : g.images)
        used[(size_t)im.bufferView] = 1;
    std::vector<int> renumber(g.bufferViews.size(), -1);
    std::vector<tinygltf::BufferView> views;
    bin_writer bin;
    for (size_t v = 0; v < g.bufferViews.size(); v++) {
        if (!used[v])
            continue;
        tinygltf::BufferView view = g.bufferViews[v];
        const unsigned char *data;
        size_t phase;
        if (v < old_views) {
            data = src.buffers[(size_t)view.buffer].data.data() + view.byteOffset;
            phase = view.byteOffset % 4;
        } else {
            data = made[v].data();
            phase = 0;
        }
        view.byteOffset = bin.append(data, view.byteLength, phase);
        view.buffer = 0;
        renumber[v] = (int)views.size();
        views.push_back(view);
    }
    for (tinygltf::Accessor &a : g.accessors) {
        if (a.bufferView >= 0)
            a.bufferView = renumber[(size_t)a.bufferView];
        if (a.sparse.isSparse) {
            a.sparse.indices.bufferView = renumber[(size_t)a.sparse.indices.bufferView];
            a.sparse.values.bufferView = renumber[(size_t)a.sparse.values.bufferView];
        }
    }
    for (tinygltf::Image &im : g.images)
        im.bufferView = renumber[(size_t)im.bufferView];
    g.bufferViews = views;
    while (bin.bytes.size() % 4 != 0)
        bin.bytes.push_back(0);

    tinygltf::Buffer buffer;
    if (!src.buffers.empty()) {
        buffer.name = src.buffers[0].name;
        buffer.extras = src.buffers[0].extras;
    }
    buffer.data = std::move(bin.bytes);
    g.buffers.clear();
    if (!buffer.data.empty())
        g.buffers.push_back(std::move(buffer));
    return TEXOPT_OK;
}

} // namespace

extern "C" texopt_status texopt_model_save_glb(const texopt_model *model, const texopt_model_edit *edit,
                                               const char *path, char *err, size_t err_len)
{
    if (!model || !path || !*path)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no model or no path to save to");
    if (!model->document)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "model was not loaded from a glTF file; there is no document to save");
    const tinygltf::Model &src = model->document->gltf;
    if ((size_t)model->image_count != src.images.size())
        return texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "model has %d images but its document %zu",
                           model->image_count, src.images.size());
    texopt_status st = check_edit(model, edit, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    std::string glb;
    try {
        tinygltf::Model out;
        st = build_output(model, edit, &out, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        std::ostringstream stream;
        tinygltf::TinyGLTF writer;
        if (!writer.WriteGltfSceneToStream(&out, stream, false, true))
            return texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "tinygltf could not serialise the model");
        glb = stream.str();
    } catch (const std::bad_alloc &) {
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory while writing %s", path);
    }
    return texopt_write_file_atomic(path, glb.data(), glb.size(), err, err_len);
}

/* gltf_texture_source.cpp - see gltf_texture_source.hpp. */
#include "gltf_texture_source.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <string>
#include <vector>

namespace
{

const char *const alternate_sources[] = {"EXT_texture_webp", "KHR_texture_basisu", "MSFT_texture_dds"};

/* Per image of g, whether a texture names it. */
std::vector<char> images_textures_name(const tinygltf::Model &g)
{
    std::vector<char> named(g.images.size(), 0);
    for (tinygltf::Texture t : g.textures)
        gltf_for_each_texture_image(t, [&](int *image) {
            if (*image >= 0 && (size_t)*image < named.size())
                named[(size_t)*image] = 1;
        });
    return named;
}

/* Extensions whose specifications name no image outside textures, so that removing an image
 * and renumbering the textures' references leaves nothing dangling. */
bool names_images_only_through_textures(const std::string &ext)
{
    static const char *const prefixes[] = {"KHR_materials_", "KHR_texture_"};
    static const char *const names[] = {"EXT_texture_webp",    "MSFT_texture_dds",        "KHR_mesh_quantization",
                                        "KHR_lights_punctual", "EXT_mesh_gpu_instancing", "KHR_xmp_json_ld"};
    for (const char *p : prefixes)
        if (ext.compare(0, strlen(p), p) == 0)
            return true;
    return std::any_of(std::begin(names), std::end(names), [&](const char *n) { return ext == n; });
}

} // namespace

int gltf_texture_source(const tinygltf::Texture &t)
{
    if (t.source >= 0)
        return t.source;
    for (const char *ext : alternate_sources) {
        auto it = t.extensions.find(ext);
        if (it != t.extensions.end() && it->second.IsObject() && it->second.Has("source") &&
            it->second.Get("source").IsInt())
            return it->second.Get("source").GetNumberAsInt();
    }
    return -1;
}

void gltf_for_each_texture_image(tinygltf::Texture &t, const std::function<void(int *)> &f)
{
    if (t.source >= 0)
        f(&t.source);
    for (const char *ext : alternate_sources) {
        auto it = t.extensions.find(ext);
        if (it == t.extensions.end() || !it->second.IsObject() || !it->second.Has("source") ||
            !it->second.Get("source").IsInt())
            continue;
        int image = it->second.Get("source").GetNumberAsInt();
        f(&image);
        it->second.Get<tinygltf::Value::Object>()["source"] = tinygltf::Value(image);
    }
}

void gltf_texture_read_only(tinygltf::Texture &t, int image)
{
    t.source = image;
    for (const char *ext : alternate_sources)
        t.extensions.erase(ext);
}

void gltf_drop_unused_source_extensions(tinygltf::Model &g)
{
    for (const char *ext : alternate_sources) {
        bool used = std::any_of(g.textures.begin(), g.textures.end(),
                                [&](const tinygltf::Texture &t) { return t.extensions.count(ext) > 0; });
        if (used)
            continue;
        for (std::vector<std::string> *list : {&g.extensionsUsed, &g.extensionsRequired})
            list->erase(std::remove(list->begin(), list->end(), std::string(ext)), list->end());
    }
}

std::vector<int> gltf_drop_images_made_unused(tinygltf::Model &g, const tinygltf::Model &before)
{
    std::vector<int> renumber(g.images.size());
    for (size_t i = 0; i < renumber.size(); i++)
        renumber[i] = (int)i;
    if (!std::all_of(g.extensionsUsed.begin(), g.extensionsUsed.end(), names_images_only_through_textures))
        return renumber;
    std::vector<char> named_before = images_textures_name(before), named = images_textures_name(g);
    std::vector<tinygltf::Image> kept;
    for (size_t i = 0; i < g.images.size(); i++) {
        if (i < named_before.size() && named_before[i] && !named[i]) {
            renumber[i] = -1;
            continue;
        }
        renumber[i] = (int)kept.size();
        kept.push_back(std::move(g.images[i]));
    }
    g.images = std::move(kept);
    for (tinygltf::Texture &t : g.textures)
        gltf_for_each_texture_image(t, [&](int *image) {
            if (*image >= 0 && (size_t)*image < renumber.size())
                *image = renumber[(size_t)*image];
        });
    return renumber;
}

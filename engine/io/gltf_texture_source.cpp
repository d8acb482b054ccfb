/* gltf_texture_source.cpp - see gltf_texture_source.hpp. */
#include "gltf_texture_source.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace {

const char *const alternate_sources[] = {"EXT_texture_webp", "KHR_texture_basisu", "MSFT_texture_dds"};

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

/* gltf_extension_textures.cpp - see gltf_extension_textures.hpp. */
#include "gltf_extension_textures.hpp"

bool gltf_is_texture_info(const std::string &key, const tinygltf::Value &v, int *texcoord)
{
    const char suffix[] = "Texture";
    size_t n = sizeof suffix - 1;
    if (key.size() < n || key.compare(key.size() - n, n, suffix) != 0 || !v.IsObject() || !v.Has("index") ||
        !v.Get("index").IsInt())
        return false;
    *texcoord = v.Has("texCoord") && v.Get("texCoord").IsInt() ? v.Get("texCoord").GetNumberAsInt() : 0;
    return true;
}

bool gltf_known_extension_texture(const std::string &extension, const std::string &key, texopt_texture_kind *kind,
                                  unsigned *channels, const char **name)
{
    int k = texopt_texture_key_of_extension(extension.c_str(), key.c_str());
    if (k < 0)
        return false;
    *kind = texopt_texture_key_kind(k);
    *channels = texopt_texture_key_channels(k);
    *name = texopt_texture_key_name(k);
    return true;
}

namespace
{

bool unknown_on_set0(const tinygltf::Value &v, const std::string *extension, std::string *name)
{
    if (!v.IsObject())
        return false;
    for (const std::string &key : v.Keys()) {
        const tinygltf::Value &child = v.Get(key);
        int texcoord = 0;
        texopt_texture_kind kind;
        unsigned channels;
        const char *known_name;
        if (gltf_is_texture_info(key, child, &texcoord)) {
            bool known_here = extension && gltf_known_extension_texture(*extension, key, &kind, &channels, &known_name);
            if (texcoord == 0 && !known_here) {
                *name = key;
                return true;
            }
        } else if (unknown_on_set0(child, nullptr, name)) {
            return true;
        }
    }
    return false;
}

} // namespace

bool gltf_unknown_extension_texture_on_set0(const std::string &extension, const tinygltf::Value &v, std::string *name)
{
    return unknown_on_set0(v, &extension, name);
}

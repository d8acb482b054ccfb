/* gltf_extension_textures.cpp - see gltf_extension_textures.hpp. */
#include "gltf_extension_textures.hpp"

namespace {

struct known_texture {
    const char *extension, *key;
    texopt_texture_kind kind;
    unsigned channels; /* where its extension stores its numbers */
};

/* Colour textures hold sRGB colours; the others numbers in the channels their extension names
 * (specular strength, sheen roughness and diffuse transmission in alpha). */
const known_texture known[] = {
    {"KHR_materials_clearcoat", "clearcoatTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_R},
    {"KHR_materials_clearcoat", "clearcoatRoughnessTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_G},
    {"KHR_materials_clearcoat", "clearcoatNormalTexture", TEXOPT_TEXTURE_NORMAL, TEXOPT_CHANNELS_RGB},
    {"KHR_materials_sheen", "sheenColorTexture", TEXOPT_TEXTURE_COLOR, TEXOPT_CHANNELS_RGB},
    {"KHR_materials_sheen", "sheenRoughnessTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_A},
    {"KHR_materials_specular", "specularTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_A},
    {"KHR_materials_specular", "specularColorTexture", TEXOPT_TEXTURE_COLOR, TEXOPT_CHANNELS_RGB},
    {"KHR_materials_transmission", "transmissionTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_R},
    {"KHR_materials_volume", "thicknessTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_G},
    {"KHR_materials_iridescence", "iridescenceTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_R},
    {"KHR_materials_iridescence", "iridescenceThicknessTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_G},
    {"KHR_materials_diffuse_transmission", "diffuseTransmissionTexture", TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_A},
    {"KHR_materials_diffuse_transmission", "diffuseTransmissionColorTexture", TEXOPT_TEXTURE_COLOR,
     TEXOPT_CHANNELS_RGB},
};

} // namespace

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

bool gltf_known_extension_texture(const std::string &extension, const std::string &key,
                                  texopt_texture_kind *kind, unsigned *channels, const char **name)
{
    for (const known_texture &k : known)
        if (extension == k.extension && key == k.key) {
            *kind = k.kind;
            *channels = k.channels;
            *name = k.key;
            return true;
        }
    return false;
}

namespace {

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

bool gltf_unknown_extension_texture_on_set0(const std::string &extension, const tinygltf::Value &v,
                                            std::string *name)
{
    return unknown_on_set0(v, &extension, name);
}

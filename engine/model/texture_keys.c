/* texture_keys.c - see texture_keys.h. */
#include "texture_keys.h"

#include <stddef.h>
#include <string.h>
#include <strings.h>

/* Colour textures hold sRGB colours; normal-kind ones a direction in the tangent frame; the
 * others numbers in the channels their extension names (specular strength, sheen roughness and
 * diffuse transmission in alpha). */
static const texopt_known_extension_texture known[TEXOPT_KNOWN_EXTENSION_TEXTURES] = {
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
    /* A direction in R and G in the tangent frame, as a normal map's XY, and a strength in B: it
     * turns with the layout as a normal map does. */
    {"KHR_materials_anisotropy", "anisotropyTexture", TEXOPT_TEXTURE_NORMAL, TEXOPT_CHANNELS_RGB},
};

const texopt_known_extension_texture *texopt_known_extension_texture_at(int i)
{
    return i >= 0 && i < TEXOPT_KNOWN_EXTENSION_TEXTURES ? &known[i] : NULL;
}

int texopt_texture_key_of_extension(const char *extension, const char *key)
{
    for (int i = 0; extension && key && i < TEXOPT_KNOWN_EXTENSION_TEXTURES; i++)
        if (!strcmp(extension, known[i].extension) && !strcmp(key, known[i].key))
            return TEXOPT_SLOT_COUNT + i;
    return -1;
}

const char *texopt_texture_key_name(int key)
{
    const texopt_known_extension_texture *k = texopt_known_extension_texture_at(key - TEXOPT_SLOT_COUNT);
    return k ? k->key : texopt_slot_name((texopt_slot)key);
}

int texopt_texture_key_from_name(const char *name)
{
    for (int key = 0; name && key < TEXOPT_TEXTURE_KEY_COUNT; key++)
        if (!strcasecmp(name, texopt_texture_key_name(key)))
            return key;
    return -1;
}

texopt_texture_kind texopt_texture_key_kind(int key)
{
    const texopt_known_extension_texture *k = texopt_known_extension_texture_at(key - TEXOPT_SLOT_COUNT);
    if (k)
        return k->kind;
    texopt_material opaque = {0};
    return key >= 0 && key < TEXOPT_SLOT_COUNT ? texopt_material_binding_kind(&opaque, key) : TEXOPT_TEXTURE_DATA;
}

unsigned texopt_texture_key_channels(int key)
{
    const texopt_known_extension_texture *k = texopt_known_extension_texture_at(key - TEXOPT_SLOT_COUNT);
    if (k)
        return k->channels;
    texopt_material opaque = {0};
    return key >= 0 && key < TEXOPT_SLOT_COUNT ? texopt_material_binding_channels(&opaque, key) : 0u;
}

const texopt_texture_ref *texopt_material_texture(const texopt_material *mat, int key)
{
    if (key >= 0 && key < TEXOPT_SLOT_COUNT)
        return &mat->slot[key];
    const char *name = texopt_known_extension_texture_at(key - TEXOPT_SLOT_COUNT) ? texopt_texture_key_name(key) : NULL;
    for (int i = TEXOPT_SLOT_COUNT; name && i < texopt_material_binding_count(mat); i++)
        if (!strcmp(texopt_material_binding_name(mat, i), name))
            return texopt_material_binding(mat, i);
    return NULL;
}

/* texture_keys.h - the textures a material can bind, named the same way in every material: the
 * five core slots of a glTF material (model.h texopt_slot, keys 0-4), then the textures of the
 * material extensions texopt knows (clearcoat, sheen, specular...), keys from
 * TEXOPT_SLOT_COUNT on. A key is what the whole-mesh evaluation measures q in (evaluate.h
 * `texture`); the extensions' table is also what the loader reads their textures by.
 *
 * Each known extension texture has a kind (model.h texopt_texture_kind) and the channels its
 * extension keeps its numbers in (clearcoat's R, specular's A). Extensions whose textures are
 * not here are refused at load (io/gltf_extension_textures.hpp says which on purpose).
 *
 * Does not: load, bind or bake anything. */
#ifndef TEXOPT_TEXTURE_KEYS_H
#define TEXOPT_TEXTURE_KEYS_H

#include "model.h"

typedef struct texopt_known_extension_texture {
    const char *extension; /* "KHR_materials_clearcoat" */
    const char *key;       /* its property in the extension's object: "clearcoatTexture" */
    texopt_texture_kind kind;
    unsigned channels; /* TEXOPT_CHANNEL_* its extension reads */
} texopt_known_extension_texture;

#define TEXOPT_KNOWN_EXTENSION_TEXTURES 14
#define TEXOPT_TEXTURE_KEY_COUNT (TEXOPT_SLOT_COUNT + TEXOPT_KNOWN_EXTENSION_TEXTURES)

/* Known extension texture i in [0, TEXOPT_KNOWN_EXTENSION_TEXTURES), or NULL. */
const texopt_known_extension_texture *texopt_known_extension_texture_at(int i);

/* The key of texture `key` of extension `extension` (exact names), or -1 when not known. */
int texopt_texture_key_of_extension(const char *extension, const char *key);

/* A key's name: texopt_slot_name of a slot, an extension texture's property name
 * ("clearcoatTexture"); "unknown" out of range. */
const char *texopt_texture_key_name(int key);

/* The key a name gives (texopt_texture_key_name's, case-insensitive), or -1. */
int texopt_texture_key_from_name(const char *name);

/* The kind of a key's texture, and the channels every material reads of it (base colour: RGB;
 * whether its alpha shows depends on the material, model.h texopt_material_binding_channels). */
texopt_texture_kind texopt_texture_key_kind(int key);
unsigned texopt_texture_key_channels(int key);

/* The material's binding of `key` (its slot, or its extension texture of that name), or NULL
 * when key is out of range or the material binds no extension texture of that name. */
const texopt_texture_ref *texopt_material_texture(const texopt_material *mat, int key);

#endif

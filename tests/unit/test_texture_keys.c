/* test_texture_keys.c - the texture keys of engine/model/texture_keys.h: the core slots keep their
 * texopt_slot numbers, every known extension texture has one key whose name, kind and
 * channels are its extension's, names resolve both ways (case-insensitive), and a material's
 * binding of a key is its slot or its extension texture of that name. */
#include <string.h>

#include "test.h"
#include "texture_keys.h"

TEST(slots_are_the_first_keys)
{
    for (int s = 0; s < TEXOPT_SLOT_COUNT; s++) {
        CHECK(strcmp(texopt_texture_key_name(s), texopt_slot_name((texopt_slot)s)) == 0);
        CHECK_EQ_INT(texopt_texture_key_from_name(texopt_slot_name((texopt_slot)s)), s);
    }
    CHECK_EQ_INT(texopt_texture_key_kind(TEXOPT_SLOT_NORMAL), TEXOPT_TEXTURE_NORMAL);
    CHECK_EQ_INT(texopt_texture_key_kind(TEXOPT_SLOT_EMISSIVE), TEXOPT_TEXTURE_COLOR);
    CHECK_EQ_INT(texopt_texture_key_channels(TEXOPT_SLOT_BASE_COLOR), TEXOPT_CHANNELS_RGB);
    CHECK_EQ_INT(texopt_texture_key_channels(TEXOPT_SLOT_METALLIC_ROUGHNESS), TEXOPT_CHANNEL_G | TEXOPT_CHANNEL_B);
    CHECK_EQ_INT(texopt_texture_key_channels(TEXOPT_SLOT_OCCLUSION), TEXOPT_CHANNEL_R);
}

TEST(every_extension_texture_has_one_key_with_its_extension_s_meaning)
{
    for (int i = 0; i < TEXOPT_KNOWN_EXTENSION_TEXTURES; i++) {
        const texopt_known_extension_texture *k = texopt_known_extension_texture_at(i);
        CHECK(k != NULL);
        int key = texopt_texture_key_of_extension(k->extension, k->key);
        CHECK_EQ_INT(key, TEXOPT_SLOT_COUNT + i);
        CHECK(strcmp(texopt_texture_key_name(key), k->key) == 0);
        CHECK_EQ_INT(texopt_texture_key_from_name(k->key), key);
        CHECK_EQ_INT(texopt_texture_key_kind(key), k->kind);
        CHECK_EQ_INT(texopt_texture_key_channels(key), k->channels);
        for (int j = 0; j < i; j++)
            CHECK(strcmp(texopt_known_extension_texture_at(j)->key, k->key) != 0);
    }
    int coat = texopt_texture_key_of_extension("KHR_materials_clearcoat", "clearcoatNormalTexture");
    CHECK_EQ_INT(texopt_texture_key_kind(coat), TEXOPT_TEXTURE_NORMAL);
    int specular = texopt_texture_key_of_extension("KHR_materials_specular", "specularTexture");
    CHECK_EQ_INT(texopt_texture_key_channels(specular), TEXOPT_CHANNEL_A);
    CHECK_EQ_INT(texopt_texture_key_from_name("SPECULARTEXTURE"), specular);
    /* A key under another extension, or a name no extension has, is not known. */
    CHECK_EQ_INT(texopt_texture_key_of_extension("KHR_materials_sheen", "clearcoatTexture"), -1);
    CHECK_EQ_INT(texopt_texture_key_of_extension("KHR_materials_pbrSpecularGlossiness", "diffuseTexture"), -1);
    CHECK_EQ_INT(texopt_texture_key_of_extension(NULL, "clearcoatTexture"), -1);
    CHECK_EQ_INT(texopt_texture_key_from_name("diffuseTexture"), -1);
    /* An anisotropy direction map turns with the layout like a normal map. */
    int anisotropy = texopt_texture_key_of_extension("KHR_materials_anisotropy", "anisotropyTexture");
    CHECK_EQ_INT(texopt_texture_key_kind(anisotropy), TEXOPT_TEXTURE_NORMAL);
    CHECK_EQ_INT(texopt_texture_key_from_name(NULL), -1);
    CHECK(texopt_known_extension_texture_at(TEXOPT_KNOWN_EXTENSION_TEXTURES) == NULL);
    CHECK(texopt_known_extension_texture_at(-1) == NULL);
    CHECK(strcmp(texopt_texture_key_name(TEXOPT_TEXTURE_KEY_COUNT), "unknown") == 0);
    CHECK(strcmp(texopt_texture_key_name(-1), "unknown") == 0);
    CHECK_EQ_INT(texopt_texture_key_channels(TEXOPT_TEXTURE_KEY_COUNT), 0);
}

TEST(a_material_s_binding_of_a_key_is_its_slot_or_its_extension_texture_of_that_name)
{
    texopt_material mat;
    memset(&mat, 0, sizeof mat);
    mat.slot[TEXOPT_SLOT_OCCLUSION].image = 3;
    mat.extra[0] = (texopt_extra_texture){{.image = 5}, TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_R, "clearcoatTexture"};
    mat.extra[1] = (texopt_extra_texture){{.image = 7}, TEXOPT_TEXTURE_COLOR, TEXOPT_CHANNELS_RGB, "sheenColorTexture"};
    mat.extra_count = 2;
    CHECK(texopt_material_texture(&mat, TEXOPT_SLOT_OCCLUSION) == &mat.slot[TEXOPT_SLOT_OCCLUSION]);
    CHECK(texopt_material_texture(&mat, texopt_texture_key_from_name("sheenColorTexture")) == &mat.extra[1].ref);
    CHECK(texopt_material_texture(&mat, texopt_texture_key_from_name("clearcoatTexture")) == &mat.extra[0].ref);
    CHECK(texopt_material_texture(&mat, texopt_texture_key_from_name("specularTexture")) == NULL);
    CHECK(texopt_material_texture(&mat, TEXOPT_TEXTURE_KEY_COUNT) == NULL);
    CHECK(texopt_material_texture(&mat, -1) == NULL);
    /* Extension textures past extra_count are not the material's. */
    mat.extra_count = 1;
    CHECK(texopt_material_texture(&mat, texopt_texture_key_from_name("sheenColorTexture")) == NULL);
}

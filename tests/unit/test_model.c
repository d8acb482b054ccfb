/* test_model.c - texture-domain grouping of engine/model/model.c (texopt_model_build_domains):
 * shared images join materials into one domain, unrelated materials stay apart, untextured
 * primitives get domain -1, TEXCOORD_1 bindings do not count, the frame is the largest
 * image, the wrap modes come from the base colour binding; and destroy accepts NULL. */
#include <stdlib.h>
#include <string.h>

#include "model.h"
#include "test.h"

/* A model with no geometry: n_img images of the given sizes (no pixels are needed), n_mat
 * empty materials and n_prim primitives without material. Tests fill in the bindings. */
static texopt_model *bare_model(int n_img, const int *sizes, int n_mat, int n_prim)
{
    texopt_model *m = calloc(1, sizeof *m);
    m->image_count = n_img;
    m->images = calloc((size_t)n_img + 1, sizeof(texopt_image));
    m->image_names = calloc((size_t)n_img + 1, sizeof(char *));
    for (int i = 0; i < n_img; i++) {
        m->images[i].width = sizes[2 * i];
        m->images[i].height = sizes[2 * i + 1];
        m->images[i].channels = 3;
    }
    m->material_count = n_mat;
    m->materials = calloc((size_t)n_mat + 1, sizeof(texopt_material));
    for (int k = 0; k < n_mat; k++)
        for (int s = 0; s < TEXOPT_SLOT_COUNT; s++)
            m->materials[k].slot[s].image = -1;
    m->primitive_count = n_prim;
    m->primitives = calloc((size_t)n_prim + 1, sizeof(texopt_primitive));
    for (int p = 0; p < n_prim; p++) {
        m->primitives[p].material = -1;
        m->primitives[p].domain = 12345; /* must be overwritten */
    }
    return m;
}

static void bind(texopt_model *m, int material, texopt_slot slot, int image, int texcoord, texopt_wrap s, texopt_wrap t)
{
    texopt_texture_ref *r = &m->materials[material].slot[slot];
    r->image = image;
    r->texcoord = texcoord;
    r->wrap_s = s;
    r->wrap_t = t;
}

static int domain_has_image(const texopt_domain *d, int image)
{
    for (int i = 0; i < d->image_count; i++)
        if (d->images[i] == image)
            return 1;
    return 0;
}

TEST(materials_sharing_an_image_form_one_domain)
{
    char err[256] = "";
    const int sizes[] = {64, 64, 256, 128, 32, 32};
    texopt_model *m = bare_model(3, sizes, 2, 2);
    /* Material 0: base colour image 0, normal image 1. Material 1: base colour image 2,
     * normal image 1 (shared), so both primitives must land in one domain of 3 images. */
    bind(m, 0, TEXOPT_SLOT_BASE_COLOR, 0, 0, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_MIRROR);
    bind(m, 0, TEXOPT_SLOT_NORMAL, 1, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 1, TEXOPT_SLOT_BASE_COLOR, 2, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 1, TEXOPT_SLOT_NORMAL, 1, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    m->primitives[0].material = 0;
    m->primitives[1].material = 1;
    CHECK_OK(texopt_model_build_domains(m, err, sizeof err), err);
    CHECK_EQ_INT(m->domain_count, 1);
    CHECK_EQ_INT(m->primitives[0].domain, 0);
    CHECK_EQ_INT(m->primitives[1].domain, 0);
    const texopt_domain *d = &m->domains[0];
    CHECK_EQ_INT(d->primitive_count, 2);
    CHECK_EQ_INT(d->image_count, 3);
    CHECK(domain_has_image(d, 0) && domain_has_image(d, 1) && domain_has_image(d, 2));
    /* Frame = the largest image (256 x 128 has the most texels), not the first. */
    CHECK_EQ_INT(d->width, 256);
    CHECK_EQ_INT(d->height, 128);
    /* Wrap modes of the first primitive's base colour binding. */
    CHECK_EQ_INT(d->wrap_s, TEXOPT_WRAP_CLAMP);
    CHECK_EQ_INT(d->wrap_t, TEXOPT_WRAP_MIRROR);
    texopt_model_destroy(m);
}

TEST(unrelated_materials_form_separate_domains_and_untextured_is_minus_one)
{
    char err[256] = "";
    const int sizes[] = {64, 64, 128, 128};
    texopt_model *m = bare_model(2, sizes, 3, 4);
    bind(m, 0, TEXOPT_SLOT_BASE_COLOR, 0, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 1, TEXOPT_SLOT_EMISSIVE, 1, 0, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP);
    /* Material 2 is untextured. Primitive order: untextured, material 1, material 0,
     * material 1 again; domains are numbered by first appearance. */
    m->primitives[0].material = 2;
    m->primitives[1].material = 1;
    m->primitives[2].material = 0;
    m->primitives[3].material = 1;
    CHECK_OK(texopt_model_build_domains(m, err, sizeof err), err);
    CHECK_EQ_INT(m->domain_count, 2);
    CHECK_EQ_INT(m->primitives[0].domain, -1);
    CHECK_EQ_INT(m->primitives[1].domain, 0);
    CHECK_EQ_INT(m->primitives[2].domain, 1);
    CHECK_EQ_INT(m->primitives[3].domain, 0);
    CHECK_EQ_INT(m->domains[0].primitive_count, 2);
    CHECK_EQ_INT(m->domains[0].primitives[0], 1);
    CHECK_EQ_INT(m->domains[0].primitives[1], 3);
    CHECK_EQ_INT(m->domains[0].width, 128);
    CHECK_EQ_INT(m->domains[0].wrap_s, TEXOPT_WRAP_CLAMP); /* only an emissive binding: use it */
    CHECK_EQ_INT(m->domains[1].width, 64);
    CHECK_EQ_INT(m->domains[1].image_count, 1);
    CHECK_EQ_INT(m->domains[1].images[0], 0);
    texopt_model_destroy(m);
}

TEST(texcoord1_bindings_and_missing_materials_do_not_make_domains)
{
    char err[256] = "";
    const int sizes[] = {64, 64, 512, 512};
    texopt_model *m = bare_model(2, sizes, 2, 3);
    bind(m, 0, TEXOPT_SLOT_OCCLUSION, 1, 1, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT); /* lightmap on UV1 */
    bind(m, 1, TEXOPT_SLOT_BASE_COLOR, 0, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 1, TEXOPT_SLOT_OCCLUSION, 1, 1, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    m->primitives[0].material = 0;
    m->primitives[1].material = 1;
    m->primitives[2].material = -1;
    CHECK_OK(texopt_model_build_domains(m, err, sizeof err), err);
    CHECK_EQ_INT(m->domain_count, 1);
    CHECK_EQ_INT(m->primitives[0].domain, -1);
    CHECK_EQ_INT(m->primitives[1].domain, 0);
    CHECK_EQ_INT(m->primitives[2].domain, -1);
    /* The 512 x 512 lightmap is read through TEXCOORD_1: not part of the frame. */
    CHECK_EQ_INT(m->domains[0].image_count, 1);
    CHECK_EQ_INT(m->domains[0].width, 64);
    texopt_model_destroy(m);
}

TEST(chains_of_shared_images_merge_transitively_and_rebuild_is_idempotent)
{
    char err[256] = "";
    const int sizes[] = {8, 8, 16, 16, 32, 32, 4, 4};
    texopt_model *m = bare_model(4, sizes, 3, 3);
    /* 0-1, 1-2 share images pairwise; material 2 bridges through image 2 and 3. */
    bind(m, 0, TEXOPT_SLOT_BASE_COLOR, 0, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 0, TEXOPT_SLOT_NORMAL, 1, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 1, TEXOPT_SLOT_BASE_COLOR, 3, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 1, TEXOPT_SLOT_NORMAL, 2, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 2, TEXOPT_SLOT_BASE_COLOR, 1, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind(m, 2, TEXOPT_SLOT_NORMAL, 2, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    for (int p = 0; p < 3; p++)
        m->primitives[p].material = p;
    for (int round = 0; round < 2; round++) {
        CHECK_OK(texopt_model_build_domains(m, err, sizeof err), err);
        CHECK_EQ_INT(m->domain_count, 1);
        CHECK_EQ_INT(m->domains[0].primitive_count, 3);
        CHECK_EQ_INT(m->domains[0].image_count, 4);
        CHECK_EQ_INT(m->domains[0].width, 32);
    }
    texopt_model_destroy(m);
}

TEST(images_of_unknown_size_count_as_one_texel)
{
    char err[256] = "";
    const int sizes[] = {0, 0};
    texopt_model *m = bare_model(1, sizes, 1, 1);
    bind(m, 0, TEXOPT_SLOT_BASE_COLOR, 0, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    m->primitives[0].material = 0;
    CHECK_OK(texopt_model_build_domains(m, err, sizeof err), err);
    CHECK_EQ_INT(m->domains[0].width, 1);
    CHECK_EQ_INT(m->domains[0].height, 1);
    texopt_model_destroy(m);
}

static void bind_extra(texopt_model *m, int material, const char *name, texopt_texture_kind kind, int image,
                       int texcoord)
{
    texopt_extra_texture *x = &m->materials[material].extra[m->materials[material].extra_count++];
    x->ref.image = image;
    x->ref.texcoord = texcoord;
    x->kind = kind;
    x->name = name;
}

TEST(extension_textures_join_their_images_to_the_domain)
{
    char err[256] = "";
    const int sizes[] = {64, 64, 512, 512, 32, 32, 16, 16};
    texopt_model *m = bare_model(4, sizes, 2, 2);
    /* Material 0: base colour 0, a clearcoat normal map 1 (the largest image) and a sheen map
     * 3 on TEXCOORD_1. Material 1: base colour 2, sheen colour 1 (shared with material 0's
     * extension texture only), so one domain of images 0, 1, 2 framed by image 1. */
    bind(m, 0, TEXOPT_SLOT_BASE_COLOR, 0, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind_extra(m, 0, "clearcoatNormalTexture", TEXOPT_TEXTURE_NORMAL, 1, 0);
    bind_extra(m, 0, "sheenRoughnessTexture", TEXOPT_TEXTURE_DATA, 3, 1);
    bind(m, 1, TEXOPT_SLOT_BASE_COLOR, 2, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT);
    bind_extra(m, 1, "sheenColorTexture", TEXOPT_TEXTURE_COLOR, 1, 0);
    m->primitives[0].material = 0;
    m->primitives[1].material = 1;
    CHECK_OK(texopt_model_build_domains(m, err, sizeof err), err);
    CHECK_EQ_INT(m->domain_count, 1);
    const texopt_domain *d = &m->domains[0];
    CHECK_EQ_INT(d->image_count, 3);
    CHECK(domain_has_image(d, 0) && domain_has_image(d, 1) && domain_has_image(d, 2));
    CHECK(!domain_has_image(d, 3));
    CHECK_EQ_INT(d->width, 512);
    /* The bindings in order: the five slots, then the extension textures with their kinds. */
    const texopt_material *mat = &m->materials[0];
    CHECK_EQ_INT(texopt_material_binding_count(mat), TEXOPT_SLOT_COUNT + 2);
    CHECK(strcmp(texopt_material_binding_name(mat, TEXOPT_SLOT_NORMAL), "normal") == 0);
    CHECK_EQ_INT(texopt_material_binding_kind(mat, TEXOPT_SLOT_NORMAL), TEXOPT_TEXTURE_NORMAL);
    CHECK_EQ_INT(texopt_material_binding_kind(mat, TEXOPT_SLOT_OCCLUSION), TEXOPT_TEXTURE_DATA);
    CHECK_EQ_INT(texopt_material_binding_kind(mat, TEXOPT_SLOT_EMISSIVE), TEXOPT_TEXTURE_COLOR);
    CHECK(strcmp(texopt_material_binding_name(mat, TEXOPT_SLOT_COUNT), "clearcoatNormalTexture") == 0);
    CHECK_EQ_INT(texopt_material_binding(mat, TEXOPT_SLOT_COUNT)->image, 1);
    CHECK_EQ_INT(texopt_material_binding_kind(mat, TEXOPT_SLOT_COUNT + 1), TEXOPT_TEXTURE_DATA);
    texopt_model_destroy(m);
}

/* Passing means not crashing: destroy must accept NULL like free(). */
TEST(destroy_accepts_null)
{
    texopt_model_destroy(NULL);
}

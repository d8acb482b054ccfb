/* model.c - texture-domain grouping, a material's bindings (slots, then extension textures)
 * and destruction of texopt_model.
 *
 * Loading lives in io/gltf_io; this file only works on the flattened data, so that tests can
 * build models in memory. */
#include "model.h"

#include <stdlib.h>
#include <string.h>

static int find_root(int *parent, int i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

#define BINDINGS_MAX (TEXOPT_SLOT_COUNT + TEXOPT_EXTRA_TEXTURES_MAX)

int texopt_material_binding_count(const texopt_material *mat)
{
    int extra = mat->extra_count < 0 ? 0 : mat->extra_count;
    return TEXOPT_SLOT_COUNT + (extra > TEXOPT_EXTRA_TEXTURES_MAX ? TEXOPT_EXTRA_TEXTURES_MAX : extra);
}

const texopt_texture_ref *texopt_material_binding(const texopt_material *mat, int i)
{
    return i < TEXOPT_SLOT_COUNT ? &mat->slot[i] : &mat->extra[i - TEXOPT_SLOT_COUNT].ref;
}

texopt_texture_kind texopt_material_binding_kind(const texopt_material *mat, int i)
{
    switch (i) {
    case TEXOPT_SLOT_BASE_COLOR:
    case TEXOPT_SLOT_EMISSIVE: return TEXOPT_TEXTURE_COLOR;
    case TEXOPT_SLOT_NORMAL: return TEXOPT_TEXTURE_NORMAL;
    case TEXOPT_SLOT_METALLIC_ROUGHNESS:
    case TEXOPT_SLOT_OCCLUSION: return TEXOPT_TEXTURE_DATA;
    default: return mat->extra[i - TEXOPT_SLOT_COUNT].kind;
    }
}

unsigned texopt_material_binding_channels(const texopt_material *mat, int i)
{
    switch (i) {
    case TEXOPT_SLOT_BASE_COLOR:
        return TEXOPT_CHANNELS_RGB | (mat->alpha_mode != TEXOPT_ALPHA_OPAQUE ? TEXOPT_CHANNEL_A : 0u);
    case TEXOPT_SLOT_EMISSIVE:
    case TEXOPT_SLOT_NORMAL: return TEXOPT_CHANNELS_RGB;
    case TEXOPT_SLOT_METALLIC_ROUGHNESS: return TEXOPT_CHANNEL_G | TEXOPT_CHANNEL_B;
    case TEXOPT_SLOT_OCCLUSION: return TEXOPT_CHANNEL_R;
    default: return mat->extra[i - TEXOPT_SLOT_COUNT].channels;
    }
}

const char *texopt_slot_name(texopt_slot slot)
{
    static const char *const names[TEXOPT_SLOT_COUNT] = {"baseColor", "normal", "metallicRoughness", "occlusion",
                                                         "emissive"};
    return (int)slot >= 0 && slot < TEXOPT_SLOT_COUNT ? names[slot] : "unknown";
}

const char *texopt_material_binding_name(const texopt_material *mat, int i)
{
    return i < TEXOPT_SLOT_COUNT ? texopt_slot_name((texopt_slot)i) : mat->extra[i - TEXOPT_SLOT_COUNT].name;
}

/* The images material m reads through TEXCOORD_0, appended to out and refs at n; returns
 * the new count. */
static int material_images(const texopt_model *model, int m, int *out, const texopt_texture_ref **refs, int n)
{
    if (m < 0 || m >= model->material_count)
        return n;
    const texopt_material *mat = &model->materials[m];
    for (int s = 0; s < texopt_material_binding_count(mat); s++) {
        const texopt_texture_ref *ref = texopt_material_binding(mat, s);
        if (ref->image < 0 || ref->image >= model->image_count || ref->texcoord != 0)
            continue;
        out[n] = ref->image;
        refs[n] = ref;
        n++;
    }
    return n;
}

int texopt_primitive_material(const texopt_model *model, const texopt_primitive *prim, int i)
{
    return i == 0 ? prim->material : model->variant_materials[prim->first_variant + (size_t)(i - 1)];
}

/* The images a primitive's material and its variants' (model.h) read through TEXCOORD_0,
 * the material's first, written to out (room for BINDINGS_MAX per material); returns how
 * many. */
static int primitive_images(const texopt_model *model, const texopt_primitive *prim, int *out,
                            const texopt_texture_ref **refs)
{
    int n = 0;
    for (int i = 0; i <= prim->variant_count; i++)
        n = material_images(model, texopt_primitive_material(model, prim, i), out, refs, n);
    return n;
}

/* The most materials one primitive may be drawn with (its own and its variants). */
static int most_materials(const texopt_model *model)
{
    int most = 1;
    for (int p = 0; p < model->primitive_count; p++)
        if (1 + model->primitives[p].variant_count > most)
            most = 1 + model->primitives[p].variant_count;
    return most;
}

static void free_domains(texopt_model *model)
{
    for (int d = 0; d < model->domain_count; d++) {
        free(model->domains[d].primitives);
        free(model->domains[d].images);
    }
    free(model->domains);
    model->domains = NULL;
    model->domain_count = 0;
}

/* Adds image to the domain's image list unless it is there already. */
static void domain_add_image(texopt_domain *dom, int image)
{
    for (int i = 0; i < dom->image_count; i++)
        if (dom->images[i] == image)
            return;
    dom->images[dom->image_count++] = image;
}

static void domain_set_frame(texopt_domain *dom, const texopt_model *model)
{
    dom->width = dom->height = 1;
    for (int i = 0; i < dom->image_count; i++) {
        const texopt_image *img = &model->images[dom->images[i]];
        if ((long long)img->width * img->height > (long long)dom->width * dom->height) {
            dom->width = img->width;
            dom->height = img->height;
        }
    }
}

texopt_status texopt_model_build_domains(texopt_model *model, char *err, size_t err_len)
{
    free_domains(model);
    int n_img = model->image_count;
    int *parent = malloc(sizeof(int) * (size_t)(n_img > 0 ? n_img : 1));
    int *domain_of_root = malloc(sizeof(int) * (size_t)(n_img > 0 ? n_img : 1));
    size_t room = (size_t)BINDINGS_MAX * (size_t)most_materials(model);
    int *imgs = malloc(room * sizeof *imgs);
    const texopt_texture_ref **refs = malloc(room * sizeof *refs);
    if (!parent || !domain_of_root || !imgs || !refs) {
        free(parent);
        free(domain_of_root);
        free(imgs);
        free(refs);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for texture domains");
    }
    for (int i = 0; i < n_img; i++) {
        parent[i] = i;
        domain_of_root[i] = -1;
    }
    for (int p = 0; p < model->primitive_count; p++) {
        int n = primitive_images(model, &model->primitives[p], imgs, refs);
        for (int k = 1; k < n; k++)
            parent[find_root(parent, imgs[k])] = find_root(parent, imgs[0]);
    }
    /* Number the domains in the order of their first primitive, so the numbering is stable. */
    int count = 0;
    for (int p = 0; p < model->primitive_count; p++) {
        int n = primitive_images(model, &model->primitives[p], imgs, refs);
        model->primitives[p].domain = -1;
        if (n == 0)
            continue;
        int root = find_root(parent, imgs[0]);
        if (domain_of_root[root] < 0)
            domain_of_root[root] = count++;
        model->primitives[p].domain = domain_of_root[root];
    }
    texopt_status st = TEXOPT_OK;
    model->domains = calloc((size_t)(count > 0 ? count : 1), sizeof(texopt_domain));
    if (!model->domains)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for texture domains");
    if (st == TEXOPT_OK) {
        model->domain_count = count;
        for (int d = 0; d < count; d++) {
            model->domains[d].primitives = malloc(sizeof(int) * (size_t)model->primitive_count);
            model->domains[d].images = malloc(sizeof(int) * (size_t)(n_img > 0 ? n_img : 1));
            model->domains[d].wrap_s = model->domains[d].wrap_t = TEXOPT_WRAP_REPEAT;
            model->domains[d].nearest_image = -1;
            if (!model->domains[d].primitives || !model->domains[d].images)
                st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for texture domains");
        }
    }
    if (st == TEXOPT_OK) {
        for (int p = 0; p < model->primitive_count; p++) {
            int d = model->primitives[p].domain;
            if (d < 0)
                continue;
            texopt_domain *dom = &model->domains[d];
            int n = primitive_images(model, &model->primitives[p], imgs, refs);
            if (dom->primitive_count == 0) {
                /* The base colour binding (slot 0) comes first when present. */
                dom->wrap_s = refs[0]->wrap_s;
                dom->wrap_t = refs[0]->wrap_t;
            }
            dom->primitives[dom->primitive_count++] = p;
            for (int k = 0; k < n; k++) {
                domain_add_image(dom, imgs[k]);
                if (refs[k]->magnify_nearest && dom->nearest_image < 0)
                    dom->nearest_image = imgs[k];
            }
        }
        for (int d = 0; d < count; d++)
            domain_set_frame(&model->domains[d], model);
    } else {
        free_domains(model);
        for (int p = 0; p < model->primitive_count; p++)
            model->primitives[p].domain = -1;
    }
    free(parent);
    free(domain_of_root);
    free(imgs);
    free(refs);
    return st;
}

void texopt_model_destroy(texopt_model *model)
{
    if (!model)
        return;
    free(model->positions);
    free(model->uvs);
    free(model->normals);
    free(model->triangles);
    free(model->file_vertex);
    free(model->primitives);
    free(model->variant_materials);
    free(model->materials);
    for (int i = 0; i < model->image_count; i++) {
        texopt_image_destroy(&model->images[i]);
        if (model->image_names)
            free(model->image_names[i]);
    }
    free(model->images);
    free(model->image_names);
    free_domains(model);
    if (model->document && model->destroy_document)
        model->destroy_document(model->document);
    free(model);
}

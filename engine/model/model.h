/* model.h - a loaded glTF model, flattened for the engine.
 *
 * Every triangle primitive of every mesh is kept once (an instanced mesh takes the world
 * transform of the first node that uses it; a skinned mesh keeps its bind pose). Vertices of
 * all primitives are concatenated: primitive p owns model vertices [first_vertex,
 * first_vertex + vertex_count) and triangles [first_triangle, first_triangle +
 * triangle_count), and its triangles index model vertices directly.
 *
 * A texture domain is a set of primitives whose materials' textures share one TEXCOORD_0
 * layout (connected through shared images); each domain is optimised as a unit. Its texel
 * frame is the size of its largest texture: a UV (u, v) is the texel position
 * (width * u, height * v).
 *
 * Loading and saving live in io/gltf_io.h; this header only describes the data. */
#ifndef TEXOPT_MODEL_H
#define TEXOPT_MODEL_H

#include <stddef.h>
#include <stdint.h>

#include "image.h"
#include "status.h"

typedef enum texopt_wrap {
    TEXOPT_WRAP_REPEAT = 0, /* glTF default */
    TEXOPT_WRAP_CLAMP,
    TEXOPT_WRAP_MIRROR
} texopt_wrap;

typedef enum texopt_slot {
    TEXOPT_SLOT_BASE_COLOR = 0,
    TEXOPT_SLOT_NORMAL,
    TEXOPT_SLOT_METALLIC_ROUGHNESS,
    TEXOPT_SLOT_OCCLUSION,
    TEXOPT_SLOT_EMISSIVE,
    TEXOPT_SLOT_COUNT
} texopt_slot;

/* One texture binding of a material. */
typedef struct texopt_texture_ref {
    int image;    /* index into texopt_model.images, -1 when the slot is empty */
    int texcoord; /* TEXCOORD_n set the binding uses */
    texopt_wrap wrap_s, wrap_t;
    int magnify_nearest; /* its sampler's magFilter is NEAREST: texels shown as blocks (pixel art) */
} texopt_texture_ref;

/* What a texture's texels are, which decides how stage 1 compares them (triloss.h) and
 * whether the re-bake turns them with the layout (rebake.h). */
typedef enum texopt_texture_kind {
    TEXOPT_TEXTURE_COLOR = 0, /* a colour: compared by its luma */
    TEXOPT_TEXTURE_DATA,      /* numbers per channel (roughness, thickness...): compared per channel */
    TEXOPT_TEXTURE_NORMAL     /* a tangent-space normal map: per channel, XY turned with the layout */
} texopt_texture_kind;

/* The channels of a texture (glTF's R, G, B, A), a bit each: which of them a binding reads. */
#define TEXOPT_CHANNEL_R 1u
#define TEXOPT_CHANNEL_G 2u
#define TEXOPT_CHANNEL_B 4u
#define TEXOPT_CHANNEL_A 8u
#define TEXOPT_CHANNELS_RGB 7u

/* How base colour's alpha shows on a material's surface (glTF alphaMode). */
typedef enum texopt_alpha_mode { TEXOPT_ALPHA_OPAQUE = 0, TEXOPT_ALPHA_MASK, TEXOPT_ALPHA_BLEND } texopt_alpha_mode;

/* Most extension textures one material may bind through TEXCOORD_0 (the loader knows 14). */
#define TEXOPT_EXTRA_TEXTURES_MAX 16

/* A texture that a material extension binds through TEXCOORD_0 (clearcoat, sheen,
 * specular...; texture_keys.h lists those texopt knows): laid out and re-baked with the slots'
 * textures, measured by the whole-mesh evaluation when asked for by its key, not rendered by
 * the lit loss, which knows the core slots only. */
typedef struct texopt_extra_texture {
    texopt_texture_ref ref;
    texopt_texture_kind kind;
    unsigned channels; /* TEXOPT_CHANNEL_* its extension reads (specularTexture: A only) */
    const char *name;  /* the binding's key, e.g. "clearcoatNormalTexture"; static storage */
} texopt_extra_texture;

typedef struct texopt_material {
    texopt_texture_ref slot[TEXOPT_SLOT_COUNT];
    int extra_count;
    texopt_extra_texture extra[TEXOPT_EXTRA_TEXTURES_MAX];
    /* pbrMetallicRoughness's factors (glTF's default 1), which multiply the texture's B and G
     * or stand alone without one: what a lit render (lit_shade.h) shows of the material. */
    double metallic_factor, roughness_factor;
    /* glTF's alphaMode and alphaCutoff (OPAQUE, the default, ignores base colour's alpha;
     * MASK cuts the surface where it is below alpha_cutoff; BLEND blends by it). */
    texopt_alpha_mode alpha_mode;
    double alpha_cutoff;
    /* The KHR_texture_transform of its TEXCOORD_0 bindings (one for all of them, or the load
     * refuses), already applied to model->uvs of its primitives: u' = m[0] u + m[1] v + m[2],
     * v' = m[3] u + m[4] v + m[5]; {1, 0, 0, 0, 1, 0} without one. */
    double uv_transform[6];
} texopt_material;

typedef struct texopt_primitive {
    int gltf_mesh, gltf_primitive; /* indices in the glTF document */
    int material;                  /* index into texopt_model.materials, -1 when none */
    int domain;                    /* index into texopt_model.domains, -1 when untextured */
    size_t first_vertex, vertex_count;
    size_t first_triangle, triangle_count;
    /* KHR_materials_variants: the other materials the primitive may be drawn with,
     * texopt_model.variant_materials[first_variant, first_variant + variant_count). Their
     * TEXCOORD_0 textures belong to its domain: re-baked into the layout it is given. */
    size_t first_variant;
    int variant_count;
    int winding_flipped; /* a mirroring node transform: each triangle's last two vertices were
                            swapped on load (saving new indices swaps them back) */
} texopt_primitive;

typedef struct texopt_domain {
    int primitive_count;
    int *primitives; /* indices into texopt_model.primitives */
    int image_count;
    int *images;                /* indices into texopt_model.images used through TEXCOORD_0 */
    int width, height;          /* texel frame: the largest of its images */
    texopt_wrap wrap_s, wrap_t; /* of the base colour texture, else of the first texture */
    int nearest_image;          /* an image a TEXCOORD_0 binding magnifies NEAREST (magnify_nearest), -1 if none */
} texopt_domain;

typedef struct texopt_model {
    size_t vertex_count;
    float *positions; /* 3 per vertex, world space */
    float *uvs;       /* 2 per vertex, TEXCOORD_0 as in the file after its material's
                         uv_transform (may leave [0,1]); NULL if none */
    float *normals;   /* 3 per vertex, world space, unit: NORMAL as in the file; a zero vector
                         where a primitive has none (shade it flat, as glTF asks); NULL if no
                         primitive has one */
    size_t triangle_count;
    uint32_t *triangles;   /* 3 per triangle, model vertex indices */
    uint32_t *file_vertex; /* per vertex: the vertex of its primitive in the file (0-based
                              within the primitive) it copies, when model_split.h split
                              vertices; NULL when every vertex is the file's own */

    int primitive_count;
    texopt_primitive *primitives;
    int material_count;
    texopt_material *materials;
    int image_count;
    texopt_image *images; /* decoded; an image no texture reads as its source (an alternate
                              beside a fallback, an orphan) is not: NULL pixels, size 0 */
    char **image_names;   /* per image: its URI or name, for messages; may hold NULLs */
    int domain_count;
    texopt_domain *domains;
    int *variant_materials; /* the primitives' variant materials (texopt_primitive); may be NULL */

    struct texopt_gltf_document *document;                           /* the parsed file, kept for saving (io/gltf_io) */
    void (*destroy_document)(struct texopt_gltf_document *document); /* set by whoever set document */
} texopt_model;

/* Groups the textured primitives into texture domains (fills domains, domain_count and each
 * primitive's domain) from the materials' TEXCOORD_0 bindings: primitives whose materials
 * share an image are one domain. Images with unknown size (not decoded) count as 1x1. */
texopt_status texopt_model_build_domains(texopt_model *model, char *err, size_t err_len);

/* The glTF name of a material slot ("baseColor", "normal", "metallicRoughness", "occlusion",
 * "emissive"; "unknown" out of range). */
const char *texopt_slot_name(texopt_slot slot);

/* Every texture binding of a material, the slots in slot order (empty ones included) then its
 * extension textures: i in [0, texopt_material_binding_count). */
int texopt_material_binding_count(const texopt_material *mat);

/* The materials primitive `prim` may be drawn with: its own (i = 0), then its variants
 * (KHR_materials_variants), i in [0, 1 + prim->variant_count); -1 where it has none. */
int texopt_primitive_material(const texopt_model *model, const texopt_primitive *prim, int i);
const texopt_texture_ref *texopt_material_binding(const texopt_material *mat, int i);
texopt_texture_kind texopt_material_binding_kind(const texopt_material *mat, int i);
/* The channels binding i reads (TEXOPT_CHANNEL_*): the core slots' from the glTF
 * specification (metallicRoughness G and B, occlusion R; base colour's alpha when
 * alpha_mode MASK or BLEND), an extension texture's from its extension. */
unsigned texopt_material_binding_channels(const texopt_material *mat, int i);
/* texopt_slot_name of a slot, or the extension texture's key. */
const char *texopt_material_binding_name(const texopt_material *mat, int i);

/* Frees everything the model owns, including the document. Accepts NULL. */
void texopt_model_destroy(texopt_model *model);

#endif

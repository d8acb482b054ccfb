/* test_hostile_input.c - every way a model file can be broken or dangerous gets a clear
 * refusal (status + a message naming the element), never a crash or a read outside the
 * model's directory. Each case is the generated quad of gltf_builder.h with one thing
 * broken; the sanitizer build runs these too. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "gltf_builder.h"
#include "gltf_io.h"
#include "json_depth.h"
#include "test.h"

/* Loads the quad with json (and the doc's binary) from memory; returns the status and
 * leaves the message in err. */
static texopt_status try_glb(const quad_doc *doc, const char *json, const texopt_load_options *opt, char *err,
                             size_t err_len)
{
    size_t len = 0;
    unsigned char *glb = builder_glb(json, doc->bin, doc->bin_len, &len);
    texopt_model *m = NULL;
    err[0] = '\0';
    texopt_status st = texopt_model_load_memory(&m, glb, len, NULL, opt, err, err_len);
    free(glb);
    if (st == TEXOPT_OK && !m)
        return TEXOPT_E_INTERNAL;
    if (st != TEXOPT_OK && m)
        return TEXOPT_E_INTERNAL; /* a failure must leave nothing behind */
    texopt_model_destroy(m);
    return st;
}

/* The quad with `from` replaced by `to` must be refused with `want` and a message holding
 * `word`. */
#define CHECK_REFUSED_JSON(from, to, want, word)                                                                       \
    do {                                                                                                               \
        quad_doc d_;                                                                                                   \
        char e_[512];                                                                                                  \
        CHECK(quad_doc_init(&d_, 4, 4));                                                                               \
        CHECK_MSG(builder_replace(&d_.json, (from), (to)), "fragment %s not in the quad", (from));                     \
        texopt_status s_ = try_glb(&d_, d_.json, NULL, e_, sizeof e_);                                                 \
        quad_doc_free(&d_);                                                                                            \
        CHECK_MSG(s_ == (want), "status %d, want %d: %s", (int)s_, (int)(want), e_);                                   \
        CHECK_MSG(strstr(e_, (word)) != NULL, "message \"%s\" lacks \"%s\"", e_, (word));                              \
    } while (0)

TEST(the_unbroken_quad_loads)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    CHECK_OK(try_glb(&d, d.json, NULL, err, sizeof err), err);
    quad_doc_free(&d);
}

TEST(every_truncation_is_refused)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    size_t len = 0;
    unsigned char *glb = builder_glb(d.json, d.bin, d.bin_len, &len);
    for (size_t cut = 0; cut < len; cut += (cut < 64 ? 1 : 7)) {
        texopt_model *m = NULL;
        texopt_status st = texopt_model_load_memory(&m, glb, cut, NULL, NULL, err, sizeof err);
        CHECK_MSG(st != TEXOPT_OK && m == NULL, "a glb cut to %zu of %zu bytes loaded", cut, len);
        CHECK_MSG(st == TEXOPT_E_MALFORMED, "cut %zu: status %d (%s)", cut, (int)st, err);
    }
    free(glb);
    quad_doc_free(&d);
}

/* Random byte corruption must never crash or leak (the sanitizer build checks reads); a
 * corrupted file may load or fail, but a failure has a message. */
TEST(random_corruption_never_crashes)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    size_t len = 0;
    unsigned char *glb = builder_glb(d.json, d.bin, d.bin_len, &len);
    unsigned char *copy = malloc(len);
    uint32_t state = 12345u;
    for (int trial = 0; trial < 300; trial++) {
        memcpy(copy, glb, len);
        for (int k = 0; k < 1 + trial % 4; k++) {
            state = state * 1664525u + 1013904223u;
            size_t at = (state >> 8) % len;
            state = state * 1664525u + 1013904223u;
            copy[at] = (unsigned char)(state >> 24);
        }
        texopt_model *m = NULL;
        err[0] = '\0';
        texopt_status st = texopt_model_load_memory(&m, copy, len, NULL, NULL, err, sizeof err);
        CHECK_MSG(st == TEXOPT_OK || err[0] != '\0', "trial %d failed (%d) without a message", trial, (int)st);
        CHECK((st == TEXOPT_OK) == (m != NULL));
        texopt_model_destroy(m);
    }
    free(copy);
    free(glb);
    quad_doc_free(&d);
}

TEST(not_gltf_and_bad_json_are_malformed)
{
    char err[512];
    texopt_model *m = NULL;
    const char *text = "hello, this is a text file";
    CHECK_EQ_INT(texopt_model_load_memory(&m, text, strlen(text), NULL, NULL, err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK(m == NULL);
    CHECK_EQ_INT(texopt_model_load_memory(&m, "", 0, NULL, NULL, err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_REFUSED_JSON("\"asset\":{\"version\":\"2.0\"},", "\"asset\":{\"version\":\"2.0\"}", TEXOPT_E_MALFORMED,
                       "glb");
    CHECK_EQ_INT(texopt_model_load(&m, "/nonexistent/model.glb", NULL, err, sizeof err), TEXOPT_E_IO);
    CHECK(strstr(err, "/nonexistent/model.glb") != NULL);
}

TEST(out_of_bounds_accessors_and_views)
{
    CHECK_REFUSED_JSON("\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"",
                       "\"componentType\":5126,\"count\":40,\"type\":\"VEC3\"", TEXOPT_E_MALFORMED, "accessor 0");
    CHECK_REFUSED_JSON("\"byteOffset\":0,\"byteLength\":48", "\"byteOffset\":0,\"byteLength\":4800", TEXOPT_E_MALFORMED,
                       "buffer view 0");
    CHECK_REFUSED_JSON("\"byteOffset\":80,\"byteLength\":12", "\"byteOffset\":4000000000,\"byteLength\":12",
                       TEXOPT_E_MALFORMED, "buffer view 2");
    CHECK_REFUSED_JSON("{\"bufferView\":1,\"componentType\":5126,\"count\":4",
                       "{\"bufferView\":1,\"byteOffset\":16,\"componentType\":5126,\"count\":4", TEXOPT_E_MALFORMED,
                       "accessor 1");
    CHECK_REFUSED_JSON("\"byteOffset\":0,\"byteLength\":48,\"target\":34962",
                       "\"byteOffset\":0,\"byteLength\":48,\"byteStride\":8,\"target\":34962", TEXOPT_E_MALFORMED,
                       "byteStride");
    CHECK_REFUSED_JSON("\"POSITION\":0", "\"POSITION\":7", TEXOPT_E_MALFORMED, "accessor 7");
    CHECK_REFUSED_JSON("\"count\":4,\"type\":\"VEC2\"", "\"count\":4,\"type\":\"SCALAR\"", TEXOPT_E_MALFORMED,
                       "expected VEC2");
}

TEST(image_buffer_view_past_the_buffer_is_refused)
{
    char big[64];
    quad_doc d;
    CHECK(quad_doc_init(&d, 4, 4));
    char old[64];
    snprintf(old, sizeof old, "\"byteOffset\":92,\"byteLength\":%zu", d.png_len);
    snprintf(big, sizeof big, "\"byteOffset\":92,\"byteLength\":%zu", d.png_len + 100000);
    quad_doc_free(&d);
    CHECK_REFUSED_JSON(old, big, TEXOPT_E_MALFORMED, "image 0");
}

TEST(index_past_vertex_count_is_refused)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    uint16_t bad = 812;
    memcpy(d.bin + QUAD_IDX_OFFSET + 4 * 2, &bad, 2);
    CHECK_EQ_INT(try_glb(&d, d.json, NULL, err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_MSG(strstr(err, "accessor 2: index 812 past vertex count 4") != NULL, "%s", err);
    quad_doc_free(&d);
    CHECK_REFUSED_JSON("\"componentType\":5123,\"count\":6", "\"componentType\":5123,\"count\":5", TEXOPT_E_MALFORMED,
                       "whole triangles");
    CHECK_REFUSED_JSON("\"componentType\":5123,\"count\":6", "\"componentType\":5126,\"count\":3", TEXOPT_E_MALFORMED,
                       "u8/u16/u32");
}

TEST(nan_and_inf_positions_and_uvs_are_refused)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    float nan_value = NAN, inf_value = INFINITY;
    memcpy(d.bin + QUAD_POS_OFFSET + 5 * 4, &nan_value, 4);
    CHECK_EQ_INT(try_glb(&d, d.json, NULL, err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_MSG(strstr(err, "POSITION") && strstr(err, "element 1") && strstr(err, "finite"), "%s", err);
    memcpy(d.bin + QUAD_POS_OFFSET + 5 * 4, &quad_positions[5], 4);
    memcpy(d.bin + QUAD_UV_OFFSET + 6 * 4, &inf_value, 4);
    CHECK_EQ_INT(try_glb(&d, d.json, NULL, err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_MSG(strstr(err, "TEXCOORD_0") && strstr(err, "element 3"), "%s", err);
    quad_doc_free(&d);
    CHECK_REFUSED_JSON("\"translation\":[1,2,3]", "\"scale\":[3e38,3e38,3e38],\"translation\":[3e38,0,0]",
                       TEXOPT_E_MALFORMED, "non-finite");
}

static uint32_t crc32_of(const unsigned char *p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

static void put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

TEST(absurd_image_sizes_hit_the_pixel_cap_before_decoding)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    /* A PNG whose header claims 30000 x 30000 (9e8 pixels, past the default 2^28). The IHDR
     * chunk starts at byte 8: length, "IHDR", width, height, ..., CRC over type + data. */
    unsigned char *ihdr = d.bin + QUAD_PNG_OFFSET + 8;
    CHECK(memcmp(ihdr + 4, "IHDR", 4) == 0);
    put_be32(ihdr + 8, 30000);
    put_be32(ihdr + 12, 30000);
    put_be32(ihdr + 8 + 13, crc32_of(ihdr + 4, 17));
    CHECK_EQ_INT(try_glb(&d, d.json, NULL, err, sizeof err), TEXOPT_E_LIMIT);
    CHECK_MSG(strstr(err, "image 0") && strstr(err, "30000x30000") && strstr(err, "limit"), "%s", err);
    quad_doc_free(&d);

    /* The cap is the option's: a 4x4 image is over a cap of 15 pixels. */
    CHECK(quad_doc_init(&d, 4, 4));
    texopt_load_options opt = {0, 15, 0};
    CHECK_EQ_INT(try_glb(&d, d.json, &opt, err, sizeof err), TEXOPT_E_LIMIT);
    opt.max_total_pixels = 16;
    CHECK_OK(try_glb(&d, d.json, &opt, err, sizeof err), err);
    texopt_load_options small = {100, 0, 0};
    CHECK_EQ_INT(try_glb(&d, d.json, &small, err, sizeof err), TEXOPT_E_LIMIT);
    CHECK(strstr(err, "bytes") != NULL);
    quad_doc_free(&d);
}

TEST(corrupt_image_data_is_malformed)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    memset(d.bin + QUAD_PNG_OFFSET, 'x', 16);
    CHECK_EQ_INT(try_glb(&d, d.json, NULL, err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_MSG(strstr(err, "image 0") != NULL, "%s", err);
    quad_doc_free(&d);
}

/* Writes the quad as a .gltf in dir whose buffer URI is buffer_uri and image URI image_uri
 * (the binary is quad.bin and the texture tex.png in dir), loads it and returns the status. */
static texopt_status try_gltf_uris(const char *dir, const char *buffer_uri, const char *image_uri, char *err,
                                   size_t err_len)
{
    quad_doc d;
    if (!quad_doc_init(&d, 4, 4))
        return TEXOPT_E_INTERNAL;
    char path[256], old[64], repl[512];
    snprintf(path, sizeof path, "%s/quad.bin", dir);
    builder_write(path, d.bin, d.bin_len);
    snprintf(path, sizeof path, "%s/tex.png", dir);
    builder_write(path, d.bin + QUAD_PNG_OFFSET, d.png_len);
    snprintf(old, sizeof old, "{\"byteLength\":%zu}", d.bin_len);
    snprintf(repl, sizeof repl, "{\"byteLength\":%zu,\"uri\":\"%s\"}", d.bin_len, buffer_uri);
    builder_replace(&d.json, old, repl);
    snprintf(repl, sizeof repl, "{\"uri\":\"%s\"}", image_uri);
    builder_replace(&d.json, "{\"bufferView\":3,\"mimeType\":\"image/png\"}", repl);
    snprintf(path, sizeof path, "%s/quad.gltf", dir);
    builder_write(path, d.json, strlen(d.json));
    quad_doc_free(&d);
    texopt_model *m = NULL;
    err[0] = '\0';
    texopt_status st = texopt_model_load(&m, path, NULL, err, err_len);
    texopt_model_destroy(m);
    return st;
}

TEST(uris_leaving_the_directory_or_naming_the_network_are_refused)
{
    char err[512], dir[64], sub[128], secret[160], link[160];
    CHECK(builder_tempdir(dir));
    snprintf(sub, sizeof sub, "%s/model", dir);
    CHECK(mkdir(sub, 0700) == 0);
    /* A real file one level up, so "../" would succeed if it were followed. */
    snprintf(secret, sizeof secret, "%s/tex.png", dir);
    CHECK_OK(try_gltf_uris(sub, "quad.bin", "tex.png", err, sizeof err), err);
    CHECK(builder_write(secret, "x", 1));

    struct {
        const char *buffer_uri, *image_uri, *word;
    } cases[] = {
        {"../model/quad.bin", "tex.png", "leaves"},
        {"quad.bin", "../tex.png", "leaves"},
        {"sub/../../quad.bin", "tex.png", "leaves"},
        {"%2e%2e/model/quad.bin", "tex.png", "leaves"},
        {"/etc/passwd", "tex.png", "leaves"},
        {"quad.bin", "http://example.com/tex.png", "network"},
        {"https://example.com/quad.bin", "tex.png", "network"},
        {"quad.bin", "//example.com/tex.png", "network"},
        {"file:///etc/passwd", "tex.png", "scheme"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        texopt_status st = try_gltf_uris(sub, cases[i].buffer_uri, cases[i].image_uri, err, sizeof err);
        CHECK_MSG(st == TEXOPT_E_MALFORMED, "case %zu (%s, %s): status %d: %s", i, cases[i].buffer_uri,
                  cases[i].image_uri, (int)st, err);
        CHECK_MSG(strstr(err, cases[i].word) != NULL, "case %zu: \"%s\" lacks \"%s\"", i, err, cases[i].word);
    }
    /* A link inside the directory that points outside it. */
    snprintf(link, sizeof link, "%s/link.png", sub);
    CHECK(symlink(secret, link) == 0);
    CHECK_EQ_INT(try_gltf_uris(sub, "quad.bin", "link.png", err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_MSG(strstr(err, "link") != NULL, "%s", err);
    /* Missing files are named. */
    CHECK_EQ_INT(try_gltf_uris(sub, "quad.bin", "missing.png", err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_MSG(strstr(err, "missing.png") != NULL, "%s", err);
    CHECK_EQ_INT(try_gltf_uris(sub, "missing.bin", "tex.png", err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_MSG(strstr(err, "missing.bin") != NULL, "%s", err);
    builder_rmdir(dir);
}

TEST(external_uris_without_a_directory_are_refused)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    CHECK(builder_replace(&d.json, "{\"bufferView\":3,\"mimeType\":\"image/png\"}", "{\"uri\":\"tex.png\"}"));
    CHECK_EQ_INT(try_glb(&d, d.json, NULL, err, sizeof err), TEXOPT_E_MALFORMED);
    CHECK_MSG(strstr(err, "tex.png") && strstr(err, "directory"), "%s", err);
    quad_doc_free(&d);
}

TEST(valid_but_unusable_models_are_unsupported)
{
    CHECK_REFUSED_JSON(",\"TEXCOORD_0\":1", "", TEXOPT_E_UNSUPPORTED, "TEXCOORD_0");
    CHECK_REFUSED_JSON("\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}", "\"pbrMetallicRoughness\":{}",
                       TEXOPT_E_UNSUPPORTED, "texture");
    CHECK_REFUSED_JSON("\"material\":0,", "", TEXOPT_E_UNSUPPORTED, "texture");
    CHECK_REFUSED_JSON("\"mode\":4", "\"mode\":1", TEXOPT_E_UNSUPPORTED, "mode 1");
    CHECK_REFUSED_JSON("\"mode\":4", "\"mode\":0", TEXOPT_E_UNSUPPORTED, "strips (5) and fans (6)");
    CHECK_REFUSED_JSON("\"asset\":{\"version\":\"2.0\"},",
                       "\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
                       "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],",
                       TEXOPT_E_UNSUPPORTED, "KHR_draco_mesh_compression");
}

#define QUAD_MATERIALS "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]"
#define TRANSFORM(body) "\"extensions\":{\"KHR_texture_transform\":{" body "}}"

TEST(texture_transforms_texopt_cannot_apply_are_refused)
{
    /* Two bindings on TEXCOORD_0 that would need two layouts. */
    CHECK_REFUSED_JSON(
        QUAD_MATERIALS,
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0," TRANSFORM(
            "\"offset\":[0.5,0]") "}},\"emissiveTexture\":{\"index\":0," TRANSFORM("\"offset\":[0,0.5]") "}}]",
        TEXOPT_E_UNSUPPORTED, "different KHR_texture_transform");
    CHECK_REFUSED_JSON(QUAD_MATERIALS,
                       "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0," TRANSFORM(
                           "\"scale\":[2,2]") "}},\"emissiveTexture\":{\"index\":0}}]",
                       TEXOPT_E_UNSUPPORTED, "emissiveTexture");
    /* Moved to another set, malformed, or turning a normal map. */
    CHECK_REFUSED_JSON("\"baseColorTexture\":{\"index\":0}",
                       "\"baseColorTexture\":{\"index\":0," TRANSFORM("\"texCoord\":1") "}", TEXOPT_E_UNSUPPORTED,
                       "texCoord");
    CHECK_REFUSED_JSON("\"baseColorTexture\":{\"index\":0}",
                       "\"baseColorTexture\":{\"index\":0," TRANSFORM("\"offset\":\"far\"") "}", TEXOPT_E_UNSUPPORTED,
                       "malformed");
    CHECK_REFUSED_JSON("\"baseColorTexture\":{\"index\":0}",
                       "\"baseColorTexture\":{\"index\":0," TRANSFORM("\"scale\":[2,0]") "}", TEXOPT_E_UNSUPPORTED,
                       "zero scale");
    CHECK_REFUSED_JSON("\"baseColorTexture\":{\"index\":0}",
                       "\"baseColorTexture\":{\"index\":0," TRANSFORM("\"scale\":[1e300,1e300]") "}",
                       TEXOPT_E_MALFORMED, "float range");
    CHECK_REFUSED_JSON(QUAD_MATERIALS,
                       "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0," TRANSFORM(
                           "\"rotation\":0.3") "}},\"normalTexture\":{\"index\":0," TRANSFORM("\"rotation\":0.3") "}}]",
                       TEXOPT_E_UNSUPPORTED, "normal map");
    /* Offset and scale on a normal map keep its directions. */
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    CHECK(builder_replace(
        &d.json, QUAD_MATERIALS,
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0," TRANSFORM(
            "\"offset\":[0.5,0],\"scale\":[2,3]") "}},\"normalTexture\":{\"index\":0," TRANSFORM("\"offset\":[0.5,"
                                                                                                 "0],\"scale\":[2,"
                                                                                                 "3]") "}}]"));
    CHECK_OK(try_glb(&d, d.json, NULL, err, sizeof err), err);
    quad_doc_free(&d);
    /* An identity written out equals none. */
    CHECK(quad_doc_init(&d, 4, 4));
    CHECK(builder_replace(
        &d.json, QUAD_MATERIALS,
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0," TRANSFORM(
            "\"offset\":[0,0],\"scale\":[1,1],\"rotation\":0") "}},\"emissiveTexture\":{\"index\":0}}]"));
    CHECK_OK(try_glb(&d, d.json, NULL, err, sizeof err), err);
    quad_doc_free(&d);
}

/* The quad's material with `ext` as its extensions object. */
#define WITH_EXTENSIONS(ext) "}},\"extensions\":{" ext "}}],\"textures\""

TEST(textures_of_unknown_material_extensions_on_texcoord0_are_refused)
{
    /* texopt would move the UVs under them without knowing how to re-bake them. */
    CHECK_REFUSED_JSON("}}}],\"textures\"",
                       WITH_EXTENSIONS("\"EXT_vendor\":{\"layer\":{\"detailTexture\":{\"index\":0}}}"),
                       TEXOPT_E_UNSUPPORTED, "detailTexture");
    /* Its diffuse texture stands for the base colour the evaluation renders. */
    CHECK_REFUSED_JSON("}}}],\"textures\"",
                       WITH_EXTENSIONS("\"KHR_materials_pbrSpecularGlossiness\":{\"diffuseTexture\":{\"index\":0}}"),
                       TEXOPT_E_UNSUPPORTED, "diffuseTexture");
    /* A known texture under another extension's name is not the known one. */
    CHECK_REFUSED_JSON("}}}],\"textures\"",
                       WITH_EXTENSIONS("\"KHR_materials_sheen\":{\"clearcoatTexture\":{\"index\":0}}"),
                       TEXOPT_E_UNSUPPORTED, "clearcoatTexture");
    /* On another set they are left as they are, like a core slot there. */
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    CHECK(builder_replace(&d.json, "}}}],\"textures\"",
                          WITH_EXTENSIONS("\"EXT_vendor\":{\"layer\":{\"detailTexture\":{\"index\":0,"
                                          "\"texCoord\":1}}}")));
    CHECK_OK(try_glb(&d, d.json, NULL, err, sizeof err), err);
    quad_doc_free(&d);
}

/* The quad with `anisotropy` as its material's KHR_materials_anisotropy object, and with a
 * TANGENT attribute when `tangents` (an accessor over the image's bytes: the load only asks
 * whether it is there). Loads it; the status, and the material's extension texture count in
 * *extra. */
static texopt_status load_anisotropic_quad(const char *anisotropy, int tangents, int *extra, char *err, size_t err_len)
{
    quad_doc d;
    char ext[256];
    snprintf(ext, sizeof ext, "}},\"extensions\":{\"KHR_materials_anisotropy\":%s}}],\"textures\"", anisotropy);
    if (!quad_doc_init(&d, 4, 4))
        return TEXOPT_E_NOMEM;
    int ok = builder_replace(&d.json, "}}}],\"textures\"", ext) &&
             (!tangents || (builder_replace(&d.json, "\"TEXCOORD_0\":1}", "\"TEXCOORD_0\":1,\"TANGENT\":3}") &&
                            builder_replace(&d.json, "\"type\":\"SCALAR\"}]",
                                            "\"type\":\"SCALAR\"},{\"bufferView\":3,\"componentType\":5126,\"count\":4,"
                                            "\"type\":\"VEC4\"}]")));
    size_t len = 0;
    unsigned char *glb = ok ? builder_glb(d.json, d.bin, d.bin_len, &len) : NULL;
    texopt_model *m = NULL;
    texopt_status st = glb ? texopt_model_load_memory(&m, glb, len, NULL, NULL, err, err_len) : TEXOPT_E_INTERNAL;
    free(glb);
    quad_doc_free(&d);
    *extra = m ? m->materials[0].extra_count : -1;
    texopt_model_destroy(m);
    return st;
}

/* An anisotropy direction set as a constant in the tangent frame a renderer derives from the
 * UVs cannot follow a new layout: refused without TANGENT, unless a direction map on
 * TEXCOORD_0 (re-baked and turned) carries it; no strength, no direction to keep. */
TEST(an_anisotropy_direction_the_layout_would_turn_is_refused)
{
    char err[512] = "";
    int extra = 0;
    CHECK(load_anisotropic_quad("{\"anisotropyStrength\":0.6,\"anisotropyRotation\":1}", 0, &extra, err, sizeof err) ==
          TEXOPT_E_UNSUPPORTED);
    CHECK_MSG(strstr(err, "KHR_materials_anisotropy") && strstr(err, "TANGENT"), "%s", err);
    CHECK(load_anisotropic_quad("{\"anisotropyStrength\":0.6,\"anisotropyTexture\":{\"index\":0,\"texCoord\":1}}", 0,
                                &extra, err, sizeof err) == TEXOPT_E_UNSUPPORTED);
    CHECK_OK(load_anisotropic_quad("{\"anisotropyStrength\":0.6,\"anisotropyTexture\":{\"index\":0}}", 0, &extra, err,
                                   sizeof err),
             err);
    CHECK_EQ_INT(extra, 1);
    CHECK_OK(load_anisotropic_quad("{\"anisotropyStrength\":0.6}", 1, &extra, err, sizeof err), err);
    CHECK_EQ_INT(extra, 0);
    CHECK_OK(load_anisotropic_quad("{\"anisotropyRotation\":1}", 0, &extra, err, sizeof err), err);
}

TEST(known_extension_textures_are_checked_like_the_slots)
{
    CHECK_REFUSED_JSON("}}}],\"textures\"",
                       WITH_EXTENSIONS("\"KHR_materials_clearcoat\":{\"clearcoatTexture\":{\"index\":7}}"),
                       TEXOPT_E_MALFORMED, "texture 7");
    CHECK_REFUSED_JSON("}}}],\"textures\"",
                       WITH_EXTENSIONS("\"KHR_materials_sheen\":{\"sheenColorTexture\":{\"index\":0," TRANSFORM(
                           "\"offset\":[0.5,0]") "}}"),
                       TEXOPT_E_UNSUPPORTED, "different KHR_texture_transform");
    CHECK_REFUSED_JSON("}}}],\"textures\"",
                       WITH_EXTENSIONS("\"KHR_materials_sheen\":{\"sheenColorTexture\":{\"index\":0," TRANSFORM(
                           "\"offset\":\"far\"") "}}"),
                       TEXOPT_E_UNSUPPORTED, "sheenColorTexture");
    CHECK_REFUSED_JSON(
        QUAD_MATERIALS,
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0," TRANSFORM(
            "\"scale\":[-1,1]") "}},\"extensions\":{\"KHR_materials_clearcoat\":{"
                                "\"clearcoatNormalTexture\":{\"index\":0," TRANSFORM("\"scale\":[-1,1]") "}}}}]",
        TEXOPT_E_UNSUPPORTED, "clearcoatNormalTexture");
}

TEST(broken_references_are_malformed)
{
    CHECK_REFUSED_JSON("\"baseColorTexture\":{\"index\":0}", "\"baseColorTexture\":{\"index\":5}", TEXOPT_E_MALFORMED,
                       "texture 5");
    CHECK_REFUSED_JSON("{\"source\":0,\"sampler\":0}", "{\"source\":3,\"sampler\":0}", TEXOPT_E_MALFORMED, "image 3");
    CHECK_REFUSED_JSON("{\"source\":0,\"sampler\":0}", "{\"source\":0,\"sampler\":9}", TEXOPT_E_MALFORMED, "sampler 9");
    CHECK_REFUSED_JSON("\"material\":0,", "\"material\":4,", TEXOPT_E_MALFORMED, "material 4");
    CHECK_REFUSED_JSON("\"nodes\":[{\"mesh\":0,", "\"nodes\":[{\"children\":[0],\"mesh\":0,", TEXOPT_E_MALFORMED,
                       "node 0");
    CHECK_REFUSED_JSON("\"nodes\":[{\"mesh\":0,", "\"nodes\":[{\"children\":[3],\"mesh\":0,", TEXOPT_E_MALFORMED,
                       "child 3");
    CHECK_REFUSED_JSON("\"nodes\":[{\"mesh\":0,", "\"nodes\":[{\"mesh\":2,", TEXOPT_E_MALFORMED, "mesh 2");
    CHECK_REFUSED_JSON("\"count\":4,\"type\":\"VEC2\"", "\"count\":3,\"type\":\"VEC2\"", TEXOPT_E_MALFORMED,
                       "TEXCOORD_0 has 3");
}

/* The quad's JSON with "extras" holding `depth` nested arrays (the root object is one more
 * level); malloc'ed. */
static char *quad_with_nested_extras(const quad_doc *d, int depth)
{
    size_t n = strlen(d->json);
    char *json = malloc(n + 2 * (size_t)depth + 16);
    if (!json)
        return NULL;
    size_t at = (size_t)sprintf(json, "{\"extras\":");
    for (int i = 0; i < depth; i++)
        json[at++] = '[';
    for (int i = 0; i < depth; i++)
        json[at++] = ']';
    json[at++] = ',';
    memcpy(json + at, d->json + 1, n); /* the quad's members and its closing brace */
    return json;
}

TEST(json_nesting_past_the_bound_is_refused_before_parsing)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    /* 100,000 deep overflowed the parser's stack (a crash) before the bound. */
    char *json = quad_with_nested_extras(&d, 100000);
    CHECK(json);
    texopt_status glb = try_glb(&d, json, NULL, err, sizeof err);
    texopt_model *m = NULL;
    texopt_status text = texopt_model_load_memory(&m, json, strlen(json), NULL, NULL, err, sizeof err);
    free(json);
    quad_doc_free(&d);
    CHECK_EQ_INT(glb, TEXOPT_E_MALFORMED);
    CHECK_EQ_INT(text, TEXOPT_E_MALFORMED);
    CHECK(m == NULL);
    CHECK_MSG(strstr(err, "JSON nests deeper than 128") != NULL, "%s", err);
}

TEST(json_brackets_inside_strings_do_not_count)
{
    quad_doc d;
    char err[512];
    CHECK(quad_doc_init(&d, 4, 4));
    char extras[600];
    memset(extras, '[', sizeof extras);
    memcpy(extras, "{\"extras\":\"\\\"", 13);
    memcpy(extras + sizeof extras - 4, "\",", 3);
    size_t n = strlen(d.json);
    char *json = malloc(n + sizeof extras);
    CHECK(json);
    memcpy(json, extras, sizeof extras - 2);
    memcpy(json + sizeof extras - 2, d.json + 1, n);
    texopt_status st = try_glb(&d, json, NULL, err, sizeof err);
    free(json);
    quad_doc_free(&d);
    CHECK_OK(st, err);
}

typedef struct nested_load {
    const quad_doc *doc;
    int depth;
    texopt_status status;
    char err[512];
} nested_load;

static void *load_nested(void *arg)
{
    nested_load *job = arg;
    char *json = quad_with_nested_extras(job->doc, job->depth);
    job->status = json ? try_glb(job->doc, json, NULL, job->err, sizeof job->err) : TEXOPT_E_NOMEM;
    free(json);
    return NULL;
}

/* The threads that parse uploads get TEXOPT_PARSE_STACK_BYTES (8 MiB): a document at the
 * bound loads on an eighth of that. */
TEST(a_document_at_the_depth_bound_loads_on_a_one_mib_stack)
{
    quad_doc d;
    CHECK(quad_doc_init(&d, 4, 4));
    nested_load at = {&d, TEXOPT_JSON_MAX_DEPTH - 1, TEXOPT_E_INTERNAL, ""};
    nested_load past = {&d, TEXOPT_JSON_MAX_DEPTH, TEXOPT_E_INTERNAL, ""};
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, TEXOPT_PARSE_STACK_BYTES / 8);
    pthread_t t;
    CHECK(pthread_create(&t, &attr, load_nested, &at) == 0);
    pthread_join(t, NULL);
    CHECK(pthread_create(&t, &attr, load_nested, &past) == 0);
    pthread_join(t, NULL);
    pthread_attr_destroy(&attr);
    quad_doc_free(&d);
    CHECK_OK(at.status, at.err);
    CHECK_EQ_INT(past.status, TEXOPT_E_MALFORMED);
}

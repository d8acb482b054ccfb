/* test_gltf_io.c - loading and saving glTF (engine/model/io/gltf_io.h): a generated textured quad
 * in every container (GLB, .gltf with data URIs, .gltf with external files), index and UV
 * encodings, strips and fans, node transforms, texture transforms applied and dropped,
 * load -> save -> load round trips on spot.glb and Fox.glb, and the Khronos validator on
 * saved files (0 errors, no warnings the input did not have). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "gltf_builder.h"
#include "gltf_io.h"
#include "image_io.h"
#include "test.h"

static texopt_model *load_quad_json(const quad_doc *doc, const char *json, char *err, size_t err_len, texopt_status *st)
{
    size_t len = 0;
    unsigned char *glb = builder_glb(json, doc->bin, doc->bin_len, &len);
    texopt_model *m = NULL;
    *st = texopt_model_load_memory(&m, glb, len, NULL, NULL, err, err_len);
    free(glb);
    return m;
}

/* The quad as placed by its node: translation (1, 2, 3). */
static int quad_positions_match(const texopt_model *m, float dx, float dy, float dz)
{
    for (int v = 0; v < 4; v++) {
        if (fabsf(m->positions[v * 3] - (quad_positions[v * 3] + dx)) > 1e-6f ||
            fabsf(m->positions[v * 3 + 1] - (quad_positions[v * 3 + 1] + dy)) > 1e-6f ||
            fabsf(m->positions[v * 3 + 2] - (quad_positions[v * 3 + 2] + dz)) > 1e-6f)
            return 0;
    }
    return 1;
}

static int image_matches_builder(const texopt_image *img, int w, int h)
{
    texopt_image ref;
    if (!builder_texture(&ref, w, h))
        return 0;
    int ok = img->width == w && img->height == h && img->channels == 3 && img->pixels;
    for (size_t i = 0; ok && i < (size_t)w * h * 3; i++)
        ok = fabsf(img->pixels[i] - ref.pixels[i]) < 1e-6f;
    texopt_image_destroy(&ref);
    return ok;
}

TEST(glb_quad_loads_completely)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 8, 4));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, doc.json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_EQ_INT(m->vertex_count, 4);
    CHECK_EQ_INT(m->triangle_count, 2);
    CHECK(quad_positions_match(m, 1, 2, 3));
    for (int i = 0; i < 8; i++)
        CHECK_NEAR(m->uvs[i], quad_uvs[i], 0);
    for (int i = 0; i < 6; i++)
        CHECK_EQ_INT(m->triangles[i], quad_indices[i]);
    CHECK_EQ_INT(m->primitive_count, 1);
    CHECK_EQ_INT(m->primitives[0].gltf_mesh, 0);
    CHECK_EQ_INT(m->primitives[0].material, 0);
    CHECK_EQ_INT(m->primitives[0].domain, 0);
    CHECK_EQ_INT(m->material_count, 1);
    const texopt_texture_ref *base = &m->materials[0].slot[TEXOPT_SLOT_BASE_COLOR];
    CHECK_EQ_INT(base->image, 0);
    CHECK_EQ_INT(base->texcoord, 0);
    CHECK_EQ_INT(base->wrap_s, TEXOPT_WRAP_CLAMP);
    CHECK_EQ_INT(base->wrap_t, TEXOPT_WRAP_MIRROR);
    CHECK_EQ_INT(m->materials[0].slot[TEXOPT_SLOT_NORMAL].image, -1);
    CHECK_EQ_INT(m->image_count, 1);
    CHECK(image_matches_builder(&m->images[0], 8, 4));
    CHECK(m->image_names[0] && strcmp(m->image_names[0], "image 0") == 0);
    CHECK_EQ_INT(m->domain_count, 1);
    CHECK_EQ_INT(m->domains[0].width, 8);
    CHECK_EQ_INT(m->domains[0].height, 4);
    CHECK_EQ_INT(m->domains[0].wrap_s, TEXOPT_WRAP_CLAMP);
    CHECK(m->document != NULL && m->destroy_document != NULL);
    /* No factors in the file: glTF's defaults. */
    CHECK_NEAR(m->materials[0].metallic_factor, 1, 0);
    CHECK_NEAR(m->materials[0].roughness_factor, 1, 0);
    texopt_model_destroy(m);
    CHECK(builder_replace(&doc.json, "\"baseColorTexture\":{\"index\":0}}",
                          "\"baseColorTexture\":{\"index\":0},\"metallicFactor\":0,\"roughnessFactor\":0.58}"));
    m = load_quad_json(&doc, doc.json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_NEAR(m->materials[0].metallic_factor, 0, 0);
    CHECK_NEAR(m->materials[0].roughness_factor, 0.58, 1e-12);
    /* OPAQUE (the default): base colour's alpha is not shown, so stage 1 does not read it. */
    CHECK_EQ_INT(m->materials[0].alpha_mode, TEXOPT_ALPHA_OPAQUE);
    CHECK_EQ_INT(texopt_material_binding_channels(&m->materials[0], TEXOPT_SLOT_BASE_COLOR), TEXOPT_CHANNELS_RGB);
    texopt_model_destroy(m);
    const char *modes[] = {"MASK", "BLEND", "OPAQUE"};
    for (int i = 0; i < 3; i++) {
        char mode[128];
        snprintf(mode, sizeof mode, "\"roughnessFactor\":0.58},\"alphaMode\":\"%s\"%s", modes[i],
                 i == 0 ? ",\"alphaCutoff\":0.3" : "");
        char *edited = strdup(doc.json);
        CHECK(edited && builder_replace(&edited, "\"roughnessFactor\":0.58}", mode));
        m = load_quad_json(&doc, edited, err, sizeof err, &st);
        free(edited);
        CHECK_OK(st, err);
        CHECK_EQ_INT(m->materials[0].alpha_mode, i == 0   ? TEXOPT_ALPHA_MASK
                                                 : i == 1 ? TEXOPT_ALPHA_BLEND
                                                          : TEXOPT_ALPHA_OPAQUE);
        CHECK_NEAR(m->materials[0].alpha_cutoff, i == 0 ? 0.3 : 0.5, 0);
        CHECK_EQ_INT(texopt_material_binding_channels(&m->materials[0], TEXOPT_SLOT_BASE_COLOR),
                     TEXOPT_CHANNELS_RGB | (i < 2 ? TEXOPT_CHANNEL_A : 0u));
        texopt_model_destroy(m);
    }
    quad_doc_free(&doc);
}

TEST(skip_images_reads_sizes_without_pixels)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 16, 8));
    size_t len = 0;
    unsigned char *glb = builder_glb(doc.json, doc.bin, doc.bin_len, &len);
    texopt_load_options opt = {0, 0, 1};
    texopt_model *m = NULL;
    CHECK_OK(texopt_model_load_memory(&m, glb, len, NULL, &opt, err, sizeof err), err);
    free(glb);
    CHECK(m->images[0].pixels == NULL);
    CHECK_EQ_INT(m->images[0].width, 16);
    CHECK_EQ_INT(m->images[0].height, 8);
    CHECK_EQ_INT(m->images[0].channels, 3);
    CHECK_EQ_INT(m->domains[0].width, 16);
    texopt_model_destroy(m);
    quad_doc_free(&doc);
}

TEST(gltf_with_data_uris_loads)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 8, 4));
    char *b64 = builder_base64(doc.bin, doc.bin_len);
    char *uri = malloc(strlen(b64) + 128);
    sprintf(uri, "{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}", doc.bin_len, b64);
    char old[64];
    snprintf(old, sizeof old, "{\"byteLength\":%zu}", doc.bin_len);
    CHECK(builder_replace(&doc.json, old, uri));
    texopt_model *m = NULL;
    CHECK_OK(texopt_model_load_memory(&m, doc.json, strlen(doc.json), NULL, NULL, err, sizeof err), err);
    CHECK(quad_positions_match(m, 1, 2, 3));
    CHECK(image_matches_builder(&m->images[0], 8, 4));
    texopt_model_destroy(m);
    free(b64);
    free(uri);
    quad_doc_free(&doc);
}

TEST(gltf_with_external_files_loads_and_saves_self_contained)
{
    char err[512] = "", dir[64], path[160], out[160];
    CHECK(builder_tempdir(dir));
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 8, 4));
    snprintf(path, sizeof path, "%s/quad data.bin", dir);
    CHECK(builder_write(path, doc.bin, doc.bin_len));
    snprintf(path, sizeof path, "%s/tex.png", dir);
    CHECK(builder_write(path, doc.bin + QUAD_PNG_OFFSET, doc.png_len));
    char old[64], repl[96];
    snprintf(old, sizeof old, "{\"byteLength\":%zu}", doc.bin_len);
    snprintf(repl, sizeof repl, "{\"byteLength\":%zu,\"uri\":\"quad%%20data.bin\"}", doc.bin_len);
    CHECK(builder_replace(&doc.json, old, repl));
    CHECK(builder_replace(&doc.json, "{\"bufferView\":3,\"mimeType\":\"image/png\"}", "{\"uri\":\"tex.png\"}"));
    snprintf(path, sizeof path, "%s/quad.gltf", dir);
    CHECK(builder_write(path, doc.json, strlen(doc.json)));
    texopt_model *m = NULL, *back = NULL;
    CHECK_OK(texopt_model_load(&m, path, NULL, err, sizeof err), err);
    CHECK(quad_positions_match(m, 1, 2, 3));
    CHECK(image_matches_builder(&m->images[0], 8, 4));
    CHECK(strcmp(m->image_names[0], "tex.png") == 0);
    snprintf(out, sizeof out, "%s/out.glb", dir);
    CHECK_OK(texopt_model_save_glb(m, NULL, out, err, sizeof err), err);
    /* The saved file must stand alone: load it from memory, where external URIs are refused. */
    FILE *f = fopen(out, "rb");
    CHECK(f != NULL);
    unsigned char buf[8192];
    size_t len = fread(buf, 1, sizeof buf, f);
    fclose(f);
    CHECK(len > 0 && len < sizeof buf);
    CHECK(builder_contains(buf, len, doc.bin + QUAD_PNG_OFFSET, doc.png_len)); /* original PNG bytes */
    CHECK(!builder_contains(buf, len, "\"uri\"", 5));
    CHECK_OK(texopt_model_load_memory(&back, buf, len, NULL, NULL, err, sizeof err), err);
    CHECK(quad_positions_match(back, 1, 2, 3));
    CHECK(image_matches_builder(&back->images[0], 8, 4));
    texopt_model_destroy(m);
    texopt_model_destroy(back);
    quad_doc_free(&doc);
    builder_rmdir(dir);
}

TEST(index_encodings_u8_u32_and_non_indexed)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    /* u8 indices in the u16 slot. */
    const unsigned char idx8[6] = {3, 2, 1, 3, 1, 0};
    memcpy(doc.bin + QUAD_IDX_OFFSET, idx8, 6);
    char *json = strdup(doc.json);
    CHECK(builder_replace(&json, "\"componentType\":5123,\"count\":6", "\"componentType\":5121,\"count\":6"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    for (int i = 0; i < 6; i++)
        CHECK_EQ_INT(m->triangles[i], idx8[i]);
    texopt_model_destroy(m);
    free(json);

    /* u32 indices in a view of their own. */
    const uint32_t idx32[6] = {2, 3, 0, 2, 0, 1};
    int view = quad_doc_add_view(&doc, idx32, sizeof idx32);
    CHECK_EQ_INT(view, 4);
    json = strdup(doc.json);
    CHECK(
        builder_replace(&json, "{\"bufferView\":2,\"componentType\":5123", "{\"bufferView\":4,\"componentType\":5125"));
    m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    for (int i = 0; i < 6; i++)
        CHECK_EQ_INT(m->triangles[i], idx32[i]);
    texopt_model_destroy(m);
    free(json);

    /* Non-indexed: the first three vertices make one triangle. */
    json = strdup(doc.json);
    CHECK(builder_replace(&json, "\"indices\":2,", ""));
    CHECK(builder_replace(&json, "\"count\":4,\"type\":\"VEC3\"", "\"count\":3,\"type\":\"VEC3\""));
    CHECK(builder_replace(&json, "\"max\":[1,1,0]", "\"max\":[1,1,0]"));
    CHECK(builder_replace(&json, "\"count\":4,\"type\":\"VEC2\"", "\"count\":3,\"type\":\"VEC2\""));
    m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_EQ_INT(m->vertex_count, 3);
    CHECK_EQ_INT(m->triangle_count, 1);
    CHECK(m->triangles[0] == 0 && m->triangles[1] == 1 && m->triangles[2] == 2);
    texopt_model_destroy(m);
    free(json);
    quad_doc_free(&doc);
}

TEST(normalized_texcoords_are_converted)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    const uint16_t uv16[8] = {0, 65535, 65535, 65535, 65535, 0, 0, 32768};
    memcpy(doc.bin + QUAD_UV_OFFSET, uv16, sizeof uv16);
    char *json = strdup(doc.json);
    CHECK(builder_replace(&json, "{\"bufferView\":1,\"componentType\":5126",
                          "{\"bufferView\":1,\"normalized\":true,\"componentType\":5123"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    for (int i = 0; i < 8; i++)
        CHECK_NEAR(m->uvs[i], uv16[i] / 65535.0, 1e-7);
    texopt_model_destroy(m);
    free(json);

    const unsigned char uv8[8] = {0, 255, 255, 255, 255, 0, 0, 51};
    memcpy(doc.bin + QUAD_UV_OFFSET, uv8, sizeof uv8);
    json = strdup(doc.json);
    CHECK(builder_replace(&json, "{\"bufferView\":1,\"componentType\":5126",
                          "{\"bufferView\":1,\"normalized\":true,\"componentType\":5121"));
    m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_NEAR(m->uvs[7], 0.2, 1e-7);
    CHECK_NEAR(m->uvs[1], 1.0, 0);
    texopt_model_destroy(m);
    free(json);
    quad_doc_free(&doc);
}

/* Whether the file at path holds the bytes of word anywhere. */
static int file_contains(const char *path, const char *word)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    static unsigned char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    return builder_contains(buf, n, word, strlen(word));
}

/* The quad's two triangles as a strip (1 2 0 3) and as a fan around vertex 0 (0 1 2 3):
 * both give (1 2 0) and (2 3 0), the triangle list's triangles with their winding; the saved
 * file keeps its strip and takes the new UVs. */
TEST(triangle_strips_and_fans_load_as_their_triangles_and_stay_strips_when_saved)
{
    const uint16_t orders[2][4] = {{1, 2, 0, 3}, {0, 1, 2, 3}};
    const char *modes[2] = {"\"mode\":5", "\"mode\":6"};
    const uint32_t want[6] = {1, 2, 0, 2, 3, 0};
    char err[512] = "", dir[64], out[128];
    CHECK(builder_tempdir(dir));
    snprintf(out, sizeof out, "%s/out.glb", dir);
    for (int k = 0; k < 2; k++) {
        quad_doc doc;
        CHECK(quad_doc_init(&doc, 4, 4));
        memcpy(doc.bin + QUAD_IDX_OFFSET, orders[k], sizeof orders[k]);
        char *json = strdup(doc.json);
        CHECK(builder_replace(&json, "\"mode\":4", modes[k]));
        CHECK(builder_replace(&json, "\"count\":6,\"type\":\"SCALAR\"", "\"count\":4,\"type\":\"SCALAR\""));
        texopt_status st;
        texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
        CHECK_OK(st, err);
        CHECK_EQ_INT(m->triangle_count, 2);
        CHECK_MSG(memcmp(m->triangles, want, sizeof want) == 0, "%s: triangles %u %u %u, %u %u %u", modes[k],
                  m->triangles[0], m->triangles[1], m->triangles[2], m->triangles[3], m->triangles[4], m->triangles[5]);
        float uvs[8];
        for (int i = 0; i < 8; i++)
            uvs[i] = 0.5f * m->uvs[i] + 0.25f;
        texopt_model_edit edit = {uvs, NULL, 0};
        CHECK_OK(texopt_model_save_glb(m, &edit, out, err, sizeof err), err);
        CHECK_EQ_INT(file_contains(out, modes[k]), 1);
        texopt_model *back = NULL;
        CHECK_OK(texopt_model_load(&back, out, NULL, err, sizeof err), err);
        CHECK(memcmp(back->triangles, want, sizeof want) == 0);
        CHECK(memcmp(back->uvs, uvs, sizeof uvs) == 0);
        texopt_model_destroy(back);
        texopt_model_destroy(m);
        free(json);
        quad_doc_free(&doc);
    }
    builder_rmdir(dir);
}

TEST(node_hierarchy_instancing_and_mirroring)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    /* Root scales by 2 around a child that translates by (1,0,0); a second user of the mesh
     * far away must not matter (the first node in node order places an instanced mesh). */
    char *json = strdup(doc.json);
    CHECK(builder_replace(&json, "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,\"translation\":[1,2,3]}]",
                          "\"scenes\":[{\"nodes\":[0,2]}],\"nodes\":[{\"children\":[1],\"scale\":[2,2,2]},"
                          "{\"mesh\":0,\"translation\":[1,0,0]},{\"mesh\":0,\"translation\":[100,0,0]}]"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_EQ_INT(m->primitive_count, 1);
    CHECK_NEAR(m->positions[2 * 3 + 0], 4.0, 1e-6); /* vertex 2 = (1,1,0) -> 2 * (2,1,0) */
    CHECK_NEAR(m->positions[2 * 3 + 1], 2.0, 1e-6);
    CHECK(m->triangles[1] == 1 && m->triangles[2] == 2);
    texopt_model_destroy(m);
    free(json);

    /* A rotation of 90 degrees about z by quaternion, and a mirror that reverses winding. */
    json = strdup(doc.json);
    CHECK(builder_replace(&json, "\"translation\":[1,2,3]", "\"rotation\":[0,0,0.70710678,0.70710678]"));
    m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_NEAR(m->positions[1 * 3 + 0], 0.0, 1e-6); /* (1,0,0) -> (0,1,0) */
    CHECK_NEAR(m->positions[1 * 3 + 1], 1.0, 1e-6);
    texopt_model_destroy(m);
    free(json);

    json = strdup(doc.json);
    CHECK(builder_replace(&json, "\"translation\":[1,2,3]", "\"matrix\":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 5,0,0,1]"));
    m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_NEAR(m->positions[1 * 3 + 0], 4.0, 1e-6); /* (1,0,0) -> (-1+5, 0, 0) */
    CHECK(m->triangles[0] == 0 && m->triangles[1] == 2 && m->triangles[2] == 1);
    texopt_model_destroy(m);
    free(json);
    quad_doc_free(&doc);
}

/* NORMAL is read into world space by the inverse transpose of the node's matrix, so a mirror
 * with a non-uniform scale keeps normals perpendicular to the placed surface and on the side
 * its (swapped) winding faces; a file without NORMAL leaves normals NULL (shaded flat). */
TEST(normals_turn_with_the_node_and_stay_on_the_front_side)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, doc.json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK(m->normals == NULL);
    texopt_model_destroy(m);

    const float r = (float)(1.0 / sqrt(2.0));
    const float normals[12] = {0, 0, 1, r, 0, r, 0, 0, 1, 0, 0, 1};
    int view = quad_doc_add_view(&doc, normals, sizeof normals);
    CHECK(view == 4);
    char *json = strdup(doc.json);
    CHECK(builder_replace(&json, "\"TEXCOORD_0\":1}", "\"TEXCOORD_0\":1,\"NORMAL\":3}"));
    CHECK(builder_replace(&json, "\"type\":\"SCALAR\"}]",
                          "\"type\":\"SCALAR\"},{\"bufferView\":4,\"componentType\":5126,\"count\":4,"
                          "\"type\":\"VEC3\"}]"));
    CHECK(builder_replace(&json, "\"translation\":[1,2,3]", "\"matrix\":[-2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]"));
    m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK(m->normals != NULL);
    /* (1, 0, 1) under diag(-2, 1, 1): the inverse transpose gives (-1/2, 0, 1), on +z where the
     * swapped winding faces. */
    CHECK_NEAR(m->normals[3 * 1 + 0], -1.0 / sqrt(5.0), 1e-6);
    CHECK_NEAR(m->normals[3 * 1 + 1], 0.0, 1e-6);
    CHECK_NEAR(m->normals[3 * 1 + 2], 2.0 / sqrt(5.0), 1e-6);
    CHECK_NEAR(m->normals[3 * 0 + 2], 1.0, 1e-6);
    texopt_model_destroy(m);
    free(json);
    quad_doc_free(&doc);
}

/* Loads path, saves it (with edit when uv_shift != 0: UVs shifted, image 0 replaced) and
 * reloads; checks what must be identical and what must have changed. */
static void check_round_trip(const char *path, float uv_shift, const char *out)
{
    char err[512] = "";
    texopt_model *m = NULL, *back = NULL;
    CHECK_OK(texopt_model_load(&m, path, NULL, err, sizeof err), err);
    float *uvs = NULL;
    texopt_image repl = {0, 0, 0, NULL};
    const texopt_image **imgs = NULL;
    texopt_model_edit edit = {NULL, NULL, 0};
    if (uv_shift != 0) {
        uvs = malloc(sizeof(float) * 2 * m->vertex_count);
        for (size_t i = 0; i < 2 * m->vertex_count; i++)
            uvs[i] = m->uvs[i] * 0.5f + uv_shift;
        CHECK(builder_texture(&repl, 24, 16));
        imgs = calloc((size_t)m->image_count, sizeof *imgs);
        imgs[0] = &repl;
        edit.uvs = uvs;
        edit.images = imgs;
    }
    CHECK_OK(texopt_model_save_glb(m, &edit, out, err, sizeof err), err);
    CHECK_OK(texopt_model_load(&back, out, NULL, err, sizeof err), err);
    CHECK_EQ_INT(back->vertex_count, m->vertex_count);
    CHECK_EQ_INT(back->triangle_count, m->triangle_count);
    CHECK_EQ_INT(back->primitive_count, m->primitive_count);
    CHECK_EQ_INT(back->material_count, m->material_count);
    CHECK_EQ_INT(back->image_count, m->image_count);
    CHECK(memcmp(back->positions, m->positions, sizeof(float) * 3 * m->vertex_count) == 0);
    CHECK(memcmp(back->triangles, m->triangles, sizeof(uint32_t) * 3 * m->triangle_count) == 0);
    const float *want_uv = uvs ? uvs : m->uvs;
    CHECK(memcmp(back->uvs, want_uv, sizeof(float) * 2 * m->vertex_count) == 0);
    CHECK(memcmp(back->materials, m->materials, sizeof(texopt_material) * (size_t)m->material_count) == 0);
    for (int p = 0; p < m->primitive_count; p++) {
        CHECK_EQ_INT(back->primitives[p].material, m->primitives[p].material);
        CHECK_EQ_INT(back->primitives[p].domain, m->primitives[p].domain);
    }
    for (int i = 0; i < m->image_count; i++) {
        const texopt_image *want = (imgs && imgs[i]) ? imgs[i] : &m->images[i];
        const texopt_image *got = &back->images[i];
        CHECK_EQ_INT(got->width, want->width);
        CHECK_EQ_INT(got->height, want->height);
        CHECK_EQ_INT(got->channels, want->channels);
        for (size_t k = 0; k < (size_t)want->width * want->height * want->channels; k++)
            CHECK_NEAR(got->pixels[k], want->pixels[k], 1e-6);
    }
    texopt_model_destroy(m);
    texopt_model_destroy(back);
    texopt_image_destroy(&repl);
    free(uvs);
    free(imgs);
}

TEST(spot_and_fox_round_trip_unchanged_and_edited)
{
    char dir[64], out[128], in[512];
    CHECK(builder_tempdir(dir));
    const char *models[] = {"spot/spot.glb", "Fox/Fox.glb"};
    for (int i = 0; i < 2; i++) {
        snprintf(in, sizeof in, "%s/%s", TEXOPT_TEST_DATA_DIR, models[i]);
        snprintf(out, sizeof out, "%s/same%d.glb", dir, i);
        check_round_trip(in, 0.0f, out);
        if (test_failed_now())
            break;
        snprintf(out, sizeof out, "%s/edit%d.glb", dir, i);
        check_round_trip(in, 0.25f, out);
        if (test_failed_now())
            break;
    }
    builder_rmdir(dir);
}

/* Largest difference of two images of one size (1 when the sizes differ). */
static double max_difference(const texopt_image *a, const texopt_image *b)
{
    if (a->width != b->width || a->height != b->height || a->channels != b->channels)
        return 1;
    double d = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height * a->channels; i++)
        d = fmax(d, fabs(a->pixels[i] - b->pixels[i]));
    return d;
}

/* Saves m with edit as out and loads it back: how far its image 0 is from want; 1 when it
 * cannot be saved or read, or the file does not hold `mime` or holds `other`. */
static double saved_image_error(const texopt_model *m, const texopt_model_edit *edit, const char *out, const char *mime,
                                const char *other, const texopt_image *want)
{
    char err[512] = "";
    texopt_model *back = NULL;
    if (texopt_model_save_glb(m, edit, out, err, sizeof err) != TEXOPT_OK || file_contains(out, mime) != 1 ||
        file_contains(out, other) != 0 || texopt_model_load(&back, out, NULL, err, sizeof err) != TEXOPT_OK)
        return 1;
    double d = max_difference(&back->images[0], want);
    texopt_model_destroy(back);
    return d;
}

TEST(jpeg_texture_keeps_its_bytes_unless_replaced_and_unused_views_are_dropped)
{
    char err[512] = "", dir[64], out[128], path[512];
    CHECK(builder_tempdir(dir));
    snprintf(path, sizeof path, "%s/images/gradient_16x8_progressive.jpg", TEXOPT_TEST_DATA_DIR);
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL);
    unsigned char jpg[4096];
    size_t jpg_len = fread(jpg, 1, sizeof jpg, f);
    fclose(f);
    CHECK(jpg_len > 100 && jpg_len < sizeof jpg);
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 8, 4));
    CHECK_EQ_INT(quad_doc_add_view(&doc, jpg, jpg_len), 4);
    /* The image now reads view 4; view 3 (the PNG) is read by no one. */
    CHECK(builder_replace(&doc.json, "{\"bufferView\":3,\"mimeType\":\"image/png\"}",
                          "{\"bufferView\":4,\"mimeType\":\"image/jpeg\"}"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, doc.json, err, sizeof err, &st), *back = NULL;
    CHECK_OK(st, err);
    CHECK_EQ_INT(m->images[0].width, 16);
    float uvs[8] = {0, 0, 0.5f, 0, 0.5f, 0.5f, 0, 0.5f};
    texopt_model_edit edit = {uvs, NULL, 0};
    snprintf(out, sizeof out, "%s/jpeg.glb", dir);
    CHECK_OK(texopt_model_save_glb(m, &edit, out, err, sizeof err), err);
    f = fopen(out, "rb");
    CHECK(f != NULL);
    unsigned char buf[16384];
    size_t len = fread(buf, 1, sizeof buf, f);
    fclose(f);
    CHECK(len > 0 && len < sizeof buf);
    CHECK(builder_contains(buf, len, jpg, jpg_len));
    CHECK(builder_contains(buf, len, "image/jpeg", 10));
    CHECK(!builder_contains(buf, len, doc.bin + QUAD_PNG_OFFSET, doc.png_len)); /* dropped */
    CHECK(!builder_contains(buf, len, quad_uvs, sizeof quad_uvs));              /* old UVs dropped */
    CHECK_OK(texopt_model_load(&back, out, NULL, err, sizeof err), err);
    CHECK(memcmp(back->uvs, uvs, sizeof uvs) == 0);
    CHECK(memcmp(back->images[0].pixels, m->images[0].pixels, sizeof(float) * 16 * 8 * 3) == 0);
    texopt_model_destroy(back);

    /* Replaced, a JPEG stays a JPEG (a tenth of a PNG's bytes), close to the replacement. */
    texopt_image rebaked;
    CHECK(texopt_image_create(&rebaked, 32, 16, 3, NULL, 0) == TEXOPT_OK);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 32; x++)
            for (int c = 0; c < 3; c++)
                texopt_image_at(&rebaked, x, y)[c] = (float)(0.2 + 0.6 * x / 31.0 - 0.1 * c + 0.2 * y / 15.0);
    const texopt_image *images[1] = {&rebaked};
    edit.images = images;
    double worst = saved_image_error(m, &edit, out, "image/jpeg", "image/png", &rebaked);
    CHECK_MSG(worst < 0.03, "JPEG off by %g", worst);
    CHECK(file_contains(out, "\xFF\xD8\xFF") == 1); /* the input's JPEG was dropped: the new one */
    /* Lossless (the copies compare measures): a PNG holding the replacement to 8 bits. */
    edit.lossless = 1;
    worst = saved_image_error(m, &edit, out, "image/png", "image/jpeg", &rebaked);
    CHECK_MSG(worst <= 0.5 / 255 + 1e-6, "PNG off by %g", worst);
    texopt_image_destroy(&rebaked);
    texopt_model_destroy(m);
    quad_doc_free(&doc);
    builder_rmdir(dir);
}

TEST(saving_refuses_bad_edits_and_keeps_the_old_file)
{
    char err[512] = "", dir[64], out[128];
    CHECK(builder_tempdir(dir));
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, doc.json, err, sizeof err, &st);
    CHECK_OK(st, err);
    snprintf(out, sizeof out, "%s/q.glb", dir);
    CHECK(builder_write(out, "old", 3));
    float uvs[8] = {0, 0, 1, 0, 1, 1, 0, NAN};
    texopt_model_edit edit = {uvs, NULL, 0};
    CHECK_EQ_INT(texopt_model_save_glb(m, &edit, out, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "vertex 3") != NULL);
    FILE *f = fopen(out, "rb");
    char buf[8] = "";
    CHECK(f && fread(buf, 1, sizeof buf, f) == 3 && memcmp(buf, "old", 3) == 0);
    fclose(f);
    texopt_image empty = {0, 0, 0, NULL};
    const texopt_image *imgs[1] = {&empty};
    texopt_model_edit edit2 = {NULL, imgs, 0};
    CHECK_EQ_INT(texopt_model_save_glb(m, &edit2, out, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    snprintf(out, sizeof out, "%s/no/such/dir/q.glb", dir);
    CHECK_EQ_INT(texopt_model_save_glb(m, NULL, out, err, sizeof err), TEXOPT_E_IO);
    texopt_model_destroy(m);
    quad_doc_free(&doc);
    builder_rmdir(dir);
}

/* ---- the Khronos validator on what we write ---------------------------------------------- */

/* Runs tools/validate-gltf.mjs on file against baseline; returns its exit status. */
static int run_validator(const char *file, const char *baseline, const char *log)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "node '%s/tools/validate-gltf.mjs' '%s' --baseline '%s' > '%s' 2>&1", TEXOPT_SOURCE_DIR,
             file, baseline, log);
    int rc = system(cmd);
    return rc == -1 ? -1 : WEXITSTATUS(rc);
}

static void print_file(const char *path)
{
    FILE *f = fopen(path, "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
        fputs(line, stderr);
    if (f)
        fclose(f);
}

TEST(validator_accepts_saved_files_with_new_uvs_and_images)
{
    char err[512] = "", dir[64], in[512], out[128], log[128];
    CHECK(builder_tempdir(dir));
    snprintf(log, sizeof log, "%s/report.json", dir);

    /* The generated quad, as a GLB on disk, is one of the inputs. */
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 8, 4));
    size_t len = 0;
    unsigned char *glb = builder_glb(doc.json, doc.bin, doc.bin_len, &len);
    char quad_path[128];
    snprintf(quad_path, sizeof quad_path, "%s/quad.glb", dir);
    CHECK(builder_write(quad_path, glb, len));
    free(glb);

    const char *inputs[3] = {"spot/spot.glb", "Fox/Fox.glb", NULL};
    for (int i = 0; i < 3; i++) {
        if (inputs[i])
            snprintf(in, sizeof in, "%s/%s", TEXOPT_TEST_DATA_DIR, inputs[i]);
        else
            snprintf(in, sizeof in, "%s", quad_path);
        snprintf(out, sizeof out, "%s/out%d.glb", dir, i);
        check_round_trip(in, 0.125f, out);
        if (test_failed_now())
            break;
        int rc = run_validator(out, in, log);
        if (rc != 0)
            print_file(log);
        CHECK_MSG(rc == 0, "validator exit %d for %s (saved from %s)", rc, out, in);
    }

    /* The check can fail: a file whose POSITION max is wrong is an error for the validator. */
    char *bad = strdup(doc.json);
    CHECK(builder_replace(&bad, "\"max\":[1,1,0]", "\"max\":[5,5,5]"));
    glb = builder_glb(bad, doc.bin, doc.bin_len, &len);
    snprintf(out, sizeof out, "%s/bad.glb", dir);
    CHECK(builder_write(out, glb, len));
    free(glb);
    free(bad);
    CHECK_EQ_INT(run_validator(out, quad_path, log), 1);
    (void)err;
    quad_doc_free(&doc);
    builder_rmdir(dir);
}

/* Runs the validator on out with the quad of `json` (written to dir/in.glb) as its baseline,
 * printing the report when it fails; its exit status. */
static int validate_against_quad(const char *out, const quad_doc *doc, const char *json, const char *dir)
{
    char in[128], log[128];
    snprintf(in, sizeof in, "%s/in.glb", dir);
    snprintf(log, sizeof log, "%s/report.json", dir);
    size_t len = 0;
    unsigned char *glb = builder_glb(json, doc->bin, doc->bin_len, &len);
    int written = glb && builder_write(in, glb, len);
    free(glb);
    if (!written)
        return -1;
    int rc = run_validator(out, in, log);
    if (rc != 0)
        print_file(log);
    return rc;
}

/* The extension's own example: offset [0, 1], rotation pi/2, scale 0.5 shows the lower-left
 * quadrant of the image, so UV (u, v) reads (0.5 v, 1 - 0.5 u). */
TEST(texture_transforms_on_texcoord0_are_applied_to_the_uvs_and_dropped_when_saved)
{
    char err[512] = "", dir[64], out[128];
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    char *json = strdup(doc.json);
    const char *transform = "\"extensions\":{\"KHR_texture_transform\":"
                            "{\"offset\":[0,1],\"rotation\":1.5707963267948966,\"scale\":[0.5,0.5]}}";
    char materials[512];
    snprintf(materials, sizeof materials,
             "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,%s}},"
             "\"emissiveTexture\":{\"index\":0,%s}}]",
             transform, transform);
    CHECK(builder_replace(&json, "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]",
                          materials));
    CHECK(builder_replace(&json, "\"asset\":{\"version\":\"2.0\"},",
                          "\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_texture_transform\"],"
                          "\"extensionsRequired\":[\"KHR_texture_transform\"],"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    for (int v = 0; v < 4; v++) {
        CHECK_NEAR(m->uvs[2 * v], 0.5 * quad_uvs[2 * v + 1], 1e-6);
        CHECK_NEAR(m->uvs[2 * v + 1], 1.0 - 0.5 * quad_uvs[2 * v], 1e-6);
    }

    /* Saved with new UVs, the file reads its textures directly: the transform is gone, and
     * loading it again applies nothing more. */
    CHECK(builder_tempdir(dir));
    snprintf(out, sizeof out, "%s/out.glb", dir);
    texopt_model_edit edit = {m->uvs, NULL, 0};
    CHECK_OK(texopt_model_save_glb(m, &edit, out, err, sizeof err), err);
    CHECK_EQ_INT(file_contains(out, "KHR_texture_transform"), 0);
    int rc = validate_against_quad(out, &doc, json, dir);
    CHECK_MSG(rc == 0, "validator exit %d for %s", rc, out);
    texopt_model *back = NULL;
    CHECK_OK(texopt_model_load(&back, out, NULL, err, sizeof err), err);
    CHECK(memcmp(back->uvs, m->uvs, sizeof(float) * 8) == 0);

    /* Saved without new UVs, the file keeps its UVs and so its transform. */
    CHECK_OK(texopt_model_save_glb(m, NULL, out, err, sizeof err), err);
    CHECK_EQ_INT(file_contains(out, "KHR_texture_transform"), 1);
    texopt_model_destroy(back);
    texopt_model_destroy(m);
    builder_rmdir(dir);
    free(json);
    quad_doc_free(&doc);
}

/* Each known extension texture carries the channels its specification stores it in. */
TEST(extension_textures_carry_the_channels_their_extension_reads)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    char *json = strdup(doc.json);
    CHECK(json &&
          builder_replace(&json, "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]",
                          "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},"
                          "\"extensions\":{\"KHR_materials_specular\":{\"specularTexture\":{\"index\":0}},"
                          "\"KHR_materials_clearcoat\":{\"clearcoatRoughnessTexture\":{\"index\":0}}}}]"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    const texopt_material *mat = &m->materials[0];
    CHECK_EQ_INT(mat->extra_count, 2);
    for (int i = 0; i < mat->extra_count; i++) {
        int specular = strcmp(mat->extra[i].name, "specularTexture") == 0;
        CHECK(specular || strcmp(mat->extra[i].name, "clearcoatRoughnessTexture") == 0);
        CHECK_EQ_INT(mat->extra[i].kind, TEXOPT_TEXTURE_DATA);
        CHECK_EQ_INT(mat->extra[i].channels, specular ? TEXOPT_CHANNEL_A : TEXOPT_CHANNEL_G);
        CHECK_EQ_INT(texopt_material_binding_channels(mat, TEXOPT_SLOT_COUNT + i), mat->extra[i].channels);
    }
    texopt_model_destroy(m);
    free(json);
    quad_doc_free(&doc);
}

/* Saves m with its UVs as new ones into dir/name and loads the file back. */
static texopt_model *save_and_reload(const texopt_model *m, const char *dir, const char *name, char *path,
                                     size_t path_len, char *err, size_t err_len)
{
    snprintf(path, path_len, "%s/%s", dir, name);
    texopt_model_edit edit = {m->uvs, NULL, 0};
    texopt_model *back = NULL;
    if (texopt_model_save_glb(m, &edit, path, err, err_len) != TEXOPT_OK ||
        texopt_model_load(&back, path, NULL, err, err_len) != TEXOPT_OK)
        return NULL;
    return back;
}

/* A clearcoat normal map on TEXCOORD_0 shares the base colour's transform and is laid out
 * with it; a clearcoat map on TEXCOORD_1 is left alone, transform included. */
TEST(textures_of_known_material_extensions_are_bound_and_lose_their_applied_transform)
{
    char err[512] = "", dir[64], out[128];
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    char *json = strdup(doc.json);
    const char *transform = "\"extensions\":{\"KHR_texture_transform\":{\"offset\":[0.25,0.5],\"scale\":[0.5,0.25]}}";
    char materials[1024];
    /* The core normal map is there so that a renderer (and the validator) can make tangents. */
    snprintf(materials, sizeof materials,
             "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,%s}},"
             "\"normalTexture\":{\"index\":0,%s},"
             "\"extensions\":{\"KHR_materials_clearcoat\":{\"clearcoatFactor\":1,"
             "\"clearcoatNormalTexture\":{\"index\":0,\"scale\":0.5,%s}}}}]",
             transform, transform, transform);
    CHECK(builder_replace(&json, "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]",
                          materials));
    CHECK(builder_replace(&json, "\"asset\":{\"version\":\"2.0\"},",
                          "\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_texture_transform\","
                          "\"KHR_materials_clearcoat\"],"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    const texopt_material *mat = &m->materials[0];
    CHECK_EQ_INT(mat->extra_count, 1);
    CHECK(strcmp(mat->extra[0].name, "clearcoatNormalTexture") == 0);
    CHECK_EQ_INT(mat->extra[0].kind, TEXOPT_TEXTURE_NORMAL);
    CHECK_EQ_INT(mat->extra[0].channels, TEXOPT_CHANNELS_RGB);
    CHECK_EQ_INT(mat->extra[0].ref.image, 0);
    CHECK_EQ_INT(mat->extra[0].ref.texcoord, 0);
    for (int v = 0; v < 4; v++) {
        CHECK_NEAR(m->uvs[2 * v], 0.5 * quad_uvs[2 * v] + 0.25, 1e-6);
        CHECK_NEAR(m->uvs[2 * v + 1], 0.25 * quad_uvs[2 * v + 1] + 0.5, 1e-6);
    }

    /* Saved with new UVs every transform is gone (one left on the clearcoat normal map would
     * also differ from the base colour's, now none, and the load would refuse the file), and
     * the file is valid. */
    CHECK(builder_tempdir(dir));
    texopt_model *back = save_and_reload(m, dir, "out.glb", out, sizeof out, err, sizeof err);
    CHECK_MSG(back != NULL, "%s", err);
    CHECK_EQ_INT(file_contains(out, "KHR_texture_transform"), 0);
    CHECK(memcmp(back->uvs, m->uvs, sizeof(float) * 8) == 0);
    CHECK_EQ_INT(back->materials[0].extra_count, 1);
    int rc = validate_against_quad(out, &doc, json, dir);
    CHECK_MSG(rc == 0, "validator exit %d for %s", rc, out);
    texopt_model_destroy(back);
    texopt_model_destroy(m);

    /* A clearcoat map on TEXCOORD_1 is not laid out, so its transform stays. */
    char *json1 = strdup(doc.json);
    CHECK(builder_replace(&json1, "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]",
                          "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},"
                          "\"extensions\":{\"KHR_materials_clearcoat\":{\"clearcoatTexture\":{\"index\":0,"
                          "\"texCoord\":1,\"extensions\":{\"KHR_texture_transform\":{\"texCoord\":1,"
                          "\"offset\":[0.5,0.5]}}}}}}]"));
    free(json);
    json = json1;
    m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_EQ_INT(m->materials[0].extra_count, 0);
    back = save_and_reload(m, dir, "out1.glb", out, sizeof out, err, sizeof err);
    CHECK_MSG(back != NULL, "%s", err);
    CHECK_EQ_INT(file_contains(out, "KHR_texture_transform"), 1);
    CHECK_EQ_INT(file_contains(out, "\"offset\":[0.5,0.5]"), 1);
    texopt_model_destroy(back);
    texopt_model_destroy(m);
    builder_rmdir(dir);
    free(json);
    quad_doc_free(&doc);
}

/* The texture index of textureInfo `key` (any depth) in the GLB's JSON at path; -1 if none. */
static int glb_texture_index(const char *path, const char *key)
{
    FILE *f = fopen(path, "rb");
    unsigned char head[20];
    int index = -1;
    if (f && fread(head, 1, 20, f) == 20) {
        size_t n = (size_t)head[12] | (size_t)head[13] << 8 | (size_t)head[14] << 16 | (size_t)head[15] << 24;
        char *json = calloc(1, n + 1);
        if (json && fread(json, 1, n, f) == n) {
            char pattern[96];
            snprintf(pattern, sizeof pattern, "\"%s\":{\"index\":", key);
            const char *at = strstr(json, pattern);
            if (at)
                index = atoi(at + strlen(pattern));
        }
        free(json);
    }
    if (f)
        fclose(f);
    return index;
}

/* Saves m with its UVs and image 0 replaced by the builder's 2 x 2 texture (its other images
 * kept) to out, and loads the file back; NULL, with err filled, when either fails. */
static texopt_model *save_rebaked_and_reload(const texopt_model *m, const char *out, char *err, size_t err_len)
{
    texopt_image rebaked;
    const texopt_image **images = calloc((size_t)m->image_count, sizeof *images);
    texopt_model *back = NULL;
    if (images && builder_texture(&rebaked, 2, 2)) {
        images[0] = &rebaked;
        texopt_model_edit edit = {m->uvs, images, 0};
        if (texopt_model_save_glb(m, &edit, out, err, err_len) != TEXOPT_OK ||
            texopt_model_load(&back, out, NULL, err, err_len) != TEXOPT_OK) {
            texopt_model_destroy(back);
            back = NULL;
        }
        texopt_image_destroy(&rebaked);
    }
    free(images);
    return back;
}

/* An image read by base colour through TEXCOORD_0 and by occlusion and a clearcoat texture
 * through TEXCOORD_1: replaced for the new TEXCOORD_0 layout, the bindings through TEXCOORD_1
 * (which keep the old UVs) read an untouched copy of the original instead, also when the
 * texture names its image only through EXT_texture_webp. */
TEST(bindings_through_another_set_keep_reading_the_original_image)
{
    char err[512] = "", dir[64], out[128];
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    CHECK(builder_tempdir(dir));
    snprintf(out, sizeof out, "%s/out.glb", dir);
    for (int webp_only = 0; webp_only < 2; webp_only++) {
        char *json = strdup(doc.json);
        CHECK(json && builder_replace(&json, "\"TEXCOORD_0\":1}", "\"TEXCOORD_0\":1,\"TEXCOORD_1\":1}"));
        CHECK(builder_replace(&json, "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]",
                              "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},"
                              "\"occlusionTexture\":{\"index\":0,\"texCoord\":1},"
                              "\"extensions\":{\"KHR_materials_clearcoat\":{\"clearcoatFactor\":1,"
                              "\"clearcoatTexture\":{\"index\":0,\"texCoord\":1}}}}]"));
        CHECK(builder_replace(&json, "\"asset\":{\"version\":\"2.0\"},",
                              webp_only ? "\"asset\":{\"version\":\"2.0\"},"
                                          "\"extensionsUsed\":[\"KHR_materials_clearcoat\",\"EXT_texture_webp\"],"
                                          "\"extensionsRequired\":[\"EXT_texture_webp\"],"
                                        : "\"asset\":{\"version\":\"2.0\"},"
                                          "\"extensionsUsed\":[\"KHR_materials_clearcoat\"],"));
        if (webp_only)
            CHECK(builder_replace(&json, "\"textures\":[{\"source\":0,\"sampler\":0}]",
                                  "\"textures\":[{\"sampler\":0,"
                                  "\"extensions\":{\"EXT_texture_webp\":{\"source\":0}}}]"));
        texopt_status st;
        texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
        CHECK_OK(st, err);
        texopt_model *back = save_rebaked_and_reload(m, out, err, sizeof err);
        CHECK_MSG(back != NULL, "%s", err);
        const texopt_material *mat = &back->materials[0];
        int colour = mat->slot[TEXOPT_SLOT_BASE_COLOR].image, occlusion = mat->slot[TEXOPT_SLOT_OCCLUSION].image;
        CHECK_EQ_INT(back->image_count, 2);
        CHECK(colour >= 0 && occlusion >= 0 && colour != occlusion);
        CHECK(image_matches_builder(&back->images[colour], 2, 2));
        CHECK_MSG(image_matches_builder(&back->images[occlusion], 4, 4), "webp_only %d", webp_only);
        int occlusion_texture = glb_texture_index(out, "occlusionTexture");
        CHECK(occlusion_texture > 0 && glb_texture_index(out, "clearcoatTexture") == occlusion_texture);
        CHECK_EQ_INT(glb_texture_index(out, "baseColorTexture"), 0);
        if (!webp_only) {
            /* The WebP-only case's image is PNG bytes, which the validator refuses under
             * EXT_texture_webp (TEXTURE_INVALID_IMAGE_MIME_TYPE), in the input as in the output. */
            int rc = validate_against_quad(out, &doc, json, dir);
            CHECK_MSG(rc == 0, "validator exit %d for %s", rc, out);
        }
        texopt_model_destroy(back);
        texopt_model_destroy(m);
        free(json);
    }
    builder_rmdir(dir);
    quad_doc_free(&doc);
}

/* A 8 x 8 RGB image of values 16-bit PNG holds and 8-bit PNG does not. */
static int fine_gradient(texopt_image *img, int offset)
{
    if (texopt_image_create(img, 8, 8, 3, NULL, 0) != TEXOPT_OK)
        return 0;
    for (int i = 0; i < 8 * 8 * 3; i++)
        img->pixels[i] = (float)(20000 + offset + 37 * i) / 65535.0f;
    return 1;
}

/* A texture stored at 16 bits per channel (a normal map exported at 16 bits) keeps that depth
 * when it is replaced: the replacement's fine values come back to the 16-bit step. */
TEST(a_16_bit_texture_is_replaced_at_16_bits)
{
    char err[512] = "", dir[64], out[128];
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    texopt_image original, rebaked;
    CHECK(fine_gradient(&original, 0) && fine_gradient(&rebaked, 11));
    unsigned char *png = NULL;
    size_t png_len = 0;
    CHECK_OK(texopt_image_encode_png_bits(&original, 16, &png, &png_len, err, sizeof err), err);
    char from[96], to[96];
    snprintf(from, sizeof from, "\"byteOffset\":92,\"byteLength\":%zu}", doc.png_len);
    snprintf(to, sizeof to, "\"byteOffset\":92,\"byteLength\":%zu}", png_len);
    char *json = strdup(doc.json);
    CHECK(json && builder_replace(&json, from, to));
    size_t bin_len = (QUAD_PNG_OFFSET + png_len + 3) / 4 * 4;
    snprintf(from, sizeof from, "\"buffers\":[{\"byteLength\":%zu}]", doc.bin_len);
    snprintf(to, sizeof to, "\"buffers\":[{\"byteLength\":%zu}]", bin_len);
    CHECK(builder_replace(&json, from, to));
    unsigned char *bin = calloc(1, bin_len);
    CHECK(bin != NULL);
    memcpy(bin, doc.bin, QUAD_PNG_OFFSET);
    memcpy(bin + QUAD_PNG_OFFSET, png, png_len);
    free(doc.bin);
    doc.bin = bin;
    doc.bin_len = bin_len;
    doc.png_len = png_len;
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_OK(st, err);
    CHECK_MSG(max_difference(&m->images[0], &original) < 0.5 / 65535, "decoded off by %g",
              max_difference(&m->images[0], &original));
    const texopt_image *images[1] = {&rebaked};
    texopt_model_edit edit = {m->uvs, images, 0};
    CHECK(builder_tempdir(dir));
    snprintf(out, sizeof out, "%s/out.glb", dir);
    CHECK_OK(texopt_model_save_glb(m, &edit, out, err, sizeof err), err);
    texopt_model *back = NULL;
    CHECK_OK(texopt_model_load(&back, out, NULL, err, sizeof err), err);
    double off = max_difference(&back->images[0], &rebaked);
    CHECK_MSG(off < 0.5 / 65535, "saved off by %g (8 bits: up to %g)", off, 0.5 / 255);
    texopt_model_destroy(back);
    texopt_model_destroy(m);
    texopt_image_destroy(&original);
    texopt_image_destroy(&rebaked);
    free(png);
    builder_rmdir(dir);
    free(json);
    quad_doc_free(&doc);
}

/* KHR_materials_variants mappings are read: a variant material joins the primitive's
 * domain; one naming no material is malformed, and one whose texture transform differs from
 * the primitive material's is refused (one layout cannot serve both), as is an untextured one
 * setting an anisotropy direction in the tangent frame the new UVs turn. */
TEST(material_variants_join_the_domain_or_are_refused_with_a_reason)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    const char *cases[4][2] = {
        {"{\"material\":1,\"variants\":[0]}", ""},
        {"{\"material\":7,\"variants\":[0]}", "names no material"},
        {"{\"material\":2,\"variants\":[0]}", "another KHR_texture_transform"},
        {"{\"material\":3,\"variants\":[0]}", "variant material 3's KHR_materials_anisotropy"},
    };
    for (int c = 0; c < 4; c++) {
        char *json = strdup(doc.json), primitive[256];
        snprintf(primitive, sizeof primitive,
                 "\"material\":0,\"mode\":4,\"extensions\":{\"KHR_materials_variants\":{\"mappings\":[%s]}}",
                 cases[c][0]);
        CHECK(json && builder_replace(&json, "\"material\":0,\"mode\":4", primitive));
        CHECK(builder_replace(&json, "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]",
                              "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}},"
                              "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":1}}},"
                              "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":1,\"extensions\":"
                              "{\"KHR_texture_transform\":{\"scale\":[0.5,0.5]}}}}},"
                              "{\"extensions\":{\"KHR_materials_anisotropy\":"
                              "{\"anisotropyStrength\":0.6,\"anisotropyRotation\":1}}}],"
                              "\"extensionsUsed\":[\"KHR_materials_variants\",\"KHR_texture_transform\","
                              "\"KHR_materials_anisotropy\"]"));
        CHECK(builder_replace(&json, "\"textures\":[{\"source\":0,\"sampler\":0}]",
                              "\"textures\":[{\"source\":0,\"sampler\":0},{\"source\":1}]"));
        CHECK(builder_replace(&json, "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"}]",
                              "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"},"
                              "{\"bufferView\":3,\"mimeType\":\"image/png\"}]"));
        texopt_status st;
        texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
        if (!*cases[c][1]) {
            CHECK_OK(st, err);
            CHECK(m->primitives[0].variant_count == 1 && m->variant_materials[m->primitives[0].first_variant] == 1);
            CHECK(m->domain_count == 1 && m->domains[0].image_count == 2);
        } else
            CHECK_MSG(st != TEXOPT_OK && strstr(err, cases[c][1]), "case %d: status %d, %s", c, (int)st, err);
        texopt_model_destroy(m);
        free(json);
    }
    quad_doc_free(&doc);
}

/* A morph target that moves TEXCOORD_0 holds offsets for the input layout only: refused. One
 * that moves positions only is read as before. */
TEST(a_morph_target_moving_texcoord0_is_refused)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    const char *targets[2] = {"{\"POSITION\":0}", "{\"POSITION\":0,\"TEXCOORD_0\":1}"};
    for (int c = 0; c < 2; c++) {
        char *json = strdup(doc.json), primitive[160];
        snprintf(primitive, sizeof primitive, "\"material\":0,\"mode\":4,\"targets\":[%s]", targets[c]);
        CHECK(json && builder_replace(&json, "\"material\":0,\"mode\":4", primitive));
        texopt_status st;
        texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
        if (c == 0)
            CHECK_OK(st, err);
        else
            CHECK_MSG(st == TEXOPT_E_UNSUPPORTED && strstr(err, "morph target 0 moves TEXCOORD_0"), "%d: %s", (int)st,
                      err);
        texopt_model_destroy(m);
        free(json);
    }
    quad_doc_free(&doc);
}

/* A texture's alternate source (EXT_texture_webp: what viewers knowing it read instead of
 * `source`) would show the old texels through the new UVs: once the texture's image is
 * replaced, the texture reads the replacement only, with the fallback present or not. */
TEST(a_replaced_texture_drops_its_alternate_source)
{
    char err[512] = "", dir[64], out[128];
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    CHECK(builder_tempdir(dir));
    snprintf(out, sizeof out, "%s/out.glb", dir);
    const char *textures[2] = {
        "\"textures\":[{\"source\":0,\"sampler\":0,\"extensions\":{\"EXT_texture_webp\":{\"source\":1}}}],"
        "\"extensionsUsed\":[\"EXT_texture_webp\"]",
        "\"textures\":[{\"sampler\":0,\"extensions\":{\"EXT_texture_webp\":{\"source\":0}}}],"
        "\"extensionsUsed\":[\"EXT_texture_webp\"],\"extensionsRequired\":[\"EXT_texture_webp\"]"};
    for (int c = 0; c < 2; c++) {
        char *json = strdup(doc.json);
        CHECK(json && builder_replace(&json, "\"textures\":[{\"source\":0,\"sampler\":0}]", textures[c]));
        CHECK(builder_replace(&json, "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"}]",
                              "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"},"
                              "{\"bufferView\":3,\"mimeType\":\"image/png\"}]"));
        texopt_status st;
        texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
        CHECK_OK(st, err);
        texopt_model *back = save_rebaked_and_reload(m, out, err, sizeof err);
        CHECK_MSG(back != NULL, "%s", err);
        CHECK_MSG(file_contains(out, "EXT_texture_webp") == 0, "case %d keeps the extension", c);
        CHECK(image_matches_builder(&back->images[back->materials[0].slot[TEXOPT_SLOT_BASE_COLOR].image], 2, 2));
        texopt_model_destroy(back);
        texopt_model_destroy(m);
        free(json);
    }
    builder_rmdir(dir);
    quad_doc_free(&doc);
}

/* A texture with a PNG source and a KTX2 alternate (bytes OpenImageIO cannot decode): the
 * alternate is not decoded, so the model loads; once the texture is replaced, nothing reads
 * the KTX2 image and it leaves the file, unless an extension texopt does not know might name
 * it. An image no texture named in the input stays. A texture with the KTX2 image alone is
 * refused, saying so. */
TEST(an_undecodable_alternate_loads_and_leaves_with_its_texture)
{
    char err[512] = "", dir[64], out[128];
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    CHECK(builder_tempdir(dir));
    snprintf(out, sizeof out, "%s/out.glb", dir);
    const char *ktx2 = "{\"uri\":\"data:application/octet-stream;base64,q0tUWCAyMLsNChoKAAAAAAAAAAAAAAAAAAAAAAAAAAA=\","
                       "\"mimeType\":\"image/ktx2\"}";
    for (int unknown = 0; unknown < 2; unknown++) {
        char *json = strdup(doc.json), images[512], used[160];
        snprintf(images, sizeof images, "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"},%s,%s]", ktx2, ktx2);
        snprintf(used, sizeof used, "\"extensionsUsed\":[\"KHR_texture_basisu\"%s]",
                 unknown ? ",\"EXT_lights_image_based\"" : "");
        CHECK(json && builder_replace(&json, "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"}]", images));
        char textures[256];
        snprintf(
            textures, sizeof textures,
            "\"textures\":[{\"source\":0,\"sampler\":0,\"extensions\":{\"KHR_texture_basisu\":{\"source\":1}}}],%s",
            used);
        CHECK(builder_replace(&json, "\"textures\":[{\"source\":0,\"sampler\":0}]", textures));
        texopt_status st;
        texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
        CHECK_OK(st, err);
        CHECK(m->image_count == 3 && m->images[1].pixels == NULL && m->images[1].width == 0);
        texopt_model *back = save_rebaked_and_reload(m, out, err, sizeof err);
        CHECK_MSG(back != NULL, "%s", err);
        CHECK_EQ_INT(back->image_count, unknown ? 3 : 2); /* the orphan (image 2) stays either way */
        CHECK(image_matches_builder(&back->images[back->materials[0].slot[TEXOPT_SLOT_BASE_COLOR].image], 2, 2));
        CHECK(file_contains(out, "KHR_texture_basisu") == 0);
        texopt_model_destroy(back);
        texopt_model_destroy(m);
        free(json);
    }
    char *json = strdup(doc.json), images[256];
    snprintf(images, sizeof images, "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"},%s]", ktx2);
    CHECK(json && builder_replace(&json, "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"}]", images));
    CHECK(
        builder_replace(&json, "\"textures\":[{\"source\":0,\"sampler\":0}]",
                        "\"textures\":[{\"sampler\":0,\"extensions\":{\"KHR_texture_basisu\":{\"source\":1}}}],"
                        "\"extensionsUsed\":[\"KHR_texture_basisu\"],\"extensionsRequired\":[\"KHR_texture_basisu\"]"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_MSG(m == NULL && st == TEXOPT_E_UNSUPPORTED && strstr(err, "image 1 (image 1) is KTX2"), "%d: %s", (int)st,
              err);
    free(json);
    builder_rmdir(dir);
    quad_doc_free(&doc);
}

/* KHR_animation_pointer animations (here a scrolling texture transform) would be lost on
 * saving (tinygltf drops channels without a node): refused, naming the extension. */
TEST(animation_pointer_models_are_refused)
{
    char err[512] = "";
    quad_doc doc;
    CHECK(quad_doc_init(&doc, 4, 4));
    char *json = strdup(doc.json);
    CHECK(json &&
          builder_replace(&json, "\"asset\":{\"version\":\"2.0\"},",
                          "\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_animation_pointer\","
                          "\"KHR_texture_transform\"],\"animations\":[{\"samplers\":[{\"input\":2,\"output\":1}],"
                          "\"channels\":[{\"sampler\":0,\"target\":{\"path\":\"pointer\",\"extensions\":"
                          "{\"KHR_animation_pointer\":{\"pointer\":\"/materials/0/pbrMetallicRoughness/"
                          "baseColorTexture/extensions/KHR_texture_transform/offset\"}}}}]}],"));
    texopt_status st;
    texopt_model *m = load_quad_json(&doc, json, err, sizeof err, &st);
    CHECK_MSG(st == TEXOPT_E_UNSUPPORTED && strstr(err, "KHR_animation_pointer is not supported"), "%d: %s", (int)st,
              err);
    texopt_model_destroy(m);
    free(json);
    quad_doc_free(&doc);
}

/* gltf_builder.h - tiny glTF files generated in code for the io tests (header only, used by
 * test_gltf_io.c and test_hostile_input.c).
 *
 * The base document is a textured quad: 4 vertices, 2 triangles (u16 indices), one material
 * whose base colour texture is a small PNG in a buffer view, a node with a translation.
 * Hostile variants are made by replacing one JSON fragment (builder_replace) or patching
 * the binary data, so each test states exactly what it breaks. */
#ifndef TEXOPT_TEST_GLTF_BUILDER_H
#define TEXOPT_TEST_GLTF_BUILDER_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image_io.h"

/* Layout of the quad's binary buffer. */
enum {
    QUAD_POS_OFFSET = 0,  /* 4 x VEC3 float */
    QUAD_UV_OFFSET = 48,  /* 4 x VEC2 float */
    QUAD_IDX_OFFSET = 80, /* 6 x u16 */
    QUAD_PNG_OFFSET = 92  /* the PNG bytes */
};

static const float quad_positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static const float quad_uvs[8] = {0.1f, 0.9f, 0.9f, 0.9f, 0.9f, 0.1f, 0.1f, 0.1f};
static const uint16_t quad_indices[6] = {0, 1, 2, 0, 2, 3};

typedef struct quad_doc {
    char *json;
    unsigned char *bin;
    size_t bin_len;
    size_t png_len;
} quad_doc;

/* Replaces the first occurrence of `from` in *s by `to`; returns 0 when `from` is absent. */
static inline int builder_replace(char **s, const char *from, const char *to)
{
    char *at = strstr(*s, from);
    if (!at)
        return 0;
    size_t head = (size_t)(at - *s), flen = strlen(from), tlen = strlen(to), rest = strlen(at + flen);
    char *out = malloc(head + tlen + rest + 1);
    memcpy(out, *s, head);
    memcpy(out + head, to, tlen);
    memcpy(out + head + tlen, at + flen, rest + 1);
    free(*s);
    *s = out;
    return 1;
}

/* A w x h RGB texture where every texel differs. */
static inline int builder_texture(texopt_image *img, int w, int h)
{
    if (texopt_image_create(img, w, h, 3, NULL, 0) != TEXOPT_OK)
        return 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            float *p = texopt_image_at(img, x, y);
            p[0] = (float)((x * 37) % 256) / 255.0f;
            p[1] = (float)((y * 53) % 256) / 255.0f;
            p[2] = (float)((x * 11 + y * 7) % 256) / 255.0f;
        }
    return 1;
}

/* Fills doc with the textured quad (texture tex_w x tex_h). Returns 0 on failure. */
static inline int quad_doc_init(quad_doc *doc, int tex_w, int tex_h)
{
    memset(doc, 0, sizeof *doc);
    texopt_image tex;
    if (!builder_texture(&tex, tex_w, tex_h))
        return 0;
    unsigned char *png = NULL;
    size_t png_len = 0;
    texopt_status st = texopt_image_encode_png(&tex, &png, &png_len, NULL, 0);
    texopt_image_destroy(&tex);
    if (st != TEXOPT_OK)
        return 0;
    doc->png_len = png_len;
    doc->bin_len = (QUAD_PNG_OFFSET + png_len + 3) / 4 * 4;
    doc->bin = calloc(1, doc->bin_len);
    memcpy(doc->bin + QUAD_POS_OFFSET, quad_positions, sizeof quad_positions);
    memcpy(doc->bin + QUAD_UV_OFFSET, quad_uvs, sizeof quad_uvs);
    memcpy(doc->bin + QUAD_IDX_OFFSET, quad_indices, sizeof quad_indices);
    memcpy(doc->bin + QUAD_PNG_OFFSET, png, png_len);
    free(png);
    char json[4096];
    snprintf(json, sizeof json,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0,\"translation\":[1,2,3]}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},"
             "\"indices\":2,\"material\":0,\"mode\":4}]}],"
             "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}],"
             "\"textures\":[{\"source\":0,\"sampler\":0}],"
             "\"samplers\":[{\"wrapS\":33071,\"wrapT\":33648}],"
             "\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"}],"
             "\"accessors\":["
             "{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
             "{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
             "\"bufferViews\":["
             "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48,\"target\":34962},"
             "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":32,\"target\":34962},"
             "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":12,\"target\":34963},"
             "{\"buffer\":0,\"byteOffset\":92,\"byteLength\":%zu}],"
             "\"buffers\":[{\"byteLength\":%zu}]}",
             png_len, doc->bin_len);
    doc->json = strdup(json);
    return 1;
}

static inline void quad_doc_free(quad_doc *doc)
{
    free(doc->json);
    free(doc->bin);
    memset(doc, 0, sizeof *doc);
}

/* Appends bytes to the binary buffer (4-aligned) as a new buffer view; returns its index
 * (4 for the first one added), or -1 on failure. */
static inline int quad_doc_add_view(quad_doc *doc, const void *bytes, size_t len)
{
    size_t at = doc->bin_len, new_len = (at + len + 3) / 4 * 4;
    unsigned char *bin = realloc(doc->bin, new_len);
    if (!bin)
        return -1;
    memset(bin + at, 0, new_len - at);
    memcpy(bin + at, bytes, len);
    doc->bin = bin;
    char old_tail[64], new_tail[160];
    snprintf(old_tail, sizeof old_tail, "],\"buffers\":[{\"byteLength\":%zu}]}", doc->bin_len);
    snprintf(new_tail, sizeof new_tail,
             ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],\"buffers\":[{\"byteLength\":%zu}]}", at, len,
             new_len);
    if (!builder_replace(&doc->json, old_tail, new_tail))
        return -1;
    doc->bin_len = new_len;
    int views = 0;
    for (const char *p = strstr(doc->json, "\"bufferViews\""); p && (p = strstr(p, "\"buffer\":")); p++)
        views++;
    return views - 1;
}

/* Whether needle occurs in hay (memmem is not C11). */
static inline int builder_contains(const unsigned char *hay, size_t n, const void *needle, size_t m)
{
    for (size_t i = 0; m <= n && i + m <= n; i++)
        if (memcmp(hay + i, needle, m) == 0)
            return 1;
    return 0;
}

static inline void put_u32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16);
    p[3] = (unsigned char)(v >> 24);
}

/* A GLB container around json and bin (bin may be NULL); malloc'ed, length in *len. */
static inline unsigned char *builder_glb(const char *json, const unsigned char *bin, size_t bin_len, size_t *len)
{
    size_t jlen = strlen(json), jpad = (jlen + 3) / 4 * 4, bpad = (bin_len + 3) / 4 * 4;
    size_t total = 12 + 8 + jpad + (bin ? 8 + bpad : 0);
    unsigned char *out = calloc(1, total);
    memcpy(out, "glTF", 4);
    put_u32(out + 4, 2);
    put_u32(out + 8, (uint32_t)total);
    put_u32(out + 12, (uint32_t)jpad);
    memcpy(out + 16, "JSON", 4);
    memcpy(out + 20, json, jlen);
    memset(out + 20 + jlen, ' ', jpad - jlen);
    if (bin) {
        unsigned char *b = out + 20 + jpad;
        put_u32(b, (uint32_t)bpad);
        memcpy(b + 4, "BIN\0", 4);
        memcpy(b + 8, bin, bin_len);
    }
    *len = total;
    return out;
}

static inline int builder_write(const char *path, const void *bytes, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return 0;
    int ok = fwrite(bytes, 1, len, f) == len;
    return fclose(f) == 0 && ok;
}

static inline char *builder_base64(const unsigned char *b, size_t n)
{
    static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *out = malloc((n + 2) / 3 * 4 + 1), *o = out;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)b[i] << 16 | (i + 1 < n ? (uint32_t)b[i + 1] << 8 : 0) | (i + 2 < n ? b[i + 2] : 0);
        *o++ = t[v >> 18 & 63];
        *o++ = t[v >> 12 & 63];
        *o++ = i + 1 < n ? t[v >> 6 & 63] : '=';
        *o++ = i + 2 < n ? t[v & 63] : '=';
    }
    *o = '\0';
    return out;
}

/* A fresh temporary directory (mkdtemp) in dir[64]; returns 0 on failure. */
static inline int builder_tempdir(char dir[64])
{
    snprintf(dir, 64, "/tmp/texopt_io_test_XXXXXX");
    return mkdtemp(dir) != NULL;
}

/* Removes a flat temporary directory made by builder_tempdir. */
static inline void builder_rmdir(const char *dir)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
}

#endif

/* grid_glb.h - a textured n x n grid (or any small mesh) written as a small .glb, for the
 * pipeline tests (header only; test_pipeline.c and test_pipeline_models_slow.c). The grid lies over
 * [0,1]^2 with UV = (x, y), u32 indices, one material whose base colour is a tex x tex PNG
 * of one of the fixtures' patterns (tests/support/fixtures.h), default sampler (REPEAT);
 * optionally a second image of a pattern as the metallic-roughness image. */
#ifndef TEXOPT_TEST_GRID_GLB_H
#define TEXOPT_TEST_GRID_GLB_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "image_io.h"

static inline void grid_put32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(v >> (8 * i));
}

/* The island whose cell is `cell` in fragmented_grid_fill's shuffle k -> (k * 37 + 11) mod
 * g^2 (37 is odd and prime to 3, so the shuffle is a bijection when g is a power of 2). */
static inline int fragment_island_of_cell(int g, int cell)
{
    for (int k = 0; k < g * g; k++)
        if ((k * 37 + 11) % (g * g) == cell)
            return k;
    return 0;
}

/* Paints a fragmented atlas (fragmented_grid_fill with n, block, side) the way a texture
 * projected onto the surface looks in it: each texel shows `base` (a fixtures.h pattern over
 * the grid's [0,1]^2) at the surface point its nearest island maps it to, so the surface
 * looks continuous across the islands' seams. 0 on success. */
static inline int fragment_fill(texopt_image *img, int n, int block, double side, const char *base)
{
    texopt_image src;
    int tex = img->width, g = n / block;
    if (texopt_image_create(&src, tex, tex, img->channels, NULL, 0) != TEXOPT_OK)
        return -1;
    if (fixture_fill_pattern(&src, base) != 0 || g < 1) {
        texopt_image_destroy(&src);
        return -1;
    }
    double size = side / g, spacing = g > 1 ? (1.0 - size) / (g - 1) : 0;
    for (int y = 0; y < tex; y++)
        for (int x = 0; x < tex; x++) {
            double u = (x + 0.5) / tex, v = (y + 0.5) / tex;
            int cx = g > 1 ? (int)lround((u - size / 2) / spacing) : 0,
                cy = g > 1 ? (int)lround((v - size / 2) / spacing) : 0;
            cx = cx < 0 ? 0 : cx >= g ? g - 1 : cx;
            cy = cy < 0 ? 0 : cy >= g ? g - 1 : cy;
            int k = fragment_island_of_cell(g, cy * g + cx);
            double gx = ((k % g) * block + (u - cx * spacing) / size * block) / n;
            double gy = ((k / g) * block + (v - cy * spacing) / size * block) / n;
            int sx = (int)floor(gx * tex), sy = (int)floor(gy * tex);
            sx = sx < 0 ? 0 : sx >= tex ? tex - 1 : sx;
            sy = sy < 0 ? 0 : sy >= tex ? tex - 1 : sy;
            memcpy(texopt_image_at(img, x, y), texopt_image_at(&src, sx, sy), (size_t)img->channels * sizeof(float));
        }
    texopt_image_destroy(&src);
    return 0;
}

/* A tex x tex image of `pattern` as PNG into *png (the caller frees it); 0 on success.
 * "COLOUR|ALPHA" names two patterns: RGB of the first, alpha the second's luma (RGBA).
 * "fragments:N:BLOCK:SIDE:BASE" paints BASE into a fragmented atlas (fragment_fill). */
static inline int grid_pattern_png(int tex, const char *pattern, unsigned char **png, size_t *png_len)
{
    int fn, fblock;
    double fside;
    char fbase[32];
    if (sscanf(pattern, "fragments:%d:%d:%lf:%31s", &fn, &fblock, &fside, fbase) == 4) {
        texopt_image img;
        if (texopt_image_create(&img, tex, tex, 3, NULL, 0) != TEXOPT_OK)
            return -1;
        int r = fragment_fill(&img, fn, fblock, fside, fbase);
        if (r == 0 && texopt_image_encode_png(&img, png, png_len, NULL, 0) != TEXOPT_OK)
            r = -1;
        texopt_image_destroy(&img);
        return r;
    }
    char colour[32];
    const char *bar = strchr(pattern, '|');
    snprintf(colour, sizeof colour, "%.*s", bar ? (int)(bar - pattern) : (int)strlen(pattern), pattern);
    texopt_image img;
    if (texopt_image_create(&img, tex, tex, 3, NULL, 0) != TEXOPT_OK || fixture_fill_pattern(&img, colour) != 0 ||
        (bar && fixture_add_alpha(&img, bar + 1) != 0)) {
        texopt_image_destroy(&img);
        return -1;
    }
    texopt_status st = texopt_image_encode_png(&img, png, png_len, NULL, 0);
    texopt_image_destroy(&img);
    return st == TEXOPT_OK ? 0 : -1;
}

/* Writes a mesh (positions 3 floats and UVs 2 floats per vertex, u32 triangles) as a .glb at
 * path with image_count tex x tex images of patterns[i], texture i showing image i, and the
 * materials `materials` (their JSON objects, comma-separated, which bind the textures): the
 * first `split` triangles are a primitive of material 0, the others (when split < nt) a second
 * primitive, on the same vertices, of material 1. Returns 0 on success. */
static inline int write_mesh_glb_primitives(const char *path, const float *positions, const float *uvs, size_t nv,
                                            const uint32_t *triangles, size_t nt, size_t split, int tex,
                                            const char *const *patterns, int image_count, const char *materials)
{
    enum { MAX_IMAGES = 6 };
    unsigned char *png[MAX_IMAGES] = {NULL};
    size_t png_len[MAX_IMAGES] = {0}, png_at[MAX_IMAGES];
    int ok = image_count >= 1 && image_count <= MAX_IMAGES;
    for (int i = 0; ok && i < image_count; i++)
        ok = grid_pattern_png(tex, patterns[i], &png[i], &png_len[i]) == 0;
    size_t pos_len = nv * 12, uv_len = nv * 8, idx_len = nt * 12, bin_len = pos_len + uv_len + idx_len;
    for (int i = 0; ok && i < image_count; i++) {
        png_at[i] = (bin_len + 3) / 4 * 4;
        bin_len = png_at[i] + png_len[i];
    }
    bin_len = (bin_len + 3) / 4 * 4;
    unsigned char *bin = ok ? calloc(1, bin_len) : NULL;
    char json[8192], textures[256] = "", images[512] = "", views[1024] = "", second[256] = "", second_indices[160] = "";
    if (split < nt) {
        snprintf(second, sizeof second,
                 ",{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":3,\"material\":1}");
        snprintf(second_indices, sizeof second_indices,
                 ",{\"bufferView\":2,\"byteOffset\":%zu,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}",
                 split * 12, (nt - split) * 3);
    }
    int jl = -1;
    if (bin) {
        memcpy(bin, positions, pos_len);
        memcpy(bin + pos_len, uvs, uv_len);
        memcpy(bin + pos_len + uv_len, triangles, idx_len);
        for (int i = 0; i < image_count; i++) {
            memcpy(bin + png_at[i], png[i], png_len[i]);
            size_t at = strlen(textures), ai = strlen(images), av = strlen(views);
            snprintf(textures + at, sizeof textures - at, "%s{\"source\":%d}", i ? "," : "", i);
            snprintf(images + ai, sizeof images - ai, "%s{\"bufferView\":%d,\"mimeType\":\"image/png\"}", i ? "," : "",
                     3 + i);
            snprintf(views + av, sizeof views - av, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}", png_at[i],
                     png_len[i]);
        }
        float lo[3] = {positions[0], positions[1], positions[2]}, hi[3] = {positions[0], positions[1], positions[2]};
        for (size_t v = 0; v < nv; v++)
            for (int k = 0; k < 3; k++) {
                lo[k] = positions[3 * v + k] < lo[k] ? positions[3 * v + k] : lo[k];
                hi[k] = positions[3 * v + k] > hi[k] ? positions[3 * v + k] : hi[k];
            }
        jl = snprintf(
            json, sizeof json,
            "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
            "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2,\"material\":"
            "0}%s]}],"
            "\"materials\":[%s],\"textures\":[%s],\"images\":[%s],"
            "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":[%.9g,%."
            "9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},"
            "{\"bufferView\":1,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC2\"},"
            "{\"bufferView\":2,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}%s],"
            "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,"
            "\"byteLength\":%zu},"
            "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}%s],"
            "\"buffers\":[{\"byteLength\":%zu}]}",
            second, materials, textures, images, nv, (double)lo[0], (double)lo[1], (double)lo[2], (double)hi[0],
            (double)hi[1], (double)hi[2], nv, split * 3, second_indices, pos_len, pos_len, uv_len, pos_len + uv_len,
            idx_len, views, bin_len);
    }
    for (int i = 0; i < MAX_IMAGES; i++)
        free(png[i]);
    if (jl < 0 || (size_t)jl >= sizeof json) {
        free(bin);
        return -1;
    }
    size_t jpad = ((size_t)jl + 3) / 4 * 4, total = 12 + 8 + jpad + 8 + bin_len;
    unsigned char *glb = calloc(1, total);
    memcpy(glb, "glTF", 4);
    grid_put32(glb + 4, 2);
    grid_put32(glb + 8, (uint32_t)total);
    grid_put32(glb + 12, (uint32_t)jpad);
    memcpy(glb + 16, "JSON", 4);
    memcpy(glb + 20, json, (size_t)jl);
    memset(glb + 20 + jl, ' ', jpad - (size_t)jl);
    grid_put32(glb + 20 + jpad, (uint32_t)bin_len);
    memcpy(glb + 24 + jpad, "BIN\0", 4);
    memcpy(glb + 28 + jpad, bin, bin_len);
    free(bin);
    FILE *f = fopen(path, "wb");
    int written = f && fwrite(glb, 1, total, f) == total;
    if (f && fclose(f) != 0)
        written = 0;
    free(glb);
    return written ? 0 : -1;
}

/* The mesh as one primitive of one material (write_mesh_glb_primitives). */
static inline int write_mesh_glb_material(const char *path, const float *positions, const float *uvs, size_t nv,
                                          const uint32_t *triangles, size_t nt, int tex, const char *const *patterns,
                                          int image_count, const char *material)
{
    return write_mesh_glb_primitives(path, positions, uvs, nv, triangles, nt, nt, tex, patterns, image_count, material);
}

/* The same with a base-colour texture of `pattern` and, with mr_pattern (NULL: none), image 1
 * a metallicRoughness texture of that pattern (the same pattern: the same pixels as base
 * colour); base_ext (may be "") goes into the base colour's textureInfo after its index, e.g.
 * ",\"extensions\":{...}". */
static inline int write_mesh_glb_ext(const char *path, const float *positions, const float *uvs, size_t nv,
                                     const uint32_t *triangles, size_t nt, int tex, const char *pattern,
                                     const char *mr_pattern, const char *base_ext)
{
    char material[512];
    snprintf(material, sizeof material, "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0%s}%s}}", base_ext,
             mr_pattern ? ",\"metallicRoughnessTexture\":{\"index\":1}" : "");
    const char *patterns[2] = {pattern, mr_pattern};
    return write_mesh_glb_material(path, positions, uvs, nv, triangles, nt, tex, patterns, mr_pattern ? 2 : 1,
                                   material);
}

static inline int write_mesh_glb(const char *path, const float *positions, const float *uvs, size_t nv,
                                 const uint32_t *triangles, size_t nt, int tex, const char *pattern,
                                 const char *mr_pattern)
{
    return write_mesh_glb_ext(path, positions, uvs, nv, triangles, nt, tex, pattern, mr_pattern, "");
}

/* Replaces the first `from` in the JSON chunk of the .glb at path by `to` (blank-padded to
 * four bytes). Returns 0 on success, -1 when `from` is absent or the file cannot be rewritten. */
static inline int glb_replace_json(const char *path, const char *from, const char *to)
{
    FILE *f = fopen(path, "rb");
    unsigned char *glb = NULL;
    long n = -1;
    if (f && fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 20 && fseek(f, 0, SEEK_SET) == 0 &&
        (glb = malloc((size_t)n)) && fread(glb, 1, (size_t)n, f) != (size_t)n)
        n = -1;
    if (f)
        fclose(f);
    size_t jl = n >= 20 ? (size_t)glb[12] | (size_t)glb[13] << 8 | (size_t)glb[14] << 16 | (size_t)glb[15] << 24 : 0;
    char *json = n >= 20 && 20 + jl <= (size_t)n ? malloc(jl + strlen(to) + 4) : NULL;
    char *at = NULL;
    if (json) {
        memcpy(json, glb + 20, jl);
        json[jl] = '\0';
        at = strstr(json, from);
    }
    int r = -1;
    if (at) {
        size_t head = (size_t)(at - json), tail = jl - head - strlen(from);
        memmove(at + strlen(to), at + strlen(from), tail + 1);
        memcpy(at, to, strlen(to));
        size_t len = strlen(json), padded = (len + 3) / 4 * 4, rest = (size_t)n - 20 - jl;
        unsigned char *out = malloc(20 + padded + rest);
        if (out) {
            memcpy(out, glb, 20);
            memcpy(out + 20, json, len);
            memset(out + 20 + len, ' ', padded - len);
            memcpy(out + 20 + padded, glb + 20 + jl, rest);
            grid_put32(out + 8, (uint32_t)(20 + padded + rest));
            grid_put32(out + 12, (uint32_t)padded);
            FILE *w = fopen(path, "wb");
            r = w && fwrite(out, 1, 20 + padded + rest, w) == 20 + padded + rest ? 0 : -1;
            if (w && fclose(w) != 0)
                r = -1;
            free(out);
        }
    }
    free(json);
    free(glb);
    return r;
}

/* An n x n grid over [0,1]^2 with UV = (x, y): (n+1)^2 vertices into pos (3 floats each) and
 * uv (2 each), 2 n^2 triangles into idx (3 each). */
static inline void grid_fill(int n, float *pos, float *uv, uint32_t *idx)
{
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            size_t v = (size_t)j * (n + 1) + i;
            pos[3 * v] = (float)i / n;
            pos[3 * v + 1] = (float)j / n;
            pos[3 * v + 2] = 0;
            uv[2 * v] = (float)i / n;
            uv[2 * v + 1] = (float)j / n;
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 2, d = a + (uint32_t)n + 1;
            uint32_t *t = idx + 6 * (size_t)(j * n + i);
            t[0] = a, t[1] = b, t[2] = c, t[3] = a, t[4] = c, t[5] = d;
        }
}

/* The n x n grid of grid_fill with its texture cut into islands of block x block quads
 * (block divides n; g = n / block islands a side), each with its own vertices, laid out in a
 * g x g arrangement shuffled by k -> (k * 37 + 11) mod g^2: an exporter's fragmented atlas.
 * Each island's UVs span `side` / g of the texture, its cells spaced evenly from 0 to
 * 1 - side / g: side < 1 leaves gutter between islands, side > 1 makes neighbours overlap.
 * fold > 0 turns the part x > 1/2 up by that angle (radians) about the line x = 1/2.
 * Writes g^2 (block + 1)^2 vertices (fragmented_grid_vertices) and 2 n^2 triangles. */
static inline size_t fragmented_grid_vertices(int n, int block)
{
    size_t g = (size_t)(n / block);
    return g * g * (size_t)(block + 1) * (size_t)(block + 1);
}

static inline void fragmented_grid_fill(int n, int block, double side, double fold, float *pos, float *uv,
                                        uint32_t *idx)
{
    int g = n / block, b1 = block + 1;
    double size = side / g, spacing = g > 1 ? (1.0 - size) / (g - 1) : 0;
    for (int k = 0; k < g * g; k++) {
        int bi = k % g, bj = k / g, cell = (k * 37 + 11) % (g * g);
        for (int j = 0; j <= block; j++)
            for (int i = 0; i <= block; i++) {
                size_t v = (size_t)k * (size_t)(b1 * b1) + (size_t)(j * b1 + i);
                double x = (double)(bi * block + i) / n, y = (double)(bj * block + j) / n;
                double px = x, pz = 0;
                if (fold > 0 && x > 0.5) {
                    px = 0.5 + (x - 0.5) * cos(fold);
                    pz = (x - 0.5) * sin(fold);
                }
                pos[3 * v] = (float)px;
                pos[3 * v + 1] = (float)y;
                pos[3 * v + 2] = (float)pz;
                uv[2 * v] = (float)((cell % g) * spacing + size * i / block);
                uv[2 * v + 1] = (float)((cell / g) * spacing + size * j / block);
            }
        for (int j = 0; j < block; j++)
            for (int i = 0; i < block; i++) {
                uint32_t a = (uint32_t)((size_t)k * (size_t)(b1 * b1) + (size_t)(j * b1 + i)), b = a + 1,
                         c = a + (uint32_t)b1 + 1, d = a + (uint32_t)b1;
                uint32_t *t = idx + 6 * (size_t)((bj * block + j) * n + bi * block + i);
                t[0] = a, t[1] = b, t[2] = c, t[3] = a, t[4] = c, t[5] = d;
            }
    }
}

/* fragmented_grid_fill written as a .glb with one tex x tex base colour texture: `pattern`
 * painted as fragment_fill paints it. Returns 0 on success. */
static inline int write_fragmented_grid_glb(const char *path, int n, int block, double side, double fold, int tex,
                                            const char *pattern)
{
    size_t nv = fragmented_grid_vertices(n, block), nt = 2 * (size_t)n * n;
    float *pos = malloc(nv * 12), *uv = malloc(nv * 8);
    uint32_t *idx = malloc(nt * 12);
    int r = -1;
    if (pos && uv && idx && block > 0 && n % block == 0) {
        fragmented_grid_fill(n, block, side, fold, pos, uv, idx);
        char painted[96];
        snprintf(painted, sizeof painted, "fragments:%d:%d:%.17g:%s", n, block, side, pattern);
        const char *patterns[1] = {painted};
        r = write_mesh_glb_material(path, pos, uv, nv, idx, nt, tex, patterns, 1,
                                    "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}");
    }
    free(pos);
    free(uv);
    free(idx);
    return r;
}

/* Writes an n x n grid (grid_fill) with image_count tex x tex images of patterns[i] and the
 * material JSON `material` (write_mesh_glb_material) as a .glb at path. Returns 0 on success. */
static inline int write_grid_glb_material(const char *path, int n, int tex, const char *const *patterns,
                                          int image_count, const char *material)
{
    size_t nv = (size_t)(n + 1) * (n + 1), nt = 2 * (size_t)n * n;
    float *pos = malloc(nv * 12), *uv = malloc(nv * 8);
    uint32_t *idx = malloc(nt * 12);
    int r = -1;
    if (pos && uv && idx) {
        grid_fill(n, pos, uv, idx);
        r = write_mesh_glb_material(path, pos, uv, nv, idx, nt, tex, patterns, image_count, material);
    }
    free(pos);
    free(uv);
    free(idx);
    return r;
}

/* The grid with a tex x tex texture of `pattern` (and mr_pattern's, or none) as base colour
 * (and metallic-roughness), as write_mesh_glb writes them. */
static inline int write_grid_glb_images(const char *path, int n, int tex, const char *pattern, const char *mr_pattern)
{
    char material[256];
    snprintf(material, sizeof material, "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}%s}}",
             mr_pattern ? ",\"metallicRoughnessTexture\":{\"index\":1}" : "");
    const char *patterns[2] = {pattern, mr_pattern};
    return write_grid_glb_material(path, n, tex, patterns, mr_pattern ? 2 : 1, material);
}

static inline int write_grid_glb(const char *path, int n, int tex, const char *pattern)
{
    return write_grid_glb_images(path, n, tex, pattern, NULL);
}

#endif

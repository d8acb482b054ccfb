/* grid_glb.h - a textured n x n grid (or any small mesh) written as a small .glb, for the
 * pipeline tests (header only; test_pipeline.c and test_pipeline_models_slow.c). The grid lies over
 * [0,1]^2 with UV = (x, y), u32 indices, one material whose base colour is a tex x tex PNG
 * of one of the fixtures' patterns (tests/support/fixtures.h), default sampler (REPEAT);
 * optionally a second image of a pattern as the metallic-roughness image. */
#ifndef TEXOPT_TEST_GRID_GLB_H
#define TEXOPT_TEST_GRID_GLB_H

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

/* A tex x tex image of `pattern` as PNG into *png (the caller frees it); 0 on success. */
static inline int grid_pattern_png(int tex, const char *pattern, unsigned char **png, size_t *png_len)
{
    texopt_image img;
    if (texopt_image_create(&img, tex, tex, 3, NULL, 0) != TEXOPT_OK || fixture_fill_pattern(&img, pattern) != 0)
        return -1;
    texopt_status st = texopt_image_encode_png(&img, png, png_len, NULL, 0);
    texopt_image_destroy(&img);
    return st == TEXOPT_OK ? 0 : -1;
}

/* Writes a mesh (positions 3 floats and UVs 2 floats per vertex, u32 triangles) with a
 * tex x tex base-colour texture of `pattern` as a .glb at path; with mr_pattern (NULL: none),
 * image 1 is a metallicRoughness texture of that pattern (the same pattern: the same pixels
 * as base colour); base_ext (may be "") goes into the base colour's textureInfo after its
 * index, e.g. ",\"extensions\":{...}". Returns 0 on success. */
static inline int write_mesh_glb_ext(const char *path, const float *positions, const float *uvs, size_t nv,
                                     const uint32_t *triangles, size_t nt, int tex, const char *pattern,
                                     const char *mr_pattern, const char *base_ext)
{
    unsigned char *png = NULL, *mr_png = NULL;
    size_t png_len = 0, mr_len = 0;
    if (grid_pattern_png(tex, pattern, &png, &png_len) != 0 ||
        (mr_pattern && grid_pattern_png(tex, mr_pattern, &mr_png, &mr_len) != 0)) {
        free(png);
        return -1;
    }
    int has_mr = mr_pattern != NULL;
    size_t pos_len = nv * 12, uv_len = nv * 8, idx_len = nt * 12;
    size_t png_at = pos_len + uv_len + idx_len, mr_at = (png_at + png_len + 3) / 4 * 4;
    size_t bin_len = (mr_at + mr_len + 3) / 4 * 4;
    unsigned char *bin = calloc(1, bin_len);
    memcpy(bin, positions, pos_len);
    memcpy(bin + pos_len, uvs, uv_len);
    memcpy(bin + pos_len + uv_len, triangles, idx_len);
    float lo[3] = {positions[0], positions[1], positions[2]}, hi[3] = {positions[0], positions[1], positions[2]};
    for (size_t v = 0; v < nv; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = positions[3 * v + k] < lo[k] ? positions[3 * v + k] : lo[k];
            hi[k] = positions[3 * v + k] > hi[k] ? positions[3 * v + k] : hi[k];
        }
    memcpy(bin + png_at, png, png_len);
    if (mr_png)
        memcpy(bin + mr_at, mr_png, mr_len);
    free(png);
    free(mr_png);
    char json[4096], mr_view[96] = "";
    if (has_mr)
        snprintf(mr_view, sizeof mr_view, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}", mr_at, mr_len);
    int jl = snprintf(json, sizeof json,
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2,\"material\":0}]}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0%s}%s}}],"
        "\"textures\":[{\"source\":0}%s],\"images\":[{\"bufferView\":3,\"mimeType\":\"image/png\"}%s],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC2\"},"
        "{\"bufferView\":2,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}%s],"
        "\"buffers\":[{\"byteLength\":%zu}]}",
        base_ext, has_mr ? ",\"metallicRoughnessTexture\":{\"index\":1}" : "", has_mr ? ",{\"source\":1}" : "",
        has_mr ? ",{\"bufferView\":4,\"mimeType\":\"image/png\"}" : "", nv, (double)lo[0], (double)lo[1],
        (double)lo[2], (double)hi[0], (double)hi[1], (double)hi[2], nv, nt * 3, pos_len,
        pos_len, uv_len, pos_len + uv_len, idx_len, png_at, png_len, mr_view, bin_len);
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
    int ok = f && fwrite(glb, 1, total, f) == total;
    if (f && fclose(f) != 0)
        ok = 0;
    free(glb);
    return ok ? 0 : -1;
}

static inline int write_mesh_glb(const char *path, const float *positions, const float *uvs, size_t nv,
                                 const uint32_t *triangles, size_t nt, int tex, const char *pattern,
                                 const char *mr_pattern)
{
    return write_mesh_glb_ext(path, positions, uvs, nv, triangles, nt, tex, pattern, mr_pattern, "");
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

/* Writes an n x n grid (grid_fill) with a tex x tex texture of `pattern` (and mr_pattern's,
 * or none) as a .glb at path (write_mesh_glb). Returns 0 on success. */
static inline int write_grid_glb_images(const char *path, int n, int tex, const char *pattern, const char *mr_pattern)
{
    size_t nv = (size_t)(n + 1) * (n + 1), nt = 2 * (size_t)n * n;
    float *pos = malloc(nv * 12), *uv = malloc(nv * 8);
    uint32_t *idx = malloc(nt * 12);
    int r = -1;
    if (pos && uv && idx) {
        grid_fill(n, pos, uv, idx);
        r = write_mesh_glb(path, pos, uv, nv, idx, nt, tex, pattern, mr_pattern);
    }
    free(pos);
    free(uv);
    free(idx);
    return r;
}

static inline int write_grid_glb(const char *path, int n, int tex, const char *pattern)
{
    return write_grid_glb_images(path, n, tex, pattern, NULL);
}

#endif

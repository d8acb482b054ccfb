/* fixtures.c - generated in-memory models and texture patterns for the unit tests.
 *
 * Builds texopt_model values directly (no glTF document, no file I/O) so that engine tests
 * run without the loader and know every count in advance. Not a mesh generator for the
 * product: only what tests need, with exact (bit-equal) positions on shared corners so the
 * weld in engine/model/mesh.c sees what real glTF exporters produce. */
#include "fixtures.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "map_patterns.h"
#include "rebake.h"
#include "sample.h"

static const float flat_colour[3] = {0.6f, 0.4f, 0.2f};

static void set_rgb(float *px, int channels, float r, float g, float b)
{
    px[0] = r;
    px[1] = g;
    px[2] = b;
    if (channels == 4)
        px[3] = 1.0f;
}

int fixture_glyph_ink(int x, int y)
{
    unsigned cx = (unsigned)x / 8u, cy = (unsigned)y / 8u;
    int lx = x % 8, ly = y % 8;
    unsigned h = (cx * 73856093u) ^ (cy * 19349663u);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    if ((h & 63u) == 0)
        h |= 1u;
    if (lx == 7 || ly == 7)
        return 0;
    return ((h & 1u) && ly == 1) || ((h & 2u) && lx == 1) || ((h & 4u) && lx == ly) || ((h & 8u) && lx == 5) ||
           ((h & 16u) && ly == 4) || ((h & 32u) && lx + ly == 6);
}

static int pattern_texel(const char *pattern, int x, int y, int w, int h, float rgb[3])
{
    if (strcmp(pattern, "flat") == 0 || (strcmp(pattern, "half") == 0 && x < w / 2)) {
        memcpy(rgb, flat_colour, sizeof flat_colour);
        return 0;
    }
    float bw;
    if (strcmp(pattern, "half") == 0)
        bw = fixture_glyph_ink(x, y) ? 0.0f : 1.0f;
    else if (strcmp(pattern, "stripes0") == 0)
        bw = (float)((x / 4) % 2);
    else if (strcmp(pattern, "stripes45") == 0)
        bw = (float)(((x + y) / 4) % 2);
    else if (strcmp(pattern, "checker") == 0) {
        int sx = w / 8 > 0 ? w / 8 : 1, sy = h / 8 > 0 ? h / 8 : 1;
        bw = (float)((x / sx + y / sy) % 2);
    } else if (strcmp(pattern, "gradient") == 0) {
        rgb[0] = ((float)x + 0.5f) / (float)w;
        rgb[1] = ((float)y + 0.5f) / (float)h;
        rgb[2] = 0.25f;
        return 0;
    } else
        return map_pattern_texel(pattern, x, y, w, h, rgb);
    rgb[0] = rgb[1] = rgb[2] = bw;
    return 0;
}

int fixture_fill_pattern(texopt_image *img, const char *pattern)
{
    if (!img || !img->pixels || !pattern || img->channels < 3)
        return -1;
    float rgb[3];
    if (pattern_texel(pattern, 0, 0, img->width, img->height, rgb) != 0)
        return -1;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            pattern_texel(pattern, x, y, img->width, img->height, rgb);
            set_rgb(texopt_image_at(img, x, y), img->channels, rgb[0], rgb[1], rgb[2]);
        }
    return 0;
}

int fixture_add_alpha(texopt_image *img, const char *pattern)
{
    float rgb[3];
    texopt_image rgba = {0};
    if (!img || !img->pixels || img->channels != 3 || !pattern ||
        pattern_texel(pattern, 0, 0, img->width, img->height, rgb) != 0 ||
        texopt_image_create(&rgba, img->width, img->height, 4, NULL, 0) != TEXOPT_OK)
        return -1;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            float *to = texopt_image_at(&rgba, x, y);
            memcpy(to, texopt_image_at(img, x, y), 3 * sizeof *to);
            pattern_texel(pattern, x, y, img->width, img->height, rgb);
            to[3] = texopt_luma(rgb, 3);
        }
    texopt_image_destroy(img);
    *img = rgba;
    return 0;
}

static char *copy_string(const char *s)
{
    size_t n = strlen(s) + 1;
    char *c = malloc(n);
    if (c)
        memcpy(c, s, n);
    return c;
}

/* One image, one material reading it as base colour through TEXCOORD_0. */
static int add_texture(texopt_model *m, int tex_w, int tex_h, const char *pattern)
{
    m->images = calloc(1, sizeof *m->images);
    m->image_names = calloc(1, sizeof *m->image_names);
    m->materials = calloc(1, sizeof *m->materials);
    if (!m->images || !m->image_names || !m->materials)
        return -1;
    m->image_count = 1;
    if (texopt_image_create(&m->images[0], tex_w, tex_h, 3, NULL, 0) != TEXOPT_OK)
        return -1;
    if (fixture_fill_pattern(&m->images[0], pattern) != 0)
        return -1;
    char name[64] = "fixture_";
    strncat(name, pattern, sizeof name - strlen(name) - 1);
    m->image_names[0] = copy_string(name);
    m->material_count = 1;
    for (int s = 0; s < TEXOPT_SLOT_COUNT; s++)
        m->materials[0].slot[s] = (texopt_texture_ref){-1, 0, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 0};
    m->materials[0].slot[TEXOPT_SLOT_BASE_COLOR].image = 0;
    /* A rough dielectric, as the single-texture sample assets declare. */
    m->materials[0].metallic_factor = 0;
    m->materials[0].roughness_factor = 1;
    return 0;
}

void fixture_fill_normal_map(texopt_image *img)
{
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            double a = (x / 8) % 2 ? 0.6 : -0.6, b = (y / 4) % 2 ? 0.3 : -0.3;
            float *p = texopt_image_at(img, x, y);
            p[0] = (float)(0.5 + 0.5 * a);
            p[1] = (float)(0.5 + 0.5 * b);
            p[2] = (float)(0.5 + 0.5 * sqrt(1.0 - a * a - b * b));
        }
}

texopt_image *fixture_add_slot_image(texopt_model *m, texopt_slot slot, int side)
{
    texopt_image *images = realloc(m->images, (size_t)(m->image_count + 1) * sizeof *images);
    if (!images)
        return NULL;
    m->images = images;
    char **names = realloc(m->image_names, (size_t)(m->image_count + 1) * sizeof *names);
    if (!names)
        return NULL;
    m->image_names = names;
    int i = m->image_count;
    names[i] = NULL;
    memset(&images[i], 0, sizeof images[i]);
    m->image_count++;
    if (texopt_image_create(&images[i], side, side, 3, NULL, 0) != TEXOPT_OK)
        return NULL;
    m->materials[0].slot[slot].image = i;
    return &images[i];
}

int fixture_rebake(const texopt_model *ref, texopt_model *cand, int image, int normal_map)
{
    if (!ref || !cand || ref->vertex_count != cand->vertex_count || image < 0 || image >= ref->image_count ||
        image >= cand->image_count)
        return -1;
    size_t n = 2 * ref->vertex_count;
    double *uv_in = malloc(n * sizeof *uv_in), *uv_out = malloc(n * sizeof *uv_out);
    int ok = uv_in && uv_out;
    for (size_t i = 0; ok && i < n; i++) {
        uv_in[i] = ref->uvs[i];
        uv_out[i] = cand->uvs[i];
    }
    texopt_rebake_layout layout = {ref->triangle_count, ref->triangles, uv_in, uv_out, 1};
    ok = ok && texopt_rebake_image(&ref->images[image], TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, normal_map, &layout,
                                   &cand->images[image], NULL, NULL, NULL, 0) == TEXOPT_OK;
    free(uv_in);
    free(uv_out);
    return ok ? 0 : -1;
}

texopt_model *fixture_model_from_arrays(const float *positions, const float *uvs, size_t vertex_count,
                                        const uint32_t *triangles, size_t triangle_count, int tex_w, int tex_h,
                                        const char *pattern)
{
    if (!positions || !uvs || !triangles || !pattern || vertex_count == 0 || triangle_count == 0 || tex_w <= 0 ||
        tex_h <= 0)
        return NULL;
    texopt_model *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->vertex_count = vertex_count;
    m->triangle_count = triangle_count;
    m->positions = malloc(sizeof(float) * 3 * vertex_count);
    m->uvs = malloc(sizeof(float) * 2 * vertex_count);
    m->triangles = malloc(sizeof(uint32_t) * 3 * triangle_count);
    m->primitives = calloc(1, sizeof *m->primitives);
    if (!m->positions || !m->uvs || !m->triangles || !m->primitives || add_texture(m, tex_w, tex_h, pattern) != 0) {
        texopt_model_destroy(m);
        return NULL;
    }
    memcpy(m->positions, positions, sizeof(float) * 3 * vertex_count);
    memcpy(m->uvs, uvs, sizeof(float) * 2 * vertex_count);
    memcpy(m->triangles, triangles, sizeof(uint32_t) * 3 * triangle_count);
    m->primitive_count = 1;
    m->primitives[0] = (texopt_primitive){.gltf_mesh = 0,
                                          .gltf_primitive = 0,
                                          .material = 0,
                                          .domain = -1,
                                          .first_vertex = 0,
                                          .vertex_count = vertex_count,
                                          .first_triangle = 0,
                                          .triangle_count = triangle_count};
    if (texopt_model_build_domains(m, NULL, 0) != TEXOPT_OK) {
        texopt_model_destroy(m);
        return NULL;
    }
    return m;
}

texopt_model *fixture_grid(int n, int tex_size, const char *pattern)
{
    if (n < 1 || n > 4096)
        return NULL;
    size_t nv = (size_t)(n + 1) * (size_t)(n + 1), nt = 2 * (size_t)n * (size_t)n;
    float *pos = malloc(sizeof(float) * 3 * nv);
    float *uv = malloc(sizeof(float) * 2 * nv);
    uint32_t *tri = malloc(sizeof(uint32_t) * 3 * nt);
    texopt_model *m = NULL;
    if (pos && uv && tri) {
        for (int j = 0; j <= n; j++)
            for (int i = 0; i <= n; i++) {
                size_t v = (size_t)j * (size_t)(n + 1) + (size_t)i;
                float x = (float)i / (float)n, y = (float)j / (float)n;
                pos[3 * v] = uv[2 * v] = x;
                pos[3 * v + 1] = uv[2 * v + 1] = y;
                pos[3 * v + 2] = 0.0f;
            }
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = b + (uint32_t)(n + 1),
                         d = a + (uint32_t)(n + 1);
                uint32_t *t = tri + 6 * ((size_t)j * (size_t)n + (size_t)i);
                t[0] = a, t[1] = b, t[2] = c;
                t[3] = a, t[4] = c, t[5] = d;
            }
        m = fixture_model_from_arrays(pos, uv, nv, tri, nt, tex_size, tex_size, pattern);
    }
    free(pos);
    free(uv);
    free(tri);
    return m;
}

texopt_model *fixture_textured_quad(int tex_size, const char *pattern)
{
    static const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    static const float uv[] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const uint32_t tri[] = {0, 1, 2, 0, 2, 3};
    return fixture_model_from_arrays(pos, uv, 4, tri, 2, tex_size, tex_size, pattern);
}

/* A cube face: corner = origin + s * a + t * b with a x b the outward normal, and its UV
 * square of side 1/4 at (u0, v0). */
typedef struct cube_face {
    float origin[3], a[3], b[3];
    float u0, v0;
} cube_face;

static const cube_face cube_faces[6] = {
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 0.0f, 0.375f},   /* front +Z */
    {{1, 0, 1}, {0, 0, -1}, {0, 1, 0}, 0.25f, 0.375f}, /* right +X */
    {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, 0.5f, 0.375f},  /* back -Z */
    {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 0.75f, 0.375f},  /* left -X */
    {{0, 1, 1}, {1, 0, 0}, {0, 0, -1}, 0.125f, 0.75f}, /* top +Y */
    {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 0.625f, 0.0f},   /* bottom -Y */
};

texopt_model *fixture_cube_with_seams(int tex_size)
{
    static const float corner_st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    float pos[24 * 3], uv[24 * 2];
    uint32_t tri[12 * 3];
    for (int f = 0; f < 6; f++) {
        const cube_face *face = &cube_faces[f];
        for (int k = 0; k < 4; k++) {
            int v = 4 * f + k;
            float s = corner_st[k][0], t = corner_st[k][1];
            for (int c = 0; c < 3; c++)
                pos[3 * v + c] = face->origin[c] + s * face->a[c] + t * face->b[c];
            uv[2 * v] = face->u0 + 0.25f * s;
            uv[2 * v + 1] = face->v0 + 0.25f * t;
        }
        uint32_t base = (uint32_t)(4 * f);
        uint32_t *t = tri + 6 * f;
        t[0] = base, t[1] = base + 1, t[2] = base + 2;
        t[3] = base, t[4] = base + 2, t[5] = base + 3;
    }
    return fixture_model_from_arrays(pos, uv, 24, tri, 12, tex_size, tex_size, "checker");
}

/* Position on the unit sphere of ring r (polar angle pi r / rings from +y) and segment s;
 * s is taken modulo segments so the seam columns are bit-identical. */
static void sphere_point(int s, int r, int segments, int rings, float *out)
{
    const double pi = 3.14159265358979323846;
    double theta = pi * (double)r / (double)rings;
    double phi = 2.0 * pi * (double)(s % segments) / (double)segments;
    out[0] = (float)(sin(theta) * cos(phi));
    out[1] = (float)cos(theta);
    out[2] = (float)(sin(theta) * sin(phi));
}

texopt_model *fixture_uv_sphere(int segments, int rings, int tex_size)
{
    if (segments < 3 || rings < 2 || segments > 4096 || rings > 4096)
        return NULL;
    size_t S = (size_t)segments, R = (size_t)rings;
    size_t nv = (S + 1) * (R - 1) + 2 * S, nt = 2 * S * (R - 1);
    float *pos = malloc(sizeof(float) * 3 * nv);
    float *uv = malloc(sizeof(float) * 2 * nv);
    uint32_t *tri = malloc(sizeof(uint32_t) * 3 * nt);
    texopt_model *m = NULL;
    if (pos && uv && tri) {
        /* Vertex numbering: north poles [0, S), ring r in 1..R-1 at S + (r-1)(S+1) + s,
         * south poles after them. */
        size_t ring0 = S, south = S + (S + 1) * (R - 1);
        for (size_t s = 0; s < S; s++) {
            float u = ((float)s + 0.5f) / (float)segments;
            pos[3 * s] = 0, pos[3 * s + 1] = 1, pos[3 * s + 2] = 0;
            uv[2 * s] = u, uv[2 * s + 1] = 0;
            size_t v = south + s;
            pos[3 * v] = 0, pos[3 * v + 1] = -1, pos[3 * v + 2] = 0;
            uv[2 * v] = u, uv[2 * v + 1] = 1;
        }
        for (size_t r = 1; r < R; r++)
            for (size_t s = 0; s <= S; s++) {
                size_t v = ring0 + (r - 1) * (S + 1) + s;
                sphere_point((int)s, (int)r, segments, rings, pos + 3 * v);
                uv[2 * v] = (float)s / (float)segments;
                uv[2 * v + 1] = (float)r / (float)rings;
            }
        uint32_t *t = tri;
        for (size_t s = 0; s < S; s++) { /* north fan */
            uint32_t a = (uint32_t)(ring0 + s);
            t[0] = (uint32_t)s, t[1] = a + 1, t[2] = a;
            t += 3;
        }
        for (size_t r = 1; r + 1 < R; r++)
            for (size_t s = 0; s < S; s++) {
                uint32_t a = (uint32_t)(ring0 + (r - 1) * (S + 1) + s), b = a + 1, d = a + (uint32_t)(S + 1), c = d + 1;
                t[0] = a, t[1] = b, t[2] = c;
                t[3] = a, t[4] = c, t[5] = d;
                t += 6;
            }
        for (size_t s = 0; s < S; s++) { /* south fan */
            uint32_t a = (uint32_t)(ring0 + (R - 2) * (S + 1) + s);
            t[0] = a, t[1] = a + 1, t[2] = (uint32_t)(south + s);
            t += 3;
        }
        m = fixture_model_from_arrays(pos, uv, nv, tri, nt, tex_size, tex_size, "checker");
    }
    free(pos);
    free(uv);
    free(tri);
    return m;
}

int fixture_split_primitive(texopt_model *m, size_t first)
{
    if (!m || m->primitive_count != 1 || first == 0 || first >= m->primitives[0].triangle_count)
        return -1;
    texopt_primitive *prims = realloc(m->primitives, 2 * sizeof *prims);
    if (prims)
        m->primitives = prims;
    texopt_material *mats = realloc(m->materials, 2 * sizeof *mats);
    if (mats)
        m->materials = mats;
    if (!prims || !mats)
        return -1;
    mats[1] = mats[0];
    m->material_count = 2;
    prims[1] = prims[0];
    m->primitive_count = 2;
    prims[1].first_triangle = prims[0].first_triangle + first;
    prims[1].triangle_count = prims[0].triangle_count - first;
    prims[0].triangle_count = first;
    prims[1].material = 1;
    return texopt_model_build_domains(m, NULL, 0) == TEXOPT_OK ? 0 : -1;
}

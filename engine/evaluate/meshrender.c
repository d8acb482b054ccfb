/* meshrender.c - the evaluation's whole-model renderer: a plain C depth-buffered rasteriser.
 *
 * Sun et al. 2022, section 5.1 (20 dodecahedron cameras, bilinear texture lookups); the 12
 * icosahedron cameras are a second set that looks between them (meshrender.h says why).
 * Why not OSMesa: the evaluation needs, for two models with the same geometry, the same
 * covered pixels and, per pixel, a bilinear lookup at the interpolated UV. A CPU raster
 * that stores triangle id + barycentrics per pixel gives exactly that: the geometry is
 * rasterised once per view and shaded twice (reference, candidate), so coverage matches by
 * construction, the lookup is texopt_sample_bilinear (the same one the bake and the
 * per-triangle loss use), and nothing depends on a GL context per thread (OSMesa does not
 * render in parallel within one process, see DEPENDENCIES.md). Cost is linear in pixels
 * and triangles: 20 views of spot at 1300 px (34 M pixels, both shadings and GMSD) take about
 * 1 s of CPU.
 *
 * Rules: pixel centres at (i + 0.5, j + 0.5); a pixel belongs to a triangle when its centre
 * is inside or on an edge; nearer depth wins, ties keep the earlier triangle (deterministic).
 * Both windings are drawn (no back-face culling): the depth test hides back faces of closed
 * meshes, and open meshes stay visible from both sides.
 *
 * Mip-mapped shading (optional, reported separately by the evaluation) uses the prefiltered
 * lookups of texture_filter.h with the per-triangle screen-to-texel Jacobian.
 *
 * The luma shading reads any one texture of the material (texture_keys.h: base colour, or a
 * data texture such as the normal map, whose RGB encoding is then shaded as if it were a colour
 * image, its XY turned per triangle when the caller asks: texel_map.h; a texture read in fewer
 * than its three colour channels shows the mean of those it is read in); the RGB shadings
 * read base colour, what the report shows.
 *
 * Base colour's alpha, where a material shows it (alphaMode MASK or BLEND), cuts or blends the
 * surface over a mid-grey backdrop (composite_cut_out says why a backdrop), so a layout is
 * judged on its cut-outs' edges too; other textures and OPAQUE materials ignore alpha.
 *
 * Does not: light (lit_shade.h does, from these shadings), see through a cut-out to the
 * surfaces behind it, decode normals or channels, choose the turns (evaluate.c), or compare
 * images. */
#include "meshrender.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sample.h"
#include "texel_map.h"
#include "texture_filter.h"
#include "texture_keys.h"
#include "vec3.h"

/* Unit vectors to the 20 vertices of a regular dodecahedron: (±1,±1,±1), (0,±1/φ,±φ),
 * (±1/φ,±φ,0), (±φ,0,±1/φ). */
static void dodecahedron_vertices(double out[TEXOPT_VIEW_COUNT][3])
{
    const double phi = (1.0 + sqrt(5.0)) / 2.0, iphi = 1.0 / phi;
    int n = 0;
    for (int a = -1; a <= 1; a += 2)
        for (int b = -1; b <= 1; b += 2) {
            for (int c = -1; c <= 1; c += 2) {
                out[n][0] = a;
                out[n][1] = b;
                out[n][2] = c;
                n++;
            }
            double p[3][3] = {{0, a * iphi, b * phi}, {a * iphi, b * phi, 0}, {a * phi, 0, b * iphi}};
            for (int k = 0; k < 3; k++, n++)
                memcpy(out[n], p[k], sizeof p[k]);
        }
    for (int i = 0; i < TEXOPT_VIEW_COUNT; i++) {
        double len = sqrt(out[i][0] * out[i][0] + out[i][1] * out[i][1] + out[i][2] * out[i][2]);
        for (int k = 0; k < 3; k++)
            out[i][k] /= len;
    }
}

/* Unit vectors to the 12 vertices of the regular icosahedron dual to the dodecahedron above,
 * (0,±φ,±1), (±1,0,±φ), (±φ,±1,0): the directions of its face centres, each 37.4 degrees
 * from its 5 nearest dodecahedron cameras. (The icosahedron (0,±1,±φ) ... would put every
 * camera 10.7 degrees from one of the dodecahedron's.) */
static int icosahedron_vertices(double out[TEXOPT_VIEW_COUNT][3])
{
    const double phi = (1.0 + sqrt(5.0)) / 2.0, len = sqrt(1.0 + phi * phi);
    int n = 0;
    for (int a = -1; a <= 1; a += 2)
        for (int b = -1; b <= 1; b += 2) {
            double p[3][3] = {{0, a * phi, b}, {a, 0, b * phi}, {a * phi, b, 0}};
            for (int k = 0; k < 3; k++, n++)
                for (int j = 0; j < 3; j++)
                    out[n][j] = p[k][j] / len;
        }
    return n;
}

/* Screen axes for a camera looking along -direction with world +Y as "up" where possible. */
static void view_axes(texopt_view *view)
{
    double world_up[3] = {0, 1, 0};
    if (fabs(view->direction[1]) > 0.99) {
        world_up[1] = 0;
        world_up[2] = 1;
    }
    /* right = up x direction, so (right, up, direction) is right-handed and the camera sees
     * the scene unmirrored. */
    texopt_cross3(world_up, view->direction, view->right);
    texopt_normalize3(view->right);
    texopt_cross3(view->direction, view->right, view->up);
    texopt_normalize3(view->up);
}

texopt_status texopt_meshrender_views(const texopt_model *model, texopt_view *views, char *err, size_t err_len)
{
    int count;
    return texopt_meshrender_camera_set(model, TEXOPT_CAMERAS_DODECAHEDRON, views, &count, err, err_len);
}

texopt_status texopt_meshrender_camera_set(const texopt_model *model, texopt_camera_set set, texopt_view *views,
                                           int *count, char *err, size_t err_len)
{
    if (set != TEXOPT_CAMERAS_DODECAHEDRON && set != TEXOPT_CAMERAS_ICOSAHEDRON)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "unknown camera set %d", (int)set);
    if (!model || !views || !count || model->triangle_count == 0 || model->vertex_count == 0 || !model->positions)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "model has no triangles to render");
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (size_t v = 0; v < model->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            double x = model->positions[3 * v + k];
            if (!isfinite(x))
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "vertex %zu has a non-finite position", v);
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
    double centre[3], radius = 0;
    for (int k = 0; k < 3; k++)
        centre[k] = 0.5 * (lo[k] + hi[k]);
    for (size_t v = 0; v < model->vertex_count; v++) {
        double d[3];
        for (int k = 0; k < 3; k++)
            d[k] = model->positions[3 * v + k] - centre[k];
        radius = fmax(radius, sqrt(texopt_dot3(d, d)));
    }
    if (!(radius > 0))
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                           "every vertex of the model is at one point: no camera sees a surface");
    double dirs[TEXOPT_VIEW_COUNT][3];
    int n = TEXOPT_VIEW_COUNT;
    if (set == TEXOPT_CAMERAS_ICOSAHEDRON)
        n = icosahedron_vertices(dirs);
    else
        dodecahedron_vertices(dirs);
    *count = n;
    for (int i = 0; i < n; i++) {
        memcpy(views[i].centre, centre, sizeof centre);
        memcpy(views[i].direction, dirs[i], sizeof dirs[i]);
        /* A hair of margin keeps the silhouette off the last pixel row. */
        views[i].half_extent = radius * 1.01;
        view_axes(&views[i]);
    }
    return TEXOPT_OK;
}

void texopt_raster_destroy(texopt_raster *raster)
{
    if (!raster)
        return;
    free(raster->triangle);
    free(raster->bary);
    memset(raster, 0, sizeof *raster);
}

/* Screen position (pixels, y down) and depth (larger = nearer) of a world point. */
static void project(const texopt_view *view, int side, const float *p, double out[3])
{
    double d[3] = {p[0] - view->centre[0], p[1] - view->centre[1], p[2] - view->centre[2]};
    double scale = side / (2.0 * view->half_extent);
    out[0] = (texopt_dot3(d, view->right) + view->half_extent) * scale;
    out[1] = (view->half_extent - texopt_dot3(d, view->up)) * scale;
    out[2] = texopt_dot3(d, view->direction);
}

static void rasterize_triangle(texopt_raster *r, float *depth, int32_t tri, const double s[3][3])
{
    double area = (s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) - (s[2][0] - s[0][0]) * (s[1][1] - s[0][1]);
    if (!(fabs(area) > 1e-12))
        return; /* seen edge-on or degenerate: covers no pixel centre robustly */
    double inv = 1.0 / area;
    int side = r->side;
    double xmin = fmin(s[0][0], fmin(s[1][0], s[2][0])), xmax = fmax(s[0][0], fmax(s[1][0], s[2][0]));
    double ymin = fmin(s[0][1], fmin(s[1][1], s[2][1])), ymax = fmax(s[0][1], fmax(s[1][1], s[2][1]));
    int x0 = (int)fmax(0, ceil(xmin - 0.5)), x1 = (int)fmin(side - 1, floor(xmax - 0.5));
    int y0 = (int)fmax(0, ceil(ymin - 0.5)), y1 = (int)fmin(side - 1, floor(ymax - 0.5));
    for (int y = y0; y <= y1; y++) {
        double py = y + 0.5;
        for (int x = x0; x <= x1; x++) {
            double px = x + 0.5;
            /* Barycentric weights of corners 1 and 2 from signed sub-areas. */
            double b1 = ((px - s[0][0]) * (s[2][1] - s[0][1]) - (s[2][0] - s[0][0]) * (py - s[0][1])) * inv;
            double b2 = ((s[1][0] - s[0][0]) * (py - s[0][1]) - (px - s[0][0]) * (s[1][1] - s[0][1])) * inv;
            double b0 = 1.0 - b1 - b2;
            if (b0 < 0 || b1 < 0 || b2 < 0)
                continue;
            float z = (float)(b0 * s[0][2] + b1 * s[1][2] + b2 * s[2][2]);
            size_t i = (size_t)y * (size_t)side + (size_t)x;
            if (r->triangle[i] >= 0 && !(z > depth[i]))
                continue;
            if (r->triangle[i] < 0)
                r->covered++;
            depth[i] = z;
            r->triangle[i] = tri;
            r->bary[2 * i] = (float)b1;
            r->bary[2 * i + 1] = (float)b2;
        }
    }
}

texopt_status texopt_meshrender_rasterize(const texopt_model *model, const texopt_view *view, int side,
                                          texopt_raster *out, char *err, size_t err_len)
{
    memset(out, 0, sizeof *out);
    if (!model || !view || side < 8 || side > 16384)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "render side %d is outside [8, 16384]", side);
    if (model->triangle_count > INT32_MAX)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "too many triangles to render");
    size_t n = (size_t)side * (size_t)side;
    out->view = *view;
    out->side = side;
    out->triangle = malloc(n * sizeof *out->triangle);
    out->bary = malloc(2 * n * sizeof *out->bary);
    float *depth = malloc(n * sizeof *depth);
    if (!out->triangle || !out->bary || !depth) {
        free(depth);
        texopt_raster_destroy(out);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d render", side, side);
    }
    for (size_t i = 0; i < n; i++)
        out->triangle[i] = -1;
    for (size_t t = 0; t < model->triangle_count; t++) {
        double s[3][3];
        int bad = 0;
        for (int k = 0; k < 3; k++) {
            uint32_t v = model->triangles[3 * t + k];
            if (v >= model->vertex_count) {
                bad = 1;
                break;
            }
            project(view, side, model->positions + 3 * (size_t)v, s[k]);
        }
        if (bad) {
            free(depth);
            texopt_raster_destroy(out);
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "triangle %zu names a vertex past the vertex count %zu", t, model->vertex_count);
        }
        rasterize_triangle(out, depth, (int32_t)t, s);
    }
    free(depth);
    return TEXOPT_OK;
}

const texopt_texture_ref *texopt_meshrender_binding(const texopt_model *model, int primitive, int texture)
{
    if (primitive < 0 || primitive >= model->primitive_count)
        return NULL;
    int mat = model->primitives[primitive].material;
    if (mat < 0 || mat >= model->material_count)
        return NULL;
    const texopt_texture_ref *r = texopt_material_texture(&model->materials[mat], texture);
    if (!r || r->image < 0 || r->image >= model->image_count || r->texcoord != 0 || !model->images[r->image].pixels)
        return NULL;
    return r;
}

int texopt_meshrender_has_texture(const texopt_model *model, int texture)
{
    for (int p = 0; model && p < model->primitive_count; p++)
        if (texopt_meshrender_binding(model, p, texture))
            return 1;
    return 0;
}

texopt_status texopt_meshrender_triangle_bindings(const texopt_model *model, int texture,
                                                  const texopt_texture_ref ***out, char *err, size_t err_len)
{
    const texopt_texture_ref **ref = calloc(model->triangle_count ? model->triangle_count : 1, sizeof *ref);
    if (!ref)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the triangle materials");
    for (int p = 0; p < model->primitive_count; p++) {
        const texopt_primitive *prim = &model->primitives[p];
        const texopt_texture_ref *r = texopt_meshrender_binding(model, p, texture);
        if (!r)
            continue;
        for (size_t t = prim->first_triangle;
             t < prim->first_triangle + prim->triangle_count && t < model->triangle_count; t++)
            ref[t] = r;
    }
    *out = ref;
    return TEXOPT_OK;
}

/* Texel position of a pixel of triangle tri in image img. */
static void pixel_texel(const texopt_model *model, const texopt_image *img, size_t tri, float b1, float b2, double *x,
                        double *y)
{
    const uint32_t *c = model->triangles + 3 * tri;
    const float *uv0 = model->uvs + 2 * (size_t)c[0], *uv1 = model->uvs + 2 * (size_t)c[1],
                *uv2 = model->uvs + 2 * (size_t)c[2];
    double b0 = 1.0 - b1 - b2;
    *x = (b0 * uv0[0] + b1 * uv1[0] + b2 * uv2[0]) * img->width;
    *y = (b0 * uv0[1] + b1 * uv1[1] + b2 * uv2[1]) * img->height;
}

/* Image texels per screen pixel of triangle tri: {dx/dsx, dx/dsy, dy/dsx, dy/dsy}. Returns
 * -1 when the triangle is edge-on (it then covers no pixel centre anyway). */
static int triangle_footprint(const texopt_model *model, const texopt_raster *r, const texopt_image *img, size_t tri,
                              double jac[4])
{
    double s[3][3], t[3][2];
    for (int k = 0; k < 3; k++) {
        uint32_t v = model->triangles[3 * tri + k];
        project(&r->view, r->side, model->positions + 3 * (size_t)v, s[k]);
        t[k][0] = model->uvs[2 * (size_t)v] * img->width;
        t[k][1] = model->uvs[2 * (size_t)v + 1] * img->height;
    }
    double a = s[1][0] - s[0][0], b = s[2][0] - s[0][0], c = s[1][1] - s[0][1], d = s[2][1] - s[0][1];
    double det = a * d - b * c;
    if (!(fabs(det) > 1e-12))
        return -1;
    /* J = T S^-1 with S = [[a, b], [c, d]] the screen edges and T the texel edges. */
    double si[4] = {d / det, -b / det, -c / det, a / det};
    double T[4] = {t[1][0] - t[0][0], t[2][0] - t[0][0], t[1][1] - t[0][1], t[2][1] - t[0][1]};
    jac[0] = T[0] * si[0] + T[1] * si[2];
    jac[1] = T[0] * si[1] + T[1] * si[3];
    jac[2] = T[2] * si[0] + T[3] * si[2];
    jac[3] = T[2] * si[1] + T[3] * si[3];
    return 0;
}

static void to_rgb(const float *texel, int channels, float *rgb)
{
    if (channels >= 3) {
        rgb[0] = texel[0];
        rgb[1] = texel[1];
        rgb[2] = texel[2];
    } else {
        rgb[0] = rgb[1] = rgb[2] = texel[0];
    }
}

/* The grey a luma shading shows of a texel whose binding reads `channels` (TEXOPT_CHANNEL_*):
 * the luma of its RGB when it reads all three, else the mean of the channels it reads, so a
 * map whose numbers are in one channel (occlusion's R, specular's A) is judged on that
 * channel, not on whatever the others of a shared image hold. */
static float texel_grey(const float *texel, int img_channels, unsigned channels, const float rgb[3])
{
    if ((channels & TEXOPT_CHANNELS_RGB) == TEXOPT_CHANNELS_RGB)
        return texopt_luma(rgb, 3);
    float sum = 0.0f;
    int n = 0;
    for (int c = 0; c < 4; c++)
        if ((channels >> c) & 1u) {
            int ic = texopt_image_channel_of(img_channels, c);
            sum += ic >= 0 ? texel[ic] : 1.0f;
            n++;
        }
    return n ? sum / (float)n : texopt_luma(rgb, 3);
}

/* Stores a shaded pixel into out: 3 floats (RGB) per pixel, or with `luma` one grey float
 * (texopt_luma of the RGB for a colour texture); background pixels are 0. */
static void store_pixel(const float rgb[3], int luma, float *px)
{
    if (luma) {
        px[0] = texopt_luma(rgb, 3);
    } else {
        px[0] = rgb[0];
        px[1] = rgb[1];
        px[2] = rgb[2];
    }
}

/* Per model triangle, its material when base colour's alpha shows on it (alphaMode MASK or
 * BLEND), else NULL; *out NULL when no triangle has one. */
static texopt_status triangle_cut_outs(const texopt_model *model, const texopt_material ***out, char *err,
                                       size_t err_len)
{
    *out = NULL;
    for (int p = 0; p < model->primitive_count; p++) {
        const texopt_primitive *prim = &model->primitives[p];
        if (prim->material < 0 || prim->material >= model->material_count ||
            model->materials[prim->material].alpha_mode == TEXOPT_ALPHA_OPAQUE)
            continue;
        if (!*out && !(*out = calloc(model->triangle_count ? model->triangle_count : 1, sizeof **out)))
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the triangle materials");
        for (size_t t = prim->first_triangle;
             t < prim->first_triangle + prim->triangle_count && t < model->triangle_count; t++)
            (*out)[t] = &model->materials[prim->material];
    }
    return TEXOPT_OK;
}

/* rgb as the surface shows it over the backdrop, mid grey, given base colour's alpha: hidden
 * below the cutoff of a MASK, blended by a BLEND. One surface is drawn per pixel, so what lies
 * behind a cut-out is not: the backdrop stands in for it, which is enough for a layout that
 * moves or blurs a cut-out's edge to change the picture as it would on screen. */
static void composite_cut_out(const texopt_material *mat, float alpha, float rgb[3])
{
    float a = mat->alpha_mode == TEXOPT_ALPHA_MASK ? (alpha >= mat->alpha_cutoff ? 1.0f : 0.0f) : alpha;
    for (int k = 0; k < 3; k++)
        rgb[k] = a * rgb[k] + (1.0f - a) * 0.5f;
}

static texopt_status shade_pixels(const texopt_model *model, const texopt_raster *raster, int texture,
                                  struct texopt_texture_filter *const *filters, const double *turn, int luma,
                                  float *out, char *err, size_t err_len)
{
    if (!model || !raster || !raster->triangle || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "nothing to shade");
    if (texture < 0 || texture >= TEXOPT_TEXTURE_KEY_COUNT)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "unknown texture %d", texture);
    if (!model->uvs)
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "model has no TEXCOORD_0 to shade with");
    for (size_t t = 0; t < model->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            if (model->triangles[3 * t + k] >= model->vertex_count)
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                                   "triangle %zu names a vertex past the vertex count", t);
    const texopt_texture_ref **ref = NULL;
    const texopt_material **cut_out = NULL;
    texopt_status st = texopt_meshrender_triangle_bindings(model, texture, &ref, err, err_len);
    if (st == TEXOPT_OK && texture == TEXOPT_SLOT_BASE_COLOR)
        st = triangle_cut_outs(model, &cut_out, err, err_len);
    if (st != TEXOPT_OK) {
        free(ref);
        return st;
    }
    int stride = luma ? 1 : 3;
    unsigned channels = texopt_texture_key_channels(texture);
    size_t n = (size_t)raster->side * (size_t)raster->side;
    int32_t jac_tri = -1; /* the triangle whose footprint jac holds */
    double jac[4] = {1, 0, 0, 1};
    int jac_ok = 0;
    for (size_t i = 0; i < n; i++) {
        int32_t tri = raster->triangle[i];
        float rgb[3] = {0, 0, 0};
        float *px = out + (size_t)stride * i;
        if (tri >= 0 && (size_t)tri >= model->triangle_count) {
            free(ref);
            free(cut_out);
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "raster names triangle %d but the model has %zu", (int)tri, model->triangle_count);
        }
        const texopt_texture_ref *r = tri >= 0 ? ref[tri] : NULL;
        if (!r) {
            if (tri >= 0)
                rgb[0] = rgb[1] = rgb[2] = 0.5f;
            store_pixel(rgb, luma, px);
            continue;
        }
        const texopt_image *img = &model->images[r->image];
        double x, y;
        pixel_texel(model, img, (size_t)tri, raster->bary[2 * i], raster->bary[2 * i + 1], &x, &y);
        float texel[4];
        struct texopt_texture_filter *f = filters ? filters[r->image] : NULL;
        if (f && tri != jac_tri) {
            jac_ok = triangle_footprint(model, raster, img, (size_t)tri, jac) == 0;
            jac_tri = tri;
        }
        if (f && jac_ok)
            texopt_texture_filter_sample(f, x, y, jac, texel);
        else
            texopt_sample_bilinear(img, r->wrap_s, r->wrap_t, x, y, texel);
        if (turn && img->channels >= 2)
            texopt_normal_turn(turn[2 * tri], turn[2 * tri + 1], texel);
        to_rgb(texel, img->channels, rgb);
        if (cut_out && cut_out[tri] && (img->channels == 2 || img->channels == 4))
            composite_cut_out(cut_out[tri], texel[img->channels - 1], rgb);
        if (luma)
            px[0] = texel_grey(texel, img->channels, channels, rgb);
        else
            store_pixel(rgb, 0, px);
    }
    free(ref);
    free(cut_out);
    return TEXOPT_OK;
}

static texopt_status shade(const texopt_model *model, const texopt_raster *raster,
                           struct texopt_texture_filter *const *filters, texopt_image *out, char *err, size_t err_len)
{
    memset(out, 0, sizeof *out);
    if (!raster || raster->side <= 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "nothing to shade");
    texopt_status st = texopt_image_create(out, raster->side, raster->side, 3, err, err_len);
    if (st == TEXOPT_OK)
        st = shade_pixels(model, raster, TEXOPT_SLOT_BASE_COLOR, filters, NULL, 0, out->pixels, err, err_len);
    if (st != TEXOPT_OK)
        texopt_image_destroy(out);
    return st;
}

texopt_status texopt_meshrender_shade(const texopt_model *model, const texopt_raster *raster, texopt_image *out,
                                      char *err, size_t err_len)
{
    return shade(model, raster, NULL, out, err, err_len);
}

texopt_status texopt_meshrender_shade_filtered(const texopt_model *model, const texopt_raster *raster,
                                               struct texopt_texture_filter *const *filters, texopt_image *out,
                                               char *err, size_t err_len)
{
    return shade(model, raster, filters, out, err, err_len);
}

texopt_status texopt_meshrender_shade_luma(const texopt_model *model, const texopt_raster *raster, int texture,
                                           struct texopt_texture_filter *const *filters, const double *normal_turn,
                                           float *luma, char *err, size_t err_len)
{
    return shade_pixels(model, raster, texture, filters, normal_turn, 1, luma, err, err_len);
}

texopt_status texopt_meshrender_shade_rgb(const texopt_model *model, const texopt_raster *raster, int texture,
                                          struct texopt_texture_filter *const *filters, const double *normal_turn,
                                          float *rgb, char *err, size_t err_len)
{
    return shade_pixels(model, raster, texture, filters, normal_turn, 0, rgb, err, err_len);
}

texopt_status texopt_meshrender_same_geometry(const texopt_model *reference, const texopt_model *candidate, char *err,
                                              size_t err_len)
{
    if (!reference || !candidate)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "missing model");
    if (reference->triangle_count != candidate->triangle_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "the models differ in triangle count (%zu vs %zu)",
                           reference->triangle_count, candidate->triangle_count);
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (size_t v = 0; v < reference->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], reference->positions[3 * v + k]);
            hi[k] = fmax(hi[k], reference->positions[3 * v + k]);
        }
    double diag = 0;
    for (int k = 0; k < 3; k++)
        diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    double tol = 1e-5 * sqrt(diag);
    for (size_t t = 0; t < reference->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            uint32_t a = reference->triangles[3 * t + c], b = candidate->triangles[3 * t + c];
            if (a >= reference->vertex_count || b >= candidate->vertex_count)
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                                   "triangle %zu names a vertex past the vertex count", t);
            for (int k = 0; k < 3; k++)
                if (!(fabs(reference->positions[3 * (size_t)a + k] - candidate->positions[3 * (size_t)b + k]) <= tol))
                    return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                                       "triangle %zu corner %d is not at the same position in both models", t, c);
        }
    return TEXOPT_OK;
}

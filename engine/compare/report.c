/* report.c - self-contained HTML report of a comparison (see report.h; Sun et al. 2022, 5).
 *
 * Built as one string in memory (the images dominate: a few hundred kB of base64 PNG), then
 * written atomically. The plot is hand-made SVG: axes, one polyline per method through its
 * successful points ordered by achieved cost, a dot per point with a <title> tooltip. UV
 * maps are rasterised here into small images (one flat colour per triangle) rather than
 * emitted as SVG polygons, which would cost ~60 bytes per triangle and method.
 * Does not: run methods, evaluate, or fetch anything. */
#include "report.h"

#include "info.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "atomic_file.h"
#include "image_io.h"
#include "meshrender.h"
#include "resize.h"

/* Before/after rows in the renders section. */
#define REPORT_VIEWS 3
/* Texture domains whose layouts the report shows (in the model's order): a model of dozens
 * of materials would otherwise make a report of hundreds of images. */
#define REPORT_DOMAINS 8

/* ---- a growing string ---------------------------------------------------------------- */

typedef struct sbuf {
    char *data;
    size_t len, cap;
    int failed;
} sbuf;

static void sb_reserve(sbuf *s, size_t extra)
{
    if (s->failed || s->len + extra + 1 <= s->cap)
        return;
    size_t cap = s->cap ? s->cap : 4096;
    while (cap < s->len + extra + 1)
        cap *= 2;
    char *d = realloc(s->data, cap);
    if (!d) {
        s->failed = 1;
        return;
    }
    s->data = d;
    s->cap = cap;
}

static void sb_append(sbuf *s, const char *text, size_t n)
{
    sb_reserve(s, n);
    if (s->failed)
        return;
    memcpy(s->data + s->len, text, n);
    s->len += n;
    s->data[s->len] = 0;
}

static void sb_puts(sbuf *s, const char *text)
{
    sb_append(s, text, strlen(text));
}

__attribute__((format(printf, 2, 3))) static void sb_printf(sbuf *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0) {
        s->failed = 1;
        return;
    }
    sb_reserve(s, (size_t)n);
    if (s->failed)
        return;
    va_start(ap, fmt);
    vsnprintf(s->data + s->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    s->len += (size_t)n;
}

static void sb_escaped(sbuf *s, const char *text)
{
    for (const char *p = text; *p; p++) {
        switch (*p) {
        case '<': sb_puts(s, "&lt;"); break;
        case '>': sb_puts(s, "&gt;"); break;
        case '&': sb_puts(s, "&amp;"); break;
        case '"': sb_puts(s, "&quot;"); break;
        default: sb_append(s, p, 1);
        }
    }
}

static void sb_base64(sbuf *s, const unsigned char *bytes, size_t n)
{
    static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    sb_reserve(s, (n + 2) / 3 * 4);
    for (size_t i = 0; i < n && !s->failed; i += 3) {
        unsigned v = (unsigned)bytes[i] << 16;
        if (i + 1 < n)
            v |= (unsigned)bytes[i + 1] << 8;
        if (i + 2 < n)
            v |= bytes[i + 2];
        char q[4] = {alphabet[(v >> 18) & 63], alphabet[(v >> 12) & 63], i + 1 < n ? alphabet[(v >> 6) & 63] : '=',
                     i + 2 < n ? alphabet[v & 63] : '='};
        sb_append(s, q, 4);
    }
}

/* <img> with img inlined as a PNG data URI. */
static texopt_status sb_png_img(sbuf *s, const texopt_image *img, const char *alt, char *err, size_t err_len)
{
    unsigned char *png = NULL;
    size_t len = 0;
    texopt_status st = texopt_image_encode_png(img, &png, &len, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    sb_printf(s, "<img width=\"%d\" height=\"%d\" alt=\"", img->width, img->height);
    sb_escaped(s, alt);
    sb_puts(s, "\" src=\"data:image/png;base64,");
    sb_base64(s, png, len);
    sb_puts(s, "\">");
    free(png);
    return TEXOPT_OK;
}

/* ---- the q_r-c_r plot ------------------------------------------------------------------ */

static const char *method_colour(texopt_method m)
{
    switch (m) {
    case TEXOPT_METHOD_PERCEPTUAL: return "#d62728";
    case TEXOPT_METHOD_INPUT: return "#1f77b4";
    case TEXOPT_METHOD_SSP: return "#2ca02c";
    case TEXOPT_METHOD_TEWARI: return "#9467bd";
    case TEXOPT_METHOD_ARAP: return "#ff7f0e";
    case TEXOPT_METHOD_PAPER: return "#8c564b";
    default: return "#555555";
    }
}

/* Indices of the curve's successful points ordered by achieved cost; returns the count. */
static int ordered_points(const texopt_compare_curve *c, int *idx)
{
    int n = 0;
    for (int i = 0; i < c->point_count; i++) {
        if (c->points[i].status != TEXOPT_OK)
            continue;
        int k = n++;
        while (k > 0 && c->points[idx[k - 1]].cost_achieved > c->points[i].cost_achieved) {
            idx[k] = idx[k - 1];
            k--;
        }
        idx[k] = i;
    }
    return n;
}

static void plot_svg(sbuf *s, const texopt_compare_result *r)
{
    const double W = 640, H = 400, L = 60, R = 150, T = 20, B = 50;
    double xmax = 1.0, ymax = 0.01;
    for (int c = 0; c < r->curve_count; c++)
        for (int i = 0; i < r->curves[c].point_count; i++) {
            const texopt_compare_point *p = &r->curves[c].points[i];
            if (p->status != TEXOPT_OK)
                continue;
            xmax = fmax(xmax, p->cost_achieved);
            ymax = fmax(ymax, p->q);
        }
    ymax *= 1.1;
    double pw = W - L - R, ph = H - T - B;
#define PX(x) (L + (x) / xmax * pw)
#define PY(y) (T + ph - (y) / ymax * ph)
    sb_printf(s, "<svg class=\"plot\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\">\n", W, H, W, H);
    sb_printf(s, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#fff\" stroke=\"#333\"/>\n", L, T,
              pw, ph);
    for (int k = 0; k <= 5; k++) {
        double x = xmax * k / 5, y = ymax * k / 5;
        sb_printf(s,
                  "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                  "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" text-anchor=\"middle\">%.2f</text>\n",
                  PX(x), T, PX(x), T + ph, PX(x), T + ph + 15, x);
        sb_printf(s,
                  "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                  "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">%.3f</text>\n",
                  L, PY(y), L + pw, PY(y), L - 5, PY(y) + 4, y);
    }
    sb_printf(s,
              "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\" text-anchor=\"middle\">relative cost c_r "
              "(covered texels / input)</text>\n",
              L + pw / 2, H - 10);
    sb_printf(s,
              "<text x=\"14\" y=\"%.1f\" font-size=\"12\" text-anchor=\"middle\" transform=\"rotate(-90 14 %.1f)\">"
              "whole-mesh loss q (GMSD)</text>\n",
              T + ph / 2, T + ph / 2);
    for (int c = 0; c < r->curve_count; c++) {
        const texopt_compare_curve *curve = &r->curves[c];
        const char *name = texopt_method_name(curve->method), *colour = method_colour(curve->method);
        int idx[TEXOPT_COMPARE_MAX_COSTS];
        int n = ordered_points(curve, idx);
        double ly = T + 10 + 20 * c;
        sb_printf(s,
                  "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2\"/>"
                  "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">%s%s</text>\n",
                  L + pw + 10, ly, L + pw + 30, ly, colour, L + pw + 35, ly + 4, name, n == 0 ? " (no points)" : "");
        if (n == 0)
            continue;
        sb_printf(
            s, "<polyline class=\"curve\" data-method=\"%s\" fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"",
            name, colour);
        for (int k = 0; k < n; k++) {
            const texopt_compare_point *p = &curve->points[idx[k]];
            sb_printf(s, "%s%.1f,%.1f", k ? " " : "", PX(p->cost_achieved), PY(p->q));
        }
        sb_puts(s, "\"/>\n");
        for (int k = 0; k < n; k++) {
            const texopt_compare_point *p = &curve->points[idx[k]];
            sb_printf(
                s, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"%s\"><title>%s: c_r %.3f, q %.4f</title></circle>\n",
                PX(p->cost_achieved), PY(p->q), colour, name, p->cost_achieved, p->q);
        }
    }
#undef PX
#undef PY
    sb_puts(s, "</svg>\n");
}

static void results_table(sbuf *s, const texopt_compare_result *r)
{
    sb_puts(s, "<table><tr><th>method</th><th>c_r asked</th><th>c_r achieved</th><th>q</th>"
               "<th>texture pixels</th><th>packing</th><th>seconds</th></tr>\n");
    for (int c = 0; c < r->curve_count; c++)
        for (int i = 0; i < r->curves[c].point_count; i++) {
            const texopt_compare_point *p = &r->curves[c].points[i];
            sb_printf(s, "<tr><td>%s</td><td>%.3f</td>", texopt_method_name(r->curves[c].method), p->cost_requested);
            if (p->status == TEXOPT_OK)
                sb_printf(s, "<td>%.3f</td><td>%.5f</td><td>%llu</td><td>%.3f</td><td>%.1f</td></tr>\n",
                          p->cost_achieved, p->q, (unsigned long long)p->texture_pixels, p->packing_efficiency,
                          p->seconds_optimize + p->seconds_evaluate);
            else {
                sb_printf(s, "<td colspan=\"5\" class=\"failed\">%s: ", texopt_strerror(p->status));
                sb_escaped(s, p->message);
                sb_puts(s, "</td></tr>\n");
            }
        }
    sb_puts(s, "</table>\n");
}

/* ---- renders, textures, UV maps ---------------------------------------------------------- */

/* The texture q's measure shows: the measured one, base colour for lit. */
static int shown_texture(int measure)
{
    return measure == TEXOPT_COMPARE_LIT ? TEXOPT_SLOT_BASE_COLOR : measure;
}

/* One view of model (the input or a showcase) as q's measure shows it (evaluate.h). */
static texopt_status render_view(const texopt_compare_result *r, const texopt_model *model, const texopt_raster *raster,
                                 sbuf *s, const char *alt, char *err, size_t err_len)
{
    texopt_evaluate_options measure = {0};
    measure.lit = r->measure == TEXOPT_COMPARE_LIT;
    measure.texture = shown_texture(r->measure);
    texopt_image img;
    texopt_status st = texopt_evaluate_render(r->input, model, &measure, raster, &img, err, err_len);
    if (st == TEXOPT_OK)
        st = sb_png_img(s, &img, alt, err, err_len);
    texopt_image_destroy(&img);
    return st;
}

/* A showcase evaluated on every one of the 20 views the renders use. */
static int has_view_losses(const texopt_compare_curve *curve)
{
    return curve->showcase && curve->showcase_evaluation.view_count == TEXOPT_VIEW_COUNT;
}

/* The REPORT_VIEWS views the renders show: those with the largest mean GMSD over the
 * showcases, largest first, so that the renders show where the budget costs the most;
 * without a measured showcase, three views spread around the model. Returns 1 when the
 * views were chosen by loss. */
static int chosen_views(const texopt_compare_result *r, int *views)
{
    static const int spread[REPORT_VIEWS] = {0, 7, 13};
    double total[TEXOPT_VIEW_COUNT] = {0}; /* over the measured showcases: ranks as the mean */
    int measured = 0;
    for (int c = 0; c < r->curve_count; c++)
        if (has_view_losses(&r->curves[c])) {
            measured++;
            for (int v = 0; v < TEXOPT_VIEW_COUNT; v++)
                total[v] += r->curves[c].showcase_evaluation.view_gmsd[v];
        }
    if (!measured) {
        memcpy(views, spread, sizeof spread);
        return 0;
    }
    for (int k = 0; k < REPORT_VIEWS; k++) {
        int best = -1;
        for (int v = 0; v < TEXOPT_VIEW_COUNT; v++) {
            int taken = 0;
            for (int j = 0; j < k; j++)
                taken |= views[j] == v;
            if (!taken && (best < 0 || total[v] > total[best]))
                best = v;
        }
        views[k] = best;
    }
    return 1;
}

static texopt_status renders_section(sbuf *s, const texopt_compare_result *r, int side, char *err, size_t err_len)
{
    int views[REPORT_VIEWS];
    int by_loss = chosen_views(r, views);
    texopt_view all[TEXOPT_VIEW_COUNT];
    texopt_status st = texopt_meshrender_views(r->input, all, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    sb_printf(s, "<h2>Renders of the %s%s at c_r = %.2f (equal pixel budget)</h2>\n<p>%s</p>\n",
              texopt_compare_measure_name(r->measure), r->measure == TEXOPT_COMPARE_LIT ? " render" : " texture",
              r->showcase_cost,
              by_loss ? "The three of the 20 views with the largest loss, mean over the methods; under each render "
                        "its GMSD in that view."
                      : "Three of the 20 views.");
    sb_puts(s, "<table class=\"renders\"><tr><th>view</th><th>input (reference)</th>");
    for (int c = 0; c < r->curve_count; c++)
        sb_printf(s, "<th>%s</th>", texopt_method_name(r->curves[c].method));
    sb_puts(s, "</tr>\n");
    for (int v = 0; v < REPORT_VIEWS && st == TEXOPT_OK; v++) {
        texopt_raster raster;
        st = texopt_meshrender_rasterize(r->input, &all[views[v]], side, &raster, err, err_len);
        if (st != TEXOPT_OK)
            break;
        sb_printf(s, "<tr><td>%d</td><td>", views[v]);
        st = render_view(r, r->input, &raster, s, "input", err, err_len);
        sb_puts(s, "</td>");
        for (int c = 0; c < r->curve_count && st == TEXOPT_OK; c++) {
            sb_puts(s, "<td>");
            if (r->curves[c].showcase) {
                st = render_view(r, r->curves[c].showcase, &raster, s, texopt_method_name(r->curves[c].method), err,
                                 err_len);
                if (has_view_losses(&r->curves[c]))
                    sb_printf(s, "<br>GMSD %.5f", r->curves[c].showcase_evaluation.view_gmsd[views[v]]);
            } else
                sb_puts(s, "(not available)");
            sb_puts(s, "</td>");
        }
        sb_puts(s, "</tr>\n");
        texopt_raster_destroy(&raster);
    }
    sb_puts(s, "</table>\n");
    return st;
}

/* The image of the measured texture (shown_texture) on the first primitive of domain d that
 * binds it; -1 when none does. */
static int measured_image(const texopt_model *m, int d, int measure)
{
    int texture = shown_texture(measure);
    for (int i = 0; d < m->domain_count && i < m->domains[d].primitive_count; i++) {
        const texopt_texture_ref *ref = texopt_meshrender_binding(m, m->domains[d].primitives[i], texture);
        if (ref)
            return ref->image;
    }
    return -1;
}

/* The measured texture's image (measured_image), resized to fit side x side. */
static texopt_status texture_thumbnail(sbuf *s, const texopt_model *m, int d, int measure, int side, const char *alt,
                                       char *err, size_t err_len)
{
    int image = measured_image(m, d, measure);
    if (image < 0 || !m->images[image].pixels) {
        sb_puts(s, "(no texture)");
        return TEXOPT_OK;
    }
    const texopt_image *img = &m->images[image];
    double f = (double)side / (img->width > img->height ? img->width : img->height);
    int w = (int)fmax(1, floor(img->width * f + 0.5)), h = (int)fmax(1, floor(img->height * f + 0.5));
    texopt_image small;
    texopt_status st = texopt_image_resize(img, w, h, &small, err, err_len);
    if (st == TEXOPT_OK) {
        sb_printf(s, "%dx%d<br>", img->width, img->height);
        st = sb_png_img(s, &small, alt, err, err_len);
    }
    texopt_image_destroy(&small);
    return st;
}

static void ramp(double t, float *rgb)
{
    /* Black -> purple -> orange -> light yellow, a perceptually ordered heat ramp. */
    static const float stops[4][3] = {
        {0, 0, 0.02f}, {0.47f, 0.11f, 0.43f}, {0.96f, 0.49f, 0.09f}, {0.99f, 1.0f, 0.64f}};
    t = fmin(1, fmax(0, t)) * 3;
    int i = (int)fmin(2, floor(t));
    double f = t - i;
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)(stops[i][k] * (1 - f) + stops[i + 1][k] * f);
}

static void diverging(double t, float *rgb)
{
    /* t in [-1, 1]: blue (shrunk) - white - red (grown). */
    t = fmin(1, fmax(-1, t));
    if (t < 0) {
        rgb[0] = rgb[1] = (float)(1 + t * 0.85);
        rgb[2] = 1;
    } else {
        rgb[0] = 1;
        rgb[1] = rgb[2] = (float)(1 - t * 0.85);
    }
}

static void fill_uv_triangle(texopt_image *img, const double p[3][2], const float *rgb)
{
    double area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
    if (!(fabs(area) > 1e-12))
        return;
    int x0 = (int)fmax(0, floor(fmin(p[0][0], fmin(p[1][0], p[2][0]))));
    int x1 = (int)fmin(img->width - 1, ceil(fmax(p[0][0], fmax(p[1][0], p[2][0]))));
    int y0 = (int)fmax(0, floor(fmin(p[0][1], fmin(p[1][1], p[2][1]))));
    int y1 = (int)fmin(img->height - 1, ceil(fmax(p[0][1], fmax(p[1][1], p[2][1]))));
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            double px = x + 0.5, py = y + 0.5;
            double b1 = ((px - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (py - p[0][1])) / area;
            double b2 = ((p[1][0] - p[0][0]) * (py - p[0][1]) - (px - p[0][0]) * (p[1][1] - p[0][1])) / area;
            if (b1 < 0 || b2 < 0 || b1 + b2 > 1)
                continue;
            memcpy(texopt_image_at(img, x, y), rgb, 3 * sizeof(float));
        }
}

/* Texel area of triangle t of m in the frame of its domain (0 when untextured). */
static double texel_area(const texopt_model *m, size_t t, const int *domain_of)
{
    int d = domain_of[t];
    if (d < 0 || !m->uvs)
        return 0;
    const uint32_t *c = m->triangles + 3 * t;
    const float *a = m->uvs + 2 * (size_t)c[0], *b = m->uvs + 2 * (size_t)c[1], *e = m->uvs + 2 * (size_t)c[2];
    double uv = 0.5 * fabs((double)(b[0] - a[0]) * (e[1] - a[1]) - (double)(e[0] - a[0]) * (b[1] - a[1]));
    return uv * m->domains[d].width * m->domains[d].height;
}

static int *triangle_domains(const texopt_model *m)
{
    int *d = malloc((m->triangle_count ? m->triangle_count : 1) * sizeof *d);
    if (!d)
        return NULL;
    for (size_t t = 0; t < m->triangle_count; t++)
        d[t] = -1;
    for (int p = 0; p < m->primitive_count; p++)
        for (size_t t = m->primitives[p].first_triangle;
             t < m->primitives[p].first_triangle + m->primitives[p].triangle_count && t < m->triangle_count; t++)
            d[t] = m->primitives[p].domain;
    return d;
}

/* Two UV maps of the showcase layout of domain d: per-triangle error (scaled by err_max)
 * and log2 of the triangle's texel area ratio over the mean ratio c_r. */
static texopt_status uv_maps(sbuf *s, const texopt_compare_result *r, const texopt_compare_curve *c, int d, int side,
                             double err_max, char *err, size_t err_len)
{
    const texopt_model *m = c->showcase;
    int *dom_in = triangle_domains(r->input), *dom_out = triangle_domains(m);
    texopt_image maps[2] = {{0}, {0}};
    texopt_status st =
        (dom_in && dom_out) ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for UV maps");
    for (int k = 0; k < 2 && st == TEXOPT_OK; k++) {
        st = texopt_image_create(&maps[k], side, side, 3, err, err_len);
        for (size_t i = 0; st == TEXOPT_OK && i < (size_t)side * side * 3; i++)
            maps[k].pixels[i] = 0.25f;
    }
    double mean_ratio = 0, in_total = 0;
    for (size_t t = 0; st == TEXOPT_OK && t < m->triangle_count; t++) {
        mean_ratio += texel_area(m, t, dom_out);
        in_total += texel_area(r->input, t, dom_in);
    }
    mean_ratio = in_total > 0 ? mean_ratio / in_total : 1;
    for (size_t t = 0; st == TEXOPT_OK && t < m->triangle_count; t++) {
        if (dom_out[t] != d)
            continue;
        double p[3][2], cu = 0, cv = 0;
        for (int k = 0; k < 3; k++) {
            cu += m->uvs[2 * (size_t)m->triangles[3 * t + k]] / 3.0;
            cv += m->uvs[2 * (size_t)m->triangles[3 * t + k] + 1] / 3.0;
        }
        /* Triangles that live in a REPEAT copy are drawn in the [0,1) square they read. */
        double su = floor(cu), sv = floor(cv);
        for (int k = 0; k < 3; k++) {
            const float *uv = m->uvs + 2 * (size_t)m->triangles[3 * t + k];
            p[k][0] = (uv[0] - su) * side;
            p[k][1] = (uv[1] - sv) * side;
        }
        float rgb[3];
        ramp(err_max > 0 && c->showcase_triangle_error ? c->showcase_triangle_error[t] / err_max : 0, rgb);
        fill_uv_triangle(&maps[0], p, rgb);
        double a_in = texel_area(r->input, t, dom_in), a_out = texel_area(m, t, dom_out);
        double ratio = a_in > 0 && a_out > 0 ? log2(a_out / a_in / mean_ratio) / 3 : 0;
        diverging(ratio, rgb);
        fill_uv_triangle(&maps[1], p, rgb);
    }
    if (st == TEXOPT_OK) {
        sb_puts(s, "<td>");
        st = sb_png_img(s, &maps[0], "per-triangle loss", err, err_len);
        sb_puts(s, "</td><td>");
        if (st == TEXOPT_OK)
            st = sb_png_img(s, &maps[1], "lambda1 lambda2", err, err_len);
        sb_puts(s, "</td>");
    }
    texopt_image_destroy(&maps[0]);
    texopt_image_destroy(&maps[1]);
    free(dom_in);
    free(dom_out);
    return st;
}

/* One row of the layouts table: a method's new texture and UV maps in domain d. */
static texopt_status layout_row(sbuf *s, const texopt_compare_result *r, const texopt_compare_curve *curve, int d,
                                int side, double err_max, char *err, size_t err_len)
{
    sb_printf(s, "<tr><td>%s</td>", texopt_method_name(curve->method));
    if (r->input->domain_count > 1)
        sb_printf(s, "<td>%d</td>", d);
    if (!curve->showcase) {
        sb_puts(s, "<td colspan=\"3\">(not available)</td></tr>\n");
        return TEXOPT_OK;
    }
    sb_puts(s, "<td>");
    texopt_status st =
        texture_thumbnail(s, curve->showcase, d, r->measure, side, texopt_method_name(curve->method), err, err_len);
    sb_puts(s, "</td>");
    if (st == TEXOPT_OK)
        st = uv_maps(s, r, curve, d, side, err_max, err, err_len);
    sb_puts(s, "</tr>\n");
    return st;
}

static texopt_status layouts_section(sbuf *s, const texopt_compare_result *r, int side, char *err, size_t err_len)
{
    double err_max = 0;
    for (int c = 0; c < r->curve_count; c++)
        if (r->curves[c].showcase && r->curves[c].showcase_triangle_error)
            for (size_t t = 0; t < r->curves[c].showcase->triangle_count; t++)
                err_max = fmax(err_max, r->curves[c].showcase_triangle_error[t]);
    int domains = r->input->domain_count, shown = domains < REPORT_DOMAINS ? domains : REPORT_DOMAINS;
    sb_printf(s,
              "<h2>Layouts at c_r = %.2f</h2>\n<p>Per-triangle loss: mean absolute luma error over "
              "the 20 views, black 0 to light yellow %.3f (common scale). &lambda;<sub>1</sub>&lambda;<sub>2</sub>: "
              "texel area of the triangle over its input texel area, relative to the whole layout's "
              "ratio: blue 8x smaller, white equal, red 8x larger.",
              r->showcase_cost, err_max);
    if (shown < domains)
        sb_printf(s, " The first %d of the model's %d texture domains.", shown, domains);
    sb_printf(s,
              "</p>\n<table class=\"layouts\"><tr><th>method</th>%s<th>new %s texture</th><th>per-triangle loss</th>"
              "<th>&lambda;<sub>1</sub>&lambda;<sub>2</sub></th></tr>\n",
              domains > 1 ? "<th>domain</th>" : "", texopt_compare_measure_name(shown_texture(r->measure)));
    texopt_status st = TEXOPT_OK;
    for (int c = 0; c < r->curve_count && st == TEXOPT_OK; c++)
        for (int d = 0; d < (r->curves[c].showcase ? shown : 1) && st == TEXOPT_OK; d++)
            st = layout_row(s, r, &r->curves[c], d, side, err_max, err, err_len);
    sb_puts(s, "</table>\n");
    return st;
}

texopt_status texopt_report_html(const texopt_compare_result *r, const texopt_report_options *opt, char **html,
                                 char *err, size_t err_len)
{
    if (!r || !html || !r->input)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "report: missing comparison");
    texopt_report_options o = {0};
    if (opt)
        o = *opt;
    if (!o.title)
        o.title = "texopt";
    if (o.render_side <= 0)
        o.render_side = r->resolution > 0 && r->resolution < 512 ? r->resolution : 512;
    if (o.thumbnail_side <= 0)
        o.thumbnail_side = 256;
    if (o.render_side < 8 || o.render_side > 4096 || o.thumbnail_side < 8 || o.thumbnail_side > 4096)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "report: image sides must be in [8, 4096]");
    sbuf s = {0};
    sb_puts(&s, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>");
    sb_escaped(&s, o.title);
    sb_puts(&s, "</title>\n<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
                "td,th{border:1px solid #ccc;padding:4px;text-align:center}.failed{color:#a00;text-align:left}"
                "img{image-rendering:pixelated}</style></head><body>\n<h1>");
    sb_escaped(&s, o.title);
    sb_printf(&s,
              "</h1>\n<p>Whole-mesh loss q of the %s%s (GMSD over 20 views at %d px, %s lookups, Sun et "
              "al. 2022 section 5.1) of every method's layout re-baked at each relative cost. Input: %llu covered "
              "texels, %llu texture pixels, packing efficiency %.3f.</p>\n<h2>Loss against cost</h2>\n",
              texopt_compare_measure_name(r->measure), r->measure == TEXOPT_COMPARE_LIT ? " render" : " texture",
              r->resolution, r->mipmapped ? "mip-mapped" : "bilinear", (unsigned long long)r->input_cost.covered_texels,
              (unsigned long long)r->input_cost.texture_pixels, r->input_cost.packing_efficiency);
    plot_svg(&s, r);
    results_table(&s, r);
    texopt_status st = renders_section(&s, r, o.render_side, err, err_len);
    if (st == TEXOPT_OK)
        st = layouts_section(&s, r, o.thumbnail_side, err, err_len);
    sb_puts(&s, "</body></html>\n");
    if (st == TEXOPT_OK && s.failed)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the report");
    if (st != TEXOPT_OK) {
        free(s.data);
        return st;
    }
    *html = s.data;
    return TEXOPT_OK;
}

texopt_status texopt_report_write_html(const texopt_compare_result *r, const texopt_report_options *opt,
                                       const char *path, char *err, size_t err_len)
{
    if (!path)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "report: missing path");
    char *html = NULL;
    texopt_status st = texopt_report_html(r, opt, &html, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    st = texopt_write_file_atomic(path, html, strlen(html), err, err_len);
    free(html);
    return st;
}

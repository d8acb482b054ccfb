/* test_report.c - the self-contained HTML report (engine/compare/report.h), on a comparison built
 * in memory (no pipeline run). */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "evaluate.h"
#include "fixtures.h"
#include "report.h"
#include "resize.h"
#include "test.h"

static size_t count(const char *hay, const char *needle)
{
    size_t n = 0;
    for (const char *p = strstr(hay, needle); p; p = strstr(p + 1, needle))
        n++;
    return n;
}

static texopt_model *sphere(int tex_side)
{
    texopt_model *m = fixture_uv_sphere(24, 12, 128);
    if (!m)
        return NULL;
    fixture_fill_pattern(&m->images[0], "half");
    if (tex_side != 128) {
        texopt_image small;
        if (texopt_image_resize(&m->images[0], tex_side, tex_side, &small, NULL, 0) != TEXOPT_OK) {
            texopt_model_destroy(m);
            return NULL;
        }
        texopt_image_destroy(&m->images[0]);
        m->images[0] = small;
    }
    return m;
}

/* Three methods: input and ssp with points (ssp with a kept output), tewari all failed. */
static int build_result(texopt_compare_result *r)
{
    memset(r, 0, sizeof *r);
    r->input = sphere(128);
    if (!r->input)
        return -1;
    r->resolution = 96;
    r->showcase_cost = 0.25;
    if (texopt_evaluate_cost(r->input, &r->input_cost, NULL, 0) != TEXOPT_OK)
        return -1;
    const texopt_method methods[3] = {TEXOPT_METHOD_INPUT, TEXOPT_METHOD_SSP, TEXOPT_METHOD_TEWARI};
    const double costs[3] = {0.25, 1.0, 0.5};
    r->curve_count = 3;
    for (int c = 0; c < 3; c++) {
        texopt_compare_curve *curve = &r->curves[c];
        curve->method = methods[c];
        curve->point_count = 3;
        for (int i = 0; i < 3; i++) {
            texopt_compare_point *p = &curve->points[i];
            p->cost_requested = costs[i];
            if (methods[c] == TEXOPT_METHOD_TEWARI) {
                p->status = TEXOPT_E_UNSUPPORTED;
                snprintf(p->message, sizeof p->message, "method <b>tewari</b> not wired");
                continue;
            }
            p->status = TEXOPT_OK;
            p->cost_achieved = costs[i] * (c ? 0.98 : 1.0);
            p->q = 0.2 * (1 - costs[i]) + 0.01 * c;
            p->texture_pixels = (uint64_t)(costs[i] * 16384);
        }
    }
    r->curves[1].showcase = sphere(64);
    r->curves[1].showcase_triangle_error = calloc(r->input->triangle_count, sizeof(double));
    if (!r->curves[1].showcase || !r->curves[1].showcase_triangle_error)
        return -1;
    for (size_t t = 0; t < r->input->triangle_count; t++)
        r->curves[1].showcase_triangle_error[t] = (double)(t % 7) / 7;
    return 0;
}

TEST(report_is_self_contained_with_one_curve_per_method)
{
    texopt_compare_result r;
    CHECK(build_result(&r) == 0);
    char *html = NULL, err[256] = "";
    texopt_report_options opt = {.title = "sphere & <friends>"};
    CHECK_OK(texopt_report_html(&r, &opt, &html, err, sizeof err), err);
    /* Nothing comes from the network: every image is a data URI, no link leaves the file. */
    CHECK(strstr(html, "http://") == NULL && strstr(html, "https://") == NULL);
    CHECK(strstr(html, "href=") == NULL);
    size_t imgs = count(html, "<img ");
    CHECK_EQ_INT(count(html, "src=\"data:image/png;base64,iVBORw0KGgo"), imgs); /* PNG signature */
    CHECK_EQ_INT(count(html, "src="), imgs);
    /* 3 views x (input + ssp) renders, ssp's texture thumbnail and its two UV maps. */
    CHECK_EQ_INT(imgs, 3 * 2 + 3);
    /* One polyline per method with points; tewari has none and says so. */
    CHECK_EQ_INT(count(html, "class=\"curve\""), 2);
    CHECK_EQ_INT(count(html, "data-method=\"input\""), 1);
    CHECK_EQ_INT(count(html, "data-method=\"ssp\""), 1);
    CHECK_EQ_INT(count(html, "data-method=\"tewari\""), 0);
    CHECK(strstr(html, "tewari (no points)") != NULL);
    /* Messages and titles are escaped. */
    CHECK(strstr(html, "&lt;b&gt;tewari&lt;/b&gt;") != NULL);
    CHECK(strstr(html, "sphere &amp; &lt;friends&gt;") != NULL);
    CHECK(strstr(html, "<friends>") == NULL);
    /* The loss is said to be the base colour's unless another slot was measured. */
    CHECK(strstr(html, "q of the baseColor texture") != NULL);
    free(html);
    html = NULL;
    r.measure = TEXOPT_SLOT_NORMAL;
    CHECK_OK(texopt_report_html(&r, &opt, &html, err, sizeof err), err);
    CHECK(strstr(html, "q of the normal texture") != NULL);
    /* Points are drawn in order of achieved cost: x grows along the input polyline. */
    const char *pl = strstr(strstr(html, "data-method=\"input\""), "points=\"");
    CHECK(pl);
    double x[3], y[3];
    CHECK(sscanf(pl, "points=\"%lf,%lf %lf,%lf %lf,%lf", &x[0], &y[0], &x[1], &y[1], &x[2], &y[2]) == 6);
    CHECK(x[0] < x[1] && x[1] < x[2]);
    CHECK(y[0] < y[1] && y[1] < y[2]); /* q falls with cost and SVG y grows downwards */
    CHECK_EQ_INT(count(html, "<svg"), count(html, "</svg>"));
    CHECK_EQ_INT(count(html, "<table"), count(html, "</table>"));
    CHECK_EQ_INT(count(html, "<tr>"), count(html, "</tr>"));
    free(html);
    texopt_compare_result_destroy(&r);
}

/* Moves m's texture to the occlusion slot and gives base colour a flat image of its own. */
static int occlusion_beside_flat_colour(texopt_model *m)
{
    texopt_image *images = realloc(m->images, 2 * sizeof *images);
    char **names = realloc(m->image_names, 2 * sizeof *names);
    if (images)
        m->images = images;
    if (names)
        m->image_names = names;
    if (!images || !names)
        return -1;
    names[1] = NULL;
    if (texopt_image_create(&images[1], 32, 32, 3, NULL, 0) != TEXOPT_OK || fixture_fill_pattern(&images[1], "flat"))
        return -1;
    m->image_count = 2;
    texopt_material *mat = &m->materials[0];
    mat->slot[TEXOPT_SLOT_OCCLUSION] = mat->slot[TEXOPT_SLOT_BASE_COLOR];
    mat->slot[TEXOPT_SLOT_BASE_COLOR].image = 1;
    return texopt_model_build_domains(m, NULL, 0) == TEXOPT_OK ? 0 : -1;
}

/* The second half of m's triangles as a primitive of a second material, whose base colour
 * is a flat image of its own: a second texture domain. */
static int split_into_two_domains(texopt_model *m)
{
    if (fixture_split_primitive(m, m->triangle_count / 2) != 0 || occlusion_beside_flat_colour(m) != 0)
        return -1;
    texopt_material *mats = m->materials;
    mats[0].slot[TEXOPT_SLOT_BASE_COLOR] = mats[0].slot[TEXOPT_SLOT_OCCLUSION];
    mats[0].slot[TEXOPT_SLOT_OCCLUSION].image = -1;
    mats[1].slot[TEXOPT_SLOT_BASE_COLOR].image = 1;
    return texopt_model_build_domains(m, NULL, 0) == TEXOPT_OK && m->domain_count == 2 ? 0 : -1;
}

/* The data URI of the n-th image (0: the first) after `from` in html, as a malloc'ed string. */
static char *image_after(const char *html, const char *from, int n)
{
    const char *p = strstr(html, from), *src = p ? strstr(p, "src=\"") : NULL;
    for (int k = 0; k < n && src; k++)
        src = strstr(src + 5, "src=\"");
    const char *end = src ? strchr(src + 5, '"') : NULL;
    if (!end)
        return NULL;
    char *uri = malloc((size_t)(end - src));
    if (uri) {
        memcpy(uri, src + 5, (size_t)(end - src - 5));
        uri[end - src - 5] = '\0';
    }
    return uri;
}

/* The renders and the texture thumbnail show the texture q measured: with base colour flat
 * and the sphere's pattern as occlusion, the occlusion report's renders and thumbnail are
 * not the base-colour report's. */
TEST(report_shows_the_texture_q_measured)
{
    texopt_compare_result r;
    CHECK(build_result(&r) == 0);
    CHECK(occlusion_beside_flat_colour(r.input) == 0 && occlusion_beside_flat_colour(r.curves[1].showcase) == 0);
    char *colour = NULL, *occlusion = NULL, err[256] = "";
    CHECK_OK(texopt_report_html(&r, NULL, &colour, err, sizeof err), err);
    r.measure = TEXOPT_SLOT_OCCLUSION;
    CHECK_OK(texopt_report_html(&r, NULL, &occlusion, err, sizeof err), err);
    CHECK(strstr(colour, "Renders of the baseColor texture") && strstr(occlusion, "Renders of the occlusion texture"));
    CHECK(strstr(occlusion, "new occlusion texture") != NULL);
    const char *where[] = {"class=\"renders\"", "class=\"layouts\""};
    for (int k = 0; k < 2; k++) {
        char *a = image_after(colour, where[k], 0), *b = image_after(occlusion, where[k], 0);
        CHECK_MSG(a && b && strcmp(a, b) != 0, "%s: the same image for both measures", where[k]);
        free(a);
        free(b);
    }
    free(colour);
    free(occlusion);
    texopt_compare_result_destroy(&r);
}

/* A model of two texture domains shows the layouts of both: one row per method and domain,
 * each with its own texture. */
TEST(report_shows_every_texture_domain)
{
    texopt_compare_result r;
    CHECK(build_result(&r) == 0);
    CHECK(split_into_two_domains(r.input) == 0 && split_into_two_domains(r.curves[1].showcase) == 0);
    char *html = NULL, err[256] = "";
    CHECK_OK(texopt_report_html(&r, NULL, &html, err, sizeof err), err);
    const char *layouts = strstr(html, "class=\"layouts\"");
    CHECK(layouts && strstr(layouts, "<th>domain</th>"));
    /* ssp (with a showcase) in domains 0 and 1, input and tewari one row each. */
    CHECK(strstr(layouts, "<tr><td>ssp</td><td>0</td>") && strstr(layouts, "<tr><td>ssp</td><td>1</td>"));
    CHECK_EQ_INT(count(layouts, "<tr><td>"), 4);
    CHECK_EQ_INT(count(layouts, "<img "), 2 * 3);
    for (int k = 0; k < 2; k++) { /* the texture, then the loss map: each domain's own */
        char *first = image_after(layouts, "<td>0</td>", k), *second = image_after(layouts, "<td>1</td>", k);
        CHECK_MSG(first && second && strcmp(first, second) != 0, "image %d the same in both domains", k);
        free(first);
        free(second);
    }
    free(html);
    texopt_compare_result_destroy(&r);
}

/* The renders table's view numbers, in row order, into views (at most n); returns how many. */
static int render_rows(const char *html, int *views, int n)
{
    const char *p = strstr(html, "class=\"renders\""), *end = p ? strstr(p, "</table>") : NULL;
    int k = 0;
    while (p && k < n && (p = strstr(p, "<tr><td>")) != NULL && p < end) {
        p += strlen("<tr><td>");
        views[k++] = atoi(p);
    }
    return k;
}

TEST(report_renders_the_views_that_lose_most)
{
    texopt_compare_result r;
    CHECK(build_result(&r) == 0);
    char *html = NULL, err[256] = "";
    int views[4];
    /* Without per-view losses, views spread around the model and no per-view figure. */
    CHECK_OK(texopt_report_html(&r, NULL, &html, err, sizeof err), err);
    CHECK_EQ_INT(render_rows(html, views, 4), 3);
    CHECK(views[0] == 0 && views[1] == 7 && views[2] == 13);
    CHECK(strstr(html, "GMSD 0.") == NULL);
    free(html);
    /* Two measured showcases: ranked by the mean, which neither alone gives (ssp alone: 3, 9,
     * 11; input alone: 11, 9, 3). */
    r.curves[0].showcase = sphere(64);
    CHECK(r.curves[0].showcase);
    texopt_evaluation *ssp = &r.curves[1].showcase_evaluation, *in = &r.curves[0].showcase_evaluation;
    ssp->view_count = in->view_count = TEXOPT_VIEW_COUNT;
    for (int v = 0; v < TEXOPT_VIEW_COUNT; v++)
        ssp->view_gmsd[v] = in->view_gmsd[v] = 0.01;
    ssp->view_gmsd[3] = 0.8, in->view_gmsd[3] = 0.0;    /* mean 0.4 */
    ssp->view_gmsd[9] = 0.5, in->view_gmsd[9] = 0.5;    /* mean 0.5 */
    ssp->view_gmsd[11] = 0.1, in->view_gmsd[11] = 0.75; /* mean 0.425 */
    CHECK_OK(texopt_report_html(&r, NULL, &html, err, sizeof err), err);
    CHECK_EQ_INT(render_rows(html, views, 4), 3);
    CHECK(views[0] == 9 && views[1] == 11 && views[2] == 3);
    /* Each measured render carries its own view's loss. */
    CHECK(strstr(html, "GMSD 0.80000") && strstr(html, "GMSD 0.75000") && strstr(html, "GMSD 0.10000"));
    CHECK_EQ_INT(count(html, "<br>GMSD "), 3 * 2);
    free(html);
    texopt_compare_result_destroy(&r);
}

TEST(report_writes_a_file_and_refuses_bad_input)
{
    texopt_compare_result r;
    CHECK(build_result(&r) == 0);
    char err[256] = "", path[256];
    snprintf(path, sizeof path, "%s/texopt_report_test_%d.html", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp",
             (int)getpid());
    CHECK_OK(texopt_report_write_html(&r, NULL, path, err, sizeof err), err);
    FILE *f = fopen(path, "rb");
    CHECK(f);
    char head[16] = {0};
    CHECK(fread(head, 1, 15, f) == 15);
    fclose(f);
    remove(path);
    CHECK(strncmp(head, "<!DOCTYPE html>", 15) == 0);
    texopt_report_options bad = {.render_side = 3};
    char *html = NULL;
    CHECK(texopt_report_html(&r, &bad, &html, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_report_html(NULL, NULL, &html, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_compare_result_destroy(&r);
}

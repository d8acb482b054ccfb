/* budget.c - scale + pack + measure loops of the two budgets (see budget.h). */
#include "budget.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "chart_orient.h"
#include "coverage.h"
#include "parallel.h"

#define MAX_SIDE 16384
#define COST_TOLERANCE 0.005
#define COST_ROUNDS 6
#define BISECTION_STEPS 14
#define SMALL_ATLAS_CHARTS 64 /* up to this many charts, more widths and orders are tried */
#define ORDER_SEARCH_STEPS 20 /* local-search moves over the placement order per rule (small atlases) */
#define RULES 3               /* texopt_pack_rule values */
#define START_ORDERS 3
#define WIDTH_LO 0.75 /* strip widths tried, relative to the estimate */
#define WIDTH_HI 1.35

static int round_up4(double x)
{
    double v = 4.0 * ceil(x / 4.0);
    return v < 4 ? 4 : (v > MAX_SIDE ? MAX_SIDE + 1 : (int)v);
}

static void scale_layout(const double *in, double s, double *out, size_t vertices)
{
    for (size_t i = 0; i < 2 * vertices; i++)
        out[i] = in[i] * s;
}

static texopt_status measure_cost(const texopt_mesh *mesh, const double *texel, int w, int h, double *cost, char *err,
                                  size_t err_len)
{
    texopt_coverage_options o = {0};
    o.texel = texel;
    o.width = w;
    o.height = h;
    o.use_wraps = 1;
    o.wrap_s = o.wrap_t = TEXOPT_WRAP_CLAMP;
    texopt_coverage c;
    texopt_status st = texopt_coverage_measure(mesh, &o, &c, err, err_len);
    if (st == TEXOPT_OK)
        *cost = (double)c.covered_texels;
    return st;
}

typedef struct work {
    const texopt_mesh *mesh;
    const double *texel;
    const texopt_pack_options *pack;
    double *scaled, *packed;
    int packings;
    const uint32_t *sequence; /* placement order of the next pack; NULL = req->pack.order */
    int rule;                 /* texopt_pack_rule of the next pack */
    const texopt_monitor *monitor;
    int cell, side; /* grid cell of every packer (0: from side), texture side hint */
    int threads;    /* for the packing search's units; >= 1 */
} work;

/* The packer of the layout scaled by s (into w->scaled, which it then reads). */
static texopt_status make_packer(work *w, double s, texopt_packer **packer, char *err, size_t err_len)
{
    if (texopt_monitor_canceled(w->monitor))
        return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "packing canceled");
    scale_layout(w->texel, s, w->scaled, w->mesh->vertex_count);
    texopt_pack_options opt = *w->pack;
    opt.cell = w->cell;
    return texopt_packer_create(packer, w->mesh, w->scaled, &opt, w->side, err, err_len);
}

/* Packs into width columns (height 0: as tall as needed; the width is then cut to the
 * columns used) or into width x height, in the order w->sequence; *fits says whether it
 * fit, *out_w x *out_h the texture. */
static texopt_status pack_at(work *w, const texopt_packer *packer, int width, int height, int *fits, int *out_w,
                             int *out_h, char *err, size_t err_len)
{
    if (texopt_monitor_canceled(w->monitor))
        return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "packing canceled");
    texopt_pack_result r;
    texopt_pack_options opt = *w->pack;
    opt.sequence = w->sequence;
    opt.rule = w->rule;
    texopt_status st = texopt_packer_run(packer, width, height, &opt, w->packed, &r, fits, err, err_len);
    w->packings++;
    if (st == TEXOPT_OK) {
        *out_w = height == 0 ? round_up4(r.used_width) : r.width;
        *out_h = r.height;
        if (height == 0 && r.height > MAX_SIDE)
            *fits = 0;
        texopt_pack_result_destroy(&r);
    }
    return st;
}

/* The best packing found so far of the order search. */
typedef struct best_packing {
    long long texels;  /* width * height of the texture; -1 = none yet */
    int strip;         /* width of the strip it was packed into */
    int rule;          /* texopt_pack_rule it was packed with */
    int width, height; /* the texture (width cut to the columns used) */
    uint32_t *sequence;
} best_packing;

/* Keeps the packing just made (w->sequence, w->rule into `strip` columns, a pw x ph
 * texture) in best when its texture is smaller; with texel_out, its positions too. Returns 1
 * when it was kept. */
static int offer(const work *w, best_packing *best, int strip, int pw, int ph, double *texel_out)
{
    if (best->texels >= 0 && (long long)pw * ph >= best->texels)
        return 0;
    best->texels = (long long)pw * ph;
    best->strip = strip;
    best->rule = w->rule;
    best->width = pw;
    best->height = ph;
    memcpy(best->sequence, w->sequence, sizeof(uint32_t) * w->mesh->chart_count);
    if (texel_out)
        memcpy(texel_out, w->packed, sizeof(double) * 2 * w->mesh->vertex_count);
    return 1;
}

/* Packs into a strip of `strip` columns with w->sequence and w->rule and offers the result
 * to `best` (positions to texel_out) and, when not NULL, to `local` (positions not kept).
 * Returns 1 when `local` kept it. */
static int try_packing(work *w, const texopt_packer *packer, int strip, best_packing *local, best_packing *best,
                       double *texel_out, texopt_status *st, char *err, size_t err_len)
{
    int fits = 0, pw = 0, ph = 0;
    *st = pack_at(w, packer, strip, 0, &fits, &pw, &ph, err, err_len);
    if (*st != TEXOPT_OK || !fits)
        return 0;
    offer(w, best, strip, pw, ph, texel_out);
    return local ? offer(w, local, strip, pw, ph, NULL) : 0;
}

typedef struct keyed_chart {
    double key;
    uint32_t chart;
} keyed_chart;

static int compare_keyed(const void *a, const void *b)
{
    const keyed_chart *x = a, *y = b;
    if (x->key != y->key)
        return x->key > y->key ? -1 : 1;
    return x->chart < y->chart ? -1 : (x->chart > y->chart);
}

/* Placement orders to start from, largest first: by triangle area, by bounding-box area
 * (elongated charts earlier), by longer side (long thin charts first, before the strip
 * fills up). orders holds START_ORDERS sequences of chart_count. */
static texopt_status start_orders(const texopt_mesh *mesh, const double *texel, uint32_t *orders, char *err,
                                  size_t err_len)
{
    size_t n = mesh->chart_count;
    keyed_chart *k = malloc(sizeof *k * (n ? n : 1));
    double *area = calloc(n ? n : 1, sizeof(double)), *box = malloc(sizeof(double) * 4 * (n ? n : 1));
    if (!k || !box || !area) {
        free(k);
        free(box);
        free(area);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the placement orders");
    }
    for (size_t c = 0; c < n; c++) {
        box[4 * c] = box[4 * c + 1] = INFINITY;
        box[4 * c + 2] = box[4 * c + 3] = -INFINITY;
    }
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t *v = mesh->triangle + 3 * t;
        const double *a = texel + 2 * v[0], *b = texel + 2 * v[1], *d = texel + 2 * v[2];
        uint32_t c = mesh->chart_of[t];
        if (c >= n)
            continue;
        area[c] += 0.5 * fabs((b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]));
        for (int j = 0; j < 3; j++)
            for (int x = 0; x < 2; x++) {
                box[4 * c + x] = fmin(box[4 * c + x], texel[2 * v[j] + x]);
                box[4 * c + 2 + x] = fmax(box[4 * c + 2 + x], texel[2 * v[j] + x]);
            }
    }
    for (int o = 0; o < START_ORDERS; o++) {
        for (size_t c = 0; c < n; c++) {
            double bw = box[4 * c + 2] - box[4 * c], bh = box[4 * c + 3] - box[4 * c + 1];
            k[c].chart = (uint32_t)c;
            k[c].key = !(bw >= 0) ? 0 : o == 0 ? area[c] : o == 1 ? bw * bh : fmax(bw, bh);
        }
        qsort(k, n, sizeof *k, compare_keyed);
        for (size_t i = 0; i < n; i++)
            orders[o * n + i] = k[i].chart;
    }
    free(k);
    free(box);
    free(area);
    return TEXOPT_OK;
}

static uint32_t next_random(uint64_t *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (uint32_t)(*state >> 33);
}

/* A neighbour of `from` in order space: one chart moved to another place in the sequence
 * (a small chart pulled forward can take a hole a large one left; a large one pushed back
 * stops blocking the strip). */
static void perturb(const uint32_t *from, uint32_t *to, size_t n, uint64_t *rng)
{
    memcpy(to, from, sizeof(uint32_t) * n);
    if (n < 2)
        return;
    size_t i = next_random(rng) % n, j = next_random(rng) % (n - 1);
    if (j >= i)
        j++;
    uint32_t c = to[i];
    if (i < j)
        memmove(to + i, to + i + 1, sizeof(uint32_t) * (j - i));
    else
        memmove(to + j + 1, to + j, sizeof(uint32_t) * (i - j));
    to[j] = c;
}

/* One unit of the packing search, run on any thread: one rule's packings of one start
 * order at every width tried, or one rule's local search over the order from the best of its
 * starts. It keeps the first smallest of its own packings, with their positions; reduced in
 * the order one thread would run the units (keep_first_smallest), they keep what that thread
 * would: the search gives the same packing whatever the thread count. */
typedef struct search_unit {
    work w; /* its own: packed positions, sequence, rule, packings spent */
    const texopt_packer *packer;
    double base;         /* start units: the estimated strip width the widths scale */
    int tries;           /* start units: widths tried */
    best_packing found;  /* the first smallest of its packings */
    double *found_texel; /* their positions */
    best_packing cur;    /* local units: the rule's best start, then the search's best */
    uint32_t *trial;     /* local units: the order tried next */
    texopt_status st;
    char err[256];
} search_unit;

static void run_start_unit(search_unit *u)
{
    for (int i = 0; i < u->tries && u->st == TEXOPT_OK; i++) {
        int strip = round_up4(u->base * (WIDTH_LO + (WIDTH_HI - WIDTH_LO) * i / (u->tries - 1)));
        if (strip <= MAX_SIDE)
            try_packing(&u->w, u->packer, strip, NULL, &u->found, u->found_texel, &u->st, u->err, sizeof u->err);
    }
}

/* Greedy descent over the order, path dependent: hence one from every rule's best start,
 * not only from the best rule's. Each rule has its own random stream. */
static void run_local_unit(search_unit *u)
{
    uint64_t rng = 0x9e3779b97f4a7c15ULL * (uint64_t)(u->w.rule + 1);
    for (int it = 0; u->st == TEXOPT_OK && u->cur.texels >= 0 && it < ORDER_SEARCH_STEPS; it++) {
        perturb(u->cur.sequence, u->trial, u->w.mesh->chart_count, &rng);
        u->w.sequence = u->trial;
        for (int d = -1; d <= 1 && u->st == TEXOPT_OK; d++) {
            int at = round_up4(u->cur.strip * (1 + 0.02 * d));
            if (at <= MAX_SIDE &&
                try_packing(&u->w, u->packer, at, &u->cur, &u->found, u->found_texel, &u->st, u->err, sizeof u->err))
                break;
        }
    }
}

typedef struct unit_pool {
    search_unit *units;
    int count;
    void (*run)(search_unit *);
    atomic_int next;
} unit_pool;

static void *unit_worker(void *arg)
{
    unit_pool *pool = arg;
    for (int i; (i = atomic_fetch_add(&pool->next, 1)) < pool->count;)
        pool->run(pool->units + i);
    return NULL;
}

/* Runs every unit on up to `threads` workers, the calling thread included. */
static void run_units(search_unit *units, int count, void (*run)(search_unit *), int threads)
{
    unit_pool pool = {units, count, run, 0};
    texopt_parallel_run(unit_worker, &pool, 0, threads < count ? threads : count);
}

/* Offers `from` (positions in from_texel) to `to` the way offer() does: kept only when
 * strictly smaller, so reducing units in their sequential order keeps the first smallest. */
static void keep_first_smallest(const work *w, best_packing *to, const best_packing *from, const double *from_texel,
                                double *to_texel)
{
    if (from->texels < 0 || (to->texels >= 0 && from->texels >= to->texels))
        return;
    uint32_t *sequence = to->sequence;
    *to = *from;
    to->sequence = sequence;
    memcpy(sequence, from->sequence, sizeof(uint32_t) * w->mesh->chart_count);
    if (to_texel)
        memcpy(to_texel, from_texel, sizeof(double) * 2 * w->mesh->vertex_count);
}

/* Adds the units' packings to w's count; returns the first failure among them, in their
 * order, with its message in err. */
static texopt_status collect_units(const search_unit *units, int count, work *w, char *err, size_t err_len)
{
    for (int i = 0; i < count; i++)
        w->packings += units[i].w.packings;
    for (int i = 0; i < count; i++)
        if (units[i].st != TEXOPT_OK)
            return texopt_fail(err, err_len, units[i].st, "%s", units[i].err);
    return TEXOPT_OK;
}

static void free_units(search_unit *units, int count)
{
    for (int i = 0; units && i < count; i++) {
        free(units[i].w.packed);
        free(units[i].found_texel);
        free(units[i].found.sequence);
        free(units[i].cur.sequence);
        free(units[i].trial);
    }
    free(units);
}

/* Units for `count` searches, each with its own buffers. */
static search_unit *make_units(const work *w, const texopt_packer *packer, int count)
{
    search_unit *units = calloc((size_t)count, sizeof *units);
    size_t n = w->mesh->chart_count ? w->mesh->chart_count : 1, v = w->mesh->vertex_count ? w->mesh->vertex_count : 1;
    for (int i = 0; units && i < count; i++) {
        search_unit *u = units + i;
        u->w = *w;
        u->w.packings = 0;
        u->packer = packer;
        u->w.packed = malloc(sizeof(double) * 2 * v);
        u->found_texel = malloc(sizeof(double) * 2 * v);
        u->found = (best_packing){-1, 0, 0, 0, 0, malloc(sizeof(uint32_t) * n)};
        u->cur = (best_packing){-1, 0, 0, 0, 0, malloc(sizeof(uint32_t) * n)};
        u->trial = malloc(sizeof(uint32_t) * n);
        if (!u->w.packed || !u->found_texel || !u->found.sequence || !u->cur.sequence || !u->trial) {
            free_units(units, count);
            return NULL;
        }
    }
    return units;
}

/* The strip width and placement order whose "as tall as needed" packing has the fewest
 * texels: both start orders at a few widths around the estimate (more for small atlases),
 * then, for small atlases, a seeded local search over the order (one chart moved at a time)
 * at the best widths. Its positions go to texel_out. Deterministic: a fixed seed and a fixed
 * number of packings; the units run on w->threads threads (search_unit). */
static texopt_status search_packing(work *w, double s, double area, double aspect, int min_strip, double *texel_out,
                                    best_packing *best, char *err, size_t err_len)
{
    size_t n = w->mesh->chart_count ? w->mesh->chart_count : 1;
    int small = w->mesh->chart_count <= SMALL_ATLAS_CHARTS;
    int rules = small ? RULES : 1, starts = rules * START_ORDERS;
    uint32_t *orders = malloc(sizeof(uint32_t) * START_ORDERS * n);
    texopt_packer *packer = NULL;
    texopt_status st = orders ? start_orders(w->mesh, w->texel, orders, err, err_len)
                              : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the placement orders");
    if (st == TEXOPT_OK)
        st = make_packer(w, s, &packer, err, err_len);
    search_unit *units = st == TEXOPT_OK ? make_units(w, packer, starts + rules) : NULL;
    if (st == TEXOPT_OK && !units)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the packing search");
    search_unit *local = units ? units + starts : NULL;
    double base = fmax(sqrt(area * s * s / 0.7 * aspect), min_strip / WIDTH_LO);
    for (int i = 0; i < starts && st == TEXOPT_OK; i++) {
        units[i].w.rule = i / START_ORDERS;
        units[i].w.sequence = orders + (size_t)(i % START_ORDERS) * n;
        units[i].base = base;
        units[i].tries = small ? 15 : 2;
    }
    if (st == TEXOPT_OK) {
        run_units(units, starts, run_start_unit, w->threads);
        st = collect_units(units, starts, w, err, err_len);
    }
    for (int i = 0; i < starts && st == TEXOPT_OK; i++) {
        keep_first_smallest(w, best, &units[i].found, units[i].found_texel, texel_out);
        keep_first_smallest(w, &local[i / START_ORDERS].cur, &units[i].found, NULL, NULL);
    }
    if (st == TEXOPT_OK && small) {
        for (int r = 0; r < rules; r++)
            local[r].w.rule = r;
        run_units(local, rules, run_local_unit, w->threads);
        st = collect_units(local, rules, w, err, err_len);
        for (int r = 0; r < rules && st == TEXOPT_OK; r++)
            keep_first_smallest(w, best, &local[r].found, local[r].found_texel, texel_out);
    }
    w->rule = best->rule;
    w->sequence = best->sequence;
    free_units(units, starts + rules);
    texopt_packer_destroy(packer);
    free(orders);
    if (st == TEXOPT_OK && best->texels < 0)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                           "budget: the layout needs a texture larger than %d texels a side", MAX_SIDE);
    return st;
}

/* The scale whose packed cost meets the target (to COST_TOLERANCE, within COST_ROUNDS),
 * found with the plain packing (first order, first rule, one width). Cost depends on scale
 * squared but also on how the charts fall on the texel grid, which moves by whole cells
 * change only through the quarter turns: so the scale found here holds, nearly, for every
 * packing the search then tries, and the search's winner is not repacked at another scale
 * (which would give another, usually worse, packing). */
static texopt_status calibrate_scale(work *w, double target, double area, double aspect, double *s, int *min_strip,
                                     char *err, size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    double best_miss = INFINITY, best_s = *s;
    for (int round = 0; st == TEXOPT_OK && round < COST_ROUNDS && best_miss > COST_TOLERANCE; round++) {
        int strip = round_up4(sqrt(area * *s * *s / 0.7 * aspect)), fits = 0, pw = 0, ph = 0;
        double cost = 0;
        texopt_packer *packer = NULL;
        w->sequence = NULL;
        w->rule = w->pack->rule;
        st = make_packer(w, *s, &packer, err, err_len);
        /* A tiny layout's gutters can make a chart wider than the estimated strip. */
        while (st == TEXOPT_OK && !fits && strip <= MAX_SIDE) {
            st = pack_at(w, packer, strip, 0, &fits, &pw, &ph, err, err_len);
            if (st == TEXOPT_OK && !fits)
                strip = round_up4(1.5 * strip + 4);
        }
        texopt_packer_destroy(packer);
        if (strip > round_up4(sqrt(area * *s * *s / 0.7 * aspect)))
            *min_strip = strip; /* widened: the search must not try narrower strips */
        if (st == TEXOPT_OK && !fits)
            st = texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                             "budget: the layout needs a texture larger than %d texels a side", MAX_SIDE);
        if (st == TEXOPT_OK)
            st = measure_cost(w->mesh, w->packed, pw, ph, &cost, err, err_len);
        if (st != TEXOPT_OK || !(cost > 0))
            break;
        if (fabs(cost / target - 1) < best_miss) {
            best_miss = fabs(cost / target - 1);
            best_s = *s;
        }
        *s *= sqrt(target / cost);
    }
    *s = best_s;
    return st;
}

/* Calibrates the scale, searches the packing at it, then (rarely: when the winner's
 * quarter turns put its cost off the target) repacks the winner at corrected scales; the
 * round closest to the target wins. */
static texopt_status fit_relative_cost(work *w, const texopt_budget_request *req, double area, double *texel_out,
                                       texopt_budget_result *res, char *err, size_t err_len)
{
    double target = req->relative_cost * req->input_cost;
    double s = sqrt(target / area);
    double aspect = (double)req->input_width / req->input_height;
    /* One grid cell for the whole search, from the expected longer side, so the correction
     * rounds repack the winning order on the grid it won on. */
    w->side = (int)fmin(MAX_SIDE, ceil(sqrt(area * s * s / 0.7) * fmax(sqrt(aspect), 1 / sqrt(aspect))));
    best_packing best = {-1, 0, 0, 0, 0, malloc(sizeof(uint32_t) * (w->mesh->chart_count ? w->mesh->chart_count : 1))};
    if (!best.sequence)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the placement order");
    int min_strip = 0;
    texopt_status st = calibrate_scale(w, target, area, aspect, &s, &min_strip, err, err_len);
    if (st == TEXOPT_OK)
        st = search_packing(w, s, area, aspect, min_strip, texel_out, &best, err, err_len);
    double cost = 0;
    if (st == TEXOPT_OK)
        st = measure_cost(w->mesh, texel_out, best.width, best.height, &cost, err, err_len);
    double best_miss = fabs(cost / target - 1);
    int strip = best.strip;
    res->width = best.width;
    res->height = best.height;
    res->scale = s;
    res->cost = cost;
    for (int round = 0; st == TEXOPT_OK && round < COST_ROUNDS && best_miss > COST_TOLERANCE && cost > 0; round++) {
        double k = sqrt(target / cost);
        int fits = 0, pw = 0, ph = 0, next_strip = round_up4(strip * k);
        if (next_strip > MAX_SIDE) {
            st = texopt_fail(err, err_len, TEXOPT_E_LIMIT, "budget: the layout needs a texture wider than %d texels",
                             MAX_SIDE);
            break;
        }
        texopt_packer *packer = NULL;
        st = make_packer(w, s * k, &packer, err, err_len);
        if (st == TEXOPT_OK)
            st = pack_at(w, packer, next_strip, 0, &fits, &pw, &ph, err, err_len);
        texopt_packer_destroy(packer);
        if (st == TEXOPT_OK && !fits)
            st = texopt_fail(err, err_len, TEXOPT_E_LIMIT, "budget: the layout needs a texture taller than %d texels",
                             MAX_SIDE);
        if (st == TEXOPT_OK)
            st = measure_cost(w->mesh, w->packed, pw, ph, &cost, err, err_len);
        if (st != TEXOPT_OK)
            break;
        s *= k;
        strip = next_strip;
        if (fabs(cost / target - 1) < best_miss) {
            best_miss = fabs(cost / target - 1);
            res->width = pw;
            res->height = ph;
            res->scale = s;
            res->cost = cost;
            memcpy(texel_out, w->packed, sizeof(double) * 2 * w->mesh->vertex_count);
        }
    }
    free(best.sequence);
    return st;
}

static texopt_status fit_texture_size(work *w, const texopt_budget_request *req, double area, double *texel_out,
                                      texopt_budget_result *res, char *err, size_t err_len)
{
    int width = req->texture_width, height = req->texture_height;
    double hi = sqrt((double)width * height / area), lo = 0, s = hi * sqrt(0.75);
    w->side = width > height ? width : height;
    texopt_status st = TEXOPT_OK;
    for (int i = 0; i < BISECTION_STEPS + 20 && st == TEXOPT_OK; i++) {
        if (lo > 0 && (hi - lo) <= 0.002 * hi)
            break;
        int fits, pw, ph;
        texopt_packer *packer = NULL;
        st = make_packer(w, s, &packer, err, err_len);
        if (st == TEXOPT_OK)
            st = pack_at(w, packer, width, height, &fits, &pw, &ph, err, err_len);
        texopt_packer_destroy(packer);
        if (st != TEXOPT_OK)
            break;
        if (fits) {
            lo = s;
            memcpy(texel_out, w->packed, sizeof(double) * 2 * w->mesh->vertex_count);
        } else {
            hi = s;
        }
        s = lo > 0 ? 0.5 * (lo + hi) : 0.5 * hi;
        if (lo == 0 && hi < 1e-6)
            break;
    }
    if (st != TEXOPT_OK)
        return st;
    if (!(lo > 0)) {
        res->no_fit = 1;
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "budget: the charts do not fit in %dx%d at any scale", width,
                           height);
    }
    res->width = width;
    res->height = height;
    res->scale = lo;
    return measure_cost(w->mesh, texel_out, width, height, &res->cost, err, err_len);
}

static texopt_status check_request(const texopt_budget_request *req, double area, char *err, size_t err_len)
{
    if (!(area > 0) || !isfinite(area))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: the layout has no area");
    if (!(req->input_cost > 0) || req->input_width < 1 || req->input_height < 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "budget: the input cost and frame must be positive");
    if (req->kind == TEXOPT_BUDGET_RELATIVE_COST && !(req->relative_cost > 0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: relative cost must be > 0");
    if (req->kind == TEXOPT_BUDGET_TEXTURE_SIZE && (req->texture_width < 1 || req->texture_height < 1 ||
                                                    req->texture_width > MAX_SIDE || req->texture_height > MAX_SIDE))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: texture size %dx%d is out of range",
                           req->texture_width, req->texture_height);
    if (req->threads < 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: threads are negative");
    if (req->kind != TEXOPT_BUDGET_RELATIVE_COST && req->kind != TEXOPT_BUDGET_TEXTURE_SIZE)
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                           "budget: only relative cost and texture size are supported");
    return TEXOPT_OK;
}

/* Turns the charts whose triangles all ignore rotation (w_rotation 0) to their smallest
 * bounding rectangle: their objective is blind to the angle, the packing is not. */
static texopt_status orient_free_charts(const texopt_mesh *mesh, const double *texel,
                                        const texopt_triangle_target *targets, double *oriented, char *err,
                                        size_t err_len)
{
    uint8_t *turnable = malloc(mesh->chart_count ? mesh->chart_count : 1);
    if (!turnable)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the chart orientation");
    memset(turnable, 1, mesh->chart_count);
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (mesh->chart_of[t] < mesh->chart_count && targets[t].w_rotation != 0)
            turnable[mesh->chart_of[t]] = 0;
    texopt_status st = texopt_chart_orient(mesh, texel, turnable, oriented, NULL, err, err_len);
    free(turnable);
    return st;
}

/* The search of the request's budget kind on w->texel, whose triangles cover `area`. */
static texopt_status fit_budget(work *w, const texopt_budget_request *req, double area, double *texel_out,
                                texopt_budget_result *res, char *err, size_t err_len)
{
    texopt_status st = req->kind == TEXOPT_BUDGET_RELATIVE_COST
                           ? fit_relative_cost(w, req, area, texel_out, res, err, err_len)
                           : fit_texture_size(w, req, area, texel_out, res, err, err_len);
    if (st == TEXOPT_OK)
        res->packing_efficiency = res->cost / ((double)res->width * res->height);
    return st;
}

texopt_status texopt_budget_fit(const texopt_mesh *mesh, const double *texel, const texopt_budget_request *req,
                                double *texel_out, texopt_budget_result *res, char *err, size_t err_len)
{
    memset(res, 0, sizeof *res);
    double area = texopt_layout_area(mesh, texel, req->paid);
    texopt_status st = check_request(req, area, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    work w = {mesh,
              texel,
              &req->pack,
              NULL,
              NULL,
              0,
              req->pack.sequence,
              req->pack.rule,
              req->monitor,
              req->pack.cell,
              0,
              req->threads > 0 ? req->threads : 1};
    size_t n = 2 * (mesh->vertex_count ? mesh->vertex_count : 1);
    w.scaled = malloc(n * sizeof(double));
    w.packed = malloc(n * sizeof(double));
    double *oriented = req->targets ? malloc(n * sizeof(double)) : NULL;
    if (!w.scaled || !w.packed || (req->targets && !oriented))
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the budget search");
    if (st == TEXOPT_OK && oriented) {
        st = orient_free_charts(mesh, texel, req->targets, oriented, err, err_len);
        w.texel = oriented;
    }
    if (st == TEXOPT_OK)
        st = fit_budget(&w, req, area, texel_out, res, err, err_len);
    free(w.scaled);
    free(w.packed);
    free(oriented);
    if (st != TEXOPT_OK)
        return st;
    res->packings = w.packings;
    res->relative_cost = res->cost / req->input_cost;
    return TEXOPT_OK;
}

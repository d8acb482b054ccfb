/* pack.c - footprint bottom-left packing of charts with quarter-turn rotations (see pack.h).
 *
 * Each chart, in each of its four rotations, becomes a footprint on a grid of cells: the
 * cells touched by its triangles grown by pad = gutter / 2 texels (conservative: a triangle
 * clipped to a row band of height cell + 2 pad, its x-range grown by pad), kept as runs of
 * cells per row. A texopt_packer builds the footprints once; each run of it packs them in
 * some order. The texture is a bitset of occupied cells; a chart is tested at (x, y) run by
 * run and marks its exact footprint when placed, so a later small chart can still use the
 * bays of a concave one. Finding the first fit in a row jumps x past each occupied run it
 * hits, so a row costs a few bit scans, not one test per cell. */
#include "pack.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct footprint {
    int w, h;         /* cells */
    int *lo, *hi;     /* per row: hull span, lo > hi for an empty row */
    uint8_t *bits;    /* w * h exact footprint */
    int *run_start;   /* h + 1 offsets into runs */
    int *runs;        /* pairs (first, last) of the footprint's runs of cells, row by row */
    int *need;        /* per row: occupied cells */
    int min_need;     /* smallest need of a row */
    int *longest;     /* per row: its longest run of cells */
    int min_longest;  /* smallest longest run of a row */
    double origin[2]; /* texel position (after rotation) of cell (0, 0) */
} footprint;

typedef struct chart_set {
    size_t count;
    uint32_t *start; /* count + 1 offsets into tris */
    uint32_t *tris;  /* triangles grouped by chart */
    double *area;    /* per chart, sum of |texel area| */
} chart_set;

typedef struct occupancy {
    int w, h, words;
    uint64_t *bits;  /* h rows of `words` words */
    int *free_cells; /* per row */
    int *free_run;   /* per row: its longest run of free cells */
} occupancy;

static void rotate(int k, double x, double y, double *ox, double *oy)
{
    switch (k & 3) {
    case 0:
        *ox = x;
        *oy = y;
        break;
    case 1:
        *ox = -y;
        *oy = x;
        break;
    case 2:
        *ox = -x;
        *oy = -y;
        break;
    default:
        *ox = y;
        *oy = -x;
        break;
    }
}

static void chart_set_destroy(chart_set *cs)
{
    free(cs->start);
    free(cs->tris);
    free(cs->area);
}

static texopt_status group_charts(const texopt_mesh *mesh, const double *texel, chart_set *cs, char *err,
                                  size_t err_len)
{
    memset(cs, 0, sizeof *cs);
    cs->count = mesh->chart_count;
    cs->start = calloc(cs->count + 1, sizeof *cs->start);
    cs->tris = malloc(sizeof *cs->tris * (mesh->triangle_count ? mesh->triangle_count : 1));
    cs->area = calloc(cs->count ? cs->count : 1, sizeof *cs->area);
    if (!cs->start || !cs->tris || !cs->area) {
        chart_set_destroy(cs);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to group charts");
    }
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        uint32_t c = mesh->chart_of[t];
        if (c >= cs->count) {
            chart_set_destroy(cs);
            return texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "triangle %zu: chart %u out of range", t, c);
        }
        cs->start[c + 1]++;
        const uint32_t *v = mesh->triangle + 3 * t;
        const double *a = texel + 2 * v[0], *b = texel + 2 * v[1], *d = texel + 2 * v[2];
        cs->area[c] += 0.5 * fabs((b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]));
    }
    for (size_t c = 0; c < cs->count; c++)
        cs->start[c + 1] += cs->start[c];
    uint32_t *fill = malloc(sizeof *fill * (cs->count ? cs->count : 1));
    if (!fill) {
        chart_set_destroy(cs);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to group charts");
    }
    memcpy(fill, cs->start, sizeof *fill * cs->count);
    for (size_t t = 0; t < mesh->triangle_count; t++)
        cs->tris[fill[mesh->chart_of[t]]++] = (uint32_t)t;
    free(fill);
    return TEXOPT_OK;
}

static void footprint_destroy(footprint *f)
{
    free(f->lo);
    free(f->hi);
    free(f->bits);
    free(f->run_start);
    free(f->runs);
    free(f->need);
    free(f->longest);
    memset(f, 0, sizeof *f);
}

/* x-range of the triangle (3 points) inside the band y0 <= y <= y1; 0 when it misses. */
static int band_x_range(const double p[3][2], double y0, double y1, double *xl, double *xr)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < 3; i++) {
        const double *a = p[i], *b = p[(i + 1) % 3];
        if (a[1] >= y0 && a[1] <= y1) {
            lo = fmin(lo, a[0]);
            hi = fmax(hi, a[0]);
        }
        const double ys[2] = {y0, y1};
        for (int k = 0; k < 2; k++)
            if ((a[1] - ys[k]) * (b[1] - ys[k]) < 0) {
                double t = (ys[k] - a[1]) / (b[1] - a[1]);
                double x = a[0] + t * (b[0] - a[0]);
                lo = fmin(lo, x);
                hi = fmax(hi, x);
            }
    }
    if (!(lo <= hi))
        return 0;
    *xl = lo;
    *xr = hi;
    return 1;
}

static void mark_triangle(footprint *f, const double p[3][2], double pad, double cell)
{
    double ymin = fmin(p[0][1], fmin(p[1][1], p[2][1])), ymax = fmax(p[0][1], fmax(p[1][1], p[2][1]));
    int r0 = (int)floor((ymin - pad) / cell), r1 = (int)floor((ymax + pad) / cell);
    for (int r = r0 < 0 ? 0 : r0; r <= r1 && r < f->h; r++) {
        double xl, xr;
        if (!band_x_range(p, r * cell - pad, (r + 1) * cell + pad, &xl, &xr))
            continue;
        int c0 = (int)floor((xl - pad) / cell), c1 = (int)floor((xr + pad) / cell);
        if (c0 < 0)
            c0 = 0;
        if (c1 >= f->w)
            c1 = f->w - 1;
        for (int c = c0; c <= c1; c++)
            f->bits[(size_t)r * f->w + c] = 1;
        if (c0 < f->lo[r])
            f->lo[r] = c0;
        if (c1 > f->hi[r])
            f->hi[r] = c1;
    }
}

/* Splits each row of the footprint into runs of occupied cells, so a placement test sees
 * the chart's own bays and two concave charts can interlock. */
static int build_runs(footprint *f)
{
    size_t count = 0;
    for (int r = 0; r < f->h; r++)
        for (int c = f->lo[r]; c <= f->hi[r]; c++)
            count += f->bits[(size_t)r * f->w + c] && (c == f->lo[r] || !f->bits[(size_t)r * f->w + c - 1]);
    f->run_start = malloc(sizeof(int) * (size_t)(f->h + 1));
    f->runs = malloc(sizeof(int) * 2 * (count ? count : 1));
    if (!f->run_start || !f->runs)
        return -1;
    int n = 0;
    for (int r = 0; r < f->h; r++) {
        f->run_start[r] = n;
        const uint8_t *row = f->bits + (size_t)r * f->w;
        for (int c = f->lo[r]; c <= f->hi[r]; c++) {
            if (!row[c] || (c > f->lo[r] && row[c - 1]))
                continue;
            int e = c;
            while (e + 1 <= f->hi[r] && row[e + 1])
                e++;
            f->runs[2 * n] = c;
            f->runs[2 * n + 1] = e;
            n++;
        }
    }
    f->run_start[f->h] = n;
    f->need = calloc(f->h > 0 ? (size_t)f->h : 1, sizeof(int));
    f->longest = calloc(f->h > 0 ? (size_t)f->h : 1, sizeof(int));
    if (!f->need || !f->longest)
        return -1;
    f->min_need = f->min_longest = f->w;
    for (int r = 0; r < f->h; r++) {
        for (int k = f->run_start[r]; k < f->run_start[r + 1]; k++) {
            int len = f->runs[2 * k + 1] - f->runs[2 * k] + 1;
            f->need[r] += len;
            if (len > f->longest[r])
                f->longest[r] = len;
        }
        if (f->need[r] < f->min_need)
            f->min_need = f->need[r];
        if (f->longest[r] < f->min_longest)
            f->min_longest = f->longest[r];
    }
    return 0;
}

/* The footprint of chart c in rotation k. */
static int build_footprint(const texopt_mesh *mesh, const double *texel, const chart_set *cs, size_t c, int k,
                           double pad, double cell, footprint *f)
{
    memset(f, 0, sizeof *f);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (uint32_t i = cs->start[c]; i < cs->start[c + 1]; i++)
        for (int j = 0; j < 3; j++) {
            uint32_t v = mesh->triangle[3 * cs->tris[i] + j];
            double x, y;
            rotate(k, texel[2 * v], texel[2 * v + 1], &x, &y);
            lo[0] = fmin(lo[0], x);
            lo[1] = fmin(lo[1], y);
            hi[0] = fmax(hi[0], x);
            hi[1] = fmax(hi[1], y);
        }
    f->origin[0] = lo[0] - pad;
    f->origin[1] = lo[1] - pad;
    f->w = (int)floor((hi[0] - lo[0] + 2 * pad) / cell) + 1;
    f->h = (int)floor((hi[1] - lo[1] + 2 * pad) / cell) + 1;
    f->lo = malloc(sizeof(int) * (size_t)f->h);
    f->hi = malloc(sizeof(int) * (size_t)f->h);
    f->bits = calloc((size_t)f->w * (size_t)f->h, 1);
    if (!f->lo || !f->hi || !f->bits)
        return -1;
    for (int r = 0; r < f->h; r++) {
        f->lo[r] = f->w;
        f->hi[r] = -1;
    }
    for (uint32_t i = cs->start[c]; i < cs->start[c + 1]; i++) {
        double p[3][2];
        for (int j = 0; j < 3; j++) {
            uint32_t v = mesh->triangle[3 * cs->tris[i] + j];
            rotate(k, texel[2 * v], texel[2 * v + 1], &p[j][0], &p[j][1]);
            p[j][0] -= f->origin[0];
            p[j][1] -= f->origin[1];
        }
        mark_triangle(f, p, pad, cell);
    }
    int r = build_runs(f);
    free(f->bits); /* placement reads the runs only */
    f->bits = NULL;
    return r;
}

static uint64_t *occ_row(const occupancy *o, int y)
{
    return o->bits + (size_t)y * (size_t)o->words;
}

/* First occupied cell in [from, to] of row, or -1. */
static int first_set(const uint64_t *row, int from, int to)
{
    int w = from >> 6;
    uint64_t m = row[w] & (~0ULL << (from & 63));
    while (1) {
        if (m) {
            int p = (w << 6) + __builtin_ctzll(m);
            return p <= to ? p : -1;
        }
        if (++w > (to >> 6))
            return -1;
        m = row[w];
    }
}

/* First free cell at or after from, or limit. */
static int first_clear(const uint64_t *row, int from, int limit)
{
    int w = from >> 6;
    uint64_t m = ~row[w] & (~0ULL << (from & 63));
    int words = (limit + 63) >> 6;
    while (1) {
        if (m) {
            int p = (w << 6) + __builtin_ctzll(m);
            return p < limit ? p : limit;
        }
        if (++w >= words)
            return limit;
        m = ~row[w];
    }
}

/* Whether row r of f fits at column x of grid row `row`; on a conflict *x becomes the
 * first column that clears the occupied run it hit. */
static int row_fits(const footprint *f, int r, const uint64_t *row, int width, int *x)
{
    for (int k = f->run_start[r]; k < f->run_start[r + 1]; k++) {
        int a = f->runs[2 * k], b = f->runs[2 * k + 1];
        int p = first_set(row, *x + a, *x + b);
        if (p >= 0) {
            *x = first_clear(row, p, width) - a;
            return 0;
        }
    }
    return 1;
}

/* Longest run of free cells in the first `width` cells of row. */
static int longest_free_run(const uint64_t *row, int width)
{
    int longest = 0;
    for (int x = 0; x < width;) {
        int a = first_clear(row, x, width);
        if (a >= width)
            break;
        int b = first_set(row, a, width - 1);
        if (b < 0)
            b = width;
        if (b - a > longest)
            longest = b - a;
        x = b;
    }
    return longest;
}

/* Whether grid row y may hold footprint row r: enough free cells, and a free run as long as
 * the row's longest run (necessary, not sufficient: the runs must also fall on free cells). */
static int row_may_fit(const occupancy *o, const footprint *f, int r, int y)
{
    return o->free_cells[y] >= f->need[r] && o->free_run[y] >= f->longest[r];
}

/* Whether grid row y can hold no row of the footprint, ruling out every position that
 * overlaps it. */
static int row_blocks_all(const occupancy *o, const footprint *f, int y)
{
    return o->free_cells[y] < f->min_need || o->free_run[y] < f->min_longest;
}

/* Lowest-then-leftmost position of f, below row `below` (exclusive bound on y + h). A y is
 * first screened row by row with row_may_fit, the grid row that ruled out the last y tested
 * first (it usually rules out the next one too), and a row that blocks every footprint row
 * skips every y that overlaps it; the same for the row that last blocked a column. */
static int find_position(const occupancy *o, const footprint *f, int below, int *px, int *py)
{
    int hot = 0, blocking = -1;
    for (int y = 0; y + f->h <= o->h && y + f->h < below; y++) {
        int bad = -1;
        if (blocking >= y && !row_may_fit(o, f, blocking - y, blocking))
            bad = blocking;
        for (int r = 0; r < f->h && bad < 0; r++)
            if (!row_may_fit(o, f, r, y + r))
                bad = y + r;
        if (bad >= 0) {
            blocking = bad;
            if (row_blocks_all(o, f, bad))
                y = bad;
            continue;
        }
        int x = 0;
        while (x + f->w <= o->w) {
            int fits = row_fits(f, hot, occ_row(o, y + hot), o->w, &x);
            for (int r = 0; r < f->h && fits; r++)
                if (r != hot && !row_fits(f, r, occ_row(o, y + r), o->w, &x)) {
                    fits = 0;
                    hot = r;
                }
            if (fits) {
                *px = x;
                *py = y;
                return 1;
            }
        }
    }
    return 0;
}

/* Occupies cells a..b of row. */
static void mark_cells(uint64_t *row, int a, int b)
{
    for (int w = a >> 6; w <= b >> 6; w++) {
        uint64_t m = ~0ULL;
        if (w == a >> 6)
            m &= ~0ULL << (a & 63);
        if (w == b >> 6)
            m &= ~0ULL >> (63 - (b & 63));
        row[w] |= m;
    }
}

static void place(occupancy *o, const footprint *f, int x, int y)
{
    for (int r = 0; r < f->h; r++) {
        uint64_t *row = occ_row(o, y + r);
        for (int k = f->run_start[r]; k < f->run_start[r + 1]; k++) {
            mark_cells(row, x + f->runs[2 * k], x + f->runs[2 * k + 1]);
            o->free_cells[y + r] -= f->runs[2 * k + 1] - f->runs[2 * k] + 1;
        }
        o->free_run[y + r] = longest_free_run(row, o->w);
    }
}

typedef struct sort_item {
    double area;
    uint32_t chart;
} sort_item;

static int compare_items(const void *a, const void *b)
{
    const sort_item *x = a, *y = b;
    if (x->area != y->area)
        return x->area > y->area ? -1 : 1;
    return x->chart < y->chart ? -1 : (x->chart > y->chart);
}

static int choose_cell(int width, int height, const texopt_pack_options *opt)
{
    if (opt && opt->cell > 0)
        return opt->cell;
    int side = width > height ? width : height;
    return side <= 1024 ? 1 : (side + 1023) / 1024;
}

static void move_chart(const texopt_mesh *mesh, const double *texel, const chart_set *cs, size_t c, int k,
                       const footprint *f, double dx, double dy, double *texel_out, uint8_t *moved)
{
    for (uint32_t i = cs->start[c]; i < cs->start[c + 1]; i++)
        for (int j = 0; j < 3; j++) {
            uint32_t v = mesh->triangle[3 * cs->tris[i] + j];
            if (moved[v])
                continue;
            double x, y;
            rotate(k, texel[2 * v], texel[2 * v + 1], &x, &y);
            texel_out[2 * v] = x - f->origin[0] + dx;
            texel_out[2 * v + 1] = y - f->origin[1] + dy;
            moved[v] = 1;
        }
}

struct texopt_packer {
    const texopt_mesh *mesh;
    const double *texel;
    chart_set cs;
    footprint *fp;      /* 4 per chart: the chart in each quarter turn */
    uint32_t *order[2]; /* charts by triangle area, by bounding-box area */
    double pad, cell;
    int unbounded_rows; /* grid rows of the "as tall as needed" mode */
};

typedef struct pack_state {
    const texopt_packer *p;
    occupancy occ;
    uint8_t *moved;
    int rule;  /* texopt_pack_rule */
    int top;   /* highest occupied row + 1 */
    int right; /* rightmost occupied column + 1 */
} pack_state;

/* The primary key of a placement under the packer's rule (smaller is better). */
static long long rule_key(int rule, int y, int h)
{
    return rule == TEXOPT_PACK_LOWEST_CENTRE ? 2LL * y + h : rule == TEXOPT_PACK_LOWEST_BOTTOM ? y : (long long)y + h;
}

/* The highest y whose key does not exceed `key` for a footprint h rows tall. */
static long long rule_max_y(int rule, long long key, int h)
{
    long long v = rule == TEXOPT_PACK_LOWEST_CENTRE ? (key - h) / 2 : rule == TEXOPT_PACK_LOWEST_BOTTOM ? key : key - h;
    return v;
}

/* Places chart c at its best rotation: each rotation at its lowest-leftmost free position,
 * the rotations compared by the rule's key, then by top, then leftmost. Returns 1 placed,
 * 0 no room. */
static int place_chart(pack_state *s, size_t c, double *texel_out, uint8_t *rotation)
{
    const texopt_packer *p = s->p;
    int best_k = -1, bx = 0, by = 0;
    long long best_key = 0;
    for (int k = 0; k < 4; k++) {
        const footprint *f = p->fp + 4 * c + k;
        long long below = s->occ.h + 1;
        if (best_k >= 0) {
            long long max_y = rule_max_y(s->rule, best_key, f->h);
            if (max_y < 0)
                continue;
            below = max_y + f->h + 1 < below ? max_y + f->h + 1 : below;
        }
        int x, y;
        if (!find_position(&s->occ, f, (int)below, &x, &y))
            continue;
        long long key = rule_key(s->rule, y, f->h);
        int top = y + f->h, best_top = best_k >= 0 ? by + p->fp[4 * c + best_k].h : 0;
        if (best_k < 0 || key < best_key || (key == best_key && (top < best_top || (top == best_top && x < bx)))) {
            best_k = k;
            bx = x;
            by = y;
            best_key = key;
        }
    }
    if (best_k < 0)
        return 0;
    const footprint *best = p->fp + 4 * c + best_k;
    place(&s->occ, best, bx, by);
    if (by + best->h > s->top)
        s->top = by + best->h;
    if (bx + best->w > s->right)
        s->right = bx + best->w;
    move_chart(p->mesh, p->texel, &p->cs, c, best_k, best, bx * p->cell, by * p->cell, texel_out, s->moved);
    rotation[c] = (uint8_t)best_k;
    return 1;
}

static texopt_status check_inputs(const texopt_mesh *mesh, const double *texel, char *err, size_t err_len)
{
    if (!mesh || !texel)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "pack: mesh and layout are required");
    for (size_t i = 0; i < 2 * mesh->vertex_count; i++)
        if (!isfinite(texel[i]))
            return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "pack: vertex %zu has a non-finite position", i / 2);
    return TEXOPT_OK;
}

static texopt_status check_size(int width, int height, char *err, size_t err_len)
{
    if (width < 1 || width > 65536 || height < 0 || height > 65536)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "pack: texture size %dx%d is out of range", width,
                           height);
    return TEXOPT_OK;
}

/* A caller's sequence must name every chart once, or charts would be lost or placed twice. */
static texopt_status check_sequence(const uint32_t *sequence, size_t count, char *err, size_t err_len)
{
    if (!sequence)
        return TEXOPT_OK;
    uint8_t *seen = calloc(count ? count : 1, 1);
    if (!seen)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to check the chart sequence");
    size_t bad = count;
    for (size_t i = 0; i < count && bad == count; i++) {
        if (sequence[i] >= count || seen[sequence[i]])
            bad = i;
        else
            seen[sequence[i]] = 1;
    }
    free(seen);
    if (bad < count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "pack: sequence entry %zu (%u) is out of range or repeated", bad, sequence[bad]);
    return TEXOPT_OK;
}

/* Rows enough to stack every chart by its longer side (the "as tall as needed" mode). */
static int unbounded_rows(const chart_set *cs, const texopt_mesh *mesh, const double *texel, double pad, double cell)
{
    double rows = 1;
    for (size_t c = 0; c < cs->count; c++) {
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (uint32_t i = cs->start[c]; i < cs->start[c + 1]; i++)
            for (int j = 0; j < 3; j++) {
                uint32_t v = mesh->triangle[3 * cs->tris[i] + j];
                for (int a = 0; a < 2; a++) {
                    lo[a] = fmin(lo[a], texel[2 * v + a]);
                    hi[a] = fmax(hi[a], texel[2 * v + a]);
                }
            }
        if (cs->start[c + 1] > cs->start[c])
            rows += (fmax(hi[0] - lo[0], hi[1] - lo[1]) + 2 * pad) / cell + 2;
    }
    return rows > 1 << 20 ? 1 << 20 : (int)rows;
}

static double chart_box_area(const texopt_packer *p, size_t c)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (uint32_t i = p->cs.start[c]; i < p->cs.start[c + 1]; i++)
        for (int j = 0; j < 3; j++) {
            uint32_t v = p->mesh->triangle[3 * p->cs.tris[i] + j];
            for (int a = 0; a < 2; a++) {
                lo[a] = fmin(lo[a], p->texel[2 * v + a]);
                hi[a] = fmax(hi[a], p->texel[2 * v + a]);
            }
        }
    return hi[0] > lo[0] ? (hi[0] - lo[0]) * (hi[1] - lo[1]) : 0;
}

/* The two built-in orders (pack.h `order`), largest first, ties by chart index. */
static texopt_status build_orders(texopt_packer *p, char *err, size_t err_len)
{
    size_t n = p->cs.count;
    sort_item *items = malloc(sizeof *items * (n ? n : 1));
    for (int o = 0; o < 2; o++)
        p->order[o] = malloc(sizeof(uint32_t) * (n ? n : 1));
    if (!items || !p->order[0] || !p->order[1]) {
        free(items);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to sort charts");
    }
    for (int o = 0; o < 2; o++) {
        for (size_t c = 0; c < n; c++) {
            items[c].area = o == 1 ? chart_box_area(p, c) : p->cs.area[c];
            items[c].chart = (uint32_t)c;
        }
        qsort(items, n, sizeof *items, compare_items);
        for (size_t i = 0; i < n; i++)
            p->order[o][i] = items[i].chart;
    }
    free(items);
    return TEXOPT_OK;
}

texopt_status texopt_packer_create(texopt_packer **out, const texopt_mesh *mesh, const double *texel,
                                   const texopt_pack_options *opt, int side, char *err, size_t err_len)
{
    *out = NULL;
    texopt_status st = check_inputs(mesh, texel, err, err_len);
    if (st == TEXOPT_OK)
        st = check_size(side, 0, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_packer *p = calloc(1, sizeof *p);
    if (!p)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the packer");
    p->mesh = mesh;
    p->texel = texel;
    int gutter = opt && opt->gutter > 0 ? opt->gutter : 4;
    p->pad = 0.5 * gutter;
    p->cell = choose_cell(side, 0, opt);
    st = group_charts(mesh, texel, &p->cs, err, err_len);
    if (st == TEXOPT_OK)
        st = build_orders(p, err, err_len);
    if (st == TEXOPT_OK) {
        p->fp = calloc(4 * (p->cs.count ? p->cs.count : 1), sizeof *p->fp);
        if (!p->fp)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for chart footprints");
    }
    for (size_t c = 0; st == TEXOPT_OK && c < p->cs.count; c++)
        for (int k = 0; k < 4 && st == TEXOPT_OK; k++)
            if (p->cs.start[c + 1] > p->cs.start[c] &&
                build_footprint(mesh, texel, &p->cs, c, k, p->pad, p->cell, p->fp + 4 * c + k) != 0)
                st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for chart footprints");
    if (st != TEXOPT_OK) {
        texopt_packer_destroy(p);
        return st;
    }
    p->unbounded_rows = unbounded_rows(&p->cs, mesh, texel, p->pad, p->cell);
    *out = p;
    return TEXOPT_OK;
}

void texopt_packer_destroy(texopt_packer *p)
{
    if (!p)
        return;
    if (p->fp)
        for (size_t i = 0; i < 4 * p->cs.count; i++)
            footprint_destroy(p->fp + i);
    free(p->fp);
    free(p->order[0]);
    free(p->order[1]);
    chart_set_destroy(&p->cs);
    free(p);
}

static void finish_result(const pack_state *s, int width, int height, texopt_pack_result *result)
{
    const texopt_packer *p = s->p;
    result->width = width;
    result->used_height = (int)ceil(s->top * p->cell);
    result->used_width = (int)ceil(s->right * p->cell);
    if (result->used_width > width)
        result->used_width = width;
    result->height = height > 0 ? height : ((result->used_height + 3) / 4) * 4;
    if (result->height < 1)
        result->height = 4;
    double area = 0;
    for (size_t c = 0; c < p->cs.count; c++)
        area += p->cs.area[c];
    result->area_efficiency = area / ((double)result->width * result->height);
}

texopt_status texopt_packer_run(const texopt_packer *p, int width, int height, const texopt_pack_options *opt,
                                double *texel_out, texopt_pack_result *result, int *fits, char *err, size_t err_len)
{
    const uint32_t *sequence = opt ? opt->sequence : NULL;
    int order = opt ? opt->order : 0;
    memset(result, 0, sizeof *result);
    *fits = 0;
    texopt_status st = check_size(width, height, err, err_len);
    if (st == TEXOPT_OK)
        st = check_sequence(sequence, p->cs.count, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    const uint32_t *seq = sequence ? sequence : p->order[order == 1];
    pack_state s;
    memset(&s, 0, sizeof s);
    s.p = p;
    s.rule = opt ? opt->rule : 0;
    s.occ.w = (int)(width / p->cell);
    s.occ.h = height > 0 ? (int)(height / p->cell) : p->unbounded_rows;
    s.occ.words = (s.occ.w + 63) / 64;
    s.occ.bits = calloc((size_t)s.occ.h * (size_t)(s.occ.words ? s.occ.words : 1), sizeof(uint64_t));
    s.occ.free_cells = malloc(sizeof(int) * (size_t)(s.occ.h ? s.occ.h : 1));
    s.occ.free_run = malloc(sizeof(int) * (size_t)(s.occ.h ? s.occ.h : 1));
    s.moved = calloc(p->mesh->vertex_count ? p->mesh->vertex_count : 1, 1);
    result->rotation = calloc(p->cs.count ? p->cs.count : 1, 1);
    result->chart_count = p->cs.count;
    if (!s.occ.bits || !s.occ.free_cells || !s.occ.free_run || !s.moved || !result->rotation)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d packing grid", s.occ.w, s.occ.h);
    if (st == TEXOPT_OK) {
        for (int y = 0; y < s.occ.h; y++)
            s.occ.free_cells[y] = s.occ.free_run[y] = s.occ.w;
        for (size_t v = 0; v < p->mesh->vertex_count; v++)
            texel_out[2 * v] = texel_out[2 * v + 1] = 0; /* vertices of no triangle */
        *fits = 1;
        for (size_t i = 0; i < p->cs.count && *fits; i++)
            if (p->cs.start[seq[i] + 1] > p->cs.start[seq[i]])
                *fits = place_chart(&s, seq[i], texel_out, result->rotation);
        finish_result(&s, width, height, result);
    }
    free(s.occ.bits);
    free(s.occ.free_cells);
    free(s.occ.free_run);
    free(s.moved);
    if (st != TEXOPT_OK)
        texopt_pack_result_destroy(result);
    return st;
}

texopt_status texopt_pack_charts(const texopt_mesh *mesh, const double *texel, int width, int height,
                                 const texopt_pack_options *opt, double *texel_out, texopt_pack_result *result,
                                 int *fits, char *err, size_t err_len)
{
    memset(result, 0, sizeof *result);
    *fits = 0;
    texopt_status st = check_size(width, height, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_packer *p = NULL;
    st = texopt_packer_create(&p, mesh, texel, opt, width > height ? width : height, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_packer_run(p, width, height, opt, texel_out, result, fits, err, err_len);
    texopt_packer_destroy(p);
    return st;
}

void texopt_pack_result_destroy(texopt_pack_result *result)
{
    if (!result)
        return;
    free(result->rotation);
    result->rotation = NULL;
}

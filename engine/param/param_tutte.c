/* param_tutte.c - mean-value (Floater) barycentric embedding of a disk chart, boundary on a
 * circle. The interior system is not symmetric, so it is solved as least squares through
 * its normal equations (sparse_spd.h): exact for a consistent system, and small charts are
 * what the methods see. */
#include "param_tutte.h"

#include <math.h>
#include <stdlib.h>

#include "sparse_spd.h"
#include "vec3.h"

/* The weighted neighbours of every vertex in CSR form, a neighbour once per adjacent
 * triangle (the least-squares rows add duplicates up). */
typedef struct neighbours {
    uint32_t *start; /* vertex_count + 1 */
    uint32_t *vertex;
    double *weight;
} neighbours;

static void neighbours_free(neighbours *n)
{
    free(n->start);
    free(n->vertex);
    free(n->weight);
}

/* Mean-value weight of edge ij from corner i of a triangle: tan(angle_i / 2) / |x_i - x_j|. */
static int mean_value_weights(const texopt_param_chart *chart, const double *divisor, neighbours *n)
{
    size_t nv = chart->vertex_count, nt = chart->triangle_count;
    n->start = calloc(nv + 1, sizeof *n->start);
    n->vertex = malloc(6 * nt * sizeof *n->vertex);
    n->weight = malloc(6 * nt * sizeof *n->weight);
    uint32_t *fill = calloc(nv, sizeof *fill);
    if (!n->start || !n->vertex || !n->weight || !fill) {
        free(fill);
        return -1;
    }
    for (size_t i = 0; i < 3 * nt; i++)
        n->start[chart->triangle[i] + 1] += 2;
    for (size_t v = 0; v < nv; v++)
        n->start[v + 1] += n->start[v];
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *tri = chart->triangle + 3 * t;
        double angle[3];
        texopt_param_corner_angles(chart, t, angle);
        for (int k = 0; k < 3; k++) {
            uint32_t i = tri[k];
            double half_tan = tan(0.5 * angle[k]);
            for (int s = 1; s <= 2; s++) {
                uint32_t j = tri[(k + s) % 3];
                uint32_t slot = n->start[i] + fill[i]++;
                n->vertex[slot] = j;
                n->weight[slot] = half_tan /
                                  texopt_distance3(chart->position + 3 * (size_t)i, chart->position + 3 * (size_t)j) /
                                  (divisor ? divisor[j] : 1.0);
            }
        }
    }
    free(fill);
    return 0;
}

/* Row of interior vertex i: u_i - sum_j lambda_ij u_j = 0, lambda normalised to sum 1. */
static texopt_status add_vertex_row(texopt_spd *spd, const neighbours *n, const int64_t *unknown, uint32_t i,
                                    const double *uv, uint32_t *cols, double *a)
{
    double total = 0.0;
    for (uint32_t s = n->start[i]; s < n->start[i + 1]; s++)
        total += n->weight[s];
    int count = 0;
    double rhs[2] = {0.0, 0.0};
    cols[count] = (uint32_t)unknown[i];
    a[count++] = 1.0;
    for (uint32_t s = n->start[i]; s < n->start[i + 1]; s++) {
        uint32_t j = n->vertex[s];
        double lambda = n->weight[s] / total;
        if (unknown[j] < 0) {
            rhs[0] += lambda * uv[2 * (size_t)j];
            rhs[1] += lambda * uv[2 * (size_t)j + 1];
        } else {
            cols[count] = (uint32_t)unknown[j];
            a[count++] = -lambda;
        }
    }
    return texopt_spd_add_row(spd, cols, a, count, rhs, 1.0);
}

static texopt_status solve_interior(const texopt_param_chart *chart, const texopt_param_boundary *b,
                                    const neighbours *n, double *uv, char *err, size_t err_len)
{
    size_t nv = chart->vertex_count, interior = 0, max_degree = 0;
    int64_t *unknown = malloc(nv * sizeof *unknown);
    if (!unknown)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "tutte: out of memory");
    for (size_t v = 0; v < nv; v++) {
        unknown[v] = b->on_boundary[v] ? -1 : (int64_t)interior++;
        size_t degree = n->start[v + 1] - n->start[v] + 1;
        max_degree = degree > max_degree ? degree : max_degree;
    }
    texopt_status st = TEXOPT_OK;
    texopt_spd *spd = NULL;
    uint32_t *cols = malloc(max_degree * sizeof *cols);
    double *a = malloc(max_degree * sizeof *a), *x = malloc(2 * (interior ? interior : 1) * sizeof *x);
    if (!cols || !a || !x)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "tutte: out of memory");
    else if (interior > 0)
        st = texopt_spd_create(&spd, interior, 2, err, err_len);
    for (size_t v = 0; v < nv && st == TEXOPT_OK && interior > 0; v++)
        if (unknown[v] >= 0)
            st = add_vertex_row(spd, n, unknown, (uint32_t)v, uv, cols, a);
    if (st == TEXOPT_OK && interior > 0)
        st = texopt_spd_solve(spd, x, err, err_len);
    for (size_t v = 0; v < nv && st == TEXOPT_OK; v++)
        if (unknown[v] >= 0) {
            uv[2 * v] = x[unknown[v]];
            uv[2 * v + 1] = x[interior + (size_t)unknown[v]];
        }
    texopt_spd_destroy(spd);
    free(unknown);
    free(cols);
    free(a);
    free(x);
    return st;
}

texopt_status texopt_param_embed_interior(const texopt_param_chart *chart, const texopt_param_boundary *boundary,
                                          const double *divisor, double *uv, char *err, size_t err_len)
{
    neighbours n = {0};
    texopt_status st = TEXOPT_OK;
    if (mean_value_weights(chart, divisor, &n) != 0)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "tutte: out of memory");
    else
        st = solve_interior(chart, boundary, &n, uv, err, err_len);
    neighbours_free(&n);
    return st;
}

texopt_status texopt_param_tutte(const texopt_param_chart *chart, double *uv, char *err, size_t err_len)
{
    if (!uv)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "tutte: NULL output");
    texopt_param_boundary *b = NULL;
    texopt_status st = texopt_param_boundary_create(&b, chart, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double length = b->arc[b->count], radius = length / (2.0 * TEXOPT_PI);
    for (size_t i = 0; i < b->count; i++) {
        double phi = 2.0 * TEXOPT_PI * b->arc[i] / length;
        uv[2 * (size_t)b->vertex[i]] = radius * cos(phi);
        uv[2 * (size_t)b->vertex[i] + 1] = radius * sin(phi);
    }
    st = texopt_param_embed_interior(chart, b, NULL, uv, err, err_len);
    texopt_param_boundary_destroy(b);
    return st;
}

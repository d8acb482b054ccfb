/* param_grids.c - generated disk charts for the parameterization tests (param_grids.h). */
#include "param_grids.h"

#include <math.h>
#include <stdlib.h>

static void lift(param_shape shape, double x, double y, double *p)
{
    switch (shape) {
    case SHAPE_TILTED_PLANE:
        /* Orthonormal columns (cos b, sin b, 0) and (-sin b cos a, cos b cos a, sin a). */
        p[0] = cos(0.3) * x - sin(0.3) * cos(0.7) * y + 1.0;
        p[1] = sin(0.3) * x + cos(0.3) * cos(0.7) * y;
        p[2] = sin(0.7) * y - 2.0;
        break;
    case SHAPE_CYLINDER: {
        double r = 0.4; /* the unit square rolls a bit over one radian */
        p[0] = r * sin(x / r);
        p[1] = y;
        p[2] = r * (1.0 - cos(x / r));
        break;
    }
    case SHAPE_BUMP:
        p[0] = x;
        p[1] = y;
        p[2] = 0.35 * exp(-((x - 0.5) * (x - 0.5) + (y - 0.45) * (y - 0.45)) / 0.06);
        break;
    }
}

param_grid *param_grid_create(int n, param_shape shape, uint32_t shift)
{
    param_grid *g = calloc(1, sizeof *g);
    size_t nv = (size_t)(n + 1) * (n + 1), nt = 2 * (size_t)n * n;
    g->position = malloc(3 * nv * sizeof *g->position);
    g->plane = malloc(2 * nv * sizeof *g->plane);
    g->triangle = malloc(3 * nt * sizeof *g->triangle);
    g->vertex_of_grid_start = shift;
#define VERTEX(i, j) ((uint32_t)(((size_t)(j) * (n + 1) + (i) + nv - shift) % nv))
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            int inside = i > 0 && j > 0 && i < n && j < n;
            double jx = inside && shape != SHAPE_CYLINDER ? 0.3 * (((i * 7 + j * 3) % 5) / 4.0 - 0.5) : 0.0;
            double jy = inside ? 0.3 * (((i * 2 + j * 5) % 4) / 3.0 - 0.5) : 0.0;
            double x = (i + jx) / n, y = (j + jy) / n;
            uint32_t v = VERTEX(i, j);
            g->plane[2 * (size_t)v] = x;
            g->plane[2 * (size_t)v + 1] = y;
            lift(shape, x, y, g->position + 3 * (size_t)v);
        }
    size_t t = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t a = VERTEX(i, j), b = VERTEX(i + 1, j), c = VERTEX(i + 1, j + 1), d = VERTEX(i, j + 1);
            /* The two corner quads the a-c diagonal would leave with a single triangle (all
             * three vertices on the boundary, flat once its corner is not a square's corner)
             * take the other diagonal. */
            int other = (i == n - 1 && j == 0) || (i == 0 && j == n - 1);
            uint32_t tris[6] = {a, b, c, a, c, d}, flipped[6] = {a, b, d, b, c, d};
            if (other)
                for (int k = 0; k < 6; k++)
                    tris[k] = flipped[k];
            for (int k = 0; k < 6; k++)
                g->triangle[3 * t + k] = tris[k];
            t += 2;
        }
#undef VERTEX
    g->chart = (texopt_param_chart){nv, g->position, nt, g->triangle};
    return g;
}

void param_grid_destroy(param_grid *grid)
{
    if (!grid)
        return;
    free(grid->position);
    free(grid->plane);
    free(grid->triangle);
    free(grid);
}

size_t param_layout_flips(const texopt_param_chart *chart, const double *uv)
{
    size_t flips = 0;
    for (size_t t = 0; t < chart->triangle_count; t++) {
        const uint32_t *v = chart->triangle + 3 * t;
        const double *a = uv + 2 * (size_t)v[0], *b = uv + 2 * (size_t)v[1], *c = uv + 2 * (size_t)v[2];
        if (!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0))
            flips++;
    }
    return flips;
}

double param_similarity_residual(const param_grid *grid, const double *uv, double *scale)
{
    /* Complex least squares: uv = z p + t with z = a + i b; centre both sets first. */
    size_t nv = grid->chart.vertex_count;
    double cp[2] = {0, 0}, cu[2] = {0, 0};
    for (size_t v = 0; v < nv; v++)
        for (int k = 0; k < 2; k++) {
            cp[k] += grid->plane[2 * v + k] / (double)nv;
            cu[k] += uv[2 * v + k] / (double)nv;
        }
    double num_a = 0, num_b = 0, den = 0;
    for (size_t v = 0; v < nv; v++) {
        double px = grid->plane[2 * v] - cp[0], py = grid->plane[2 * v + 1] - cp[1];
        double ux = uv[2 * v] - cu[0], uy = uv[2 * v + 1] - cu[1];
        num_a += px * ux + py * uy;
        num_b += px * uy - py * ux;
        den += px * px + py * py;
    }
    double a = num_a / den, b = num_b / den, worst = 0.0;
    for (size_t v = 0; v < nv; v++) {
        double px = grid->plane[2 * v] - cp[0], py = grid->plane[2 * v + 1] - cp[1];
        double ex = a * px - b * py - (uv[2 * v] - cu[0]), ey = b * px + a * py - (uv[2 * v + 1] - cu[1]);
        worst = fmax(worst, sqrt(ex * ex + ey * ey));
    }
    *scale = sqrt(a * a + b * b);
    return worst;
}

/* seam_jump.c - the texture's jump across one input seam (seam_jump.h). */
#include "seam_jump.h"

#include <math.h>

#include "sample.h"

#define EDGE_SAMPLES 8

/* The shared 3D edge of t and u as the mesh vertices of each side (vt[i] and vu[i] on the
 * same point); returns how many points they share (2 for an edge). */
static int shared_edge(const texopt_mesh *mesh, uint32_t t, uint32_t u, uint32_t vt[2], uint32_t vu[2])
{
    int n = 0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3 && n < 2; b++) {
            uint32_t p = mesh->triangle[3 * (size_t)t + (size_t)a], q = mesh->triangle[3 * (size_t)u + (size_t)b];
            if (mesh->point_of[p] == mesh->point_of[q]) {
                vt[n] = p;
                vu[n] = q;
                n++;
                break;
            }
        }
    return n;
}

/* The point at fraction f from vertex a to vertex b, in image texels. */
static void along(const texopt_mesh *mesh, const texopt_image *image, uint32_t a, uint32_t b, double f, double xy[2])
{
    double scale[2] = {(double)image->width / mesh->width, (double)image->height / mesh->height};
    for (int k = 0; k < 2; k++)
        xy[k] =
            ((1 - f) * mesh->texel[2 * (size_t)a + (size_t)k] + f * mesh->texel[2 * (size_t)b + (size_t)k]) * scale[k];
}

double texopt_seam_jump(const texopt_mesh *mesh, const texopt_image *image, uint32_t t, uint32_t u)
{
    uint32_t vt[2], vu[2];
    if (shared_edge(mesh, t, u, vt, vu) < 2 || (vt[0] == vu[0] && vt[1] == vu[1]) || !image->pixels ||
        mesh->width <= 0 || mesh->height <= 0)
        return 0;
    int channels = image->channels < 3 ? image->channels : 3;
    float a[4], b[4];
    double sum = 0;
    for (int i = 0; i < EDGE_SAMPLES; i++) {
        double f = (i + 0.5) / EDGE_SAMPLES, p[2], q[2];
        along(mesh, image, vt[0], vt[1], f, p);
        along(mesh, image, vu[0], vu[1], f, q);
        texopt_sample_bilinear(image, mesh->wrap_s, mesh->wrap_t, p[0], p[1], a);
        texopt_sample_bilinear(image, mesh->wrap_s, mesh->wrap_t, q[0], q[1], b);
        for (int c = 0; c < channels; c++)
            sum += fabs((double)a[c] - (double)b[c]);
    }
    return sum / (EDGE_SAMPLES * (channels > 0 ? channels : 1));
}

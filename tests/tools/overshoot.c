/* overshoot.c - `texopt_overshoot INPUT OUTPUT [RADIUS]`: how far each texture of OUTPUT (a
 * `texopt optimize` result of INPUT, any method) rings beyond the values of INPUT's texture
 * around each texel (tests/support/overshoot.h, window RADIUS output texels, default 1.5).
 * One line per image: its index, the slot that reads it, the largest overshoot above and
 * below in code values and the share of texel channels over one code value. Normal maps are
 * measured on Z alone (the re-bake turns their XY with the layout). Both models must have
 * the same vertices and triangles in the same order (texopt keeps them); triangles count for
 * an image when their primitive's material reads it through TEXCOORD_0.
 * Does not: render, or judge (scripts and the reader compare the lines of two outputs). */
#include <stdio.h>
#include <stdlib.h>

#include "gltf_io.h"
#include "overshoot.h"

/* The slot of material m that reads image i through TEXCOORD_0, or -1. */
static int slot_reading(const texopt_material *m, int i)
{
    for (int s = 0; s < TEXOPT_SLOT_COUNT; s++)
        if (m->slot[s].image == i && m->slot[s].texcoord == 0)
            return s;
    return -1;
}

/* The triangles of primitives whose material reads image i (3 indices each) into out; their
 * count, and the slot into *slot. */
static size_t triangles_reading(const texopt_model *m, int i, uint32_t *out, int *slot)
{
    size_t n = 0;
    *slot = -1;
    for (int p = 0; p < m->primitive_count; p++) {
        const texopt_primitive *pr = &m->primitives[p];
        int s = pr->material >= 0 ? slot_reading(&m->materials[pr->material], i) : -1;
        if (s < 0)
            continue;
        *slot = s;
        for (size_t t = pr->first_triangle; t < pr->first_triangle + pr->triangle_count; t++, n++)
            for (int k = 0; k < 3; k++)
                out[3 * n + k] = m->triangles[3 * t + k];
    }
    return n;
}

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: texopt_overshoot INPUT OUTPUT [RADIUS]\n");
        return 2;
    }
    double radius = argc > 3 ? atof(argv[3]) : 1.5;
    char err[512] = "";
    texopt_model *in = NULL, *out = NULL;
    if (texopt_model_load(&in, argv[1], NULL, err, sizeof err) != TEXOPT_OK ||
        texopt_model_load(&out, argv[2], NULL, err, sizeof err) != TEXOPT_OK) {
        fprintf(stderr, "texopt_overshoot: %s\n", err);
        return 1;
    }
    int rc = 0;
    uint32_t *tris = malloc(3 * sizeof *tris * (in->triangle_count ? in->triangle_count : 1));
    if (!tris || in->vertex_count != out->vertex_count || in->triangle_count != out->triangle_count ||
        in->image_count != out->image_count || !in->uvs || !out->uvs) {
        fprintf(stderr, "texopt_overshoot: the models differ in vertices, triangles or images\n");
        rc = 1;
    }
    printf("image\tslot\tabove\tbelow\tshare\n");
    for (int i = 0; rc == 0 && i < in->image_count; i++) {
        int slot;
        size_t n = triangles_reading(in, i, tris, &slot);
        if (n == 0 || !in->images[i].pixels || !out->images[i].pixels)
            continue;
        const int normal_z[4] = {0, 0, 1, 0};
        overshoot o;
        if (overshoot_measure(&in->images[i], &out->images[i], in->uvs, out->uvs, tris, n, radius,
                              slot == TEXOPT_SLOT_NORMAL ? normal_z : NULL, &o) != 0) {
            fprintf(stderr, "texopt_overshoot: image %d cannot be measured\n", i);
            rc = 1;
            break;
        }
        printf("%d\t%s\t%.1f\t%.1f\t%.4f\n", i, texopt_slot_name((texopt_slot)slot), o.above, o.below, o.share);
    }
    free(tris);
    texopt_model_destroy(in);
    texopt_model_destroy(out);
    return rc;
}

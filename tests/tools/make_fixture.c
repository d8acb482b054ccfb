/* make_fixture.c - `texopt_make_fixture KIND OUT.glb [TEXTURE_SIZE [GRID]]`: writes one of the
 * generated models of issue 45 as a .glb, for the benchmarks (scripts/bench.d) and by hand.
 *
 * Each model is a GRID x GRID quad grid over [0,1]^2 (UV = position, default 16) with a flat
 * base colour texture (fixtures.h "flat") and one map of map_patterns.h, both TEXTURE_SIZE
 * square (default 512):
 *   emissive  "play" as emissiveTexture (emissiveFactor 1), metallicFactor 0;
 *   orm       "orm" as metallicRoughnessTexture and occlusionTexture (one image);
 *   normal    "grooves" as normalTexture, metallicFactor 0.
 * Base colour is flat, so every texel a layout needs is one the other map asks for.
 * Two more are the fragmented atlases of issue 41 (grid_glb.h fragmented_grid_fill, GRID
 * default 32, islands of 2 x 2 quads, "checker" base colour only, folded 90 degrees at x = 1/2):
 *   fragmented   the islands with gutter between them (3/4 of a cell each);
 *   overlapping  neighbouring islands overlapping (each 1.5 cells wide).
 * Does not: check the model (texopt info does) or write anything but OUT.glb. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grid_glb.h"

typedef struct fixture_kind {
    const char *name, *pattern, *material;
} fixture_kind;

static const fixture_kind KINDS[] = {
    {"emissive", "play",
     "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0},\"metallicFactor\":0},"
     "\"emissiveTexture\":{\"index\":1},\"emissiveFactor\":[1,1,1]}"},
    {"orm", "orm",
     "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0},\"metallicRoughnessTexture\":{\"index\":1}},"
     "\"occlusionTexture\":{\"index\":1}}"},
    {"normal", "grooves",
     "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0},\"metallicFactor\":0},"
     "\"normalTexture\":{\"index\":1}}"},
};

static int usage(void)
{
    fprintf(stderr, "usage: texopt_make_fixture emissive|orm|normal|fragmented|overlapping OUT.glb [TEXTURE_SIZE "
                    "[GRID]]\n");
    return 2;
}

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 5)
        return usage();
    if (strcmp(argv[1], "fragmented") == 0 || strcmp(argv[1], "overlapping") == 0) {
        int tex = argc > 3 ? atoi(argv[3]) : 512, grid = argc > 4 ? atoi(argv[4]) : 32;
        double side = strcmp(argv[1], "fragmented") == 0 ? 0.75 : 1.5;
        if (tex < 8 || tex > 8192 || grid < 2 || grid > 256 || grid % 2 != 0)
            return usage();
        if (write_fragmented_grid_glb(argv[2], grid, 2, side, 1.5707963267948966, tex, "checker") != 0) {
            fprintf(stderr, "texopt_make_fixture: cannot write %s\n", argv[2]);
            return 1;
        }
        return 0;
    }
    const fixture_kind *kind = NULL;
    for (size_t k = 0; k < sizeof KINDS / sizeof KINDS[0]; k++)
        if (strcmp(argv[1], KINDS[k].name) == 0)
            kind = &KINDS[k];
    int tex = argc > 3 ? atoi(argv[3]) : 512, grid = argc > 4 ? atoi(argv[4]) : 16;
    if (!kind || tex < 8 || tex > 8192 || grid < 1 || grid > 256)
        return usage();
    const char *patterns[2] = {"flat", kind->pattern};
    if (write_grid_glb_material(argv[2], grid, tex, patterns, 2, kind->material) != 0) {
        fprintf(stderr, "texopt_make_fixture: cannot write %s\n", argv[2]);
        return 1;
    }
    return 0;
}

/* fuzz_gltf.c - libFuzzer harness: the glTF / GLB loader with its validation and image
 * decoding (texopt_model_load_memory), as `texopt info` runs it (image headers only, then the
 * info document) and as the service's upload check runs it (images decoded). An input is the
 * model file's bytes, .glb or .gltf; its external URIs resolve in tests/fuzz/files/
 * (quad.bin, quad.png: what the .gltf seeds name), so the confined file callbacks are fuzzed
 * too. Limits are small (1 MiB per file, 2^20 pixels) so that an input declaring a huge
 * image is refused rather than exhausting the fuzzer's memory; the loader's own defaults are
 * tested in tests/unit. Properties checked beyond memory safety: a model exactly when the
 * status is OK, a message otherwise, and a model that loads with its images also loads from
 * the headers alone (what `texopt info` accepts is not narrower than the upload check).
 * Seeds (tests/fuzz/corpus/gltf) are textured quads made with tests/unit/gltf_builder.h: GLB
 * with a PNG, .gltf with an external .bin, .gltf with a data-URI buffer, an external PNG and
 * texture transforms, GLB with a JPEG under a node tree, GLB with two primitives (normalized
 * u16 UVs, u32 indices, a fan). The sample assets (spot, Fox: over 160 KB each) are left out:
 * libFuzzer's input length follows the largest seed, and mutating 160 KB inputs that decode
 * a 1024^2 texture is 100x slower. Does not: save models (gltf_save.cpp). */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cjson/cJSON.h>

#include "gltf_io.h"
#include "info.h"
#include "model.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static texopt_status load(const uint8_t *data, size_t size, int skip_images)
{
    texopt_load_options opt = {0};
    opt.max_file_bytes = 1u << 20;
    opt.max_total_pixels = 1u << 20;
    opt.skip_images = skip_images;
    texopt_model *model = NULL;
    char err[512] = "";
    texopt_status status =
        texopt_model_load_memory(&model, data, size, TEXOPT_SOURCE_DIR "/tests/fuzz/files", &opt, err, sizeof err);
    if ((status == TEXOPT_OK) != (model != NULL) || (status != TEXOPT_OK && !err[0]))
        __builtin_trap();
    if (model && skip_images) {
        cJSON *doc = NULL;
        if (texopt_info_json(model, &doc, err, sizeof err) == TEXOPT_OK) {
            free(cJSON_PrintUnformatted(doc));
            cJSON_Delete(doc);
        }
    }
    texopt_model_destroy(model);
    return status;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    texopt_status headers = load(data, size, 1);
    texopt_status decoded = load(data, size, 0);
    if (decoded == TEXOPT_OK && headers != TEXOPT_OK)
        __builtin_trap();
    return 0;
}

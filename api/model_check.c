/* model_check.c - header-only validation of an uploaded model (see model_check.h). */
#include "model_check.h"

#include "texopt.h"

texopt_status api_model_check(const char *path, uint64_t max_file_bytes, uint64_t max_pixels, uint64_t *pixels,
                              char *detail, size_t detail_len)
{
    texopt_load_options opt = {0};
    opt.max_file_bytes = max_file_bytes;
    opt.max_total_pixels = max_pixels;
    opt.skip_images = 1;
    texopt_model *model = NULL;
    texopt_status status = texopt_model_load(&model, path, &opt, detail, detail_len);
    *pixels = 0;
    for (int i = 0; model && i < model->image_count; i++)
        *pixels += (uint64_t)model->images[i].width * (uint64_t)model->images[i].height;
    texopt_model_destroy(model);
    return status;
}

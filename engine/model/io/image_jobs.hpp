/* image_jobs.hpp - runs one job per image of a model on a few threads.
 *
 * Decoding on load and PNG encoding on save each take about a third of a second per 2048²
 * texture and the images are independent, so a model with five textures spends most of
 * its load and save time in work that shares out over the cores. Up to one thread per image
 * and never more than the online cores. Errors are reported as the serial loop would have:
 * the status and message of the lowest-numbered failing job.
 * Does not: know what the jobs do. */
#ifndef TEXOPT_IMAGE_JOBS_HPP
#define TEXOPT_IMAGE_JOBS_HPP

#include <cstddef>
#include <functional>

extern "C" {
#include "status.h"
}

/* job(i, err, err_len) for every i in [0, count); every job runs even after one fails. */
texopt_status texopt_run_image_jobs(size_t count, const std::function<texopt_status(size_t, char *, size_t)> &job,
                                    char *err, size_t err_len);

#endif

/* image_jobs.cpp - one job per image on up to min(images, online cores) threads (see
 * image_jobs.hpp). A thread that cannot be started leaves its share to the others. */
#include "image_jobs.hpp"

#include <atomic>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include <unistd.h>

namespace
{

struct job_result {
    texopt_status status = TEXOPT_OK;
    char message[512] = "";
};

} // namespace

texopt_status texopt_run_image_jobs(size_t count, const std::function<texopt_status(size_t, char *, size_t)> &job,
                                    char *err, size_t err_len)
{
    std::vector<job_result> results(count);
    std::atomic<size_t> next(0);
    auto work = [&]() {
        for (size_t i = next++; i < count; i = next++)
            results[i].status = job(i, results[i].message, sizeof results[i].message);
    };
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    size_t threads = cores > 1 ? (size_t)cores : 1;
    if (threads > count)
        threads = count;
    std::vector<std::thread> pool;
    for (size_t k = 1; k < threads; k++) {
        try {
            pool.emplace_back(work);
        } catch (const std::system_error &) {
            break; /* fewer threads is still correct */
        }
    }
    work();
    for (std::thread &t : pool)
        t.join();
    for (const job_result &r : results)
        if (r.status != TEXOPT_OK)
            return texopt_fail(err, err_len, r.status, "%s", r.message);
    return TEXOPT_OK;
}

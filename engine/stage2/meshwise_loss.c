/* meshwise_loss.c - per-triangle perceptual loss under a finished layout (Sun et al. 2022,
 * Fig. 16: share of triangles with E <= eps after the mesh-wise stage).
 *
 * Workers each own a texopt_triloss (it is for one thread at a time) and take triangles
 * from a shared counter; each triangle's E depends only on the triangle, so the result is
 * the same for any thread count. It does not optimise or move anything. */
#include "meshwise_loss.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "parallel.h"
#include "triloss.h"

#define PROGRESS_EVERY 256

typedef struct shared {
    const texopt_model *model;
    const texopt_mesh *mesh;
    const double *texel;
    const double *signal_weights;
    int viewport;
    double *loss; /* per triangle, NaN when skipped */
    const texopt_monitor *monitor;

    atomic_size_t next;
    atomic_size_t done;
    atomic_int stop;
    pthread_mutex_t lock; /* guards status, err and monitor calls */
    texopt_status status;
    char err[512];
} shared;

static int is_evaluated(const texopt_mesh *mesh, size_t t)
{
    return !(mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV));
}

/* J (row-major) from the input texel triangle to the same triangle in `texel`. */
static int layout_jacobian(const texopt_mesh *mesh, const double *texel, size_t t, double J[4])
{
    const uint32_t *tri = mesh->triangle + 3 * t;
    double e[4], f[4]; /* [row][edge] */
    for (int r = 0; r < 2; r++) {
        e[2 * r] = mesh->texel[2 * tri[1] + r] - mesh->texel[2 * tri[0] + r];
        e[2 * r + 1] = mesh->texel[2 * tri[2] + r] - mesh->texel[2 * tri[0] + r];
        f[2 * r] = texel[2 * tri[1] + r] - texel[2 * tri[0] + r];
        f[2 * r + 1] = texel[2 * tri[2] + r] - texel[2 * tri[0] + r];
    }
    double det = e[0] * e[3] - e[1] * e[2];
    if (!(fabs(det) > 0.0))
        return 0;
    double inv[4] = {e[3] / det, -e[1] / det, -e[2] / det, e[0] / det};
    J[0] = f[0] * inv[0] + f[1] * inv[2];
    J[1] = f[0] * inv[1] + f[1] * inv[3];
    J[2] = f[2] * inv[0] + f[3] * inv[2];
    J[3] = f[2] * inv[1] + f[3] * inv[3];
    return isfinite(J[0]) && isfinite(J[1]) && isfinite(J[2]) && isfinite(J[3]);
}

static void record_failure(shared *sh, texopt_status st, const char *msg)
{
    pthread_mutex_lock(&sh->lock);
    if (sh->status == TEXOPT_OK) {
        sh->status = st;
        snprintf(sh->err, sizeof sh->err, "%s", msg);
    }
    pthread_mutex_unlock(&sh->lock);
    atomic_store(&sh->stop, 1);
}

static void report_progress(shared *sh, size_t done)
{
    if (!sh->monitor || !sh->monitor->on_progress)
        return;
    texopt_progress p = {0};
    p.stage = "stage2";
    p.stage_fraction = (double)done / (double)sh->mesh->triangle_count;
    p.fraction = p.stage_fraction;
    p.eta_seconds = -1.0;
    pthread_mutex_lock(&sh->lock);
    texopt_monitor_report(sh->monitor, &p);
    pthread_mutex_unlock(&sh->lock);
}

static texopt_status evaluate_triangle(shared *sh, texopt_triloss *loss, size_t t, char *err, size_t err_len)
{
    sh->loss[t] = NAN;
    if (!is_evaluated(sh->mesh, t))
        return TEXOPT_OK;
    double J[4];
    if (!layout_jacobian(sh->mesh, sh->texel, t, J))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "loss share: triangle %zu has a non-finite layout Jacobian", t);
    texopt_status st = texopt_triloss_prepare(loss, (uint32_t)t, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_triloss_eval(loss, J, INFINITY, &sh->loss[t], err, err_len);
    return st;
}

static void *worker_main(void *arg)
{
    shared *sh = arg;
    char err[512] = "";
    texopt_triloss *loss = NULL;
    texopt_status st = texopt_triloss_create(&loss, sh->model, sh->mesh, sh->viewport, err, sizeof err);
    if (st != TEXOPT_OK) {
        record_failure(sh, st, err);
        return NULL;
    }
    texopt_triloss_weigh_signals(loss, sh->signal_weights);
    while (!atomic_load(&sh->stop)) {
        if (texopt_monitor_canceled(sh->monitor)) {
            record_failure(sh, TEXOPT_E_CANCELED, "loss share: canceled");
            break;
        }
        size_t t = atomic_fetch_add(&sh->next, 1);
        if (t >= sh->mesh->triangle_count)
            break;
        st = evaluate_triangle(sh, loss, t, err, sizeof err);
        if (st != TEXOPT_OK) {
            record_failure(sh, st, err);
            break;
        }
        size_t done = atomic_fetch_add(&sh->done, 1) + 1;
        if (done % PROGRESS_EVERY == 0 || done == sh->mesh->triangle_count)
            report_progress(sh, done);
    }
    texopt_triloss_destroy(loss);
    return NULL;
}

static int thread_count(int requested, size_t triangles)
{
    long n = requested > 0 ? requested : sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1)
        n = 1;
    if ((size_t)n > triangles)
        n = triangles ? (long)triangles : 1;
    return (int)n;
}

static void summarise(const texopt_mesh *mesh, const double *loss, double epsilon, texopt_loss_share *out)
{
    memset(out, 0, sizeof *out);
    double sum = 0.0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (isnan(loss[t]))
            continue;
        out->evaluated++;
        out->within += loss[t] <= epsilon;
        sum += loss[t];
        out->max_loss = fmax(out->max_loss, loss[t]);
    }
    if (out->evaluated) {
        out->share = (double)out->within / (double)out->evaluated;
        out->mean_loss = sum / (double)out->evaluated;
    }
}

texopt_status texopt_meshwise_loss_share(const texopt_model *model, const texopt_mesh *mesh, const double *texel,
                                         const double *signal_weights, double epsilon, int threads, int viewport,
                                         double *loss_out, texopt_loss_share *out, const texopt_monitor *monitor,
                                         char *err, size_t err_len)
{
    if (!model || !mesh || !texel || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "loss share: NULL model, mesh, layout or output");
    if (!(epsilon > 0.0) || threads < 0 || viewport < 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "loss share: epsilon must be > 0 and threads, viewport >= 0 "
                           "(got %g, %d, %d)",
                           epsilon, threads, viewport);
    shared sh;
    memset(&sh, 0, sizeof sh);
    sh.model = model;
    sh.mesh = mesh;
    sh.texel = texel;
    sh.signal_weights = signal_weights;
    sh.viewport = viewport > 0 ? viewport : 64;
    sh.monitor = monitor;
    sh.loss = loss_out ? loss_out : malloc((mesh->triangle_count ? mesh->triangle_count : 1) * sizeof *sh.loss);
    if (!sh.loss)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "loss share: out of memory");
    atomic_init(&sh.next, 0);
    atomic_init(&sh.done, 0);
    atomic_init(&sh.stop, 0);
    pthread_mutex_init(&sh.lock, NULL);
    texopt_parallel_run(worker_main, &sh, 0, thread_count(threads, mesh->triangle_count));
    pthread_mutex_destroy(&sh.lock);
    texopt_status st = sh.status;
    if (st == TEXOPT_OK)
        summarise(mesh, sh.loss, epsilon, out);
    else
        texopt_fail(err, err_len, st, "%s", sh.err);
    if (!loss_out)
        free(sh.loss);
    return st;
}

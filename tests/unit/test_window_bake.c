/* test_window_bake.c - the least-squares bake (Sun et al. 2022, eq. 11): exact reconstructions,
 * agreement with a dense textbook solve, error falling with more texels, wrap seams and
 * scattered footprints, bad arguments. */
#include <stdlib.h>
#include <string.h>

#include "sample.h"
#include "test.h"
#include "window_bake.h"

static double pattern(double x, double y, int channel)
{
    return 0.5 + 0.25 * sin(1.3 * x + 0.7 * channel) * cos(0.9 * y - 0.4 * channel) +
           0.2 * ((int)floor(x / 3.0 + y / 5.0) % 2 == 0 ? 1.0 : -1.0) * (channel == 0);
}

TEST(texture_sampled_at_its_own_texel_centres_is_reconstructed_exactly)
{
    enum { W = 12, H = 9, C = 3 };
    double pos[2 * W * H];
    float ref[C * W * H], out[C * W * H];
    for (int j = 0; j < H; j++) {
        for (int i = 0; i < W; i++) {
            int q = j * W + i;
            pos[2 * q] = i + 0.5;
            pos[2 * q + 1] = j + 0.5;
            for (int c = 0; c < C; c++)
                ref[C * q + c] = (float)pattern(i, j, c);
        }
    }
    texopt_bake_workspace *ws = texopt_bake_workspace_create(W * H, 4);
    CHECK(ws != NULL);
    char err[256] = "";
    CHECK_OK(
        texopt_bake_fit(ws, W * H, pos, ref, C, W, H, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1e-9, out, err, sizeof err),
        err);
    CHECK_EQ_INT(texopt_bake_last_texel_count(ws), W * H);
    for (int k = 0; k < C * W * H; k++)
        CHECK_NEAR(out[k], ref[k], 1e-6);
    texopt_bake_workspace_destroy(ws);
}

/* Dense normal equations solved by textbook Cholesky: the independent check. */
static int dense_reference_fit(int pixels, const double *pos, const float *ref, int channels, int w, int h,
                               texopt_wrap ws_, texopt_wrap wt, double ridge, double *out)
{
    int texels = w * h;
    double *m = calloc((size_t)texels * texels, sizeof *m);
    double *b = calloc((size_t)texels * channels, sizeof *b);
    int *used = calloc((size_t)texels, sizeof *used);
    if (!m || !b || !used)
        return 0;
    double mean[4] = {0};
    for (int q = 0; q < pixels; q++) {
        int idx[4];
        double wt4[4];
        texopt_bilinear_footprint(w, h, ws_, wt, pos[2 * q], pos[2 * q + 1], idx, wt4);
        for (int a = 0; a < 4; a++) {
            used[idx[a]] = 1;
            for (int c = 0; c < 4; c++)
                m[(size_t)idx[a] * texels + idx[c]] += wt4[a] * wt4[c];
            for (int c = 0; c < channels; c++)
                b[(size_t)idx[a] * channels + c] += wt4[a] * ref[q * channels + c];
        }
        for (int c = 0; c < channels; c++)
            mean[c] += ref[q * channels + c] / pixels;
    }
    /* Untouched texels are not unknowns: give them an identity row so the system stays
     * solvable without changing the touched block. */
    for (int t = 0; t < texels; t++) {
        m[(size_t)t * texels + t] += used[t] ? ridge : 1.0;
        for (int c = 0; c < channels; c++)
            b[(size_t)t * channels + c] += used[t] ? ridge * mean[c] : 0.0;
    }
    for (int k = 0; k < texels; k++) { /* Gaussian elimination, SPD so no pivoting */
        for (int i = k + 1; i < texels; i++) {
            double f = m[(size_t)i * texels + k] / m[(size_t)k * texels + k];
            if (f == 0.0)
                continue;
            for (int j = k; j < texels; j++)
                m[(size_t)i * texels + j] -= f * m[(size_t)k * texels + j];
            for (int c = 0; c < channels; c++)
                b[(size_t)i * channels + c] -= f * b[(size_t)k * channels + c];
        }
    }
    for (int k = texels - 1; k >= 0; k--) {
        for (int c = 0; c < channels; c++) {
            double s = b[(size_t)k * channels + c];
            for (int j = k + 1; j < texels; j++)
                s -= m[(size_t)k * texels + j] * b[(size_t)j * channels + c];
            b[(size_t)k * channels + c] = s / m[(size_t)k * texels + k];
        }
    }
    for (int q = 0; q < pixels; q++) {
        int idx[4];
        double wt4[4];
        texopt_bilinear_footprint(w, h, ws_, wt, pos[2 * q], pos[2 * q + 1], idx, wt4);
        for (int c = 0; c < channels; c++) {
            double s = 0.0;
            for (int a = 0; a < 4; a++)
                s += wt4[a] * b[(size_t)idx[a] * channels + c];
            out[q * channels + c] = s;
        }
    }
    free(m);
    free(b);
    free(used);
    return 1;
}

/* Pixels of a side x side screen mapped by p = J q + t. */
static void screen_positions(int side, const double jac[4], double tx, double ty, double *pos)
{
    for (int j = 0; j < side; j++) {
        for (int i = 0; i < side; i++) {
            double qx = i + 0.5, qy = j + 0.5;
            pos[2 * (j * side + i)] = jac[0] * qx + jac[1] * qy + tx;
            pos[2 * (j * side + i) + 1] = jac[2] * qx + jac[3] * qy + ty;
        }
    }
}

static void reference_on_screen(int side, int channels, float *ref)
{
    for (int j = 0; j < side; j++)
        for (int i = 0; i < side; i++)
            for (int c = 0; c < channels; c++)
                ref[(j * side + i) * channels + c] = (float)pattern(i + 0.5, j + 0.5, c);
}

static void check_against_dense(texopt_wrap wrap, const double jac[4], double tx, double ty, double ridge, int tex_w,
                                int tex_h)
{
    enum { S = 20, C = 2 };
    double pos[2 * S * S], expect[C * S * S];
    float ref[C * S * S], out[C * S * S];
    screen_positions(S, jac, tx, ty, pos);
    reference_on_screen(S, C, ref);
    texopt_bake_workspace *ws = texopt_bake_workspace_create(S * S, C);
    CHECK(ws != NULL);
    char err[256] = "";
    CHECK_OK(texopt_bake_fit(ws, S * S, pos, ref, C, tex_w, tex_h, wrap, wrap, ridge, out, err, sizeof err), err);
    CHECK(dense_reference_fit(S * S, pos, ref, C, tex_w, tex_h, wrap, wrap, ridge, expect));
    for (int k = 0; k < C * S * S; k++)
        CHECK_NEAR(out[k], expect[k], 2e-5);
    texopt_bake_workspace_destroy(ws);
}

TEST(bake_equals_a_dense_normal_equation_solve)
{
    const double shrink_rotate[4] = {0.45, -0.2, 0.15, 0.55};
    check_against_dense(TEXOPT_WRAP_CLAMP, shrink_rotate, 3.3, 2.7, 1e-3, 24, 20);
    check_against_dense(TEXOPT_WRAP_REPEAT, shrink_rotate, 3.3, 2.7, 1e-2, 24, 20);
    /* Straddles the texture's corner under REPEAT: footprints wrap across both seams. */
    check_against_dense(TEXOPT_WRAP_REPEAT, shrink_rotate, -4.1, -3.2, 1e-3, 16, 12);
    check_against_dense(TEXOPT_WRAP_MIRROR, shrink_rotate, -4.1, -3.2, 1e-3, 16, 12);
    /* A patch wider than tall: its texels are numbered column by column. */
    const double wide[4] = {0.9, 0.1, -0.05, 0.3};
    check_against_dense(TEXOPT_WRAP_CLAMP, wide, 1.3, 2.7, 1e-3, 24, 20);
    /* A strong ridge pulls toward the mean: the dense solve includes it the same way. */
    const double identity[4] = {1, 0, 0, 1};
    check_against_dense(TEXOPT_WRAP_CLAMP, identity, 0.25, 0.1, 0.5, 24, 24);
}

static double bake_rms_error(double scale, int *texels)
{
    enum { S = 64, C = 1 };
    static double pos[2 * S * S];
    static float ref[C * S * S], out[C * S * S];
    const double jac[4] = {scale, 0.1 * scale, -0.05 * scale, scale};
    screen_positions(S, jac, 1.0, 1.0, pos);
    reference_on_screen(S, C, ref);
    texopt_bake_workspace *ws = texopt_bake_workspace_create(S * S, C);
    char err[256] = "";
    if (!ws || texopt_bake_fit(ws, S * S, pos, ref, C, 256, 256, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1e-6, out, err,
                               sizeof err) != TEXOPT_OK) {
        texopt_bake_workspace_destroy(ws);
        return NAN;
    }
    *texels = texopt_bake_last_texel_count(ws);
    texopt_bake_workspace_destroy(ws);
    double ss = 0.0;
    for (int k = 0; k < S * S; k++)
        ss += (out[k] - ref[k]) * (out[k] - ref[k]);
    return sqrt(ss / (S * S));
}

TEST(reconstruction_error_falls_as_texels_grow)
{
    const double scales[] = {0.15, 0.3, 0.6, 1.0};
    double previous = INFINITY;
    int previous_texels = 0;
    for (int i = 0; i < 4; i++) {
        int texels = 0;
        double e = bake_rms_error(scales[i], &texels);
        CHECK(isfinite(e));
        CHECK(texels > previous_texels);
        CHECK_MSG(e < 0.95 * previous, "scale %g: rms %g, previous %g", scales[i], e, previous);
        previous = e;
        previous_texels = texels;
    }
    /* At scale 1 the screen pixels sample the texels one to one (slightly sheared): still
     * an inexact fit of a non-bilinear pattern, but a close one. */
    CHECK(previous < 0.05);
}

/* pattern() channel 0 as a one-channel w x h texture. */
static texopt_status pattern_texture(texopt_image *tex, int w, int h, char *err, size_t err_len)
{
    texopt_status st = texopt_image_create(tex, w, h, 1, err, err_len);
    for (int k = 0; st == TEXOPT_OK && k < w * h; k++)
        tex->pixels[k] = (float)pattern(k % w, k / w, 0);
    return st;
}

/* A reference in the range of A: the texture looked up at the side x side screen positions
 * p = J q + t, which are written to pos. */
static void reference_through(const texopt_image *tex, texopt_wrap wrap, int side, const double jac[4], double tx,
                              double ty, double *pos, float *ref)
{
    screen_positions(side, jac, tx, ty, pos);
    for (int q = 0; q < side * side; q++)
        texopt_sample_bilinear(tex, wrap, wrap, pos[2 * q], pos[2 * q + 1], ref + q);
}

TEST(bilinear_reference_in_the_range_of_a_is_reproduced)
{
    /* The reference is itself a bilinear lookup of a texture on the candidate grid, so the
     * least-squares fit is exact whatever the sampling (here 3 pixels per texel). */
    enum { S = 48, W = 20, H = 20 };
    texopt_image tex;
    char err[256] = "";
    CHECK_OK(pattern_texture(&tex, W, H, err, sizeof err), err);
    static double pos[2 * S * S];
    static float ref[S * S], out[S * S];
    const double jac[4] = {0.3, 0.05, -0.04, 0.31};
    reference_through(&tex, TEXOPT_WRAP_REPEAT, S, jac, 2.0, 3.0, pos, ref);
    texopt_bake_workspace *ws = texopt_bake_workspace_create(S * S, 1);
    CHECK_OK(texopt_bake_fit(ws, S * S, pos, ref, 1, W, H, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 1e-9, out, err,
                             sizeof err),
             err);
    for (int q = 0; q < S * S; q++)
        CHECK_NEAR(out[q], ref[q], 1e-5);
    texopt_bake_workspace_destroy(ws);
    texopt_image_destroy(&tex);
}

TEST(every_factorisation_path_reproduces_a_bilinear_reference)
{
    /* Patches 29, 53 and 77 texels wide (bandwidths 32, 56, 80: both sides of the automatic
     * switches), each factored by every path; the fit must be exact and the paths agree. */
    enum { S = 96, W = 128, H = 128 };
    texopt_image tex;
    char err[256] = "";
    CHECK_OK(texopt_image_create(&tex, W, H, 2, err, sizeof err), err);
    for (int k = 0; k < W * H; k++) {
        tex.pixels[2 * k] = (float)pattern(k % W, k / W, 0);
        tex.pixels[2 * k + 1] = (float)pattern(k % W, k / W, 1);
    }
    static double pos[2 * S * S];
    static float ref[2 * S * S], out[2 * S * S], first_path[2 * S * S];
    texopt_bake_workspace *ws = texopt_bake_workspace_create(S * S, 2);
    CHECK(ws != NULL);
    const double scales[3] = {0.3, 0.55, 0.8};
    for (int i = 0; i < 3; i++) {
        const double jac[4] = {scales[i], 0.02, -0.03, scales[i]};
        screen_positions(S, jac, 10.0, 12.0, pos);
        for (int q = 0; q < S * S; q++)
            texopt_sample_bilinear(&tex, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, pos[2 * q], pos[2 * q + 1], ref + 2 * q);
        for (int solver = TEXOPT_BAKE_SOLVER_AUTO; solver <= TEXOPT_BAKE_SOLVER_LAPACK; solver++) {
            texopt_bake_workspace_set_solver(ws, (texopt_bake_solver)solver);
            CHECK_OK(texopt_bake_fit(ws, S * S, pos, ref, 2, W, H, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1e-9, out, err,
                                     sizeof err),
                     err);
            CHECK(texopt_bake_last_texel_count(ws) > (int)(0.9 * (S * scales[i]) * (S * scales[i])));
            for (int k = 0; k < 2 * S * S; k++) {
                CHECK_NEAR(out[k], ref[k], 1e-5);
                if (solver == TEXOPT_BAKE_SOLVER_AUTO)
                    first_path[k] = out[k];
                else
                    CHECK_NEAR(out[k], first_path[k], 1e-6);
            }
        }
    }
    texopt_bake_workspace_destroy(ws);
    texopt_image_destroy(&tex);
}

TEST(wide_and_tall_patches_are_banded_along_their_short_side)
{
    /* A 65 x 10 texel patch and its transpose: numbered along the short side, the band is
     * about 10 texels either way (numbered by rows, the wide one's would be ~66), and the fit
     * of a reference in the range of A is exact. */
    enum { S = 64, W = 128, H = 128 };
    texopt_image tex;
    char err[256] = "";
    CHECK_OK(pattern_texture(&tex, W, H, err, sizeof err), err);
    static double pos[2 * S * S];
    static float ref[S * S], out[S * S];
    texopt_bake_workspace *ws = texopt_bake_workspace_create(S * S, 1);
    CHECK(ws != NULL);
    const double shapes[2][4] = {{1.0, 0.0, 0.0, 0.125}, {0.125, 0.0, 0.0, 1.0}};
    for (int i = 0; i < 2; i++) {
        reference_through(&tex, TEXOPT_WRAP_CLAMP, S, shapes[i], 10.0, 12.0, pos, ref);
        CHECK_OK(texopt_bake_fit(ws, S * S, pos, ref, 1, W, H, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1e-9, out, err,
                                 sizeof err),
                 err);
        CHECK(texopt_bake_last_side(ws) == TEXOPT_BAKE_SIDE_TEXEL);
        CHECK_EQ_INT(texopt_bake_last_texel_count(ws), 65 * 10);
        CHECK_MSG(texopt_bake_last_bandwidth(ws) <= 11, "shape %d: bandwidth %d", i, texopt_bake_last_bandwidth(ws));
        for (int q = 0; q < S * S; q++)
            CHECK_NEAR(out[q], ref[q], 1e-5);
    }
    texopt_bake_workspace_destroy(ws);
    texopt_image_destroy(&tex);
}

TEST(scattered_footprints_over_a_huge_texture_fit_each_pixel)
{
    /* Pixels far apart on a 4096^2 texture: the bounding box is too big for the dense
     * map, every footprint is its own little system, so each pixel is matched exactly. */
    enum { P = 300 };
    double pos[2 * P];
    float ref[P], out[P];
    for (int q = 0; q < P; q++) {
        pos[2 * q] = 13.7 * q + 0.3 + (q % 7);
        pos[2 * q + 1] = 4095.0 - 13.1 * q;
        ref[q] = (float)(0.1 + 0.8 * ((q * 37) % 11) / 10.0);
    }
    texopt_bake_workspace *ws = texopt_bake_workspace_create(P, 1);
    char err[256] = "";
    CHECK_OK(texopt_bake_fit(ws, P, pos, ref, 1, 4096, 4096, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 1e-9, out, err,
                             sizeof err),
             err);
    CHECK_EQ_INT(texopt_bake_last_texel_count(ws), 4 * P);
    for (int q = 0; q < P; q++)
        CHECK_NEAR(out[q], ref[q], 1e-6);
    /* The workspace is reusable: a second, small fit after the scattered one. */
    CHECK_OK(
        texopt_bake_fit(ws, 1, pos, ref, 1, 8, 8, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1e-9, out, err, sizeof err),
        err);
    CHECK_NEAR(out[0], ref[0], 1e-6);
    texopt_bake_workspace_destroy(ws);
}

/* One fit of several right-hand sides shares the factorisation; each channel must come out
 * as a fit of that channel alone would (the solves per column are independent). Counts:
 * every number of four-lane vectors of the multi-channel solve, with partial last ones. */
static void multi_channel_fit_equals_single_fits(int channels)
{
    enum { S = 32, CMAX = TEXOPT_BAKE_MAX_CHANNELS };
    const int C = channels;
    static double pos[2 * S * S];
    static float ref[CMAX * S * S], out[CMAX * S * S], one_ref[S * S], one_out[S * S];
    const double jac[4] = {0.55, -0.3, 0.25, 0.7};
    screen_positions(S, jac, 5.2, 4.9, pos);
    reference_on_screen(S, C, ref);
    texopt_bake_workspace *multi = texopt_bake_workspace_create(S * S, C);
    texopt_bake_workspace *single = texopt_bake_workspace_create(S * S, 1);
    CHECK(multi != NULL && single != NULL);
    char err[256] = "";
    CHECK_OK(texopt_bake_fit(multi, S * S, pos, ref, C, 64, 64, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 1e-6, out, err,
                             sizeof err),
             err);
    int texels = texopt_bake_last_texel_count(multi);
    CHECK(texels > 100);
    double worst = 0.0, spread = 0.0;
    for (int c = 0; c < C; c++) {
        for (int q = 0; q < S * S; q++)
            one_ref[q] = ref[q * C + c];
        CHECK_OK(texopt_bake_fit(single, S * S, pos, one_ref, 1, 64, 64, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 1e-6,
                                 one_out, err, sizeof err),
                 err);
        CHECK_EQ_INT(texopt_bake_last_texel_count(single), texels);
        for (int q = 0; q < S * S; q++) {
            worst = fmax(worst, fabs((double)out[q * C + c] - one_out[q]));
            spread = fmax(spread, fabs((double)out[q * C + c] - out[q * C]));
        }
    }
    CHECK_MSG(worst <= 1e-9, "largest difference %g", worst);
    /* The channels differ, so a mix-up of columns would show. */
    CHECK(spread > 0.05);
    texopt_bake_workspace_destroy(multi);
    texopt_bake_workspace_destroy(single);
}

TEST(multi_channel_fits_equal_separate_single_channel_fits)
{
    const int counts[] = {TEXOPT_BAKE_MAX_CHANNELS, 11, 7, 3, 2};
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++)
        multi_channel_fit_equals_single_fits(counts[i]);
}

/* A minified patch (2.7 texels a pixel) has ~4 unknowns per pixel: the pixel-side system
 * A A^T + r I must give the texel side's reconstruction (push-through identity), and both
 * the dense textbook solve's. */
static void fit_on_side(texopt_bake_side side, const double *pos, const float *ref, int pixels, int channels,
                        double ridge, float *out, texopt_bake_side *used)
{
    texopt_bake_workspace *ws = texopt_bake_workspace_create(pixels, channels);
    CHECK(ws != NULL);
    texopt_bake_workspace_set_side(ws, side);
    char err[256] = "";
    CHECK_OK(texopt_bake_fit(ws, pixels, pos, ref, channels, 96, 96, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, ridge, out,
                             err, sizeof err),
             err);
    CHECK(texopt_bake_last_texel_count(ws) > 2 * pixels);
    *used = texopt_bake_last_side(ws);
    texopt_bake_workspace_destroy(ws);
}

TEST(pixel_side_solve_equals_texel_side_on_a_minified_patch)
{
    enum { S = 20, C = 2 };
    double pos[2 * S * S], expect[C * S * S];
    float ref[C * S * S], texel_out[C * S * S], pixel_out[C * S * S], auto_out[C * S * S];
    const double minify[4] = {2.6, 0.7, -0.6, 2.5};
    screen_positions(S, minify, 20.3, 7.9, pos);
    reference_on_screen(S, C, ref);
    const double ridges[2] = {1e-6, 1e-2};
    for (int r = 0; r < 2; r++) {
        texopt_bake_side used_texel, used_pixel, used_auto;
        fit_on_side(TEXOPT_BAKE_SIDE_TEXEL, pos, ref, S * S, C, ridges[r], texel_out, &used_texel);
        fit_on_side(TEXOPT_BAKE_SIDE_PIXEL, pos, ref, S * S, C, ridges[r], pixel_out, &used_pixel);
        fit_on_side(TEXOPT_BAKE_SIDE_AUTO, pos, ref, S * S, C, ridges[r], auto_out, &used_auto);
        CHECK(used_texel == TEXOPT_BAKE_SIDE_TEXEL);
        CHECK(used_pixel == TEXOPT_BAKE_SIDE_PIXEL);
        CHECK(used_auto == TEXOPT_BAKE_SIDE_PIXEL);
        CHECK(dense_reference_fit(S * S, pos, ref, C, 96, 96, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, ridges[r], expect));
        double worst = 0.0, residual = 0.0;
        for (int k = 0; k < C * S * S; k++) {
            worst = fmax(worst, fabs((double)pixel_out[k] - texel_out[k]));
            CHECK_NEAR(pixel_out[k], expect[k], 2e-5);
            CHECK(auto_out[k] == pixel_out[k]);
            residual = fmax(residual, fabs((double)pixel_out[k] - ref[k]));
        }
        CHECK_MSG(worst <= 1e-6, "ridge %g: sides differ by %g", ridges[r], worst);
        /* Many more texels than pixels: the tiny ridge nearly interpolates, the strong one
         * visibly does not (so the ridge and mean terms are really exercised). */
        if (r == 0)
            CHECK_MSG(residual < 1e-4, "residual %g", residual);
        else
            CHECK_MSG(residual > 1e-3, "residual %g", residual);
    }
}

TEST(refit_reuses_the_factorisation_and_equals_a_new_fit)
{
    /* On both sides: a fit of channels 0-1, then a refit with channels 2-3 of the pattern,
     * equals a new fit of channels 2-3 bit for bit; a one-channel refit equals a one-channel
     * fit. Magnified (texel side) and minified (pixel side) patches. */
    enum { S = 20, C = 4 };
    double pos[2 * S * S];
    float ref[C * S * S], first[2 * S * S], second[2 * S * S], out[2 * S * S], expect[2 * S * S];
    const double jacs[2][4] = {{0.6, 0.2, -0.1, 0.7}, {2.6, 0.7, -0.6, 2.5}};
    const texopt_bake_side sides[2] = {TEXOPT_BAKE_SIDE_TEXEL, TEXOPT_BAKE_SIDE_PIXEL};
    reference_on_screen(S, C, ref);
    for (int k = 0; k < S * S; k++)
        for (int c = 0; c < 2; c++) {
            first[k * 2 + c] = ref[k * C + c];
            second[k * 2 + c] = ref[k * C + 2 + c];
        }
    char err[256] = "";
    for (int v = 0; v < 2; v++) {
        screen_positions(S, jacs[v], 20.3, 7.9, pos);
        texopt_bake_workspace *ws = texopt_bake_workspace_create(S * S, C);
        texopt_bake_workspace *fresh = texopt_bake_workspace_create(S * S, C);
        CHECK(ws && fresh);
        CHECK(texopt_bake_refit(ws, second, 2, out, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
        CHECK_OK(texopt_bake_fit(ws, S * S, pos, first, 2, 96, 96, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1e-6, out, err,
                                 sizeof err),
                 err);
        CHECK(texopt_bake_last_side(ws) == sides[v]);
        CHECK_OK(texopt_bake_refit(ws, second, 2, out, err, sizeof err), err);
        CHECK_OK(texopt_bake_fit(fresh, S * S, pos, second, 2, 96, 96, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1e-6,
                                 expect, err, sizeof err),
                 err);
        CHECK(memcmp(out, expect, sizeof(float) * 2 * S * S) == 0);
        double moved = 0.0;
        for (int k = 0; k < 2 * S * S; k++)
            moved = fmax(moved, fabs((double)out[k] - first[k]));
        CHECK(moved > 0.1); /* the second signal is not the first one's reconstruction */
        float one[S * S], one_out[S * S], one_expect[S * S];
        for (int k = 0; k < S * S; k++)
            one[k] = ref[k * C + 3];
        CHECK_OK(texopt_bake_refit(ws, one, 1, one_out, err, sizeof err), err);
        CHECK_OK(texopt_bake_fit(fresh, S * S, pos, one, 1, 96, 96, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1e-6,
                                 one_expect, err, sizeof err),
                 err);
        CHECK(memcmp(one_out, one_expect, sizeof one_out) == 0);
        CHECK(texopt_bake_refit(ws, one, C + 1, one_out, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
        texopt_bake_workspace_destroy(ws);
        texopt_bake_workspace_destroy(fresh);
    }
}

TEST(bake_rejects_bad_arguments_with_messages)
{
    texopt_bake_workspace *ws = texopt_bake_workspace_create(4, 3);
    double pos[2] = {0.5, 0.5};
    float ref[3] = {0}, out[3];
    char err[256] = "";
    CHECK(texopt_bake_fit(ws, 5, pos, ref, 1, 4, 4, 0, 0, 1e-6, out, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "5 pixels") != NULL);
    CHECK(texopt_bake_fit(ws, 1, pos, ref, 4, 4, 4, 0, 0, 1e-6, out, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_bake_fit(ws, 1, pos, ref, 1, 4, 4, 0, 0, 0.0, out, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_bake_fit(ws, 1, pos, ref, 1, 0, 4, 0, 0, 1e-6, out, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_bake_fit(ws, 1, NULL, ref, 1, 4, 4, 0, 0, 1e-6, out, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_bake_fit(NULL, 1, pos, ref, 1, 4, 4, 0, 0, 1e-6, out, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_bake_fit(ws, 0, pos, ref, 1, 4, 4, 0, 0, 1e-6, out, NULL, 0) == TEXOPT_OK);
    CHECK(texopt_bake_workspace_create(0, 1) == NULL);
    CHECK(texopt_bake_workspace_create(4, TEXOPT_BAKE_MAX_CHANNELS + 1) == NULL);
    texopt_bake_workspace_destroy(ws);
    texopt_bake_workspace_destroy(NULL);
}

/* test_camera.c - the per-triangle orthographic camera (Sun et al. 2022, appendix A). */
#include <math.h>
#include <string.h>

#include "camera.h"
#include "test.h"

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

TEST(camera_frame_follows_appendix_a)
{
    /* A triangle in the plane z = 2, counter-clockwise seen from +z. */
    double a[3] = {3, 0, 2}, b[3] = {0, 3, 2}, c[3] = {0, 0, 2};
    texopt_camera cam;
    char err[256] = "";
    CHECK_OK(texopt_camera_create(&cam, a, b, c, NULL, 0, 64, err, sizeof err), err);
    CHECK_NEAR(cam.center[0], 1.0, 1e-12);
    CHECK_NEAR(cam.center[1], 1.0, 1e-12);
    CHECK_NEAR(cam.center[2], 2.0, 1e-12);
    CHECK_NEAR(cam.normal[2], 1.0, 1e-12);
    /* R points from the centroid to a = (3,0): direction (2,-1)/sqrt(5). */
    CHECK_NEAR(cam.right[0], 2 / sqrt(5.0), 1e-12);
    CHECK_NEAR(cam.right[1], -1 / sqrt(5.0), 1e-12);
    /* U = N x R = (1/sqrt5, 2/sqrt5, 0). */
    CHECK_NEAR(cam.up[0], 1 / sqrt(5.0), 1e-12);
    CHECK_NEAR(cam.up[1], 2 / sqrt(5.0), 1e-12);
    CHECK_NEAR(dot(cam.right, cam.up), 0.0, 1e-12);
    CHECK_NEAR(dot(cam.right, cam.normal), 0.0, 1e-12);
}

TEST(camera_window_is_square_and_shows_the_one_ring)
{
    double a[3] = {1, 0, 0}, b[3] = {0, 1, 0}, c[3] = {-1, -1, 0};
    /* A one-ring point far along -x: the window must grow to show it. */
    double ring[6] = {-5, 0, 0, 0.5, 0.5, 0};
    texopt_camera cam;
    char err[256] = "";
    CHECK_OK(texopt_camera_create(&cam, a, b, c, ring, 2, 32, err, sizeof err), err);
    double pts[5][3] = {{1, 0, 0}, {0, 1, 0}, {-1, -1, 0}, {-5, 0, 0}, {0.5, 0.5, 0}};
    double minx = 1e9, maxx = -1e9, miny = 1e9, maxy = -1e9;
    for (int i = 0; i < 5; i++) {
        double s[2], d;
        texopt_camera_project(&cam, pts[i], s, &d);
        CHECK(s[0] >= 0 && s[0] <= 32 && s[1] >= 0 && s[1] <= 32);
        CHECK_NEAR(d, 0.0, 1e-12);
        minx = fmin(minx, s[0]);
        maxx = fmax(maxx, s[0]);
        miny = fmin(miny, s[1]);
        maxy = fmax(maxy, s[1]);
    }
    /* The longer side of the box fills the viewport; the shorter one is centred. */
    double w = maxx - minx, h = maxy - miny;
    CHECK_NEAR(fmax(w, h), 32.0, 1e-3);
    if (w < h)
        CHECK_NEAR(minx, 32.0 - maxx, 1e-6);
    else
        CHECK_NEAR(miny, 32.0 - maxy, 1e-6);
    /* Square pixels: equal world distances along R and U project to equal pixel lengths. */
    double o[3] = {0, 0, 0}, pr[3], pu[3], so[2], sr[2], su[2];
    for (int k = 0; k < 3; k++) {
        pr[k] = cam.right[k];
        pu[k] = cam.up[k];
    }
    texopt_camera_project(&cam, o, so, NULL);
    texopt_camera_project(&cam, pr, sr, NULL);
    texopt_camera_project(&cam, pu, su, NULL);
    CHECK_NEAR(sr[0] - so[0], 32.0 / cam.window_side, 1e-9);
    CHECK_NEAR(sr[1] - so[1], 0.0, 1e-9);
    /* Up is up: rows grow downwards. */
    CHECK_NEAR(su[1] - so[1], -32.0 / cam.window_side, 1e-9);
}

TEST(camera_depth_grows_towards_the_camera)
{
    double a[3] = {1, 0, 0}, b[3] = {0, 1, 0}, c[3] = {0, 0, 0};
    texopt_camera cam;
    char err[256] = "";
    CHECK_OK(texopt_camera_create(&cam, a, b, c, NULL, 0, 16, err, sizeof err), err);
    double above[3] = {0.3, 0.3, 0.5}, below[3] = {0.3, 0.3, -0.5}, s[2], d1, d2;
    texopt_camera_project(&cam, above, s, &d1);
    texopt_camera_project(&cam, below, s, &d2);
    CHECK_NEAR(d1, 0.5, 1e-12);
    CHECK_NEAR(d2, -0.5, 1e-12);
}

TEST(camera_rejects_degenerate_input)
{
    double a[3] = {0, 0, 0}, b[3] = {1, 1, 1}, c[3] = {2, 2, 2};
    texopt_camera cam;
    char err[256] = "";
    CHECK(texopt_camera_create(&cam, a, b, c, NULL, 0, 64, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(err[0] != '\0');
    double d[3] = {0, 1, 0};
    CHECK(texopt_camera_create(&cam, a, b, d, NULL, 0, 1, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
}

/* Projects the corners and checks each lies inside the viewport. */
static int corners_inside(const texopt_camera *cam, const double *corners[3])
{
    for (int i = 0; i < 3; i++) {
        double s[2];
        texopt_camera_project(cam, corners[i], s, NULL);
        if (!(s[0] >= 0 && s[0] <= cam->size && s[1] >= 0 && s[1] <= cam->size))
            return 0;
    }
    return 1;
}

TEST(limited_zoom_narrows_the_window_about_the_centroid)
{
    /* A small triangle at the origin in a ring 20 units wide. */
    double a[3] = {0.5, 0, 0}, b[3] = {-0.25, 0.4, 0}, c[3] = {-0.25, -0.4, 0};
    double ring[6] = {-10, -10, 0, 10, 10, 0};
    texopt_camera paper, cam;
    char err[256] = "";
    CHECK_OK(texopt_camera_create(&paper, a, b, c, ring, 2, 64, err, sizeof err), err);
    /* 8 texels per unit: the paper's window (20 units) shows 8 * 20 / 64 = 2.5 texels a pixel. */
    CHECK_NEAR(texopt_camera_zoom(&paper, 8.0), 8.0 * paper.window_side / 64, 1e-12);
    CHECK_NEAR(texopt_camera_zoom(&paper, 8.0), 2.5, 1e-4);
    cam = paper;
    texopt_camera_limit_zoom(&cam, a, b, c, 8.0, 1.0);
    CHECK_NEAR(texopt_camera_zoom(&cam, 8.0), 1.0, 1e-12);
    CHECK_NEAR(cam.window_side, 8.0, 1e-12);
    /* Centred on the centroid, which the frame's origin is. */
    CHECK_NEAR(cam.window_x0, -4.0, 1e-12);
    CHECK_NEAR(cam.window_y0, -4.0, 1e-12);
    const double *corners[3] = {a, b, c};
    CHECK(corners_inside(&cam, corners));
    /* The frame does not move: only the window narrows. */
    CHECK(memcmp(cam.center, paper.center, sizeof cam.center) == 0);
    CHECK(memcmp(cam.right, paper.right, sizeof cam.right) == 0);
    CHECK(cam.size == 64);
}

TEST(limited_zoom_keeps_the_triangle_and_stays_inside_the_papers_window)
{
    /* The triangle spans 6 units and sits at the edge of its ring: a 2-unit window about the
     * centroid would cut it, and one centred there would leave the ring. */
    double a[3] = {4, 0, 0}, b[3] = {-2, 3, 0}, c[3] = {-2, -3, 0};
    double ring[3] = {-20, 0, 0};
    texopt_camera paper, cam;
    char err[256] = "";
    CHECK_OK(texopt_camera_create(&paper, a, b, c, ring, 1, 32, err, sizeof err), err);
    cam = paper;
    texopt_camera_limit_zoom(&cam, a, b, c, 16.0, 1.0);
    const double *corners[3] = {a, b, c};
    CHECK(corners_inside(&cam, corners));
    /* As narrow as the triangle allows: its 6 units along R and U. */
    CHECK_NEAR(cam.window_side, 6.0, 1e-4);
    CHECK(cam.window_x0 >= paper.window_x0 - 1e-12);
    CHECK(cam.window_y0 >= paper.window_y0 - 1e-12);
    CHECK(cam.window_x0 + cam.window_side <= paper.window_x0 + paper.window_side + 1e-12);
    CHECK(cam.window_y0 + cam.window_side <= paper.window_y0 + paper.window_side + 1e-12);
}

TEST(limited_zoom_leaves_a_window_under_the_limit_or_without_density_alone)
{
    double a[3] = {1, 0, 0}, b[3] = {0, 1, 0}, c[3] = {-1, -1, 0};
    double ring[3] = {-5, 0, 0};
    texopt_camera paper, cam;
    char err[256] = "";
    CHECK_OK(texopt_camera_create(&paper, a, b, c, ring, 1, 64, err, sizeof err), err);
    /* Only the window can change; compared exactly. */
    double density[5] = {0.5 * 64 / paper.window_side, 0, NAN, INFINITY, 100.0};
    double limit[5] = {1.0, 1.0, 1.0, 1.0, 0.0};
    for (int i = 0; i < 5; i++) {
        cam = paper;
        texopt_camera_limit_zoom(&cam, a, b, c, density[i], limit[i]);
        CHECK(cam.window_x0 == paper.window_x0 && cam.window_y0 == paper.window_y0 &&
              cam.window_side == paper.window_side);
    }
}

TEST(close_up_centres_tile_the_triangle_and_respect_the_cap)
{
    /* Centroid at the origin, first corner on +x: the camera's (R, U) frame is the world's
     * (x, y). The box is [-15, 30] x [-30, 30]; 15-unit cells make a 3 x 4 grid whose centres
     * at x = -7.5 (4 of them) and x = 7.5, y = +-7.5 lie in the triangle. */
    double a[3] = {30, 0, 0}, b[3] = {-15, 30, 0}, c[3] = {-15, -30, 0};
    texopt_camera cam;
    char err[256] = "";
    CHECK_OK(texopt_camera_create(&cam, a, b, c, NULL, 0, 64, err, sizeof err), err);
    CHECK_NEAR(cam.right[0], 1.0, 1e-12);
    CHECK_NEAR(cam.up[1], 1.0, 1e-12);
    double centres[2 * 64];
    size_t n = texopt_camera_close_up_centres(&cam, a, b, c, 15.0, 64, centres);
    CHECK_EQ_INT(n, 6);
    const double want[6][2] = {{-7.5, -22.5}, {-7.5, -7.5}, {-7.5, 7.5}, {-7.5, 22.5}, {7.5, -7.5}, {7.5, 7.5}};
    for (size_t i = 0; i < n && i < 6; i++) {
        CHECK_NEAR(centres[2 * i], want[i][0], 1e-9);
        CHECK_NEAR(centres[2 * i + 1], want[i][1], 1e-9);
    }
    /* At most 4 cells: the cells grow by 1.25 until the grid is 2 x 2 (22.5 x 30 units), of
     * which the two at x = -3.75 lie in the triangle. */
    n = texopt_camera_close_up_centres(&cam, a, b, c, 15.0, 4, centres);
    CHECK_EQ_INT(n, 2);
    CHECK_NEAR(centres[0], -3.75, 1e-9);
    CHECK_NEAR(centres[1], -15.0, 1e-9);
    CHECK_NEAR(centres[3], 15.0, 1e-9);
    /* A window larger than the triangle: one cell, the box's centre. */
    CHECK_EQ_INT(texopt_camera_close_up_centres(&cam, a, b, c, 100.0, 64, centres), 1);
    CHECK_NEAR(centres[0], 7.5, 1e-9);
    CHECK_NEAR(centres[1], 0.0, 1e-9);
    CHECK_EQ_INT(texopt_camera_close_up_centres(&cam, a, b, c, 0.0, 64, centres), 0);
    CHECK_EQ_INT(texopt_camera_close_up_centres(&cam, a, b, c, NAN, 64, centres), 0);
    CHECK_EQ_INT(texopt_camera_close_up_centres(&cam, a, b, c, 15.0, 0, centres), 0);
    /* A vanishing window: the grid coarsens to the cap instead of overflowing a count. */
    n = texopt_camera_close_up_centres(&cam, a, b, c, 1e-300, 64, centres);
    CHECK(n >= 1 && n <= 64);
}

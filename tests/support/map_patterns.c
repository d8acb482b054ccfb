/* map_patterns.c - the emissive, ORM and normal-map patterns of map_patterns.h.
 *
 * Scratches and cracks are segments drawn from a fixed linear congruential generator; a texel
 * is on a segment when its centre lies within half a line width of it (in texels). Each call
 * regenerates the segments (a few hundred multiplications), so a pattern needs no state. */
#include "map_patterns.h"

#include <math.h>
#include <string.h>

#include "fixtures.h"

#define PI 3.14159265358979323846
#define SCRATCHES 90
#define CRACKS 3
#define CRACK_STEPS 24
#define VISOR_U 0.6
#define VISOR_V 0.4
#define VISOR_R 0.3

typedef struct segment {
    double a[2], b[2];
} segment;

static double next_uniform(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / 16777216.0;
}

/* The distance of point p from segment s (in their units); *side gets a number whose sign
 * says on which side of the segment's line p lies. */
static double segment_distance(const segment *s, const double p[2], double *side)
{
    double d[2] = {s->b[0] - s->a[0], s->b[1] - s->a[1]};
    double e[2] = {p[0] - s->a[0], p[1] - s->a[1]};
    double len2 = d[0] * d[0] + d[1] * d[1];
    double t = len2 > 0 ? (e[0] * d[0] + e[1] * d[1]) / len2 : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    double f[2] = {e[0] - t * d[0], e[1] - t * d[1]};
    *side = d[0] * e[1] - d[1] * e[0];
    return sqrt(f[0] * f[0] + f[1] * f[1]);
}

/* The scratches in texel units of a w x h image. */
static void scratches(int w, int h, segment out[SCRATCHES])
{
    unsigned state = 45u;
    for (int i = 0; i < SCRATCHES; i++) {
        double r = VISOR_R * sqrt(next_uniform(&state)), phi = 2 * PI * next_uniform(&state);
        double angle = PI * next_uniform(&state), len = 0.03 + 0.15 * next_uniform(&state);
        double u = VISOR_U + r * cos(phi), v = VISOR_V + r * sin(phi);
        out[i] = (segment){{u * w, v * h}, {(u + len * cos(angle)) * w, (v + len * sin(angle)) * h}};
    }
}

/* Whether texel centre p lies on a crack (jagged random walks across the image). */
static int on_crack(const double p[2], int w, int h, double half_width)
{
    unsigned state = 7u;
    for (int c = 0; c < CRACKS; c++) {
        double at[2] = {(0.15 + 0.7 * next_uniform(&state)) * w, (0.15 + 0.7 * next_uniform(&state)) * h};
        double heading = 2 * PI * next_uniform(&state);
        for (int k = 0; k < CRACK_STEPS; k++) {
            heading += 1.2 * (next_uniform(&state) - 0.5);
            segment s = {{at[0], at[1]}, {at[0] + 0.02 * w * cos(heading), at[1] + 0.02 * h * sin(heading)}};
            double side;
            if (segment_distance(&s, p, &side) < half_width)
                return 1;
            at[0] = s.b[0];
            at[1] = s.b[1];
        }
    }
    return 0;
}

/* Whether texel centre p lies on a scratch; *hit gets that scratch and *side which side of
 * it p lies. */
static int on_scratch(const double p[2], int w, int h, double half_width, segment *hit, double *side)
{
    double u = p[0] / w - VISOR_U, v = p[1] / h - VISOR_V;
    if (u * u + v * v > VISOR_R * VISOR_R)
        return 0;
    segment s[SCRATCHES];
    scratches(w, h, s);
    for (int i = 0; i < SCRATCHES; i++)
        if (segment_distance(&s[i], p, side) < half_width) {
            *hit = s[i];
            return 1;
        }
    return 0;
}

static void set3(float rgb[3], float r, float g, float b)
{
    rgb[0] = r;
    rgb[1] = g;
    rgb[2] = b;
}

/* Which side of the directed edge a -> b point p lies (> 0: left in a y-down frame). */
static double edge_side(const double a[2], const double b[2], const double p[2])
{
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

static void play_texel(int x, int y, int w, int h, float rgb[3])
{
    double u = (x + 0.5) / w, v = (y + 0.5) / h;
    double p[2] = {u, v};
    set3(rgb, 0, 0, 0);
    double du = u - 0.5, dv = v - 0.4;
    if (du * du + dv * dv <= 0.04) {
        static const double tri[3][2] = {{0.44, 0.31}, {0.6, 0.4}, {0.44, 0.49}};
        int inside =
            edge_side(tri[0], tri[1], p) >= 0 && edge_side(tri[1], tri[2], p) >= 0 && edge_side(tri[2], tri[0], p) >= 0;
        if (inside)
            set3(rgb, 1, 1, 1);
        else
            set3(rgb, 0.9f, 0.15f, 0.1f);
        return;
    }
    if (u >= 0.2 && u < 0.8 && v >= 0.68 && v < 0.8) {
        double glyph_texel = w / 256.0 > 1 ? w / 256.0 : 1; /* a glyph's 8 x 8 cell in texels / 8 */
        int gx = (int)floor((x - 0.2 * w) / glyph_texel), gy = (int)floor((y - 0.68 * h) / glyph_texel);
        if (fixture_glyph_ink(gx, gy))
            set3(rgb, 0.2f, 0.9f, 1.0f);
    }
}

static double half_line_width(int w)
{
    return w / 512.0 > 1 ? 0.5 * w / 512.0 : 0.5;
}

static void orm_texel(int x, int y, int w, int h, float rgb[3])
{
    double p[2] = {x + 0.5, y + 0.5}, side;
    double hw = half_line_width(w);
    segment hit;
    set3(rgb, on_crack(p, w, h, 1.5 * hw) ? 0.25f : 1.0f, 0.55f, 1.0f);
    if (on_scratch(p, w, h, hw, &hit, &side)) {
        rgb[1] = 0.1f;
        rgb[2] = 0.0f;
    }
}

static void grooves_texel(int x, int y, int w, int h, float rgb[3])
{
    double p[2] = {x + 0.5, y + 0.5}, side;
    segment hit;
    set3(rgb, 0.5f, 0.5f, 1.0f);
    if (!on_scratch(p, w, h, 2 * half_line_width(w), &hit, &side))
        return;
    /* Tilt across the groove, away from its axis on either side; image frame x right, y
     * down, so the map's components are (t_x, -t_y) (glTF: X = +u, Y = -v). */
    double d[2] = {hit.b[0] - hit.a[0], hit.b[1] - hit.a[1]}, len = hypot(d[0], d[1]);
    double sign = side > 0 ? 1 : -1, a = -sign * 0.45 * d[1] / len, b = -sign * 0.45 * d[0] / len;
    set3(rgb, (float)(0.5 + 0.5 * a), (float)(0.5 + 0.5 * b), (float)(0.5 + 0.5 * sqrt(1 - a * a - b * b)));
}

int map_pattern_texel(const char *pattern, int x, int y, int w, int h, float rgb[3])
{
    if (strcmp(pattern, "play") == 0)
        play_texel(x, y, w, h, rgb);
    else if (strcmp(pattern, "orm") == 0)
        orm_texel(x, y, w, h, rgb);
    else if (strcmp(pattern, "grooves") == 0)
        grooves_texel(x, y, w, h, rgb);
    else
        return -1;
    return 0;
}

/* texel_map.c - one triangle's texel map, its rotation, the normal-map turn (texel_map.h). */
#include "texel_map.h"

#include <math.h>

int texopt_texel_map(const double from[3][2], const double to[3][2], double m[4], double *area2)
{
    double e1x = to[1][0] - to[0][0], e1y = to[1][1] - to[0][1];
    double e2x = to[2][0] - to[0][0], e2y = to[2][1] - to[0][1];
    double twice_area = e1x * e2y - e2x * e1y;
    if (area2)
        *area2 = twice_area;
    if (!(fabs(twice_area) > 1e-12) || !isfinite(twice_area))
        return 0;
    double f1x = from[1][0] - from[0][0], f1y = from[1][1] - from[0][1];
    double f2x = from[2][0] - from[0][0], f2y = from[2][1] - from[0][1];
    /* M = [f1 f2] [e1 e2]^-1 */
    double inv = 1.0 / twice_area;
    double i00 = e2y * inv, i01 = -e2x * inv, i10 = -e1y * inv, i11 = e1x * inv;
    m[0] = f1x * i00 + f2x * i10;
    m[1] = f1x * i01 + f2x * i11;
    m[2] = f1y * i00 + f2y * i10;
    m[3] = f1y * i01 + f2y * i11;
    return 1;
}

void texopt_texel_map_rotation(const double m[4], double *c, double *s)
{
    double theta = atan2(m[2] - m[1], m[0] + m[3]);
    *c = cos(theta);
    *s = sin(theta);
}

void texopt_normal_turn(double c, double s, float *xy)
{
    double a = 2.0 * xy[0] - 1.0, b = 2.0 * xy[1] - 1.0;
    xy[0] = (float)(0.5 * (c * a - s * b + 1.0));
    xy[1] = (float)(0.5 * (s * a + c * b + 1.0));
}

/* Tests of vec2.h: the signed area's sign follows the orientation, its size the triangle. */
#include "test.h"
#include "vec2.h"

TEST(signed_area_is_half_the_cross_product_with_its_orientation)
{
    const double a[2] = {1, 1}, b[2] = {4, 1}, c[2] = {1, 3};
    CHECK_NEAR(texopt_signed_area(a, b, c), 3.0, 0);  /* counter-clockwise: +3 x 2 / 2 */
    CHECK_NEAR(texopt_signed_area(a, c, b), -3.0, 0); /* clockwise */
    CHECK_NEAR(texopt_signed_area(b, c, a), 3.0, 0);  /* any start */
    const double d[2] = {7, 1};
    CHECK_NEAR(texopt_signed_area(a, b, d), 0.0, 0); /* collinear */
}

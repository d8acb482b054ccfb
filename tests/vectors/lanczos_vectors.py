#!/usr/bin/python3
"""Writes lanczos_vectors.txt: Pillow's Lanczos resizes for tests/unit/test_lanczos.c.

The reference is Pillow itself, Image.resize(size, Image.LANCZOS) on an 8-bit RGB image, the
resize asset pipelines apply (sharp and ImageMagick use the same filter). The input is a
generated texture with smooth ramps, hard edges, a one-texel grid and noise, so that the
kernel's lobes, its stretch on downsizing and the edge rule all show. Pillow rounds to 8 bits
after each of its two passes; engine/bake/lanczos.c does not, which the C test's tolerance covers.

Run: /usr/bin/python3 tests/vectors/lanczos_vectors.py  (needs python3-pil; the C test does
not)."""
import os
import random

from PIL import Image

WIDTH, HEIGHT = 45, 33
SIZES = [(13, 9), (29, 17), (71, 50), (45, 14), (6, 33), (1, 1)]


def texture():
    rng = random.Random(37)
    px = []
    for y in range(HEIGHT):
        for x in range(WIDTH):
            r = int(255 * x / (WIDTH - 1))
            g = 230 if (x // 7 + y // 5) % 2 else 20
            b = 255 if (x % 2 == 0 and y % 3 == 0) else 0
            if x > 30 and y > 20:
                b = rng.randrange(256)
            px.append((r, g, b))
    img = Image.new("RGB", (WIDTH, HEIGHT))
    img.putdata(px)
    return img


def codes(img):
    return " ".join(str(c) for p in img.getdata() for c in p)


def main():
    img = texture()
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "lanczos_vectors.txt")
    lanczos = getattr(Image, "Resampling", Image).LANCZOS
    with open(path, "w") as f:
        f.write("# input width height; its RGB codes; then per case: width height; Pillow %s's "
                "Image.resize(..., LANCZOS) codes. Written by lanczos_vectors.py.\n" % Image.__version__)
        f.write("%d %d\n%s\n" % (WIDTH, HEIGHT, codes(img)))
        for w, h in SIZES:
            f.write("%d %d\n%s\n" % (w, h, codes(img.resize((w, h), lanczos))))


if __name__ == "__main__":
    main()

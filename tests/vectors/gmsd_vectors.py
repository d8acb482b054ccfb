#!/usr/bin/python3
"""Writes gmsd_vectors.txt: GMSD test vectors for tests/unit/test_gmsd.c.

An implementation independent of engine/evaluate/gmsd.c, written from the authors' MATLAB reference
(Xue et al. 2013, GMSD.m): full 2-D convolution and MATLAB's 'same' slicing are emulated
literally with numpy instead of the C code's direct indexing. The mask rule is the one
documented in engine/evaluate/gmsd.h (a downsampled pixel counts when its 2x2 sources and its 3x3
Prewitt support inside the image are covered), written here with morphological erosion.

Run: /usr/bin/python3 tests/vectors/gmsd_vectors.py  (needs numpy; the C test does not).
Images are stored as 8-bit codes; both sides use code / 255 rounded to float32."""
import math
import os

import numpy as np

T = 170.0 / 255.0 ** 2


def conv2_same(a, k):
    """MATLAB conv2(a, k, 'same'): the full convolution, then its central part starting
    at floor(size(k)/2)."""
    m, n = a.shape
    km, kn = k.shape
    full = np.zeros((m + km - 1, n + kn - 1))
    for p in range(km):
        for q in range(kn):
            full[p:p + m, q:q + n] += k[p, q] * a
    r0, c0 = km // 2, kn // 2
    return full[r0:r0 + m, c0:c0 + n]


def gms_map(y1, y2):
    ave = np.full((2, 2), 0.25)
    y1 = conv2_same(y1, ave)[0::2, 0::2]
    y2 = conv2_same(y2, ave)[0::2, 0::2]
    dx = np.array([[1.0, 0.0, -1.0]] * 3) / 3.0
    dy = dx.T
    g1 = np.sqrt(conv2_same(y1, dx) ** 2 + conv2_same(y1, dy) ** 2)
    g2 = np.sqrt(conv2_same(y2, dx) ** 2 + conv2_same(y2, dy) ** 2)
    return (2 * g1 * g2 + T) / (g1 ** 2 + g2 ** 2 + T)


def counted_pixels(mask):
    h, w = mask.shape
    # Pad with covered pixels: outside the image is the reference's zero padding, not
    # background, so it never excludes a pixel.
    padded = np.ones((h + (h % 2), w + (w % 2)), dtype=bool)
    padded[:h, :w] = mask != 0
    down = padded[0::2, 0::2] & padded[1::2, 0::2] & padded[0::2, 1::2] & padded[1::2, 1::2]
    dh, dw = down.shape
    ring = np.ones((dh + 2, dw + 2), dtype=bool)
    ring[1:-1, 1:-1] = down
    counted = np.ones_like(down)
    for p in range(3):
        for q in range(3):
            counted &= ring[p:p + dh, q:q + dw]
    return counted


def gmsd(y1, y2, mask=None):
    g = gms_map(y1.astype(np.float64), y2.astype(np.float64))
    if mask is not None:
        g = g[counted_pixels(mask)]
    g = g.ravel()
    return float(np.std(g, ddof=1)) if g.size >= 2 else 0.0


def smooth_noise(rng, h, w, cells):
    coarse = rng.random((cells + 1, cells + 1))
    ys = np.linspace(0, cells, h)
    xs = np.linspace(0, cells, w)
    out = np.empty((h, w))
    for i, y in enumerate(ys):
        y0 = min(int(y), cells - 1)
        fy = y - y0
        row = (1 - fy) * coarse[y0] + fy * coarse[y0 + 1]
        out[i] = np.interp(xs, np.arange(cells + 1), row)
    return out


def strokes(rng, h, w):
    img = np.full((h, w), 0.9)
    for _ in range(6):
        if rng.random() < 0.5:
            r = rng.integers(0, h)
            img[r:r + 2, rng.integers(0, w // 2 + 1):] = 0.1
        else:
            c = rng.integers(0, w)
            img[rng.integers(0, h // 2 + 1):, c:c + 2] = 0.1
    return img


def disk_mask(h, w, radius):
    yy, xx = np.mgrid[0:h, 0:w]
    return ((yy - h / 2 + 0.5) ** 2 + (xx - w / 2 + 0.5) ** 2 <= radius ** 2).astype(np.uint8)


def box_blur(img):
    return conv2_same(img, np.full((3, 3), 1.0 / 9.0))


def cases(rng):
    for (h, w) in [(16, 16), (17, 13), (31, 33), (36, 40), (5, 7), (1, 9)]:
        ref = 0.5 * smooth_noise(rng, h, w, 3) + 0.5 * strokes(rng, h, w)
        yield f"blur_{w}x{h}", ref, box_blur(ref), None
        noisy = np.clip(ref + rng.normal(0.0, 0.05, ref.shape), 0.0, 1.0)
        yield f"noise_{w}x{h}", ref, noisy, None
        if h >= 5 and w >= 5:
            mask = disk_mask(h, w, 0.4 * min(h, w))
            yield f"blur_masked_{w}x{h}", ref, box_blur(ref), mask
            yield f"noise_masked_{w}x{h}", ref, noisy, mask
    h, w = 24, 20
    ref = strokes(rng, h, w)
    yield "shifted_strokes_20x24", ref, np.roll(ref, 1, axis=1), None
    yield "constant_vs_strokes_20x24", np.full((h, w), 0.5), ref, None
    mask = np.ones((h, w), dtype=np.uint8)
    for _ in range(4):
        r, c = rng.integers(0, h - 2), rng.integers(0, w - 2)
        mask[r:r + 2, c:c + 3] = 0
    yield "holes_mask_20x24", ref, box_blur(ref), mask


def quantize(values):
    """8-bit codes, as textures are stored; the images are code / 255 in float32."""
    return np.clip(np.rint(np.asarray(values) * 255.0), 0, 255).astype(np.int32)


def write_codes(out, codes):
    out.write(" ".join(str(int(v)) for v in codes.ravel()) + "\n")


def main():
    rng = np.random.default_rng(20131)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "gmsd_vectors.txt")
    tmp = path + ".tmp"
    with open(tmp, "w") as out:
        out.write("# name width height has_mask expected_gmsd; then reference, distorted "
                  "(8-bit codes, image = code / 255 in float32) [, mask] rows. "
                  "Written by gmsd_vectors.py.\n")
        for name, ref, dist, mask in cases(rng):
            ref_codes, dist_codes = quantize(ref), quantize(dist)
            ref = ref_codes.astype(np.float32) / np.float32(255.0)
            dist = dist_codes.astype(np.float32) / np.float32(255.0)
            value = gmsd(ref, dist, mask)
            assert math.isfinite(value)
            h, w = ref.shape
            out.write(f"{name} {w} {h} {0 if mask is None else 1} {value:.17g}\n")
            write_codes(out, ref_codes)
            write_codes(out, dist_codes)
            if mask is not None:
                out.write(" ".join(str(int(v)) for v in mask.ravel()) + "\n")
        out.flush()
        os.fsync(out.fileno())
    os.replace(tmp, path)


if __name__ == "__main__":
    main()

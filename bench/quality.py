#!/usr/bin/python3
"""How close an image is to a converged one, over the pixels lit in the converged one.

    bench/quality.py IMAGE CONVERGED [--down K]

prints "ssim=S psnr=P lit=L" for IMAGE against CONVERGED (8-bit PNGs of one size; with --down K,
CONVERGED is K times larger in each direction and is box-filtered down first: the mean of each
K x K block of its display values). The black background would hide the noise, so both measures
are taken over the lit pixels of the converged image (luminance above 2/255), grown by one pixel
so that an edge's anti-aliasing counts: SSIM on the luminance with 7 x 7 box windows (the
windows' statistics over the whole image, the mean of the SSIM map over the lit pixels), PSNR
on the RGB values in [0, 1]. Uses numpy and Pillow (Debian's python3-numpy, python3-pil).
"""
import sys

import numpy as np
from PIL import Image


def load(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0


def down(img, k):
    h, w, c = img.shape
    return img[: h // k * k, : w // k * k].reshape(h // k, k, w // k, k, c).mean(axis=(1, 3))


def box(a, r):
    """The mean over (2r + 1)^2 windows, the edges padded by reflection."""
    p = np.pad(a, r, mode="reflect")
    s = p.cumsum(0).cumsum(1)
    s = np.pad(s, ((1, 0), (1, 0)))
    n = 2 * r + 1
    return (s[n:, n:] - s[:-n, n:] - s[n:, :-n] + s[:-n, :-n]) / (n * n)


def luminance(img):
    return img @ np.array([0.2126, 0.7152, 0.0722])


def lit_mask(converged):
    lit = luminance(converged) > 2.0 / 255
    grown = lit.copy()
    grown[1:] |= lit[:-1]
    grown[:-1] |= lit[1:]
    grown[:, 1:] |= lit[:, :-1]
    grown[:, :-1] |= lit[:, 1:]
    return grown


def measures(img, converged):
    lit = lit_mask(converged)
    x, y = luminance(img), luminance(converged)
    c1, c2, r = 0.01**2, 0.03**2, 3
    mx, my = box(x, r), box(y, r)
    vx, vy, cxy = box(x * x, r) - mx * mx, box(y * y, r) - my * my, box(x * y, r) - mx * my
    ssim = ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2))
    mse = ((img - converged) ** 2)[lit].mean()
    psnr = 10 * np.log10(1.0 / mse) if mse > 0 else float("inf")
    return float(ssim[lit].mean()), float(psnr), int(lit.sum())


def main(argv):
    args = argv[1:]
    k = 1
    if "--down" in args:
        i = args.index("--down")
        k = int(args[i + 1])
        del args[i : i + 2]
    if len(args) != 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    img, conv = load(args[0]), load(args[1])
    if k > 1:
        conv = down(conv, k)
    if img.shape != conv.shape:
        print(f"quality.py: {args[0]} is {img.shape[1]}x{img.shape[0]}, the converged image "
              f"{conv.shape[1]}x{conv.shape[0]}", file=sys.stderr)
        return 2
    s, p, n = measures(img, conv)
    print(f"ssim={s:.4f} psnr={p:.2f} lit={n}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

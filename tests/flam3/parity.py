#!/usr/bin/python3
"""fixpoint against flam3-render on random genomes of flam3-genome: the structural similarity
(SSIM) of the two pictures of each genome, as a Markdown table.

    tests/flam3/parity.py [--fixpoint build/bin/fixpoint] [--genomes DIR] [--make N]
                          [--scale 2] [--quality 20] [--out DIR] > table.md

--make N writes N new genomes into --genomes first (flam3-genome's random mode; two of its
runs with the same seed give different genomes, so the genomes are kept, not their seeds).
Each genome is rendered by flam3-render (one thread, `ss` times its size, `qs` times its
quality) and by fixpoint from the same file (`fixpoint render GENOME.flam3`, at that size
and density), and by flam3-render once more with another seed: flam3 against itself is the
noise floor that no renderer can beat at that quality. SSIM is Wang et al.'s (2004), on the
luma (Rec. 601) in [0, 255], with an 11-tap Gaussian window of sigma 1.5, K1 0.01, K2 0.03.

Needs Debian's flam3-utils and python3-pil; nothing else.
"""
import argparse
import glob
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

from PIL import Image


def luma(path):
    im = Image.open(path).convert("RGB")
    w, h = im.size
    px = im.load()
    return w, h, [[0.299 * px[x, y][0] + 0.587 * px[x, y][1] + 0.114 * px[x, y][2]
                   for x in range(w)] for y in range(h)]


def kernel():
    k = [math.exp(-((i - 5) ** 2) / (2 * 1.5 ** 2)) for i in range(11)]
    s = sum(k)
    return [v / s for v in k]


def blur(img, k):
    """The 'valid' part of the separable convolution with k."""
    n = len(k)
    rows = [[sum(k[j] * r[x + j] for j in range(n)) for x in range(len(r) - n + 1)]
            for r in img]
    return [[sum(k[j] * rows[y + j][x] for j in range(n)) for x in range(len(rows[0]))]
            for y in range(len(rows) - n + 1)]


def ssim(a, b):
    k = kernel()
    c1, c2 = (0.01 * 255) ** 2, (0.03 * 255) ** 2
    ma, mb = blur(a, k), blur(b, k)
    saa = blur([[v * v for v in r] for r in a], k)
    sbb = blur([[v * v for v in r] for r in b], k)
    sab = blur([[u * v for u, v in zip(ra, rb)] for ra, rb in zip(a, b)], k)
    total, n = 0.0, 0
    for y in range(len(ma)):
        for x in range(len(ma[0])):
            mx, my = ma[y][x], mb[y][x]
            vx, vy, cxy = saa[y][x] - mx * mx, sbb[y][x] - my * my, sab[y][x] - mx * my
            total += ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2))
            n += 1
    return total / n


def run(cmd, **kw):
    """Runs cmd; its standard error's last line when it fails, else None."""
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, **kw)
    return (r.stderr.strip().splitlines() or ["exit %d" % r.returncode])[-1] if r.returncode else None


def flam3_render(genome, out, scale, quality, seed):
    env = dict(os.environ, ss=str(scale), qs=str(quality), nthreads="1", out=out, isaac_seed="fixpoint-%d" % seed)
    with open(genome) as f:
        err = run(["flam3-render"], stdin=f, env=env)
    if err:
        sys.exit("flam3-render failed on %s: %s" % (genome, err))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fixpoint", default="build/bin/fixpoint")
    ap.add_argument("--genomes", default="tests/fixtures/flam3/parity")
    ap.add_argument("--make", type=int, default=0)
    ap.add_argument("--scale", type=int, default=2)
    ap.add_argument("--quality", type=float, default=20)
    ap.add_argument("--out", default="/tmp/fixpoint-flam3-parity")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.make:
        os.makedirs(a.genomes, exist_ok=True)
        for i in range(a.make):
            path = os.path.join(a.genomes, "genome-%03d.flam3" % i)
            with open(path, "w") as f:
                subprocess.run(["flam3-genome"], stdout=f, check=True, stderr=subprocess.DEVNULL,
                               env=dict(os.environ, seed=str(1000 + i)))
    genomes = sorted(glob.glob(os.path.join(a.genomes, "*.flam3")))
    if not genomes:
        sys.exit("no genomes in " + a.genomes)
    print("| genome | SSIM fixpoint : flam3 | SSIM flam3 : flam3 (noise) |")
    print("|---|---|---|")
    scores = []
    for g in genomes:
        name = os.path.splitext(os.path.basename(g))[0]
        f1, f2, o = (os.path.join(a.out, name + s + ".png") for s in ("-flam3", "-flam3b", "-fixpoint"))
        flam3_render(g, f1, a.scale, a.quality, 1)
        flam3_render(g, f2, a.scale, a.quality, 2)
        w, h, lf = luma(f1)
        flame = ET.parse(g).getroot()
        flame = flame if flame.tag == "flame" else flame.find("flame")
        # flam3's samples: its quality times qs, per pixel of the image at its zoom.
        q = float(flame.get("quality", "1")) * a.quality * 4 ** float(flame.get("zoom", "0"))
        err = run([a.fixpoint, "render", "--quiet", "--force", "--threads", "1", g, "-o", o,
             "--set", "renderer.width=%d" % w, "--set", "renderer.height=%d" % h,
             "--set", "renderer.points=%d" % round(q * w * h)])
        noise = ssim(lf, luma(f2)[2])
        if err:
            # (fixpoint refuses the genome: its line, and no score.)
            scores.append((0.0, noise, name))
            print("| %s | refused: `%s` | %.3f |" % (name, err.split(": ", 1)[-1], noise), flush=True)
            continue
        s = ssim(lf, luma(o)[2])
        scores.append((s, noise, name))
        print("| %s | %.3f | %.3f |" % (name, s, noise), flush=True)
    good = sum(1 for s, _, _ in scores if s >= 0.9)
    print()
    print("%d of %d genomes at SSIM >= 0.9 (flam3 against itself: %d); median %.3f (flam3's own %.3f)." % (
        good, len(scores), sum(1 for _, n, _ in scores if n >= 0.9),
        sorted(s for s, _, _ in scores)[len(scores) // 2], sorted(n for _, n, _ in scores)[len(scores) // 2]))


if __name__ == "__main__":
    main()

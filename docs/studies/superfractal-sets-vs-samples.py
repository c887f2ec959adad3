# Study behind the "Buffers: point samples, not sets" note of plugins/renderers/superfractal.cpp
# (Python standard library only). Usage: python3 superfractal-sets-vs-samples.py W N SEED...
# e.g. 256 300000 12 3; writes overlays (red: set form only, green: samples only, yellow: both)
# to the working folder (seedS-WW.png: the bitmap at W; seedS-WW-4x.png: at 4 W, read at W).
# Sets vs fixed-size samples in the buffer algorithm of paper 03, Sec. III (F and G of eq. (2)).
# The same random choices drive both forms:
#   set form (the paper's): each buffer is a set of pixels of a W x W bitmap; a new buffer is
#     the union of f_j(pixel centres of its source buffer), each image point lighting its pixel;
#   sample form (the renderer's): each buffer is N points; share j of the new buffer is f_j of
#     the source points j, j + m, j + 2m, ... (every source point used once when all maps read
#     the same buffer).
# The child (buffer 0 after `steps` steps) is compared as a set of lit pixels of the W x W view.
import random, sys, zlib, struct
F = [(0.5, 0.375, 0.5, -0.375, -0.0625, 0.5625), (0.5, -0.375, -0.5, -0.375, 0.5625, 1.0625)]
G = [(0.5, 0.375, -0.5, 0.375, -0.0625, 0.4375), (0.5, -0.375, 0.5, 0.375, 0.5625, -0.0625)]
IFS = [F, G]
X0, X1 = 0.1, 0.9  # view, square

def ap(c, x, y): return c[0]*x + c[1]*y + c[4], c[2]*x + c[3]*y + c[5]

def pix(x, y, W):
    if not (X0 <= x < X1 and X0 < y <= X1): return None
    return (min(int((x - X0) * W / (X1 - X0)), W - 1), min(int((X1 - y) * W / (X1 - X0)), W - 1))

def centre(p, W):
    c, r = p
    return X0 + (c + 0.5) * (X1 - X0) / W, X1 - (r + 0.5) * (X1 - X0) / W

def choices(seed, steps, B=2):
    rng = random.Random(seed)
    out = []
    for s in range(steps):
        step = []
        for b in range(B):
            i = rng.randrange(2)
            step.append((i, [rng.randrange(B) for _ in IFS[i]]))
        out.append(step)
    return out

def set_form(ch, W, sub=1):
    # bitmap at sub * W, reported at W
    Wi = W * sub
    start = {(c, r) for c in range(0, Wi, 3) for r in range(0, Wi, 3)}
    bufs = [set(start), set(start)]
    for step in ch:
        new = []
        for (i, src) in step:
            s = set()
            for j, m in enumerate(IFS[i]):
                for p in bufs[src[j]]:
                    q = pix(*ap(m, *centre(p, Wi)), Wi)
                    if q: s.add(q)
            new.append(s)
        bufs = new
    return {(c // sub, r // sub) for (c, r) in bufs[0]}

def sample_form(ch, W, N, seed=1):
    rng = random.Random(seed + 1000)
    bufs = [[(X0 + (X1 - X0) * rng.random(), X0 + (X1 - X0) * rng.random()) for _ in range(N)] for _ in range(2)]
    for step in ch:
        new = []
        for (i, src) in step:
            maps = IFS[i]; m = len(maps); out = []
            for j, mp in enumerate(maps):
                sb = bufs[src[j]]
                out += [ap(mp, *sb[k]) for k in range(j, N, m)]
            new.append(out)
        bufs = new
    lit = set()
    for (x, y) in bufs[0]:
        q = pix(x, y, W)
        if q: lit.add(q)
    return lit

def unmatched(a, b):
    return sum(1 for (c, r) in a if not any((c + dc, r + dr) in b for dc in (-1, 0, 1) for dr in (-1, 0, 1)))

def write_png(path, W, layers):  # layers: list of (set, rgb)
    rows = []
    for r in range(W):
        row = bytearray([0])
        for c in range(W):
            px = [0, 0, 0]
            for s, rgb in layers:
                if (c, r) in s: px = [min(255, a + b) for a, b in zip(px, rgb)]
            row += bytes(px)
        rows.append(bytes(row))
    def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', W, W, 8, 2, 0, 0, 0)) +
                           chunk(b'IDAT', zlib.compress(b''.join(rows))) + chunk(b'IEND', b''))

if __name__ == '__main__':
    W = int(sys.argv[1]); N = int(sys.argv[2]); steps = 30
    for seed in [int(s) for s in sys.argv[3:]]:
        ch = choices(seed, steps)
        S = set_form(ch, W); S4 = set_form(ch, W, 4); P = sample_form(ch, W, N)
        print(f"seed {seed}: W={W} N={N}: set form {len(S)} px, set form 4x {len(S4)} px, samples {len(P)} px; "
              f"|S-P|={len(S-P)} |P-S|={len(P-S)}; set px >1 px from samples {unmatched(S, P)}, "
              f"sample px >1 px from set {unmatched(P, S)}; 4x set vs samples: |S4-P|={len(S4-P)} |P-S4|={len(P-S4)} "
              f"far {unmatched(S4, P)}/{unmatched(P, S4)}")
        # red: set form only, green: samples only, yellow: both
        write_png(f'seed{seed}-W{W}.png', W, [(S, (255, 0, 0)), (P, (0, 255, 0))])
        write_png(f'seed{seed}-W{W}-4x.png', W, [(S4, (255, 0, 0)), (P, (0, 255, 0))])

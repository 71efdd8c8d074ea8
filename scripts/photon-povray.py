#!/usr/bin/env python3
"""Side by side with POV-Ray 3.7's photons on a glass-ball caustic.

The scene is bench/photons/caustic.txt for glint and caustic-pov.pov for
POV-Ray (the same camera, point light, floor and glass ball of IOR 1.5,
320x240). For each renderer, a sweep of photon budgets is rendered and
each picture's error is measured against that renderer's own reference,
rendered with 100 times the sweep's largest budget:

- glint: PPM (`--photons ppm`), 100 000 photons emitted an iteration,
  1 to 16 iterations; reference 1600 iterations.
- POV-Ray: `photons { count N }`, N = 10 000 to 300 000; reference 30 M.

The error is a relative L2 on linear values, ||img - ref|| / ||ref||, over
the floor pixels that lie in the ball's shadow (computed exactly from the
scene's geometry, see shadow_pixels): there the picture is the caustic and
nothing else in both renderers (glint's shadow rays stop at the glass;
POV-Ray's stop at a photon target with `refraction on` when photons are on,
and without photons POV-Ray casts no shadow there at all). Both renderers
write Radiance .hdr (linear floats, not clamped), so no gamma or 8-bit
clipping enters; POV-Ray's caustic is about 28 times brighter than glint's
(its photons do not fall off with distance, glint's do as 1/d^2), which a
relative error does not see.

The timed renders alternate between the two renderers (glint's level i,
then POV-Ray's level i, ...) and are repeated --reps times; each time is
the whole process (wall clock, and the CPU time of the child process), one
thread each (--threads 1, +WT1). The errors do not change between
repetitions (both renderers are deterministic); the script checks it.

Usage: scripts/photon-povray.py [--threshold 0.40] [--reps 5] [--png FILE]
(needs `apt-get install povray` and `cargo build --release`). The two
references are cached in target/photon-povray/ (about 95 CPU-seconds on
the first run); --fresh renders them again. --png FILE writes a side by
side of the two references (docs/photons/povray-side-by-side.png).
--gather N sets POV-Ray's `gather 20, N`, the most photons one estimate
uses (POV-Ray's default, 100, bounds how far its noise falls however many
photons it shoots).
"""
import argparse
import math
import os
import resource
import statistics
import struct
import subprocess
import sys
import time
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
GLINT = os.path.join(ROOT, "target", "release", "glint")
SCENE = os.path.join(ROOT, "bench", "photons", "caustic.txt")
POV = os.path.join(ROOT, "bench", "photons", "caustic-pov.pov")
CACHE = os.path.join(ROOT, "target", "photon-povray")
W, H = 320, 240

GLINT_EMIT = 100_000            # photons emitted per PPM iteration
GLINT_LEVELS = [1, 2, 3, 4, 6, 8, 12, 16]  # PPM iterations
POV_LEVELS = [10_000, 20_000, 30_000, 50_000, 100_000, 150_000, 200_000, 300_000]  # counts
REF_FACTOR = 100                # reference = 100 x the largest level
POV_GATHER = 100                # POV-Ray's most photons an estimate (its default; --gather)

# The scene's geometry in POV-Ray's coordinates (y up; glint's file is the
# same with y and z swapped): keep in step with bench/photons/.
EYE, LOOK_AT, HALF_FOV = (0.0, 3.2, -7.0), (0.0, 0.4, 0.0), math.radians(24)
LIGHT, BALL, RADIUS = (1.5, 5.0, 0.5), (0.0, 1.0, 0.0), 1.0


# ---------------------------------------------------------------- images

def read_hdr(path):
    """A Radiance RGBE picture (flat or new-style run-length encoded), as a
    list of (r, g, b) floats, rows from the top."""
    with open(path, "rb") as f:
        data = f.read()
    i = 0
    while True:  # header lines, then the resolution line
        j = data.index(b"\n", i)
        line, i = data[i:j], j + 1
        if line[:2] in (b"-Y", b"+Y"):
            t = line.split()
            h, w = int(t[1]), int(t[3])
            assert t[0] == b"-Y" and t[2] == b"+X", f"{path}: unusual orientation"
            break
    assert (w, h) == (W, H), f"{path}: {w}x{h}, expected {W}x{H}"
    px = []
    for _ in range(h):
        if data[i] == 2 and data[i + 1] == 2 and (data[i + 2] << 8 | data[i + 3]) == w:
            i += 4
            chans = []
            for _ in range(4):  # r, g, b and e, each run-length encoded
                row = bytearray()
                while len(row) < w:
                    n = data[i]
                    i += 1
                    if n > 128:
                        row += bytes([data[i]]) * (n - 128)
                        i += 1
                    else:
                        row += data[i:i + n]
                        i += n
                chans.append(row)
            quads = zip(*chans)
        else:
            quads = [tuple(data[i + 4 * k:i + 4 * k + 4]) for k in range(w)]
            i += 4 * w
        for r, g, b, e in quads:
            f = 0.0 if e == 0 else math.ldexp(1.0, e - 136)
            px.append((r * f, g * f, b * f))
    return px


def write_png(path, w, h, rows):
    """An 8-bit RGB PNG from rows of (r, g, b) byte triples."""
    raw = b"".join(b"\0" + bytes(v for p in row for v in p) for row in rows)

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n"
                + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


# ------------------------------------------------------- the caustic region

def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def unit(a):
    n = math.sqrt(dot(a, a))
    return tuple(x / n for x in a)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def meets_ball(o, d, t_max):
    """Whether o + t d meets the ball for some 0 < t < t_max."""
    oc = sub(o, BALL)
    a, b, c = dot(d, d), dot(oc, d), dot(oc, oc) - RADIUS * RADIUS
    disc = b * b - a * c
    return disc >= 0 and 1e-9 < (-b - math.sqrt(disc)) / a < t_max


def shadow_pixels():
    """Indices of the pixels that see the floor (not the ball) at a point
    the ball hides from the light. A pixel counts only when its four
    corners and its centre all do, so the region does not depend on where
    in the pixel either renderer puts its one ray."""
    f = unit(sub(LOOK_AT, EYE))
    r = unit(cross((0.0, 1.0, 0.0), f))  # left-handed, as POV-Ray: x right
    u = cross(f, r)
    half_w = math.tan(HALF_FOV)
    half_h = half_w * H / W

    def shadowed(x, y):  # x, y in pixels from the top-left corner
        a, b = (2 * x / W - 1) * half_w, (1 - 2 * y / H) * half_h
        d = tuple(f[k] + a * r[k] + b * u[k] for k in range(3))
        if d[1] >= 0 or meets_ball(EYE, d, math.inf):
            return False
        t = -EYE[1] / d[1]
        p = tuple(EYE[k] + t * d[k] for k in range(3))
        return meets_ball(p, sub(LIGHT, p), 1.0)

    corners = ((0, 0), (1, 0), (0, 1), (1, 1), (0.5, 0.5))
    return [k for k in range(W * H)
            if all(shadowed(k % W + dx, k // W + dy) for dx, dy in corners)]


def rel_error(img, ref, region):
    """||img - ref|| / ||ref|| over the region's pixels, all three channels."""
    num = sum((img[k][c] - ref[k][c]) ** 2 for k in region for c in range(3))
    den = sum(ref[k][c] ** 2 for k in region for c in range(3))
    return math.sqrt(num / den)


# ---------------------------------------------------------------- renders

def glint_args(iterations, out, threads=1):
    return [GLINT, "render", SCENE, "-o", out, "--spp", "1", "-q", "--photons", "ppm",
            "--emit", str(GLINT_EMIT), "--iterations", str(iterations),
            "--checkpoint", str(iterations), "--threads", str(threads)]


def povray_args(count, out, threads=1):
    # -A: no anti-aliasing (glint's --spp 1: one ray a pixel); -D: no
    # display; -GA: fewer console streams; +FH: Radiance .hdr, linear
    # floats, not clamped (gamma settings do not apply to it).
    return ["povray", "+I" + POV, "+O" + out, "+FH", f"+W{W}", f"+H{H}", "-D", "-A",
            "-GA", f"+WT{threads}", f"Declare=COUNT={count}", f"Declare=GATHER={POV_GATHER}"]


def run(args, out):
    """Runs one render; returns (wall s, CPU s of the child, picture)."""
    if os.path.exists(out):
        os.remove(out)  # never read a stale picture
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, read_hdr(out)


def reference(name, args_of, level, fresh):
    """The cached reference picture, rendered (two threads) when missing."""
    tag = f"-gather{POV_GATHER}" if name == "povray" and POV_GATHER != 100 else ""
    path = os.path.join(CACHE, f"{name}-ref-{level}{tag}.hdr")
    if fresh or not os.path.exists(path):
        print(f"rendering {name}'s reference ({level}) ...", flush=True)
        wall, cpu, _ = run(args_of(level, path, 2), path)
        print(f"  {wall:.0f} s wall, {cpu:.0f} s CPU", flush=True)
    return read_hdr(path)


def side_by_side(path, g_ref, p_ref, region):
    """glint's reference left, POV-Ray's right. Top: the whole pictures,
    linear values at the same exposure, gamma 2.2 for the screen (POV-Ray's
    caustic clips: its photons do not fall off with distance). Bottom: the
    caustic region (the ball's shadow, 2x), each picture divided by its own
    99.5th percentile there; grey outside the region."""
    gap = 8
    grey, white = (96, 96, 96), (255, 255, 255)

    def enc(colour, scale):  # linear -> 8-bit, gamma 2.2, clipped
        return tuple(min(255, round(255 * min(1.0, max(0.0, v * scale)) ** (1 / 2.2)))
                     for v in colour)

    rows = [[enc(img[y * W + x], 1.0) for img in (g_ref, p_ref) for x in range(W)]
            for y in range(H)]
    rows = [r[:W] + [white] * gap + r[W:] for r in rows]
    rows += [[white] * (2 * W + gap)] * gap
    xs, ys = [k % W for k in region], [k // W for k in region]
    x0, y0 = min(xs), min(ys)
    bw, bh = max(xs) - x0 + 1, max(ys) - y0 + 1
    zoom = max(1, min(2, W // bw))
    inside = set(region)
    scales = []
    for img in (g_ref, p_ref):
        lum = sorted(sum(img[k]) / 3 for k in region)
        scales.append(1.0 / lum[int(0.995 * (len(lum) - 1))])
    for y in range(bh * zoom):
        row = []
        for img, s in zip((g_ref, p_ref), scales):
            part = []
            for x in range(bw * zoom):
                k = (y0 + y // zoom) * W + x0 + x // zoom
                part.append(enc(img[k], s) if k in inside else grey)
            part += [grey] * (W - len(part))
            row += part + ([white] * gap if img is g_ref else [])
        rows.append(row)
    write_png(path, 2 * W + gap, len(rows), rows)
    ratio = sum(sum(p_ref[k]) for k in region) / sum(sum(g_ref[k]) for k in region)
    return ratio


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--threshold", type=float, default=0.40,
                    help="relative L2 error in the caustic region (default 0.40)")
    ap.add_argument("--reps", type=int, default=5, help="timed repetitions (default 5)")
    ap.add_argument("--fresh", action="store_true", help="render the references again")
    ap.add_argument("--png", help="write a side by side of the two references")
    ap.add_argument("--gather", type=int, default=100,
                    help="POV-Ray's `gather 20, N`: the most photons one estimate uses "
                         "(default 100, POV-Ray's own)")
    a = ap.parse_args()
    global POV_GATHER
    POV_GATHER = a.gather
    os.makedirs(CACHE, exist_ok=True)
    print(f"load average before: {os.getloadavg()[0]:.1f} (on {os.cpu_count()} cores)")

    region = shadow_pixels()
    g_ref = reference("glint", glint_args, REF_FACTOR * GLINT_LEVELS[-1], a.fresh)
    p_ref = reference("povray", povray_args, REF_FACTOR * POV_LEVELS[-1], a.fresh)
    if a.png:
        ratio = side_by_side(a.png, g_ref, p_ref, region)
        print(f"wrote {a.png}; POV-Ray's caustic / glint's (mean in the region): {ratio:.1f}")

    # Timed sweeps: glint's level i, then POV-Ray's level i, repeated.
    out_g, out_p = os.path.join(CACHE, "glint.hdr"), os.path.join(CACHE, "povray.hdr")
    times = {("glint", n): [] for n in GLINT_LEVELS}
    times.update({("povray", n): [] for n in POV_LEVELS})
    errors = {}
    for rep in range(a.reps):
        for i in range(max(len(GLINT_LEVELS), len(POV_LEVELS))):
            jobs = []
            if i < len(GLINT_LEVELS):
                n = GLINT_LEVELS[i]
                jobs.append(("glint", n, glint_args(n, out_g), out_g, g_ref))
            if i < len(POV_LEVELS):
                n = POV_LEVELS[i]
                jobs.append(("povray", n, povray_args(n, out_p), out_p, p_ref))
            for name, n, args, out, ref in jobs:
                wall, cpu, img = run(args, out)
                e = rel_error(img, ref, region)
                if errors.setdefault((name, n), e) != e:  # both are deterministic
                    print(f"warning: {name} {n}: error {e} differs from the first "
                          f"run's {errors[name, n]}")
                times[name, n].append((wall, cpu))
        print(f"repetition {rep + 1} done; load average {os.getloadavg()[0]:.1f}", flush=True)

    med = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v))
           for k, v in times.items()}

    def spread(name, n, i):  # "median (min-max)" of wall (i = 0) or CPU (1) times
        xs = [t[i] for t in times[name, n]]
        return f"{med[name, n][i]:.2f} ({min(xs):.2f}-{max(xs):.2f})"

    print(f"\ncaustic region: {len(region)} pixels (the ball's shadow on the floor); "
          f"references: glint {REF_FACTOR * GLINT_LEVELS[-1]} iterations, "
          f"POV-Ray {REF_FACTOR * POV_LEVELS[-1]} photons (gather 20, {POV_GATHER}); "
          f"medians of {a.reps} runs\n")
    sweeps = (("glint", GLINT_LEVELS, "PPM iterations (x100 000 photons)"),
              ("povray", POV_LEVELS, "photons (count)"))
    for name, levels, what in sweeps:
        print(f"| {name} {what} | relative error | wall s, median (range) | CPU s |")
        print("|---:|---:|---:|---:|")
        for n in levels:
            print(f"| {n} | {errors[name, n]:.3f} | {spread(name, n, 0)} | "
                  f"{spread(name, n, 1)} |")
        print()
    # The first level of each sweep under the threshold (no interpolation).
    for name, levels, _ in sweeps:
        under = [n for n in levels if errors[name, n] < a.threshold]
        if under:
            print(f"{name}: under {a.threshold} at {under[0]}: "
                  f"{spread(name, under[0], 0)} s wall, {spread(name, under[0], 1)} s CPU")
        else:
            print(f"{name}: not under {a.threshold} in the sweep")
    print(f"load average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    sys.exit(main())

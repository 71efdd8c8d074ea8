#!/usr/bin/env python3
"""Side by side with POV-Ray 3.7's photons on a glass-ball caustic
(bench/photons/): for each renderer, the time to bring the caustic's error
against its own converged reference (10x glint's iterations, 100x POV-Ray's photons) under a threshold.

The caustic region is where the reference with photons is brighter than
the same render without photons by more than 8/255; the error is the RMS
difference in that region, in 8-bit units. Renders alternate between the
two renderers. Usage: scripts/photon-povray.py [--threshold 4]
(needs `apt-get install povray`, and `cargo build --release`).
"""
import argparse, os, struct, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
GLINT = os.path.join(ROOT, "target", "release", "glint")
SCENE = os.path.join(ROOT, "bench", "photons", "caustic.txt")
POV = os.path.join(ROOT, "bench", "photons", "caustic-pov.pov")
W, H = 480, 360


def read_bmp(path):
    with open(path, "rb") as f:
        data = f.read()
    off = struct.unpack_from("<I", data, 10)[0]
    w, h = struct.unpack_from("<ii", data, 18)
    row = (w * 3 + 3) & ~3
    px = []
    for y in range(abs(h)):
        r = (abs(h) - 1 - y) if h > 0 else y
        base = off + r * row
        for x in range(w):
            b, g, rr = data[base + 3 * x: base + 3 * x + 3]
            px.append((rr, g, b))
    return px


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts, i = [], 0
    while len(parts) < 4:
        while data[i:i + 1].isspace():
            i += 1
        if data[i:i + 1] == b"#":
            while data[i:i + 1] != b"\n":
                i += 1
            continue
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        parts.append(data[i:j])
        i = j
    i += 1
    body = data[i:]
    return [tuple(body[3 * k: 3 * k + 3]) for k in range(W * H)]


def glint(iterations, out):
    """PPM with 100 000 photons an iteration (0: photons off)."""
    mode = "off" if iterations == 0 else "ppm"
    args = [GLINT, "render", SCENE, "-o", out, "--spp", "1", "-q", "--photons", mode]
    if iterations:
        args += ["--emit", "100000", "--iterations", str(iterations)]
    t = time.perf_counter()
    subprocess.run(args, check=True, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t, read_bmp(out)


def povray(count, out):
    args = ["povray", "+I" + POV, "+O" + out, "+FP", f"+W{W}", f"+H{H}", "-D", "-A",
            "-GA", f"Declare=COUNT={count}"]
    t = time.perf_counter()
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t, read_ppm(out)


def region(ref, off):
    return [k for k in range(len(ref)) if sum(ref[k]) - sum(off[k]) > 3 * 8]


def rms(img, ref, where):
    s = sum((img[k][c] - ref[k][c]) ** 2 for k in where for c in range(3))
    return (s / (3 * max(len(where), 1))) ** 0.5


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--threshold", type=float, default=4.0)
    a = ap.parse_args()
    # POV-Ray aims its photons at the ball; glint emits over the whole
    # sphere, as the lineage does: about 1/60 of them meet the ball here.
    g_counts = [1, 3, 10, 30, 100]  # PPM iterations of 100 000 photons
    p_counts = [300, 1000, 3000, 10000, 30000]
    tmp = tempfile.mkdtemp()
    g = lambda n: os.path.join(tmp, f"g{n}.bmp")
    p = lambda n: os.path.join(tmp, f"p{n}.ppm")
    _, g_off = glint(0, g(0))
    _, p_off = povray(0, p(0))
    _, g_ref = glint(10 * g_counts[-1], g("ref"))
    _, p_ref = povray(100 * p_counts[-1], p("ref"))
    g_where, p_where = region(g_ref, g_off), region(p_ref, p_off)
    print(f"caustic region: glint {len(g_where)} px, POV-Ray {len(p_where)} px; "
          f"threshold {a.threshold}/255 RMS")
    print("| glint PPM iterations | glint s | glint RMS | POV-Ray photons | POV-Ray s | POV-Ray RMS |")
    print("|---|---|---|---|---|---|")
    first = {"glint": None, "povray": None}
    for n, m in zip(g_counts, p_counts):
        tg, ig = glint(n, g(n))
        tp, ip = povray(m, p(m))
        eg, ep = rms(ig, g_ref, g_where), rms(ip, p_ref, p_where)
        print(f"| {n} | {tg:.2f} | {eg:.2f} | {m} | {tp:.2f} | {ep:.2f} |")
        if eg < a.threshold and first["glint"] is None:
            first["glint"] = (n, tg)
        if ep < a.threshold and first["povray"] is None:
            first["povray"] = (m, tp)
    for k, v in first.items():
        print(f"{k}: " + (f"under {a.threshold} at {v[0]} photons, {v[1]:.2f} s" if v else "not under the threshold"))


if __name__ == "__main__":
    sys.exit(main())

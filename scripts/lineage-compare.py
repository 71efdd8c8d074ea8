#!/usr/bin/env python3
"""Renders the lineages' own scene files at the size of the pictures their
repositories ship and compares them with `glint compare` (docs/lineages.md,
"Side by side").

    scripts/lineage-compare.py LINEAGES OUT [--only LABEL ...] [--noise]
                               [--docs DIR] [--glint BINARY] [--build]

LINEAGES holds the repositories' checkouts as OWNER+NAME folders (their
licences keep them out of this repository); OUT receives, for each pair,
glint's render (NAME.glint.bmp), the heat map (NAME.heat.bmp), the report
(NAME.json) and any scene copied with a stand-in (below). A pair whose
repository or file is missing is reported and skipped. Each file is rendered
from its repository's root, as its own renderer ran, so the textures it
names from there are found (glint looks beside the scene first, then in the
working directory). `--noise` renders each file a second time with another
seed and compares glint with itself: the part of the difference that is
the renders' noise (photons, glossy and shadow samples). `--docs DIR`
writes small PNGs of glint's render and of the heat map there. The table is
printed in Markdown. Python's standard library only.
"""

import argparse
import json
import os
import struct
import subprocess
import sys
import time
import zlib
from collections import namedtuple
from pathlib import Path

# One pair a line. `options`: glint's options for the settings the picture
# was drawn with where the file does not say them. `stand_ins`: bytes of a
# scene copy replaced, (what the file says, what the copy says instead), for
# a file the repository lacks; the copy is written to OUT. `runs_in`: the
# folder (in the repository) its renderer ran in, where the files the scene
# names are found (default: the repository's root).
Pair = namedtuple("Pair", "label repo scene picture options stand_ins note runs_in",
                  defaults=((), (), "", ""))
PAIRS = [
    Pair("z14", "zsyzgu+new_photon_mapping", "picture/all.txt", "picture.bmp",
         note="the picture is 640x380; all.txt says 1280x760"),
    Pair("pm3", "daibiaoxuwu+PM3", "scene.txt", "picture.bmp", ("--dialect", "pm3", "--emit", "1"),
         ((b"primitive polyhedron", b"primitive missing_polyhedron"),),
         "dragon.obj is not in the repository: its block is skipped; PM3 read `emit_photons= 1e7` as 1"),
    Pair("pm3-copy", "daibiaoxuwu+PM3", "scene - 3个珠子1龙亮.txt", "picture - 副本.bmp", ("--dialect", "pm3"),
         ((b"primitive polyhedron", b"primitive missing_polyhedron"),),
         "dragon.obj is not in the repository: its block is skipped"),
    Pair("w", "wangxr14+raytrace", "scene.txt", "picture.bmp"),
    Pair("v", "LuChengTHU+RayTracing-PPM-NormalMap", "src/scene.txt", "效果图.bmp", ("--iterations", "10"),
         ((b"texture= marble.bmp", b""), (b"algorithm= PPM", b"algorithm= PPM\n\tmax_hitpoints= 8000000")),
         "src/marble.bmp is not in the repository: a plain white floor stands in; max_hitpoints= 8e6 "
         "(V stores past its 4e6 without a check); 10 PPM iterations (V writes its picture every 10)", "src"),
    Pair("f1", "kevinpruvost+Ray_Tracing", "src/scene1.txt", "screenshots/Raytracer_output1.bmp"),
    Pair("f2", "kevinpruvost+Ray_Tracing", "src/scene2.txt", "screenshots/Raytracer_output2.bmp"),
    Pair("f3", "kevinpruvost+Ray_Tracing", "src/scene3.txt", "screenshots/Raytracer_output3.bmp"),
    Pair("f4", "kevinpruvost+Ray_Tracing", "src/scene4.txt", "screenshots/Raytracer_output4.bmp"),
    Pair("f5", "kevinpruvost+Ray_Tracing", "src/scene5.txt", "screenshots/Raytracer_output5.bmp", (),
         ((b"texture= src/estuary.bmp", b""),),
         "src/estuary.bmp is not in the repository: no texture stands in"),
    Pair("l17-rt", "lazycal+Progressive-Photon-Mapping", "scenes/scene_bowling.txt",
         "scenes/bowling_rt_noresampled.bmp", ("--photons", "off"), (),
         "lazycal's ray-traced picture before its anti-aliasing (glint's is anti-aliased)", "scenes"),
    Pair("l17-1", "lazycal+Progressive-Photon-Mapping", "scenes/scene_bowling.txt",
         "scenes/bowling-1.bmp", ("--iterations", "1"), (),
         "the photon estimate after lazycal's first pass of 10^6 photons", "scenes"),
    Pair("colon-bar3", "hta1996+Raytracing", "bar3.txt", "RTbar3.bmp",
         note="its ray-traced pass (`RT`), before its anti-aliasing; bar3.txt says 1280x720"),
    Pair("colon-scene1", "hta1996+Raytracing", "scene1.txt", "RTscene1.bmp",
         note="its ray-traced pass (`RT`), before its anti-aliasing; scene1.txt says 1920x1080"),
    Pair("colon-bar", "hta1996+Raytracing", "bar.txt", "bar.bmp", ("--photons", "ppm", "--iterations", "4"),
         note="its PPM picture after an unknown number of its 15000 rounds of 10^6 photons; glint: 4 rounds"),
]

# Pictures that cannot be compared, and why.
NOT_COMPARABLE = [
    ("f-cuda", "kevinpruvost+CUDA_RayTracing", "CUDA_RayTracing/resources/screenshot*.jpg",
     "JPEG screenshots of the GPU port's window, lossy (lineage spec §6)"),
    ("a18", "abcbdf+photon_mapping-bezier", "74b1OOOPICad.jpg",
     "a 650x430 JPEG, lossy, of no file of the repository (its scene_1.txt is 128x76)"),
    ("colon-bar32", "hta1996+Raytracing", "RTbar32.bmp",
     "drawn from a version of bar3.txt the repository lacks (grey stone walls behind bar3's glasses)"),
    ("colon-cornell", "hta1996+Raytracing", "cornell_box_ppm.png",
     "a PPM picture at 1600x1280, a size no file sets (the cornell_box files say 1348x1080), "
     "of one of the four cornell_box files"),
    ("colon-pre", "hta1996+Raytracing", "precornell_box_glass.bmp", "empty: its header says 0x0"),
]


def read_bmp(path):
    """A 24- or 32-bit BMP as (width, height, rows of RGB bytes from the top)."""
    d = Path(path).read_bytes()
    if d[:2] != b"BM":
        raise ValueError(f"{path}: not a BMP")
    off = struct.unpack("<I", d[10:14])[0]
    w, h = struct.unpack("<ii", d[18:26])
    step = struct.unpack("<H", d[28:30])[0] // 8
    stride = (w * step + 3) & ~3
    rows = []
    for r in range(abs(h)):
        y = abs(h) - 1 - r if h > 0 else r
        raw = d[off + y * stride: off + y * stride + w * step]
        row = bytearray(3 * w)
        row[0::3], row[1::3], row[2::3] = raw[2::step], raw[1::step], raw[0::step]
        rows.append(bytes(row))
    return w, abs(h), rows


def bmp_size(path):
    """A BMP's (width, height) from its header."""
    d = Path(path).read_bytes()[:26]
    w, h = struct.unpack("<ii", d[18:26])
    return w, abs(h)


def write_png(path, w, h, rows):
    """Writes RGB rows (from the top) as a PNG."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    raw = b"".join(b"\0" + r for r in rows)
    Path(path).write_bytes(b"\x89PNG\r\n\x1a\n"
                           + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                           + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def shrink(picture, width):
    """The picture scaled down by a whole factor to at most `width` wide (box filter)."""
    w, h, rows = picture
    k = max(1, -(-w // width))
    out = []
    for y in range(h // k):
        row = bytearray()
        for x in range(w // k):
            for c in range(3):
                total = sum(rows[y * k + j][3 * (x * k + i) + c] for j in range(k) for i in range(k))
                row.append(total // (k * k))
        out.append(bytes(row))
    return w // k, h // k, out


def glint_binary(args, root):
    """The glint to run: --glint, else the release build (built with --build)."""
    if args.glint:
        return Path(args.glint).resolve()
    if args.build:
        subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=root, check=True)
    target = Path(os.environ.get("CARGO_TARGET_DIR", root / "target"))
    return (target / "release" / "glint").resolve()


def scene_to_render(repo, scene, stand_ins, out, label):
    """The scene file to render: the repository's own, or a copy with the
    stand-ins in OUT (None, with why, when a stand-in's text is not found)."""
    path = repo / scene
    if not stand_ins:
        return path, None
    text = path.read_bytes()
    for old, new in stand_ins:
        if old not in text:
            return None, f"{scene} does not say {old.decode()}"
        text = text.replace(old, new)
    copy = out / f"{label}.scene.txt"
    copy.write_bytes(text)
    return copy, None


def compare(glint, runs_in, scene, theirs, size, options, out, name, seed=0):
    """Runs `glint compare`; returns (its JSON, the dialect line, seconds)."""
    command = [str(glint), "compare", str(scene), str(theirs), "--json",
               "--width", str(size[0]), "--height", str(size[1]), *options]
    if seed:
        command += ["--seed", str(seed)]
    else:
        command += ["-o", str(out / f"{name}.heat.bmp"), "--ours", str(out / f"{name}.glint.bmp")]
    start = time.monotonic()
    run = subprocess.run(command, cwd=runs_in, capture_output=True, text=True)
    seconds = time.monotonic() - start
    if run.returncode != 0:
        raise RuntimeError(run.stderr.strip().splitlines()[-1] if run.stderr.strip() else "failed")
    dialect = next((line for line in run.stderr.splitlines() if line.startswith("dialect ")), "")
    return json.loads(run.stdout), dialect, seconds


def main():
    root = Path(__file__).resolve().parent.parent
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("lineages", type=Path, help="the folder of OWNER+NAME checkouts")
    parser.add_argument("out", type=Path, help="where renders, heat maps and reports go")
    parser.add_argument("--only", nargs="*", help="labels of the pairs to run (default: all)")
    parser.add_argument("--noise", action="store_true", help="also compare glint with itself (seed 1)")
    parser.add_argument("--docs", type=Path, help="write small PNGs of the renders and heat maps here")
    parser.add_argument("--glint", help="the glint binary (default: the release build)")
    parser.add_argument("--build", action="store_true", help="cargo build --release first")
    args = parser.parse_args()
    if not args.lineages.is_dir():
        sys.exit(f"error: {args.lineages} is not a folder")
    args.out.mkdir(parents=True, exist_ok=True)
    out = args.out.resolve()
    if args.docs:
        args.docs.mkdir(parents=True, exist_ok=True)
    glint = glint_binary(args, root)
    if not glint.is_file():
        sys.exit(f"error: {glint} not found: build it (--build) or name one (--glint)")
    noise_head = " noise MAE | noise % > 8 |" if args.noise else ""
    print(f"| pair | file | size | dialect | MAE /255 | % > 8 |{noise_head} time | note |")
    print("|---|---|---|---|---|---|" + ("---|---|" if args.noise else "") + "---|---|")
    failed = False
    for pair in PAIRS:
        label, repo_name, scene = pair.label, pair.repo, pair.scene
        if args.only and label not in args.only:
            continue
        repo = (args.lineages / repo_name).resolve()
        theirs = repo / pair.picture
        cells = [label, f"{repo_name} `{scene}`"]
        if not (repo / scene).is_file() or not theirs.is_file():
            print(f"| {label} | {repo_name} `{scene}` | | | | | " + ("| | " if args.noise else "")
                  + "| not there: skipped |")
            continue
        size = bmp_size(theirs)
        path, why = scene_to_render(repo, scene, pair.stand_ins, out, label)
        runs_in = repo / pair.runs_in
        try:
            if path is None:
                raise RuntimeError(why)
            report, dialect, seconds = compare(glint, runs_in, path, theirs, size, pair.options, out, label)
            if args.noise:
                own = out / f"{label}.glint.bmp"
                noise, _, _ = compare(glint, runs_in, path, own, size, pair.options, out, label, seed=1)
        except (RuntimeError, json.JSONDecodeError) as e:
            failed = True
            print(f"| {label} | {repo_name} `{scene}` | {size[0]}×{size[1]} | | | | "
                  + ("| | " if args.noise else "") + f"| error: {e} |")
            continue
        (out / f"{label}.json").write_text(json.dumps(report, indent=1, ensure_ascii=False))
        dialect = dialect.split(":")[0].replace("dialect ", "")
        cells += [f"{size[0]}×{size[1]}", dialect, f"{report['mae']:.2f}", f"{100 * report['share']:.1f}"]
        if args.noise:
            cells += [f"{noise['mae']:.2f}", f"{100 * noise['share']:.1f}"]
        cells += [f"{seconds:.0f} s", pair.note]
        print("| " + " | ".join(cells) + " |", flush=True)
        if args.docs:
            for kind in ("glint", "heat"):
                small = shrink(read_bmp(out / f"{label}.{kind}.bmp"), 320)
                write_png(args.docs / f"side-{label}.{kind}.png", *small)
    for label, repo_name, pictures, why in NOT_COMPARABLE:
        if not args.only or label in args.only:
            print(f"| {label} | {repo_name} `{pictures}` | | | | | " + ("| | " if args.noise else "")
                  + f"| not comparable: {why} |")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()

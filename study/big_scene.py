"""Writes a scene manifest of many meshes: a big scene for hrpp's memory limits and build times.

Usage: python3 -m study big-scene [--copies N] [--out FILE]
       python3 -m study big-scene --layout random --triangles N [--meshes A,B] [--seed S] [--out FILE]

The manifest (scenes/README.md, "Scene manifest") places N copies of
scenes/fetched/stanford_dragon.glb (871,414 triangles each; tools/fetch-scenes.sh makes it) on a
grid over a floor, with an area light and a camera that sees them all. The loader flattens each
copy into the scene, so 12 copies (the default) are 10,456,968 dragon triangles + 4 (floor,
light). The glTF path is written relative to the manifest's folder, so the default output
scenes/fetched/big_dragons.scene.json (not committed, like the dragon) works from any directory:

    tools/fetch-scenes.sh && python3 -m study big-scene
    build/release/host/hrpp render scenes/fetched/big_dragons.scene.json --size 256x256 --spp 1

--layout random is a stand-in for the paper's 53M-triangle Sportscar as a BVH workload, not a
grid of identical copies: meshes (--meshes, default dragon,bunny,lamborghini,teapot; the dragon
needs tools/fetch-scenes.sh) drawn at random until the scene holds at least --triangles, each
at a random position on a floor whose area grows with the count (the density stays the same),
a random heading, a tilt of up to 20 degrees and a random size from 0.3 to 2.5 units, so they
overlap; an area light and a camera over the floor. --seed makes it reproducible. For example
(scenes/SCENES.md, "Big scenes"):

    python3 -m study big-scene --layout random --triangles 52000000 --out scenes/fetched/big_random.scene.json
"""
import argparse
import json
import math
import os
import random
import struct
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DRAGON = os.path.join(REPO, "scenes", "fetched", "stanford_dragon.glb")
MESHES = {
    "dragon": DRAGON,
    "bunny": os.path.join(REPO, "scenes", "meshes", "mcguire_bunny.glb"),
    "lamborghini": os.path.join(REPO, "scenes", "meshes", "lamborghini_huracan.glb"),
    "teapot": os.path.join(REPO, "scenes", "meshes", "utah_teapot.glb"),
}


def glb_triangles(path):
    """Triangles of a binary glTF's triangle primitives (indices, else positions, over 3)."""
    with open(path, "rb") as f:
        head = f.read(20)
        magic, _, _, length, kind = struct.unpack("<4sIIII", head)
        if magic != b"glTF" or kind != 0x4E4F534A:
            sys.exit(f"study big-scene: {path}: not a binary glTF")
        doc = json.loads(f.read(length))
    total = 0
    for mesh in doc.get("meshes", []):
        for prim in mesh["primitives"]:
            if prim.get("mode", 4) != 4:
                continue
            acc = prim.get("indices", prim["attributes"]["POSITION"])
            total += doc["accessors"][acc]["count"] // 3
    return total


def random_manifest(target, names, seed, out_dir):
    """Meshes drawn from `names` at random until `target` triangles, on a floor, overlapping."""
    rng = random.Random(seed)
    meshes = [(n, os.path.relpath(MESHES[n], out_dir), glb_triangles(MESHES[n])) for n in names]
    picks, total = [], 0
    while total < target:
        picks.append(rng.choice(meshes))
        total += picks[-1][2]
    half = 0.8 * math.sqrt(len(picks)) + 1.5  # an object per 2.6 square units, and more
    objects = []
    for name, path, _ in picks:
        objects.append({
            "gltf": path,
            "fit": {"base": [0.0, 0.0, 0.0], "size": round(rng.uniform(0.3, 2.5), 4)},
            "transform": {
                "rotate_deg": [round(rng.uniform(-20, 20), 3), round(rng.uniform(0, 360), 3),
                               round(rng.uniform(-20, 20), 3)],
                "translate": [round(rng.uniform(-half + 1, half - 1), 4),
                              round(rng.uniform(-0.2, 0.1), 4),
                              round(rng.uniform(-half + 1, half - 1), 4)]},
            "material": {"type": "diffuse",
                         "color": [round(rng.uniform(0.4, 0.9), 3) for _ in range(3)]},
        })
    objects.append({
        "quad": {"corner": [-half, 0.0, -half], "u": [0.0, 0.0, 2 * half],
                 "v": [2 * half, 0.0, 0.0]},
        "material": {"type": "diffuse", "color": [0.5, 0.5, 0.5]},
    })
    light = max(2.0, half / 3)
    return {
        "name": f"big_random_{total}",
        "objects": objects,
        "lights": [{"type": "area", "corner": [-light / 2, 4.0 + half / 4, -light / 2],
                    "u": [light, 0.0, 0.0], "v": [0.0, 0.0, light],
                    "radiance": [12.0, 12.0, 12.0]},
                   {"type": "environment", "radiance": [0.05, 0.05, 0.05]}],
        "camera": {"position": [0.0, 1.5 + 0.4 * half, 1.1 * half],
                   "target": [0.0, 0.3, -0.2 * half], "up": [0.0, 1.0, 0.0], "yfov_deg": 50},
    }, total + 4  # + the floor and the light quad


def manifest(copies, dragon_path):
    cols = math.ceil(math.sqrt(copies))
    rows = math.ceil(copies / cols)
    spacing = 1.2  # each dragon is fitted to 1 unit
    objects = []
    for i in range(copies):
        x = (i % cols - (cols - 1) / 2) * spacing
        z = -(i // cols) * spacing
        objects.append({
            "gltf": dragon_path,
            "fit": {"base": [0.0, 0.0, 0.0], "size": 1.0},
            "transform": {"rotate_deg": [0.0, 30.0 * i, 0.0], "translate": [x, 0.0, z]},
            "material": {"type": "diffuse", "color": [0.8, 0.8 - 0.05 * (i % 4), 0.8]},
        })
    half = max(cols, rows) * spacing + 2.0
    objects.append({
        "quad": {"corner": [-half, 0.0, -half], "u": [0.0, 0.0, 2 * half],
                 "v": [2 * half, 0.0, 0.0]},
        "material": {"type": "diffuse", "color": [0.5, 0.5, 0.5]},
    })
    depth = rows * spacing
    return {
        "name": f"big_dragons_{copies}",
        "objects": objects,
        "lights": [{"type": "area", "corner": [-1.5, 4.0, -depth / 2 - 1.5], "u": [3.0, 0.0, 0.0],
                    "v": [0.0, 0.0, 3.0], "radiance": [12.0, 12.0, 12.0]},
                   {"type": "environment", "radiance": [0.05, 0.05, 0.05]}],
        "camera": {"position": [0.0, 2.0 + 0.3 * rows, 2.5 + 0.6 * cols],
                   "target": [0.0, 0.3, -depth / 2 + spacing / 2], "up": [0.0, 1.0, 0.0],
                   "yfov_deg": 50},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--layout", choices=["grid", "random"], default="grid",
                    help="grid: --copies dragons in rows (default); random: --triangles of "
                         "--meshes at random places, headings and sizes")
    ap.add_argument("--copies", type=int, default=12, help="grid: dragons (1..64, default 12)")
    ap.add_argument("--triangles", type=int, default=52_000_000,
                    help="random: at least this many mesh triangles (default 52,000,000)")
    ap.add_argument("--meshes", default="dragon,bunny,lamborghini,teapot",
                    help="random: the meshes drawn from, of " + ",".join(MESHES))
    ap.add_argument("--seed", type=int, default=1, help="random: the layout's seed")
    ap.add_argument("--out", default=None,
                    help="manifest to write (default scenes/fetched/big_dragons.scene.json or "
                         "big_random.scene.json, beside the dragon and, like it, not committed)")
    a = ap.parse_args()
    if a.out is None:
        a.out = os.path.join(REPO, "scenes", "fetched",
                             "big_dragons.scene.json" if a.layout == "grid"
                             else "big_random.scene.json")
    out_dir = os.path.dirname(os.path.abspath(a.out))
    if not os.path.isdir(out_dir):
        sys.exit(f"study big-scene: --out {a.out}: directory {out_dir} does not exist")
    if a.layout == "grid":
        if not 1 <= a.copies <= 64:
            sys.exit(f"study big-scene: --copies {a.copies}: must be 1..64")
        names = ["dragon"]
    else:
        if not 1 <= a.triangles <= 1_000_000_000:
            sys.exit(f"study big-scene: --triangles {a.triangles}: must be 1..10^9")
        names = a.meshes.split(",")
        for n in names:
            if n not in MESHES:
                sys.exit(f"study big-scene: --meshes {a.meshes}: '{n}' is none of "
                         + ",".join(MESHES))
    for n in names:
        if not os.path.isfile(MESHES[n]):
            sys.exit(f"study big-scene: {MESHES[n]} is missing; run tools/fetch-scenes.sh first")
    if a.layout == "grid":
        scene, triangles = manifest(a.copies, os.path.relpath(DRAGON, out_dir)), a.copies * 871414 + 4
        what = f"{a.copies} dragons"
    else:
        scene, triangles = random_manifest(a.triangles, names, a.seed, out_dir)
        what = f"{len(scene['objects']) - 1} meshes"
    text = json.dumps(scene, indent=2) + "\n"
    tmp = a.out + ".partial"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, a.out)
    print(f"study big-scene: {a.out}: {what}, {triangles} triangles")


if __name__ == "__main__":
    main()

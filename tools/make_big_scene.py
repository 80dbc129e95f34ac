#!/usr/bin/env python3
"""Writes a scene manifest of many Stanford dragons: a big scene for hrpp's memory limits.

Usage: tools/make_big_scene.py [--copies N] [--out FILE]

The manifest (scenes/README.md, "Scene manifest") places N copies of
scenes/fetched/stanford_dragon.glb (871,414 triangles each; tools/fetch-scenes.sh makes it) on a
grid over a floor, with an area light and a camera that sees them all. The loader flattens each
copy into the scene, so 12 copies (the default) are 10,456,968 dragon triangles + 4 (floor,
light). The glTF path is written relative to the manifest's folder, so the default output
scenes/fetched/big_dragons.scene.json (not committed, like the dragon) works from any directory:

    tools/fetch-scenes.sh && tools/make_big_scene.py
    build/release/host/hrpp render scenes/fetched/big_dragons.scene.json --size 256x256 --spp 1
"""
import argparse
import json
import math
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DRAGON = os.path.join(REPO, "scenes", "fetched", "stanford_dragon.glb")


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
    ap.add_argument("--copies", type=int, default=12, help="dragons (1..64, default 12)")
    ap.add_argument("--out",
                    default=os.path.join(REPO, "scenes", "fetched", "big_dragons.scene.json"),
                    help="manifest to write (default scenes/fetched/big_dragons.scene.json, "
                         "beside the dragon and, like it, not committed)")
    a = ap.parse_args()
    if not 1 <= a.copies <= 64:
        sys.exit(f"make_big_scene: --copies {a.copies}: must be 1..64")
    if not os.path.isfile(DRAGON):
        sys.exit(f"make_big_scene: {DRAGON} is missing; run tools/fetch-scenes.sh first")
    out_dir = os.path.dirname(os.path.abspath(a.out))
    if not os.path.isdir(out_dir):
        sys.exit(f"make_big_scene: --out {a.out}: directory {out_dir} does not exist")
    rel = os.path.relpath(DRAGON, out_dir)
    text = json.dumps(manifest(a.copies, rel), indent=2) + "\n"
    tmp = a.out + ".partial"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, a.out)
    print(f"make_big_scene: {a.out}: {a.copies} dragons, "
          f"{a.copies * 871414 + 4} triangles")


if __name__ == "__main__":
    main()

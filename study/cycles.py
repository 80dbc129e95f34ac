"""hrpp render against Blender's Cycles, an independent renderer set up to compute the same
integral (study/cycles_reference.py says how). For each scene: the scene exported by hrpp
(`hrpp scene --export-json`), two Cycles renders with different seeds, and hrpp renders with
its default estimator (MIS, Sobol samples) and with light sampling alone and independent samples,
all at the same size and samples per pixel.

Printed per scene: the noise floor, relMSE between the two Cycles renders (two independent
estimates of the same image: twice Cycles' variance, relatively); each hrpp render's relMSE
against Cycles seed 0, its ratio to the floor, and the variance ratio it implies,
var(hrpp) / var(Cycles) = 2 x relMSE / floor - 1 (1: as noisy as Cycles at equal spp; 1.5 at
relMSE = 1.25 x floor); and the means' ratio per channel. The default estimator also renders
with seed 2: its relMSE against seed 1 over the floor is the same variance ratio measured again,
without the noise of Cycles seed 0 in it. Verdict "agrees" when relMSE is within
2x the floor and every channel's mean within 1%. relMSE = mean of (x - ref)^2 / (ref^2 + 0.01).

Runs with Debian's python3 (numpy, python3-openimageio) and blender (tools/setup.sh installs
neither blender nor this benchmark's needs beyond numpy: `apt-get install blender`).
Usage: python3 -m study cycles
                               [--scenes builtin:cornell,cornell,bunny,teapot,wall-lamp,floor-panel]
                               [--size 64x64] [--spp 1024] [--max-depth 8] [--hrpp BIN]
                               [--blender BIN] [--json FILE] [--images DIR]
"""
import argparse
import json
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
from common import (DEFAULT_BIN, EPS, ESTIMATOR_SCENES, read_exr, run,
                         scene_arg)
from estimator_error import error_summary, mean_text, output_dir, write_json
HRPP_CONFIGS = {"hrpp mis/sobol": ["--light-sampling", "mis", "--sampler", "sobol"],
                "hrpp light/independent": ["--light-sampling", "light", "--sampler",
                                           "independent"]}


def cycles(a, export, out, seed):
    """Cycles' image of the export, flipped left to right for a mirrored camera
    (cycles_reference.py renders it unmirrored)."""
    with open(export) as f:
        mirrored = json.load(f)["cameras"][0].get("mirrored", False)
    run([a.blender, "--background", "--factory-startup", "--python",
         os.path.join(HERE, "cycles_reference.py"), "--", "--scene", export, "--out", out,
         "--size", a.size, "--spp", str(a.spp), "--max-depth", str(a.max_depth), "--seed",
         str(seed)], "study cycles", echo=True)
    img = read_exr(out)
    return img[:, ::-1].copy() if mirrored else img


def hrpp(a, scene, flags, out, seed=1):
    run([a.hrpp, "render", scene_arg(scene), "--size", a.size, "--spp", str(a.spp), "--max-depth",
         str(a.max_depth), "--seed", str(seed), "--out", out] + flags, "study cycles", echo=True)
    return read_exr(out)


def pair_relmse(x, y, ref):
    """relMSE between two renders, weighted by the reference as error_summary() weights: for two
    independent estimates, twice their variance, comparable with the floor."""
    return float(((x - y) ** 2 / (ref ** 2 + EPS)).mean())


def compare_scene(a, scene, out_dir):
    base = os.path.basename(scene).replace(":", "_")
    export = os.path.join(out_dir, f"{base}.json")
    run([a.hrpp, "scene", scene_arg(scene), "--export-json", export], "study cycles", echo=True)
    ref = cycles(a, export, os.path.join(out_dir, f"{base}_cycles0.exr"), 0)
    other = cycles(a, export, os.path.join(out_dir, f"{base}_cycles1.exr"), 1)
    floor, _, floor_mean = error_summary(other, ref)
    rows = {"cycles seed 1": {"relmse": floor, "mean_ratio": floor_mean}}
    for name, flags in HRPP_CONFIGS.items():
        tag = name.split()[1].replace("/", "_")
        img = hrpp(a, scene, flags, os.path.join(out_dir, f"{base}_{tag}.exr"))
        rel, worst, mean_ratio = error_summary(img, ref)
        rows[name] = {"relmse": rel, "worst_1pct_share": worst, "mean_ratio": mean_ratio}
    first = "hrpp mis/sobol"
    second = hrpp(a, scene, HRPP_CONFIGS[first],
                  os.path.join(out_dir, f"{base}_mis_sobol_seed2.exr"), seed=2)
    rows[first]["seeds_variance_ratio"] = pair_relmse(
        read_exr(os.path.join(out_dir, f"{base}_mis_sobol.exr")), second, ref) / floor
    for r in rows.values():
        r["floor_ratio"] = r["relmse"] / floor
        r["variance_ratio"] = 2.0 * r["relmse"] / floor - 1.0
        r["agrees"] = r["relmse"] <= 2.0 * floor and all(abs(m - 1.0) <= 0.01
                                                          for m in r["mean_ratio"])
    return floor, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", default=ESTIMATOR_SCENES)
    ap.add_argument("--size", default="64x64")
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--max-depth", type=int, default=8)
    ap.add_argument("--hrpp", default=DEFAULT_BIN)
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--json", help="write every figure here")
    ap.add_argument("--images", help="keep the renders and exports here")
    a = ap.parse_args()
    if shutil.which(a.blender) is None:
        sys.exit(f"study cycles: --blender {a.blender}: not found (apt-get install blender)")
    out_dir = output_dir(a, "study cycles", "hrpp_cycles_")
    report = {"size": a.size, "spp": a.spp, "max_depth": a.max_depth, "scenes": {}}
    for scene in a.scenes.split(","):
        print(f"{scene}:", file=sys.stderr, flush=True)
        floor, rows = compare_scene(a, scene, out_dir)
        print(f"\n{scene}: {a.size}, {a.spp} spp, max depth {a.max_depth}; against Cycles seed 0, "
              f"noise floor (Cycles seed 1) relMSE {floor:.5f}")
        print(f"  {'render':<24} {'relMSE':>9} {'/floor':>7} {'var/Cycles':>10} "
              f"{'mean ratio r g b':>22}  verdict")
        for name, r in rows.items():
            print(f"  {name:<24} {r['relmse']:9.5f} {r['floor_ratio']:7.2f} "
                  f"{r['variance_ratio']:10.2f} {mean_text(r['mean_ratio']):>22}  "
                  f"{'agrees' if r['agrees'] else 'DIFFERS'}")
        print(f"  hrpp mis/sobol seed 2 against seed 1: var/Cycles "
              f"{rows['hrpp mis/sobol']['seeds_variance_ratio']:.2f}")
        report["scenes"][scene] = {"floor": floor, "renders": rows}
    write_json(a.json, report)


if __name__ == "__main__":
    main()

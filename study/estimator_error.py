"""How fast does hrpp render's estimator converge? relMSE against a converged reference at equal
samples per pixel and the wall time it took, per light-sampling strategy and sampler.

For each scene: a reference (--ref-spp samples, --light-sampling mis, --sampler independent, its
own seed), then one render per (strategy, sampler) at --spp with another seed. Printed per scene
and configuration: relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01) (the
limit study's measure), its ratio to the baseline configuration (light sampling alone,
independent samples: the estimator before MIS and Sobol), the mean's ratio to the reference per
channel, the share of the squared error in the worst 1% of pixels (fireflies concentrate it
there), the wall time, and relMSE x time (the work-normalised error: lower is better at equal
time). The reference is hrpp's own, so this measures convergence, not correctness: the
independent witnesses are the furnace tests (tests/render_test.cpp) and a Blender Cycles render.

Runs with Debian's python3 (numpy, python3-openimageio: tools/setup.sh).
Usage: python3 -m study error
         [--scenes builtin:cornell,cornell,bunny,teapot,wall-lamp,floor-panel]
         [--size 64x64] [--spp 64] [--ref-spp 4096] [--hrpp BIN] [--json FILE] [--images DIR]
"""
import argparse
import json
import os
import sys
import tempfile

import common
from common import DEFAULT_BIN, EPS, ESTIMATOR_SCENES, read_exr

CONFIGS = [("light", "independent"), ("mis", "independent"), ("light", "sobol"),
           ("mis", "sobol"), ("bsdf", "sobol")]
BASELINE = ("light", "independent")


def output_dir(a, who, prefix):
    """Checks --hrpp and returns the directory the renders go to (--images, else a new one)."""
    common.need_binary(a.hrpp, who)
    out_dir = a.images or tempfile.mkdtemp(prefix=prefix)
    os.makedirs(out_dir, exist_ok=True)
    return out_dir


def mean_text(ratios):
    return " ".join(f"{x:.4f}" for x in ratios)


def write_json(path, report):
    if path:
        with open(path, "w") as f:
            json.dump(report, f, indent=2)


def render(a, scene, spp, seed, strategy, sampler, out_dir, tag):
    """One render's image and wall time."""
    out = os.path.join(out_dir, f"{os.path.basename(scene).replace(':', '_')}_{tag}")
    stats, exr = common.render(a.hrpp, scene, out, a.size, spp, seed,
                                    ["--light-sampling", strategy, "--sampler", sampler],
                                    "estimator_error", echo=True)
    return read_exr(exr), stats["wall_s"]


def error_summary(img, ref):
    """relMSE against ref, the worst 1% of pixels' share of it, and the means' ratio per channel."""
    import numpy as np
    sq = (img - ref) ** 2 / (ref ** 2 + EPS)
    per_pixel = sq.mean(axis=-1).ravel()
    worst = np.sort(per_pixel)[::-1][:max(1, per_pixel.size // 100)]
    mean_ratio = img.reshape(-1, 3).mean(0) / ref.reshape(-1, 3).mean(0)
    return float(sq.mean()), float(worst.sum() / per_pixel.sum()), [float(r) for r in mean_ratio]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", default=ESTIMATOR_SCENES,
                    help="builtin:cornell and names of scenes/NAME.scene.json (cornell: the "
                         "glTF Cornell box)")
    ap.add_argument("--size", default="64x64")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--hrpp", default=DEFAULT_BIN)
    ap.add_argument("--json", help="write every figure here")
    ap.add_argument("--images", help="keep the renders here")
    a = ap.parse_args()
    out_dir = output_dir(a, "study error", "hrpp_estimator_")
    report = {"size": a.size, "spp": a.spp, "ref_spp": a.ref_spp, "scenes": {}}
    for scene in a.scenes.split(","):
        print(f"{scene}: reference, {a.ref_spp} spp", file=sys.stderr, flush=True)
        ref, ref_s = render(a, scene, a.ref_spp, 1000, "mis", "independent", out_dir, "ref")
        rows = {}
        for strategy, sampler in CONFIGS:
            img, wall = render(a, scene, a.spp, 1, strategy, sampler, out_dir,
                               f"{strategy}_{sampler}")
            rel, worst, mean_ratio = error_summary(img, ref)
            rows[f"{strategy}/{sampler}"] = {"relmse": rel, "worst_1pct_share": worst,
                                             "mean_ratio": mean_ratio, "wall_s": wall}
        base = rows["/".join(BASELINE)]
        print(f"\n{scene}: {a.size}, {a.spp} spp against {a.ref_spp} spp (mis/independent, "
              f"{ref_s:.0f} s)")
        print(f"  {'strategy/sampler':<20} {'relMSE':>9} {'/base':>6} {'worst 1%':>8} "
              f"{'mean ratio r g b':>22} {'wall s':>7} {'relMSE*s /base':>14}")
        for name, r in rows.items():
            r["relmse_ratio"] = r["relmse"] / base["relmse"]
            r["work_ratio"] = r["relmse"] * r["wall_s"] / (base["relmse"] * base["wall_s"])
            print(f"  {name:<20} {r['relmse']:9.5f} {r['relmse_ratio']:6.2f} "
                  f"{r['worst_1pct_share']:8.2f} {mean_text(r['mean_ratio']):>22} "
                  f"{r['wall_s']:7.2f} "
                  f"{r['work_ratio']:14.2f}")
        report["scenes"][scene] = {"reference_wall_s": ref_s, "configs": rows}
    write_json(a.json, report)


if __name__ == "__main__":
    main()

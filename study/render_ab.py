"""Two or more hrpp binaries rendering the same frames, interleaved: what a change to the renderer
costs per frame. Every binary renders every scene with the same size, samples and seed, round by
round, the binaries' order reversed each round. Per scene and binary: the frame's kernel time
(kernels_ms_total, the median of the rounds), the shade kernel's, the rays traced per sample and
each time's ratio to the first binary (the reference), taken round by round (the pair rendered
back to back) and its median printed; the rounds' spread (a cell's worst round
against its best, median over the cells); the load. The images' means and the share of pixels
that differ from the reference binary's image at all: a change meant to leave a scene's light
as it was shows whether it did, one meant to change it by how much.

With --results the table becomes the generated block --block of that file.

Usage: python3 -m study render-ab --binary OLD=HRPP --binary NEW=HRPP
                          [--scenes cornell,bunny,teapot,lamborghini] [--size 256x192]
                          [--spp 8] [--rounds 3] [--results FILE [--block NAME]] [-- FLAGS]
FLAGS go to every `hrpp render` (e.g. -- --hrpp on).
"""
import argparse
import os
import statistics
import sys
import tempfile
import time

from common import REPO, cpu_model, image_errors, read_exr, render, repo_commit, rewrite_block

WHO = "study render-ab"


def parse_args():
    p = argparse.ArgumentParser(prog=WHO, description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--binary", action="append", required=True, help="NAME=HRPP (twice or more)")
    p.add_argument("--scenes", default="cornell,bunny,teapot,lamborghini")
    p.add_argument("--size", default="256x192")
    p.add_argument("--spp", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--results")
    p.add_argument("--block", default="render_ab")
    p.add_argument("flags", nargs="*", help="after --: flags for every hrpp render")
    a = p.parse_args()
    a.binaries = {}
    for v in a.binary:
        name, _, path = v.partition("=")
        if not path or not os.path.isfile(path):
            sys.exit(f"{WHO}: --binary {v}: expected NAME=HRPP, an existing file")
        a.binaries[name] = path
    if len(a.binaries) < 2:
        sys.exit(f"{WHO}: give --binary at least twice")
    return a


def frame(a, binary, scene, out, image):
    """One render's figures; its image only when `image` (the first round's are compared)."""
    stats, exr = render(binary, scene, out, a.size, a.spp, a.seed, a.flags, WHO)
    pixels = stats["config"]["width"] * stats["config"]["height"] * a.spp
    return {"total": stats["kernels_ms_total"], "shade": stats["kernels_ms"]["render_shade"],
            "rays": stats["totals"]["rays"] / pixels, "image": read_exr(exr) if image else None}


def main():
    a = parse_args()
    names, scenes = list(a.binaries), a.scenes.split(",")
    runs, loads = {}, []
    with tempfile.TemporaryDirectory(prefix="hrpp_render_ab_") as tmp:
        for rnd in range(a.rounds):
            order = names if rnd % 2 == 0 else names[::-1]
            for scene in scenes:
                for b in order:
                    loads.append(os.getloadavg()[0])
                    f = frame(a, a.binaries[b], scene, os.path.join(tmp, f"{b}_{rnd}"),
                              rnd == 0)
                    runs.setdefault((scene, b), []).append(f)
            print(f"{WHO}: round {rnd + 1}/{a.rounds}", file=sys.stderr, flush=True)
    spread = statistics.median(1 - min(r["total"] for r in v) / max(r["total"] for r in v)
                               for v in runs.values())
    med = {k: {"total": statistics.median(r["total"] for r in v),
               "shade": statistics.median(r["shade"] for r in v),
               "rays": v[0]["rays"], "image": v[0]["image"]} for k, v in runs.items()}

    def ratio(scene, b, key):  # the median of the rounds' ratios, pair by pair
        pairs = zip(runs[(scene, b)], runs[(scene, names[0])])
        return statistics.median(x[key] / y[key] for x, y in pairs)
    results = f" --results {a.results} --block {a.block}" if a.results else ""
    flags = " -- " + " ".join(a.flags) if a.flags else ""
    lines = [f"Made by `python3 -m study render-ab "
             + " ".join(f"--binary {b}" for b in a.binary)
             + f" --scenes {a.scenes} --size {a.size} --spp {a.spp} --rounds {a.rounds}"
             f"{results}{flags}` at commit {repo_commit(REPO)}, {time.strftime('%Y-%m-%d')}, "
             f"{cpu_model()}; load {min(loads):.1f}-{max(loads):.1f}. Kernel ms a frame, the "
             f"median of the rounds (in brackets the median of the rounds' ratios to {names[0]}, "
             f"round by round); a cell's rounds differ by {spread:.0%} (median over the cells):",
             "",
             "| scene | binary | frame ms | shade ms | rays/sample | image mean | pixels that "
             "differ |", "|---|---|---|---|---|---|---|"]
    for scene in scenes:
        ref = med[(scene, names[0])]
        for b in names:
            c = med[(scene, b)]
            total = "" if b == names[0] else f" ({ratio(scene, b, 'total'):.3f})"
            shade = "" if b == names[0] else f" ({ratio(scene, b, 'shade'):.3f})"
            differ = image_errors(c["image"], ref["image"])[2]
            lines.append(f"| {scene} | {b} | {c['total']:.1f}{total} | {c['shade']:.1f}{shade} | "
                         f"{c['rays']:.2f} | {c['image'].mean():.4f} | {differ:.1%} |")
    if a.results:
        rewrite_block(a.results, a.block, lines, WHO)
    print("\n".join(lines))


if __name__ == "__main__":
    main()

"""Is `hrpp bench`'s Embree figure right? The bench against an independent Embree harness.

`hrpp bench SCENE --save-rays DIR` writes its batches and the scene's triangle dump and prints
GPU/Embree per batch. Then, on exactly those rays, `hrpp trace` times the device kernels alone
and bench/embree_harness.cpp (`bench_embree_harness`, which shares no code with hrpp: its own
file reading, scene setup and threads pulling blocks of rays) times Embree; their ratio is the
independent GPU/Embree. Printed per batch: each side's Embree Mrays/s and GPU/Embree, and the
hits each counted. With --results FILE the table replaces the generated block
`embree_check:SCENE` there, headed by the command, commit, device, CPU, date and load.

Usage: python3 -m study embree-check [--hrpp BIN] [--harness BIN] [--scene bunny] [--repeat N]
                             [--results bench/README.md]
"""
import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile

import common
from common import DEFAULT_BIN, REPO, need_binary, repo_commit, rewrite_block, run, scene_arg, table

KINDS = ["primary", "ao", "diffuse"]


def harness(a, tmp, kind, gpu_ms):
    """The harness on one batch: (Embree Mrays/s, GPU/Embree, hits)."""
    cmd = [a.harness, "--triangles", os.path.join(tmp, "triangles.bin"), "--rays",
           os.path.join(tmp, f"{kind}.rays"), "--threads", "2", "--repeat", str(a.repeat),
           "--gpu-ms", str(gpu_ms)] + (["--any-hit"] if kind == "ao" else [])
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    trace = re.search(r"([\d.]+) Mrays/s, (\d+)", out)
    ratio = re.search(r"gpu/embree\s+([\d.]+)", out)
    return float(trace.group(1)), float(ratio.group(1)), int(trace.group(2))


def rows_for(a, tmp):
    run([a.hrpp, "bench", scene_arg(a.scene), "--save-rays", tmp, "--repeat", str(a.repeat),
         "--json", os.path.join(tmp, "bench.json")], "study embree-check")
    with open(os.path.join(tmp, "bench.json")) as f:
        bench = {k["kind"]: k for k in json.load(f)["kinds"]}
    rows, device = [], "?"
    for kind in KINDS:
        stats = os.path.join(tmp, f"{kind}.json")
        run([a.hrpp, "trace", scene_arg(a.scene), "--rays", os.path.join(tmp, f"{kind}.rays"),
             "--hits", os.path.join(tmp, "hits.bin"), "--repeat", str(a.repeat), "--stats", stats]
            + (["--any-hit"] if kind == "ao" else []), "study embree-check")
        with open(stats) as f:
            trace = json.load(f)
        device = common.device_name(trace)
        embree = next(t for t in bench[kind]["tracers"] if t["tracer"] == "embree")
        hits = next(t for t in bench[kind]["tracers"] if t["tracer"] == "gpu")["hits"]
        mrays, ratio, harness_hits = harness(a, tmp, kind, trace["kernel_ms_median"])
        rows.append([kind, f"{embree['mrays_per_s']:.2f}, {bench[kind]['gpu_over_embree']:.3f}",
                     f"{mrays:.2f}, {ratio:.3f}",
                     f"{hits:,} both" if hits == harness_hits else f"{hits:,} / {harness_hits:,}"])
        print(" | ".join(rows[-1]), file=sys.stderr, flush=True)
    return rows, device


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hrpp", default=DEFAULT_BIN, help="the hrpp binary")
    ap.add_argument("--harness", help="bench_embree_harness (default: beside --hrpp's build)")
    ap.add_argument("--scene", default="bunny")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--results", help="rewrite this Markdown file's block embree_check:SCENE")
    a = ap.parse_args()
    a.harness = a.harness or os.path.join(os.path.dirname(os.path.dirname(a.hrpp)), "bench",
                                          "bench_embree_harness")
    need_binary(a.hrpp, "study embree-check")
    need_binary(a.harness, "study embree-check", "--harness")
    with tempfile.TemporaryDirectory(prefix="embree_check_") as tmp:
        rows, device = rows_for(a, tmp)
    command = shlex.join(["python3 -m study embree-check"] + sys.argv[1:])
    lines = [f"Made by `{command}` ({a.scene}, the bench's 2^20-ray batches, median of "
             f"{a.repeat}, 2 threads) at commit {repo_commit(REPO)} on "
             f"{common.machine_line(device)}:", "",
             table(["batch", "hrpp bench: Embree Mrays/s, gpu/embree",
                    "harness: Embree Mrays/s, gpu/embree (with `hrpp trace`'s device time)",
                    "hits"], rows)]
    print("\n".join(lines))
    if a.results:
        rewrite_block(a.results, f"embree_check:{a.scene}", lines, "python3 -m study embree-check")


if __name__ == "__main__":
    main()

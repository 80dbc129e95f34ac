"""The driver's ray queries beside the compute kernels and Embree: the three-way table.

For every round and scene, one `hrpp bench SCENE --tracer rayquery --hrpp on` process traces
the scene's primary, AO and diffuse batches with Embree, the BVH kernels (`gpu`), the driver's
ray queries (`rayquery`, host/gpu/ray_query_tracer.h) and the ray queries with the HRPP stage in
front (`rq-hrpp`), on the same rays, each tracer timed in turn on the same batch. Printed per
scene and batch: each tracer's Mrays/s (first round), gpu/rayquery and rq-hrpp/rayquery speed
per round (> 1: the first is faster), rq-hrpp's share of rays answered by a prediction, and the
mismatches against the CPU reference (the driver's triangle test is not watertight); then per
scene the driver's structure (bytes, build ms) against the project's BVH. With --results FILE
the tables replace the generated block `rayquery:bench` there, headed by the command, commit,
device, date and load.

Usage: python3 -m study rayquery-table [--hrpp BIN] [--scenes a,b] [--rounds N] [--rays N]
                               [--repeat N] [--results bench/README.md]
"""
import argparse
import datetime
import json
import os
import sys
import tempfile

from common import (DEFAULT_BIN, REPO, cpu_model, need_binary, repo_commit, rewrite_block, run,
                    scene_arg, table)

SCENES = "bunny,lamborghini,dragon"


def bench(a, scene, out):
    """One process's report (hrpp bench --json)."""
    run([a.hrpp, "bench", scene_arg(scene), "--tracer", "rayquery", "--hrpp", "on",
         "--warn-mismatches", "--rays", str(a.rays), "--repeat", str(a.repeat), "--json", out], "study rayquery-table")
    with open(out) as f:
        return json.load(f)


def tracer(kind_report, name):
    return next((t for t in kind_report["tracers"] if t["tracer"] == name), None)


def speed_rows(reports, a):
    rows = []
    for scene in a.scenes:
        first = reports[(0, scene)]
        for k, kind in enumerate(first["kinds"]):
            per_round = [reports[(r, scene)]["kinds"][k] for r in range(a.rounds)]
            mrays = {n: tracer(kind, n)["mrays_per_s"] if tracer(kind, n) else float("nan")
                     for n in ("embree", "gpu", "rayquery", "rq-hrpp")}
            hrpp = (tracer(kind, "rq-hrpp") or {}).get("predictor", {})
            answered = hrpp.get("true_positives", 0) / max(hrpp.get("probes", 0), 1)
            mismatches = tracer(kind, "rayquery")["validation"]["mismatches"]
            rows.append([scene, kind["kind"]] +
                        [f"{mrays[n]:.2f}" for n in ("embree", "gpu", "rayquery", "rq-hrpp")] +
                        [", ".join(f"{p.get('gpu_over_rayquery', float('nan')):.2f}"
                                   for p in per_round),
                         ", ".join(f"{p.get('rayquery_hrpp_speedup', float('nan')):.2f}"
                                   for p in per_round),
                         f"{100 * answered:.1f}%", str(mismatches)])
    return rows


def structure_rows(reports, a):
    rows = []
    for scene in a.scenes:
        r = reports[(0, scene)]
        q = r["rayquery"]
        rows.append([scene, str(r["scene"]["triangles"]),
                     f"{q['structure_bytes'] / 2**20:.2f} MiB",
                     f"{q['uncompacted_bytes'] / 2**20:.2f} MiB", f"{q['build_ms']:.1f}",
                     f"{q['bvh_bytes'] / 2**20:.2f} MiB", f"{r['scene']['bvh_build_ms']:.1f}"])
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hrpp", default=DEFAULT_BIN, help="the hrpp binary")
    ap.add_argument("--scenes", default=SCENES, help="comma-separated scene names")
    ap.add_argument("--rounds", type=int, default=2, help="processes per scene")
    ap.add_argument("--rays", type=int, default=1 << 18)
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per tracer (median)")
    ap.add_argument("--results", help="rewrite the block rayquery:bench of this Markdown file")
    a = ap.parse_args()
    a.scenes = a.scenes.split(",")
    need_binary(a.hrpp, "study rayquery-table")
    load = [os.getloadavg()[0]]
    reports = {}
    with tempfile.TemporaryDirectory(prefix="rayquery_") as tmp:
        for r in range(a.rounds):  # rounds outermost: each scene's processes interleave
            for scene in a.scenes:
                print(f"study rayquery-table: round {r + 1} {scene}", file=sys.stderr, flush=True)
                reports[(r, scene)] = bench(a, scene, os.path.join(tmp, "b.json"))
    load.append(os.getloadavg()[0])
    machine = reports[(0, a.scenes[0])]["machine"]
    command = " ".join(["python3 -m study rayquery-table"] + sys.argv[1:])
    lines = [f"Made by `{command}` ({a.rays} rays per batch, median of {a.repeat} runs; Mrays/s "
             f"of the first round, ratios one per round) at commit {repo_commit(REPO)} on "
             f"{machine.get('vulkan_device')} ({machine.get('vulkan_driver')}), {cpu_model()}, "
             f"{datetime.date.today()}, load {load[0]:.1f} before and {load[1]:.1f} after:", "",
             table(["scene", "batch", "embree", "gpu", "rayquery", "rq-hrpp", "gpu/rayquery",
                    "rq-hrpp/rayquery", "rq-hrpp predicted", "rayquery mismatches"],
                   speed_rows(reports, a)), "",
             table(["scene", "triangles", "driver's structure", "before compaction",
                    "its build ms", "project's BVH", "its build ms"],
                   structure_rows(reports, a))]
    print("\n".join(lines))
    if a.results:
        rewrite_block(a.results, "rayquery:bench", lines, "python3 -m study rayquery-table")


if __name__ == "__main__":
    main()

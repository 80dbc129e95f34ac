"""Two Vulkan drivers against each other: `hrpp bench` on each scene under each driver, chosen by
VK_DRIVER_FILES, alternating the order round by round (same binary, rays and seed). Prints a
Markdown table: the GPU's median kernel time per query kind under each driver (median over the
rounds), the per-round time ratio B/A, the GPU/Embree speed under each (Embree runs in the same
process, so it is the same under both) and the GPU's mismatches against the CPU reference,
headed by one line of provenance (command, commit, date, drivers, load). With --results the
same lines become the generated block --block of that Markdown file.

Usage: python3 -m study driver-ab --driver A=ICD.json --driver B=ICD.json
                          [--scenes bunny,lamborghini,dragon] [--rounds 2] [--hrpp BIN]
                          [--json FILE] [--results FILE [--block NAME]]
Example (Mesa 22.3 unpacked beside the system's Mesa 25):
  python3 -m study driver-ab --driver 22.3=/opt/mesa22/lvp_icd.json \\
                     --driver 25.0=/usr/share/vulkan/icd.d/lvp_icd.json
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

from common import DEFAULT_BIN, REPO, need_binary, repo_commit, rewrite_block

KINDS = ["primary", "ao", "diffuse"]


def fail(msg):
    print(f"study driver-ab: {msg}", file=sys.stderr)
    sys.exit(1)


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--driver", action="append", default=[], help="NAME=ICD_JSON (twice)")
    p.add_argument("--scenes", default="bunny,lamborghini,dragon")
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--hrpp", default=DEFAULT_BIN)
    p.add_argument("--json", help="write every bench report, by scene and driver")
    p.add_argument("--results", help="rewrite the generated block --block of this Markdown file")
    p.add_argument("--block", default="driver_ab:bench", help="the block's name (with --results)")
    a = p.parse_args()
    if len(a.driver) != 2 or any("=" not in d for d in a.driver):
        fail("--driver NAME=ICD_JSON must be given twice")
    a.drivers = dict(d.split("=", 1) for d in a.driver)
    for name, icd in a.drivers.items():
        if not os.path.isfile(icd):
            fail(f"--driver {name}={icd}: no such file")
    if a.rounds < 1:
        fail(f"--rounds {a.rounds}: at least 1")
    need_binary(a.hrpp, "study driver-ab")
    return a


def bench(a, scene, icd):
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        env = dict(os.environ, VK_DRIVER_FILES=icd)
        p = subprocess.run([a.hrpp, "bench", scene, "--warn-mismatches", "--repeat", "3",
                            "--check-rays", "10000", "--json", f.name], env=env, capture_output=True, text=True)
        if p.returncode != 0 or "GPU skipped" in p.stdout:
            fail(f"hrpp bench {scene} under {icd} failed:\n{p.stdout[-1500:]}{p.stderr[-1500:]}")
        return json.load(open(f.name))


def kind_row(reports, kind):
    gpu, embree, mismatches = [], [], 0
    for r in reports:
        k = next(x for x in r["kinds"] if x["kind"] == kind)
        t = {x["tracer"]: x for x in k["tracers"]}
        gpu.append(t["gpu"]["median_ms"])
        embree.append(t["embree"]["median_ms"])
        mismatches += t["gpu"]["validation"]["mismatches"]
    return gpu, embree, mismatches


def main():
    a = parse_args()
    names = list(a.drivers)
    scenes = a.scenes.split(",")
    reports = {(s, n): [] for s in scenes for n in names}
    loads = []
    for rnd in range(a.rounds):
        for scene in scenes:
            for name in names if rnd % 2 == 0 else names[::-1]:
                loads.append(os.getloadavg()[0])
                reports[(scene, name)].append(bench(a, scene, a.drivers[name]))
                print(f"study driver-ab: round {rnd + 1}/{a.rounds} {scene} {name}", file=sys.stderr)
    A, B = names
    drivers = "; ".join(f"{n}: {reports[(scenes[0], n)][0]['machine']['vulkan_driver']}"
                        for n in names)
    results = f" --results {a.results} --block {a.block}" if a.results else ""
    lines = [f"Made by `python3 -m study driver-ab {' '.join('--driver ' + d for d in a.driver)} "
             f"--scenes {a.scenes} --rounds {a.rounds}{results}` at commit {repo_commit(REPO)}, "
             f"{time.strftime('%Y-%m-%d')}, {reports[(scenes[0], A)][0]['machine']['cpu']}; "
             f"{drivers}; load {min(loads):.1f}-{max(loads):.1f}:", "",
             f"| scene | kind | {A} ms | {B} ms | {B}/{A} time, per round | GPU/Embree {A} | "
             f"GPU/Embree {B} | mismatches {A}, {B} |",
             "|---|---|---|---|---|---|---|---|"]
    for scene in scenes:
        for kind in KINDS:
            ga, ea, ma = kind_row(reports[(scene, A)], kind)
            gb, eb, mb = kind_row(reports[(scene, B)], kind)
            ratios = " / ".join(f"{y / x:.2f}" for x, y in zip(ga, gb))
            sa = statistics.median(e / g for g, e in zip(ga, ea))
            sb = statistics.median(e / g for g, e in zip(gb, eb))
            lines.append(f"| {scene} | {kind} | {statistics.median(ga):.1f} | "
                         f"{statistics.median(gb):.1f} | {ratios} | {sa:.2f} | {sb:.2f} | "
                         f"{ma}, {mb} |")
    print("\n".join(lines))
    if a.results:
        rewrite_block(a.results, a.block, lines, "python3 -m study driver-ab")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({f"{s}|{n}": v for (s, n), v in reports.items()}, f)


if __name__ == "__main__":
    main()

"""HRPP inline on the CPU against the same traversal without it: the on/off table.

For every round, scene and hash precision, one `hrpp bench SCENE --no-gpu --no-embree --hrpp on
--hrpp-config F` process (F: every class's hash_bits N) traces the scene's primary, AO and diffuse batches with the CPU
reference (`cpu-ref`) and with HRPP inline in it (`cpu-hrpp`, per-thread tables emptied before
each timed run; docs/HRPP.md, "HRPP inline on the CPU"), on the same rays and threads. Printed:
cpu-hrpp / cpu-ref wall time per batch (each process's medians; one figure per round) and, for
the speculative closest-hit batches, the share of checked rays whose predicted hit was not the
closest. With --results FILE the table replaces the generated block `cpu_hrpp:bench` there,
headed by the command, commit, CPU, date and load.

Usage: python3 -m study cpu-table [--hrpp BIN] [--scenes a,b] [--bits 6,5] [--rounds N]
                               [--rays N] [--repeat N] [--results RESULTS.md]
"""
import argparse
import datetime
import json
import os
import subprocess
import sys
import tempfile

from common import (DEFAULT_BIN, REPO, cpu_model, hrpp_settings, need_binary, repo_commit,
                    rewrite_block, run, scene_arg, settings_args, table)

SCENES = "cornell,teapot,bunny,lamborghini,dragon"
KINDS = ["primary", "ao", "diffuse"]


def bench(a, scene, bits, out):
    """One process: {kind: (cpu-hrpp / cpu-ref, wrong share or None, true-positive share)}."""
    settings = settings_args([hrpp_settings({"hash_bits": bits})], out + ".hrpp.json")
    run([a.hrpp, "bench", scene_arg(scene), "--no-gpu", "--no-embree", "--hrpp", "on", *settings,
         "--rays", str(a.rays), "--repeat", str(a.repeat), "--json", out], "study cpu-table")
    with open(out) as f:
        report = json.load(f)
    figures = {}
    for k in report["kinds"]:
        if "cpu_hrpp" not in k:
            continue
        h = k["cpu_hrpp"]
        hrpp = next(t for t in k["tracers"] if t["tracer"] == "cpu-hrpp")["validation"]
        wrong = hrpp["mismatches"] / max(hrpp["checked"], 1) if k["query"] == "closest" else None
        figures[k["kind"]] = (h["time_over_off"], wrong, h["true_positives"] / max(h["probes"], 1))
    return figures


def rows_of(results, a):
    """Table rows: per scene, each precision's figures per kind over the rounds."""
    rows = []
    for scene in a.scenes:
        row = [scene]
        for bits in a.bits:
            for kind in KINDS:
                per_round = [results[(r, scene, bits)].get(kind) for r in range(a.rounds)]
                if None in per_round:
                    row.append("-")
                    continue
                cell = ", ".join(f"{f[0]:.3f}" for f in per_round)
                wrong = per_round[0][1]
                if wrong is not None:
                    cell += f" ({100 * wrong:.1f}% wrong)"
                row.append(cell)
        rows.append(row)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hrpp", default=DEFAULT_BIN, help="the hrpp binary")
    ap.add_argument("--scenes", default=SCENES, help="comma-separated scene names")
    ap.add_argument("--bits", default="6,5", help="hash precisions, comma-separated")
    ap.add_argument("--rounds", type=int, default=2, help="processes per scene and precision")
    ap.add_argument("--rays", type=int, default=1 << 20)
    ap.add_argument("--repeat", type=int, default=5, help="timed runs per tracer (median)")
    ap.add_argument("--results", help="rewrite the block cpu_hrpp:bench of this Markdown file")
    a = ap.parse_args()
    a.scenes, a.bits = a.scenes.split(","), [int(b) for b in a.bits.split(",")]
    need_binary(a.hrpp, "study cpu-table")
    load = [os.getloadavg()[0]]
    results = {}
    with tempfile.TemporaryDirectory(prefix="cpu_hrpp_") as tmp:
        for r in range(a.rounds):  # rounds outermost: each scene's processes interleave
            for scene in a.scenes:
                for bits in a.bits:
                    print(f"study cpu-table: round {r + 1} {scene} hash_bits {bits}",
                          file=sys.stderr, flush=True)
                    results[(r, scene, bits)] = bench(a, scene, bits, os.path.join(tmp, "b.json"))
    load.append(os.getloadavg()[0])
    head = ["scene"] + [f"{k}, bits {b}" for b in a.bits for k in KINDS]
    command = " ".join(["python3 -m study cpu-table"] + sys.argv[1:])
    threads = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip() or "?"
    lines = [f"Made by `{command}` (cpu-hrpp / cpu-ref wall time per batch, {a.rays} rays, "
             f"median of {a.repeat} runs, one figure per round; wrong: the speculative closest "
             f"hits that were not the closest, first round) at commit {repo_commit(REPO)} on "
             f"{cpu_model()}, {threads} threads, {datetime.date.today()}, load "
             f"{load[0]:.1f} before and {load[1]:.1f} after:", "",
             table(head, rows_of(results, a))]
    print("\n".join(lines))
    if a.results:
        rewrite_block(a.results, "cpu_hrpp:bench", lines, "python3 -m study cpu-table")


if __name__ == "__main__":
    main()

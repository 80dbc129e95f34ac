"""What stopping, limiting and sharing a render cost and keep (docs/RENDERER.md, "Output").

Four measurements of `hrpp render` on the Vulkan device, HRPP off:
  interrupts  a --spp 512 render stopped with SIGINT at --interrupts random moments: each must
              exit 130 and leave a whole image whose sample count (EXR attribute hrpp:samples)
              is the stats' passes, its mean radiance within 4 standard errors of the finished
              render's (the error of K passes: the spread of single-pass renders' means / sqrt K);
  time limit  --time-limit 10 at 256x256: how far past 10 s the passes ran, against a pass;
  save-every  a 60 s render (--time-limit 60) with --save-every 1 against none: passes done;
  load        8 renders at once against the same 8 in sequence: wall time (throughput) and
              every image equal to its lone render's.
Prints one table; --results FILE --block NAME writes it as a generated block.

Usage: python3 -m study render-session [--scene bunny] [--interrupts 20] [--quick]
                                     [--hrpp BIN] [--results MD --block NAME]
"""
import argparse
import datetime
import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import time

import numpy as np

from common import (DEFAULT_BIN, REPO, device_name, need_binary, read_exr, repo_commit,
                    rewrite_block, scene_arg, table)


def render_cmd(a, out, size, spp, seed=1, extra=()):
    return [a.hrpp, "render", scene_arg(a.scene), "--size", size, "--spp", str(spp), "--seed",
            str(seed), "--out", out + ".exr", "--stats", out + ".json", *extra]


def finish(cmd):
    """Runs `cmd`; its stats JSON (exits on failure)."""
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"study render-session: {' '.join(cmd)}: {r.stderr.strip()}")
    with open(cmd[cmd.index("--stats") + 1]) as f:
        return json.load(f)


def exr_samples(path):
    """The EXR's hrpp:samples attribute (name, type "string", 4-byte size, value)."""
    b = open(path, "rb").read()
    key = b"hrpp:samples\0string\0"
    at = b.find(key)
    if at < 0:
        return None
    n = int.from_bytes(b[at + len(key):at + len(key) + 4], "little")
    return int(b[at + len(key) + 4:at + len(key) + 4 + n])


def interrupts(a, tmp):
    size = "96x96" if a.quick else "128x128"
    t0 = time.monotonic()
    whole = finish(render_cmd(a, os.path.join(tmp, "whole"), size, 512))
    process_s = time.monotonic() - t0  # start-up included
    ref = read_exr(os.path.join(tmp, "whole.exr")).mean()
    full_s = whole["session"]["passes_s"]
    singles = []  # single-pass renders' means: the noise of one pass
    for s in range(8):
        finish(render_cmd(a, os.path.join(tmp, f"one{s}"), size, 1, seed=100 + s))
        singles.append(read_exr(os.path.join(tmp, f"one{s}.exr")).mean())
    sigma1 = float(np.std(singles, ddof=1))
    rng = random.Random(a.seed)
    rows, bad = [], 0
    for k in range(a.interrupts):
        out = os.path.join(tmp, f"stop{k}")
        p = subprocess.Popen(render_cmd(a, out, size, 512), stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        # After the start-up (load, BVH, kernels: the process time less the passes'), before the
        # last tenth of the passes.
        time.sleep(rng.uniform(process_s - full_s, process_s - 0.1 * full_s))
        p.send_signal(signal.SIGINT)
        status = p.wait()
        if not os.path.exists(out + ".json"):  # the signal came before the render began
            rows.append(f"exit {status} before the first pass")
            continue
        s = json.load(open(out + ".json"))
        passes = s["session"]["passes"]
        if passes == 512 and not s["session"]["interrupted"]:  # the signal came after the end
            rows.append(f"exit {status} after the last pass")
            continue
        mean = read_exr(out + ".exr").mean()
        z = abs(mean - ref) / (sigma1 / np.sqrt(passes))
        ok = status == 130 and exr_samples(out + ".exr") == passes and z < 4
        bad += not ok
        rows.append(f"{passes}:{z:.1f}{'' if ok else '!'}")
    stopped = sum(":" in r for r in rows)
    return [["interrupts", f"{a.interrupts} SIGINTs into `--spp 512` at {size} "
             f"(whole render {full_s:.0f} s)", f"{stopped - bad} of the {stopped} that stopped "
             f"it left an image of their passes within 4 SE of the whole render's mean",
             "passes:z (! fails) " + " ".join(rows)]]


def time_limit(a, tmp):
    rows = []
    for k in range(1 if a.quick else 3):
        t0 = time.monotonic()
        s = finish(render_cmd(a, os.path.join(tmp, f"limit{k}"), "256x256", 100000,
                              extra=["--time-limit", "10"]))
        wall = time.monotonic() - t0
        ss = s["session"]
        pass_s = ss["passes_s"] / ss["passes"]
        rows.append([f"time limit {k + 1}", "`--time-limit 10`, 256x256",
                     f"passes ended {ss['passes_s'] - 10:+.2f} s from 10 s (a pass: "
                     f"{pass_s:.2f} s; worst prediction {ss['worst_pass_end_prediction_s']:.2f} s)",
                     f"{ss['passes']} passes; the process {wall:.1f} s"])
    return rows


def save_every(a, tmp):
    limit = "20" if a.quick else "60"
    got = {}
    for tag, extra in (("none", []), ("every 1 s", ["--save-every", "1"])):
        s = finish(render_cmd(a, os.path.join(tmp, "save" + tag[:4]), "256x256", 100000,
                              extra=["--time-limit", limit] + extra))
        got[tag] = (s["session"]["passes"] / s["session"]["passes_s"], s["session"]["saves"])
    ratio = got["every 1 s"][0] / got["none"][0]
    return [["save-every", f"`--time-limit {limit}`, 256x256, `--save-every 1` against none",
             f"passes per second {ratio:.3f}x of none's", f"{got['every 1 s'][1]} saves"]]


def load(a, tmp):
    n, size, spp = 8, "128x128", 8 if a.quick else 32
    cmds = [render_cmd(a, os.path.join(tmp, f"seq{k}"), size, spp, seed=k + 1) for k in range(n)]
    t0 = time.monotonic()
    for c in cmds:
        finish(c)
    sequence = time.monotonic() - t0
    cmds = [render_cmd(a, os.path.join(tmp, f"par{k}"), size, spp, seed=k + 1) for k in range(n)]
    t0 = time.monotonic()
    procs = [subprocess.Popen(c, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE) for c in cmds]
    failed = sum(p.wait() != 0 for p in procs)
    at_once = time.monotonic() - t0
    equal = sum(np.array_equal(read_exr(os.path.join(tmp, f"seq{k}.exr")),
                               read_exr(os.path.join(tmp, f"par{k}.exr"))) for k in range(n))
    return [["load", f"{n} renders at once against in sequence, {size}, {spp} spp",
             f"throughput {sequence / at_once:.2f}x of in sequence ({at_once:.1f} s against "
             f"{sequence:.1f} s)", f"{n - failed} of {n} ran, {equal} of {n} images equal"]]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scene", default="bunny")
    p.add_argument("--interrupts", type=int, default=20)
    p.add_argument("--seed", type=int, default=1, help="of the random interrupt moments")
    p.add_argument("--quick", action="store_true", help="smaller and shorter: a smoke run")
    p.add_argument("--hrpp", default=DEFAULT_BIN)
    p.add_argument("--results")
    p.add_argument("--block")
    a = p.parse_args()
    need_binary(a.hrpp, "study render-session")
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        rows = interrupts(a, tmp) + time_limit(a, tmp) + save_every(a, tmp) + load(a, tmp)
        device = device_name(json.load(open(os.path.join(tmp, "whole.json"))))
    lines = [f"`{' '.join(['python3 -m study render-session'] + sys.argv[1:])}` at "
             f"{repo_commit(REPO)}, {device}, {datetime.date.today()}, scene {a.scene}, load "
             f"{load_before:.1f} before, {os.getloadavg()[0]:.1f} after:", "",
             table(["measure", "setup", "result", "detail"], rows)]
    print("\n".join(lines))
    if a.results and a.block:
        rewrite_block(a.results, a.block, lines, "python3 -m study render-session")


if __name__ == "__main__":
    main()

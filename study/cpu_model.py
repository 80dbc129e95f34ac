"""Where would HRPP pay on the CPU? The cost model of the CPU renderer with HRPP inline.

The CPU reference renderer (`hrpp render --backend cpu`) has no kernels and so no time per
class: a frame's wall time is fitted as a sum of operations times their costs (ms each) over
every ray class: ray (its setup and shading), interior node, leaf, triangle test, probe (hash
and table lookup), verified leaf, verified triangle, insert. Every render runs on one core
(`--core`): the platform must be quiet first, so each render is repeated and the spread of the
same render's frames is printed (the issue's test: under 3%). The fit (non-negative least
squares on relative error) is checked on renders it was not fitted on: each run predicted by a
fit on the other settings' runs, and by one on the other scenes'. Then per stand-in and class,
at `--hrpp on`'s keys: the break-even probe cost, in interior-node visits of this platform (a
traversal's time per interior node it visits, leaves and triangles included), at which the
class's prediction would cost what HRPP off does (below 0: at no probe cost), beside the
measured probe cost and the frame's on/off.

Usage: python3 -m study cpu-model [--hrpp BIN] [--scenes a,b] [--size WxH] [--spp N] [--repeat N]
                          [--core C] [--json FILE]
"""
import argparse
import json
import os
import sys
import tempfile

import numpy as np

import cost_model as cm
from common import DEFAULT_BIN, hrpp_settings, need_binary, render

CLASSES = ["camera", "bounce", "shadow"]
SETTINGS = {
    "off": ["--hrpp", "off"],
    "keys": ["--hrpp", "on"],
    "camera": ["--hrpp", "on", "--hrpp-rays", "camera"],
    "bits4": ["--hrpp", "on", hrpp_settings({"hash_bits": 4})],
    "exact": ["--hrpp", "on", "--hrpp-mode", "exact"],
}
FEATURES = ["rays", "interior", "leaves", "triangles", "probes", "verify_leaves",
            "verify_triangles", "inserts"]


def class_features(c):
    """One class's operation counts (a frame's or a render's)."""
    h = c.get("hrpp", {})
    return {"rays": c["rays"], "interior": c["interior_visited"], "leaves": c["leaves_visited"],
            "triangles": c["triangles_tested"], "probes": h.get("probes", 0),
            "verify_leaves": h.get("verify_leaves", 0),
            "verify_triangles": h.get("verify_triangles", 0), "inserts": h.get("inserts", 0)}


def frame_row(frame):
    """A frame's features summed over the classes, and its wall time (ms)."""
    f = {k: 0 for k in FEATURES}
    for c in CLASSES:
        for k, v in class_features(frame["classes"][c]).items():
            f[k] += v
    return [f[k] for k in FEATURES], 1e3 * frame["wall_s"]


def least_disturbed(repeats):
    """Per frame, the repeat in which it took the least time; and the spread of the same frame
    over the repeats (max / min - 1), the platform's noise."""
    frames, spreads = [], []
    for i in range(len(repeats[0]["frames"])):
        times = [r["frames"][i]["wall_s"] for r in repeats]
        frames.append(repeats[int(np.argmin(times))]["frames"][i])
        spreads.append(max(times) / min(times) - 1)
    return frames, spreads


def fit(rows):
    x = np.array([r[0] for r in rows], float)
    y = np.array([r[1] for r in rows], float)
    return cm.nnls(x / y[:, None], np.ones(len(y)))


def predict(costs, row):
    return float(np.dot(costs, row[0]))


def held_out(runs):
    """Max relative error of each run's frames predicted by fits without its setting, and
    without its scene."""
    errors = {"setting": [], "scene": []}
    for (scene, setting), frames in runs.items():
        for scheme, keep in (("setting", lambda k: k[1] != setting),
                             ("scene", lambda k: k[0] != scene)):
            costs = fit([frame_row(f) for k, fs in runs.items() if keep(k) for f in fs])
            for f in frames:
                row = frame_row(f)
                errors[scheme].append(abs(predict(costs, row) / row[1] - 1))
    return {k: max(v) for k, v in errors.items()}


def summed(frames, cls):
    """The class's operation counts over the frames."""
    out = {k: 0 for k in FEATURES}
    for f in frames:
        for k, v in class_features(f["classes"][cls]).items():
            out[k] += v
    return out


def break_even(costs, on, off, cls):
    """The class's break-even probe cost in interior-node visits (a traversal's time per
    interior node it visits, its leaves and triangles included), and its measured one, from the
    frames of a render with HRPP on (`on`) and off."""
    c = dict(zip(FEATURES, costs))
    a, b = summed(on, cls), summed(off, cls)
    traversal = lambda f: (c["rays"] * f["rays"] + c["interior"] * f["interior"] +  # noqa: E731
                           c["leaves"] * f["leaves"] + c["triangles"] * f["triangles"])
    if a["probes"] == 0 or b["interior"] == 0:
        return float("nan"), float("nan")
    per_visit = traversal(b) / b["interior"]
    rest = (traversal(a) + c["verify_leaves"] * a["verify_leaves"] +
            c["verify_triangles"] * a["verify_triangles"] + c["inserts"] * a["inserts"])
    return (traversal(b) - rest) / a["probes"] / per_visit, c["probes"] / per_visit


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hrpp", default=DEFAULT_BIN, help="the hrpp binary")
    ap.add_argument("--scenes", default="cornell,teapot,bunny,lamborghini")
    ap.add_argument("--size", default="256x256")
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=3, help="renders per scene and setting")
    ap.add_argument("--core", type=int, default=1, help="the one core every render runs on")
    ap.add_argument("--json", help="write every figure here")
    a = ap.parse_args()
    need_binary(a.hrpp, "study cpu-model")
    os.sched_setaffinity(0, {a.core})  # the renders inherit it
    load = os.getloadavg()[0]
    runs, spreads = {}, []
    with tempfile.TemporaryDirectory(prefix="cpu_model_") as tmp:
        for scene in a.scenes.split(","):
            for name, flags in SETTINGS.items():
                repeats = [render(a.hrpp, scene, os.path.join(tmp, f"{scene}_{name}_{r}"), a.size,
                                  a.spp, 5, ["--backend", "cpu"] + flags, "study cpu-model")[0]
                           for r in range(a.repeat)]
                runs[(scene, name)], s = least_disturbed(repeats)
                spreads += s
    costs = fit([frame_row(f) for fs in runs.values() for f in fs])
    held = held_out(runs)
    print(f"study cpu-model: {a.size}, {a.spp} spp, {a.repeat} renders each on core {a.core}, "
          f"load {load:.2f} before, {os.getloadavg()[0]:.2f} after")
    print(f"quiet: the same frame's spread over its renders: median {100 * np.median(spreads):.1f}%"
          f", max {100 * max(spreads):.1f}%")
    print("costs (ns): " + ", ".join(f"{k} {1e6 * v:.2f}" for k, v in zip(FEATURES, costs)))
    print("| scene | class | break-even probe | probe | frame on/off (keys) |")
    print("|---|---|---|---|---|")
    answers = []
    for scene in a.scenes.split(","):
        off, on = runs[(scene, "off")], runs[(scene, "keys")]
        frame = sum(f["wall_s"] for f in on) / sum(f["wall_s"] for f in off)
        for cls in CLASSES:
            be, probe = break_even(costs, on, off, cls)
            answers.append(dict(scene=scene, cls=cls, break_even=be, probe=probe, frame=frame))
            print(f"| {scene} | {cls} | {be:.3f} | {probe:.3f} | {frame:.3f} |")
    print(f"model: max relative error {100 * held['setting']:.1f}% held out by setting, "
          f"{100 * held['scene']:.1f}% by scene")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(dict(costs=dict(zip(FEATURES, costs.tolist())), held_out=held,
                           spread_median=float(np.median(spreads)), spread_max=max(spreads),
                           answers=answers), f, indent=1)


if __name__ == "__main__":
    main()

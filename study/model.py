"""Where would HRPP pay? Fits the device's cost per operation from renders and asks the model.

Renders each stand-in with HRPP off and with every ray predicted under a few predictor settings
(`--hrpp on`'s keys and tables per class; hash precision 4; go-up 2; exact mode), --repeat
times each (each frame and class timed by the render in which it took the least time), then
fits the cost of each operation of the trace and HRPP kernels (study/cost_model.py: dispatch, ray,
interior node, leaf, triangle test, probe, verification, queue entry, insert) from the kernels'
timestamps and counters. It checks the model on renders it was not fitted on (each run predicted
by a fit on the other settings' runs, and by one on the other settings of the other scenes), then
answers per class and stand-in, at `--hrpp on`'s keys with every ray predicted:
  - break-even answered share: the share of probed rays the prediction must answer for HRPP to
    cost what HRPP off does, at today's probe cost (above 1: never);
  - break-even probe: the probe cost, in interior-node visits of this device (a traversal's
    time per interior node it visits, leaves and triangles included), at which HRPP breaks even
    at the measured answered share (below 0: at no probe cost);
  - hardware: on/off if a probe cost what MICRO'21's simulated predictor costs (2 cycles, where
    its RT unit spends 24 on a node: 1/12 of an interior-node visit) and the queue cost nothing
    (the RT unit regroups rays itself).
It draws on/off against probe cost per class (the model's lines, the measured points) and can
rewrite its block in RESULTS.md. The last line is `model: max relative error E on N held-out
runs` (class times, HRPP on and off).

Usage: python3 -m study model [--mode full|quick|smoke|test | --quick] [--hrpp BIN] [--scenes a,b]
                           [--size WxH] [--spp N] [--repeat N] [--runs DIR] [--reuse]
                           [--json FILE] [--figure PNG] [--results MD] [--command TEXT]
study/sweep.sh runs it as its `model` grid (--results RESULTS.md, block hrpp_model:MODE).
"""
import argparse
import json
import os
import sys
import time

import numpy as np

import cost_model as cm
import common
from common import HERE, REPO, STAND_INS, note_run, rewrite_block, run_line

EVERY_RAY = {"adaptive": False}  # every ray of every class predicted (--hrpp-config)
PREDICT_ALL = ["--hrpp", "on", common.hrpp_settings(None, EVERY_RAY)]
SETTINGS = {
    "off": ["--hrpp", "off"],
    "keys": PREDICT_ALL,
    "bits4": ["--hrpp", "on", common.hrpp_settings({"hash_bits": 4}, EVERY_RAY)],
    "up2": ["--hrpp", "on", common.hrpp_settings({"go_up": 2}, EVERY_RAY)],
    "exact": PREDICT_ALL + ["--hrpp-mode", "exact"],
    "default": ["--hrpp", "on"],  # the adaptive predictor: its decisions, not fitted
}
FITTED = [k for k in SETTINGS if k != "default"]
DEFAULT_SETTING = "keys"
HARDWARE_PROBE = 2.0 / 24.0  # interior-node visits: MICRO'21 predictor lookup / RT node latency
# The modes of study/sweep.sh (--mode; --quick is --mode quick): size, spp, scenes, repeats.
MODES = {
    "full": dict(size="512x512", spp=4, scenes=STAND_INS, repeat=3),
    "quick": dict(size="128x128", spp=2, scenes=["cornell", "teapot", "bunny"], repeat=2),
    "smoke": dict(size="64x64", spp=1, scenes=["cornell", "teapot"], repeat=1),
    "test": dict(size="32x32", spp=1, scenes=["builtin:cornell", "teapot"], repeat=1),
}


def default_binary():
    for b in ("build/release", "build/ci", "build/portable"):
        p = os.path.join(REPO, b, "host", "hrpp")
        if os.access(p, os.X_OK):
            return p
    return os.path.join(REPO, "build", "release", "host", "hrpp")


def render(a, scene, setting, repeat):
    """One render's stats (reused from --runs when --reuse and present)."""
    out = os.path.join(a.runs, f"{scene.replace(':', '_')}_{setting}_{repeat}")
    stats, _ = common.render(a.hrpp, scene, out, a.size, a.spp, a.seed, SETTINGS[setting],
                                  "hrpp_model", a.reuse)
    return stats


def collect(a):
    """{(scene, setting): [stats of each of the --repeat renders]} over every scene and setting,
    the settings interleaved."""
    os.makedirs(a.runs, exist_ok=True)
    runs, start = {}, time.time()
    todo = [(s, r, k) for s in a.scenes for r in range(a.repeat) for k in SETTINGS]
    for i, (scene, repeat, setting) in enumerate(todo):
        runs.setdefault((scene, setting), []).append(render(a, scene, setting, repeat))
        print(f"study model: render {i + 1}/{len(todo)} {scene} {setting} "
              f"({time.time() - start:.0f} s)", file=sys.stderr, flush=True)
    return runs


def least_disturbed(repeats, run):
    """One observation per frame and class (study/cost_model.py) of a run rendered several
    times: of the repeats, the one whose class took the least time in that frame, with its own
    counts. Another process on the machine adds time to the frames it overlaps, not to a whole
    render, so the least time of each frame is its least disturbed measurement."""
    best = {}
    for stats in repeats:
        for o in cm.observations(stats, run):
            key = (o["frame"], o["class"])
            if key not in best or o["class_ms"] < best[key]["class_ms"]:
                best[key] = o
    return [best[k] for k in sorted(best, key=lambda k: (k[0], cm.CLASSES.index(k[1])))]


def all_observations(runs):
    return [o for key, repeats in runs.items() if key[1] in FITTED
            for o in least_disturbed(repeats, key)]


def adaptive_frames(repeats, cls):
    """Frames in which the default's adaptive predictor predicted every ray of the class, over
    the repeats."""
    modes = [f.get("hrpp_decisions", {}).get(cls, {}).get("mode")
             for stats in repeats for f in stats["frames"]]
    return f"{modes.count('all')}/{len(modes)}"


HOLD_OUT = {"setting": (1,), "setting and scene": (0, 1)}  # the parts of a run's key held out


def held_out(obs, scheme):
    """Every run's class times predicted by a fit on the runs that share none of the held-out
    parts of its key: its setting ("setting": HRPP off and each predictor setting in turn) and,
    for "setting and scene", its scene too."""
    parts = HOLD_OUT[scheme]
    rows = []
    for run in sorted({o["run"] for o in obs}):
        costs = cm.fit([o for o in obs if all(o["run"][i] != run[i] for i in parts)])
        mine = [o for o in obs if o["run"] == run]
        for (_, cls), t in sorted(cm.class_totals(mine, costs).items()):
            err = t["modelled"] / t["measured"] - 1 if t["measured"] > 0 else float("nan")
            rows.append({"scene": run[0], "setting": run[1], "class": cls, **t, "error": err})
    return rows


def twin_rows(runs):
    """The spread of the device itself: each run's class times in one render against another
    render of the same run (every pair of its repeats, the earlier one as measured), as held-out
    rows ("measured": the earlier render, "modelled": the later). None with one render each."""
    rows = []
    for key, repeats in sorted(runs.items()):
        if key[1] not in FITTED:
            continue
        totals = []  # per render, {class: its time summed over the frames}
        for stats in repeats:
            totals.append({})
            for o in cm.observations(stats, key):
                totals[-1][o["class"]] = totals[-1].get(o["class"], 0.0) + o["class_ms"]
        for i in range(len(totals)):
            for j in range(i + 1, len(totals)):
                for cls, t in sorted(totals[i].items()):
                    u = totals[j].get(cls)
                    if u and t > 0:
                        rows.append({"scene": key[0], "setting": key[1], "class": cls,
                                     "measured": t, "modelled": u, "error": u / t - 1})
    return rows or None


def ratio_errors(rows):
    """Modelled against measured on/off ratios of the held-out class times."""
    by = {(r["scene"], r["setting"], r["class"]): r for r in rows}
    out = []
    for (scene, setting, cls), r in by.items():
        off = by.get((scene, "off", cls))
        if setting == "off" or not off or min(off["measured"], off["modelled"], r["measured"]) <= 0:
            continue
        measured = r["measured"] / off["measured"]
        modelled = r["modelled"] / off["modelled"]
        out.append({"scene": scene, "setting": setting, "class": cls, "measured": measured,
                    "modelled": modelled, "error": modelled / measured - 1})
    return out


def answers(obs, costs, runs, scenes):
    """Per scene and class at `--hrpp on`'s keys: the model's break-even figures, and what
    the adaptive predictor of `--hrpp on` decided."""
    out = []
    for scene in scenes:
        for cls in cm.CLASSES:
            pick = lambda k: [o for o in obs if o["run"] == (scene, k) and o["class"] == cls]
            off, on = pick("off"), pick(DEFAULT_SETTING)
            if not off or not on or not sum(o["counts"]["probes"] for o in on):
                continue
            cc = cm.ClassCosts(costs, cm.per_ray_rates(off), cm.per_ray_rates(on), f"trace:{cls}")
            measured = sum(o["class_ms"] for o in on) / sum(o["class_ms"] for o in off)
            out.append({"scene": scene, "class": cls, "measured": measured,
                        "modelled": cc.ratio(), "answered": cc.a,
                        "break_even_answered": cc.break_even_answered(),
                        "probe": cc.probe_in_interior_visits(),
                        "break_even_probe": cc.break_even_probe(),
                        "hardware": cc.ratio(s=HARDWARE_PROBE * cc.interior_cost, queue=False),
                        "adaptive": adaptive_frames(runs[(scene, "default")], cls),
                        "curve": cc})
    return out


def plot(rows, path):
    """The figure; False where matplotlib is missing (a bare Python on a GPU machine)."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return False
    xs = np.logspace(-2, 2, 60)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), sharey=True)
    for ax, cls in zip(axes, cm.CLASSES):
        for i, r in enumerate(x for x in rows if x["class"] == cls):
            cc, color = r["curve"], f"C{i}"
            ax.plot(xs, [cc.ratio(s=x * cc.interior_cost) for x in xs], color=color,
                    label=f"{r['scene']} (answered {r['answered']:.2f})")
            ax.plot([r["probe"]], [r["measured"]], "o", color=color)
        ax.axhline(1, color="k", lw=0.8)
        ax.axvline(HARDWARE_PROBE, color="gray", ls="--", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("probe cost (interior-node visits)")
        ax.set_title(f"{cls} rays")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("HRPP on / off, class time")
    fig.suptitle("Model lines and measured points (dots); dashed: MICRO'21's probe", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def fmt(x, d=2):
    if x is None or not np.isfinite(x):
        return "never" if x == float("inf") else "n/a"
    return f"{x:.{d}f}"


def summary(rows):
    """Max |relative error| of the class times, the runs, and the same for the on/off ratios."""
    ratios = ratio_errors(rows)
    errors = sorted(abs(r["error"]) for r in rows)
    return {"error": errors[-1], "median": errors[len(errors) // 2],
            "within_10": sum(e <= 0.1 for e in errors), "classes": len(errors),
            "runs": len({(r["scene"], r["setting"]) for r in rows}),
            "ratio_error": max((abs(r["error"]) for r in ratios), default=float("nan")),
            "worst": max(rows, key=lambda r: abs(r["error"]))}


def report_lines(a, costs, held, twins, ans, provenance):
    timed = (f"each frame and class timed by the least of {a.repeat} renders" if a.repeat > 1
             else "one render of each")
    lines = [f"Made by `{a.command}` ({a.size}, {a.spp} spp, seed {a.seed}, {timed}; "
             f"scenes {', '.join(a.scenes)}) at {provenance}.", "",
             "Costs per operation (ns), fitted on every run:", "",
             "| kernel | op | ns |", "|---|---|---|"]
    for model, c in costs.items():
        for f, v in c.items():
            lines.append(f"| {model} | {f} | {v * 1e6:.3g} |")
    lines += ["", "Held out: each run's class times predicted by a fit on the runs of the other "
              "settings (HRPP off and each predictor setting in turn), and by a fit on the other "
              "settings of the other scenes:", "",
              "| held out | runs | class times within | median | within 10% | on/off ratios within "
              "| worst class time |",
              "|---|---|---|---|---|---|---|"]
    rows = [(scheme, r, "ms measured", "modelled") for scheme, r in held.items()]
    if twins:
        rows.append(("none: another render of the run", twins, "ms in one render", "in another"))
    for label, r, first, second in rows:
        s = summary(r)
        w = s["worst"]
        lines.append(f"| {label} | {s['runs']} | {100 * s['error']:.1f}% | "
                     f"{100 * s['median']:.1f}% | {s['within_10']} of {s['classes']} | "
                     f"{100 * s['ratio_error']:.1f}% | {w['scene']} {w['setting']} {w['class']}: "
                     f"{w['measured']:.1f} {first}, {w['modelled']:.1f} {second} |")
    if twins:
        lines += ["", "The last row is the device's own spread: each run's class times in one "
                  "render against another render of it (every pair of repeats, the earlier one "
                  "as measured), as if a model predicted a render from its twin."]
    lines += ["", "At `--hrpp on`'s keys and tables, every ray predicted (setting `keys`):", "",
              "| scene | class | on/off measured | modelled | answered | break-even answered "
              "| probe today (interior visits) | break-even probe | hardware probe on/off "
              "| `--hrpp on` predicted frames |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for r in ans:
        lines.append(f"| {r['scene']} | {r['class']} | {fmt(r['measured'])} | "
                     f"{fmt(r['modelled'])} | {fmt(r['answered'])} | "
                     f"{fmt(r['break_even_answered'])} | {fmt(r['probe'], 1)} | "
                     f"{fmt(r['break_even_probe'], 1)} | {fmt(r['hardware'])} | "
                     f"{r['adaptive']} |")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hrpp", default=default_binary(), help="the hrpp binary")
    ap.add_argument("--mode", choices=MODES, default="full",
                    help="sizes, scenes and repeats: " + "; ".join(
                        f"{k}: {v['size']}, {v['spp']} spp, {', '.join(v['scenes'])}, "
                        f"{v['repeat']} of each" for k, v in MODES.items()))
    ap.add_argument("--quick", action="store_true", help="--mode quick")
    ap.add_argument("--scenes", help="comma-separated scenes (default: the mode's)")
    ap.add_argument("--size", help="WxH (default: the mode's)")
    ap.add_argument("--spp", type=int, help="samples per pixel (default: the mode's)")
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--repeat", type=int,
                    help="renders of each setting (default: the mode's); each frame and class "
                    "counts the one in which it took the least time")
    ap.add_argument("--runs", help="render directory (default build/hrpp-model/MODE)")
    ap.add_argument("--reuse", action="store_true", help="reuse the renders --runs holds")
    ap.add_argument("--json", help="write the costs, held-out errors and answers here")
    ap.add_argument("--figure", help="on/off against probe cost (default results/figures/"
                    "hrpp_model.png; other modes: results/figures/MODE/hrpp_model.png)")
    ap.add_argument("--results", help="rewrite this Markdown file's block hrpp_model:MODE")
    ap.add_argument("--command", help="the command named in the report (default: this one)")
    a = ap.parse_args()
    if a.quick:
        a.mode = "quick"
    m = MODES[a.mode]
    a.size, a.spp = a.size or m["size"], a.spp or m["spp"]
    a.repeat = a.repeat or m["repeat"]
    a.scenes = [s for s in a.scenes.split(",") if s] if a.scenes else m["scenes"]
    a.command = a.command or " ".join(["python3 -m study model"] + sys.argv[1:])
    if len(a.scenes) < 2:
        sys.exit("study model: --scenes needs at least two scenes (each is held out in turn)")
    common.need_binary(a.hrpp, "study model")
    a.runs = a.runs or os.path.join(REPO, "build", "hrpp-model", a.mode)
    a.figure = a.figure or os.path.join(HERE, "figures", *([] if a.mode == "full" else [a.mode]),
                                        "hrpp_model.png")
    note = os.path.join(a.runs, "provenance.json")  # commit, CPU, date, load of the renders
    fresh = not (a.reuse and os.path.exists(note))
    os.makedirs(a.runs, exist_ok=True)
    if fresh:
        note_run(a.runs, "before")
    runs = collect(a)
    if fresh:
        note_run(a.runs, "after")
    with open(note) as f:
        provenance = run_line(json.load(f), common.device_name(next(iter(runs.values()))[0]))
    obs = all_observations(runs)
    costs = cm.fit(obs)
    held = {scheme: held_out(obs, scheme) for scheme in HOLD_OUT}
    twins = twin_rows(runs)
    ans = answers(obs, costs, runs, a.scenes)
    os.makedirs(os.path.dirname(a.figure), exist_ok=True)
    if not plot(ans, a.figure):
        a.figure = None
    lines = report_lines(a, costs, held, twins, ans, provenance)
    print("\n".join(lines))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"costs_ms": costs, "held_out": held, "twins": twins,
                       "answers": [{k: v for k, v in r.items() if k != "curve"} for r in ans]},
                      f, indent=1)
    if a.results:
        fig = []
        if a.figure:
            rel = os.path.relpath(a.figure, os.path.dirname(os.path.abspath(a.results)))
            fig = ["", f"![on/off against probe cost]({rel})"]
        rewrite_block(a.results, f"hrpp_model:{a.mode}", lines + fig, "python3 -m study model")
    print(f"figure: {a.figure or 'none (no matplotlib)'}")
    for scheme, rows in held.items():
        s = summary(rows)
        print(f"model ({scheme} held out): max relative error {s['error']:.3f} on {s['runs']} runs")
    if twins:
        s = summary(twins)
        print(f"model (another render of the run): max relative error {s['error']:.3f}")
    s = summary(held["setting"])
    print(f"model: max relative error {s['error']:.3f} on {s['runs']} held-out runs")


if __name__ == "__main__":
    main()

"""Is HRPP faster? HRPP on against HRPP off, per ray class and per frame, on the Table 1 stand-ins.

For each scene the same binary renders the same image (same size, spp and seed) with --hrpp off
and with --hrpp on (plus --flags), alternating off/on --repeat times; the fastest run of each
side counts. Printed per scene: on/off device-time ratios of each ray class's kernels (camera,
bounce, shadow: every kernel of the class against the trace alone), of the whole frame (all
kernels) and of the wall time; the classes' true-positive rates (of the probed rays), the
interior-node visits saved (counted by the kernels: visits with HRPP on against off, verification
included), the frames each class predicted every ray and the frames it sampled (the adaptive
predictor: "2+3s/8"), and the image error of on against off: relMSE and the fraction of pixels
that differ. --json writes every figure.

It also prints each class's *floor*: hrpp_predict's device time per probed ray (the stage's
first kernel, which every probed ray pays whatever the prediction finds) against the plain
trace's time per ray with HRPP off. At 1 or above, the class cannot save time at any
true-positive rate on this device: even a ray whose prediction answers it costs what its whole
traversal did. `--flags "--hrpp-config configs/hrpp/every-ray.json"` measures it with every
ray predicted; the default measures it on the adaptive predictor's samples.

Runs with Debian's python3 (numpy, python3-openimageio: tools/setup.sh); without OpenImageIO it
reads the uncompressed EXR files of a portable build with numpy alone.

--backend cpu renders with the CPU renderer, HRPP inline in its traversal (one path at a time:
no kernels, so no time per class). Its times are the frames' wall time, and a class's ratio is
the frame with only that class predicted (--hrpp-rays CLASS, one more render per class) against
the frame with HRPP off; the frame's and the image's figures are those of every class
predicted. No floor (no separate probe). --cpu-tracer embree puts Embree in place of the CPU
traversal there, HRPP in front of it.

--results FILE --block NAME writes the table into that generated block of FILE, headed by the
command, commit, device, date and load.

--tracer rayquery renders with the driver's ray queries (VK_KHR_ray_query) with HRPP in front of
them: on/off ratios per ray class for that tracer (no interior-node counts: the driver's work is
invisible).
Usage: python3 -m study bench [--quick] [--scenes a,b] [--size WxH] [--spp N] [--repeat N]
                           [--flags "--hrpp-mode exact ..."] [--hrpp BIN] [--json FILE]
                           [--images DIR] [--backend gpu|cpu] [--tracer compute|rayquery]
                           [--cpu-tracer scalar|embree] [--results MD --block NAME]
"""
import argparse
import datetime
import json
import os
import shlex
import sys
import tempfile

from common import (DEFAULT_BIN, REPO, STAND_INS, cpu_model, device_name, image_errors, need_binary,
                    read_exr, render, repo_commit, rewrite_block, table)

CLASSES = ["camera", "bounce", "shadow"]


def render_pair_side(binary, scene, a, flags, out_dir, tag):
    """One side of an off/on pair: its stats and its image's path."""
    out = os.path.join(out_dir, f"{os.path.basename(scene).replace(':', '_')}_{tag}")
    return render(binary, scene, out, a.size, a.spp, a.seed, flags, "study bench")


def class_ms(stats, c):
    return sum(stats["classes"][c]["kernels_ms"].values())


def kernel_ms(stats, c, kernel):
    """A class's time in one kernel, its sample's runs included."""
    return sum(ms for k, ms in stats["classes"][c]["kernels_ms"].items()
               if k in (kernel, "sample_" + kernel))


def floor(ons, offs, c):
    """hrpp_predict's time per probed ray over the plain trace's per ray with HRPP off."""
    probes = [s["classes"][c].get("hrpp", {}).get("probes", 0) for s in ons]
    predict = min((kernel_ms(s, c, "hrpp_predict") / n for s, n in zip(ons, probes) if n),
                  default=float("nan"))
    trace = min(class_ms(s, c) / max(1, s["classes"][c]["rays"]) for s in offs)
    return {"predict_ns_per_probe": 1e6 * predict, "trace_ns_per_ray_off": 1e6 * trace,
            "floor": ratio(predict, trace)}


def fastest(runs):
    """Per figure, the fastest of the runs (kernel times and wall time)."""
    best = {"frame": min(s["kernels_ms_total"] for s in runs),
            "wall": min(s["wall_s"] for s in runs)}
    for c in CLASSES:
        best[c] = min(class_ms(s, c) for s in runs)
    return best


def frames_ms(stats):
    """The CPU renderer's frames' wall time (ms): the render without its setup."""
    return 1e3 * sum(f["wall_s"] for f in stats["frames"])


def fastest_cpu(runs, per_class):
    """fastest() for --backend cpu: frame wall times; a class's, that of its own runs."""
    best = {"frame": min(frames_ms(s) for s in runs), "wall": min(s["wall_s"] for s in runs)}
    for c in CLASSES:
        best[c] = min(frames_ms(s) for s in per_class[c]) if per_class.get(c) else best["frame"]
    return best


def ratio(a, b):
    return a / b if b > 0 else float("nan")


def bench_scene(binary, scene, a, tmp):
    offs, ons, per_class = [], [], {}
    exr_off = exr_on = None
    base = ["--backend", a.backend] + (["--tracer", a.tracer] if a.backend == "gpu" else
                                       ["--cpu-tracer", a.cpu_tracer])
    on_flags = base + ["--hrpp", "on"] + a.flags.split()
    for i in range(a.repeat):
        s, exr_off = render_pair_side(binary, scene, a, base + ["--hrpp", "off"], tmp, f"off{i}")
        offs.append(s)
        s, exr_on = render_pair_side(binary, scene, a, on_flags, tmp, f"on{i}")
        ons.append(s)
        if a.backend == "cpu":  # the frame with one class predicted
            for c in CLASSES:
                s, _ = render_pair_side(binary, scene, a, on_flags + ["--hrpp-rays", c], tmp,
                                        f"on_{c}{i}")
                per_class.setdefault(c, []).append(s)
    if a.backend == "cpu":
        off, on = fastest_cpu(offs, {}), fastest_cpu(ons, per_class)
    else:
        off, on = fastest(offs), fastest(ons)
    row = {"scene": scene, "off": off, "on": on,
           "ratio": {k: ratio(on[k], off[k]) for k in off}}
    last_on, last_off = ons[-1], offs[-1]
    for c in CLASSES:
        h = last_on["classes"][c].get("hrpp", {})
        probes = max(1, h.get("probes", 0))
        frames = last_on.get("frames", [])
        modes = [f.get("hrpp_decisions", {}).get(c, {}).get("mode", "off") for f in frames]
        visits_on = last_on["classes"][c]["interior_visited"]
        visits_off = last_off["classes"][c]["interior_visited"]
        row[c] = {"tp_rate": h.get("true_positives", 0) / probes,
                  "interior_saved": 1 - ratio(visits_on, visits_off) if visits_off else 0.0,
                  "wrong_closest": h.get("wrong_closest", 0),
                  "frames_all": modes.count("all"), "frames_sample": modes.count("sample"),
                  "frames": len(frames),
                  **(floor(ons, offs, c) if a.backend == "gpu" else
                     {"predict_ns_per_probe": float("nan"), "trace_ns_per_ray_off": float("nan"),
                      "floor": float("nan")})}
    _, row["relmse"], row["pixels_differ"] = image_errors(read_exr(exr_on), read_exr(exr_off))
    row["device"] = device_name(last_off)
    return row


def print_row(r):
    q = r["ratio"]
    cls = "  ".join(f"{c} {q[c]:.2f} (tp {r[c]['tp_rate']:.2f}, saved {100 * r[c]['interior_saved']:.0f}%,"
                    f" {r[c]['frames_all']}+{r[c]['frames_sample']}s/{r[c]['frames']} frames)"
                    for c in CLASSES)
    print(f"{r['scene']:14s} frame {q['frame']:.3f}  wall {q['wall']:.3f}  | {cls}  | "
          f"relMSE {r['relmse']:.2e}, {100 * r['pixels_differ']:.1f}% pixels differ", flush=True)
    if r[CLASSES[0]]["floor"] != r[CLASSES[0]]["floor"]:  # NaN: --backend cpu has none
        return
    floors = "  ".join(f"{c} {r[c]['floor']:.2f} ({r[c]['predict_ns_per_probe']:.3g} / "
                       f"{r[c]['trace_ns_per_ray_off']:.3g} ns)" for c in CLASSES)
    print(f"{'':14s} floor (hrpp_predict per probed ray / off trace per ray): {floors}", flush=True)


def block_lines(a, rows, load, device):
    """The generated block of --results: the command, commit, device, date and load, then one
    row per scene: ratios on/off (true-positive rate), relMSE, and the floors."""
    command = shlex.join(["python3 -m study bench"] + sys.argv[1:])
    head = [f"Made by `{command}` ({a.size}, {a.spp} spp, seed {a.seed}, fastest of {a.repeat} "
            f"off/on pairs; ratios on/off, above 1: HRPP slower; (true-positive rate, floor)) "
            f"at commit {repo_commit(REPO)} on {device}, {cpu_model()}, "
            f"{datetime.date.today()}, load {load[0]:.1f} before and {load[1]:.1f} after:", ""]
    body = []
    for r in rows:
        q = r["ratio"]
        cls = [f"{q[c]:.2f} ({r[c]['tp_rate']:.2f}, {r[c]['floor']:.2f})" for c in CLASSES]
        body.append([r["scene"], f"{q['frame']:.3f}", f"{q['wall']:.3f}"] + cls +
                    [f"{r['relmse']:.1e}", f"{100 * r['pixels_differ']:.1f}%"])
    return head + [table(["scene", "frame", "wall"] + CLASSES + ["relMSE vs off", "pixels differ"],
                         body)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hrpp", default=DEFAULT_BIN, help="the hrpp binary")
    ap.add_argument("--scenes", default=",".join(STAND_INS), help="comma-separated scene names")
    ap.add_argument("--size", default="1024x1024")
    ap.add_argument("--spp", type=int, default=8)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=2, help="off/on pairs per scene (fastest counts)")
    ap.add_argument("--flags", default="", help="extra flags of the HRPP-on renders")
    ap.add_argument("--quick", action="store_true", help="256x256, 2 spp, one pair")
    ap.add_argument("--json", help="write every figure here")
    ap.add_argument("--images", help="keep the renders (SCENE_offN.exr, SCENE_onN.exr, stats) here")
    ap.add_argument("--backend", choices=["gpu", "cpu"], default="gpu",
                    help="cpu: the CPU renderer with HRPP inline (frame wall times)")
    ap.add_argument("--tracer", choices=["compute", "rayquery"], default="compute",
                    help="--backend gpu: the device tracer HRPP runs in front of")
    ap.add_argument("--results", help="rewrite the generated block --block of this Markdown file")
    ap.add_argument("--block", default="hrpp_bench", help="the block's name (with --results)")
    ap.add_argument("--cpu-tracer", choices=["scalar", "embree"], default="scalar",
                    help="--backend cpu: the CPU tracer HRPP runs in front of")
    a = ap.parse_args()
    if a.backend == "cpu" and a.tracer != "compute":
        ap.error("--tracer: the CPU backend traces on the CPU (--cpu-tracer)")
    if a.backend == "gpu" and a.cpu_tracer != "scalar":
        ap.error("--cpu-tracer: the CPU backend's (--backend cpu)")
    if a.quick:
        a.size, a.spp, a.repeat = "256x256", 2, 1
    need_binary(a.hrpp, "study bench")
    tracer = a.tracer if a.backend == "gpu" else a.cpu_tracer
    print(f"study bench: {a.backend} {tracer}, {a.size}, {a.spp} spp, seed {a.seed}, {a.repeat} off/on "
          f"pairs, on = --hrpp on {a.flags}; ratios on/off (< 1: HRPP faster); "
          f"load {os.getloadavg()[0]:.2f}", flush=True)
    rows, load, device = [], [os.getloadavg()[0]], "?"
    with tempfile.TemporaryDirectory(prefix="hrpp_bench_") as tmp:
        out = a.images or tmp
        os.makedirs(out, exist_ok=True)
        for scene in a.scenes.split(","):
            rows.append(bench_scene(a.hrpp, scene, a, out))
            device = rows[-1].pop("device")
            print_row(rows[-1])
    load.append(os.getloadavg()[0])
    if a.results:
        rewrite_block(a.results, a.block, block_lines(a, rows, load, device), "python3 -m study bench")
    if a.json:
        with open(a.json + ".partial", "w") as f:
            json.dump({"backend": a.backend, "tracer": tracer, "size": a.size, "spp": a.spp,
                       "seed": a.seed, "flags": a.flags, "rows": rows}, f, indent=1)
        os.replace(a.json + ".partial", a.json)


if __name__ == "__main__":
    main()

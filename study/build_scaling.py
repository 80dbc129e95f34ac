"""BVH build time and memory per triangle across scene sizes, with the exponent fitted.

Usage: python3 -m study build-scaling [--hrpp BIN] [--sizes 0.1,1,10] [--repeat R] [--render]
                              [--meshes A,B] [--work DIR] [--json FILE]

For each size (millions of mesh triangles) python3 -m study big-scene --layout random writes a
manifest (seed 1) into --work; then, --repeat rounds interleaving the sizes:
  - `hrpp bench M --no-gpu` (a few rays): hrpp's BVH build time (binned SAH, all hardware
    threads) and Embree's (quality high, robust) on the same triangles and threads;
  - `hrpp scene M --json`: the scene-sized buffers' bytes per triangle, and the process's peak
    resident memory (getrusage of the child: load, BVH, GPU layout, indexed shading);
  - with --render, `hrpp render M --size 32x32 --spp 1`: its peak host RSS and device bytes
    per triangle (the render stats' memory object).
It prints the median of the rounds per size, ns per triangle, and the exponent b of
time = a * n^b fitted by least squares over the sizes (n log n over 0.1M..10M is about 1.07).
Wall times on a loaded machine are noisy: the user CPU time of each child is printed beside
them, and `uptime`'s load before and after. Not a test (bench/BVH_BUILD.md, "Build scaling").
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys

from common import REPO, need_binary


CAPTURE = os.devnull  # the children's stdout, set in main


def child_usage(cmd):
    """Runs cmd as a child; returns (stdout, user seconds, peak RSS bytes)."""
    pid = os.fork()
    if pid == 0:
        fd = os.open(os.devnull, os.O_WRONLY)
        os.dup2(fd, 2)
        out = os.open(CAPTURE, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        os.dup2(out, 1)
        try:
            os.execv(cmd[0], cmd)
        finally:
            os._exit(127)
    _, status, ru = os.wait4(pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"study build-scaling: {' '.join(cmd)} failed (exit {os.waitstatus_to_exitcode(status)})")
    with open(CAPTURE) as f:
        return f.read(), ru.ru_utime, ru.ru_maxrss * 1024


def fit_exponent(ns, ts):
    xs = [math.log(n) for n in ns]
    ys = [math.log(t) for t in ts]
    mx, my = statistics.mean(xs), statistics.mean(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def measure(a, manifest, tmp):
    r = {}
    bench = os.path.join(tmp, "bench.json")
    _, r["bench_user_s"], _ = child_usage(
        [a.hrpp, "bench", manifest, "--no-gpu", "--warn-mismatches", "--kinds", "primary",
         "--rays", "1024", "--repeat", "1", "--check-rays", "16", "--threads", str(a.threads), "--json", bench])
    j = json.load(open(bench))
    r["triangles"] = j["scene"]["triangles"]
    r["hrpp_build_ms"] = j["scene"]["bvh_build_ms"]
    r["embree_build_ms"] = j["embree"]["build_ms"] if "embree" in j else None
    out, r["scene_user_s"], rss = child_usage([a.hrpp, "scene", manifest, "--json"])
    s = json.loads(out)
    r["scene_rss_per_triangle"] = rss / r["triangles"]
    per = s["bytes_per_triangle"]
    r["device_per_triangle"] = sum(v for k, v in per.items() if not k.startswith("host"))
    if a.render:
        stats = os.path.join(tmp, "render.json")
        child_usage([a.hrpp, "render", manifest, "--size", "32x32", "--spp", "1", "--out",
                     os.path.join(tmp, "render.exr"), "--stats", stats])
        m = json.load(open(stats))["memory"]
        r["render_rss_per_triangle"] = m["host_peak_rss_bytes_per_triangle"]
        r["render_device_per_triangle"] = m["total_bytes_per_triangle"]
    return r


def main():
    global CAPTURE
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default_bin = os.path.join(REPO, "build", "release", "host", "hrpp")
    if not os.path.exists(default_bin):
        default_bin = os.path.join(REPO, "build", "ci", "host", "hrpp")
    ap.add_argument("--hrpp", default=default_bin, help="the hrpp binary (default: build/release, "
                    "else build/ci)")
    ap.add_argument("--sizes", default="0.1,1,10", help="millions of triangles (default 0.1,1,10)")
    ap.add_argument("--repeat", type=int, default=3, help="rounds, sizes interleaved (default 3)")
    ap.add_argument("--threads", type=int, default=os.cpu_count(), help="Embree's threads "
                    "(default: all, as hrpp's builder)")
    ap.add_argument("--meshes", default="dragon,bunny,lamborghini,teapot",
                    help="make_big_scene.py --meshes")
    ap.add_argument("--render", action="store_true", help="also hrpp render's peak RSS and device "
                    "bytes per triangle")
    ap.add_argument("--work", default=os.path.join(REPO, "scenes", "fetched", "scaling"),
                    help="where the manifests and outputs go (default scenes/fetched/scaling)")
    ap.add_argument("--json", help="also write the figures as JSON")
    a = ap.parse_args()
    try:
        sizes = [float(s) for s in a.sizes.split(",")]
    except ValueError:
        sys.exit(f"study build-scaling: --sizes {a.sizes}: expected numbers, e.g. 0.1,1,10")
    if not sizes or min(sizes) <= 0 or a.repeat < 1:
        sys.exit("study build-scaling: --sizes must be positive and --repeat at least 1")
    need_binary(a.hrpp, "study build-scaling")
    os.makedirs(a.work, exist_ok=True)
    CAPTURE = os.path.join(a.work, "stdout.txt")
    manifests = []
    for m in sizes:
        path = os.path.join(a.work, f"random_{m:g}M.scene.json")
        subprocess.run([sys.executable, os.path.join(REPO, "study"), "big-scene",
                        "--layout", "random", "--triangles", str(int(m * 1e6)), "--meshes",
                        a.meshes, "--out", path], check=True, stdout=subprocess.DEVNULL)
        manifests.append(path)
    load_before = os.getloadavg()
    rounds = [[] for _ in sizes]
    for _ in range(a.repeat):
        for i, path in enumerate(manifests):
            rounds[i].append(measure(a, path, a.work))
    load_after = os.getloadavg()
    rows = []
    for i, rs in enumerate(rounds):
        row = {"size_m": sizes[i], "triangles": rs[0]["triangles"]}
        for k in rs[0]:
            if k != "triangles" and rs[0][k] is not None:
                row[k] = statistics.median(r[k] for r in rs)
        rows.append(row)
    print(f"load (1-minute) before {load_before[0]:.2f}, after {load_after[0]:.2f}; "
          f"{a.repeat} rounds, medians; {a.hrpp}")
    print(f"{'triangles':>11} {'hrpp ms':>9} {'ns/tri':>7} {'embree ms':>10} {'ns/tri':>7} "
          f"{'hrpp/emb':>8} {'scene RSS':>9} {'device':>7}" + (
              f" {'render RSS':>10} {'device':>7}" if a.render else "") + "   (bytes/triangle)")
    for r in rows:
        n = r["triangles"]
        e = r.get("embree_build_ms")
        line = (f"{n:>11,} {r['hrpp_build_ms']:>9.1f} {1e6 * r['hrpp_build_ms'] / n:>7.1f} "
                + (f"{e:>10.1f} {1e6 * e / n:>7.1f} {r['hrpp_build_ms'] / e:>8.2f}" if e else
                   f"{'-':>10} {'-':>7} {'-':>8}")
                + f" {r['scene_rss_per_triangle']:>9.1f} {r['device_per_triangle']:>7.1f}")
        if a.render:
            line += f" {r['render_rss_per_triangle']:>10.1f} {r['render_device_per_triangle']:>7.1f}"
        print(line)
    fits = {}
    if len(rows) >= 2:
        ns = [r["triangles"] for r in rows]
        fits["hrpp"] = fit_exponent(ns, [r["hrpp_build_ms"] for r in rows])
        if all(r.get("embree_build_ms") for r in rows):
            fits["embree"] = fit_exponent(ns, [r["embree_build_ms"] for r in rows])
        nlogn = fit_exponent(ns, [n * math.log(n) for n in ns])
        print("exponent b of time = a n^b: " + ", ".join(f"{k} {v:.3f}" for k, v in fits.items())
              + f" (n log n over these sizes: {nlogn:.3f})")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"rows": rows, "exponents": fits, "load": [load_before, load_after],
                       "hrpp": a.hrpp, "repeat": a.repeat}, f, indent=2)


if __name__ == "__main__":
    main()

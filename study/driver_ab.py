"""Vulkan drivers and hrpp binaries against each other on the same rays: every binary under every
driver (chosen by VK_DRIVER_FILES), `hrpp trace --repeat N` on each scene's ray sets, the cells
interleaved and their order reversed round by round. Two kinds of ray set per scene:
  - bench: `hrpp bench`'s own batches (primary, AO, diffuse; --save-rays), the rays the project
    chose;
  - close: rays it did not choose, from an independent generator here: a camera close to the
    mesh (at 1.2 of its bounding sphere's radius from the centre; a floor quad, 1000 times the
    median triangle's area or more, is not the mesh), its primary rays aimed at
    points spread over the triangles by area, so most hit; and from points on the triangles, on
    the side facing that camera, cosine-distributed AO rays (0.1 of the radius long, any hit) and
    diffuse rays (unbounded, closest hit).
Prints a Markdown table, Mrays/s per cell (best of the rounds) and each cell's ratio to the first
(the reference), with the run-to-run spread (a cell's worst round against its best), headed by one line of provenance (command, commit, date, drivers, binaries,
load). With --results the same lines become the generated block --block of that file.

Usage: python3 -m study driver-ab --driver A=ICD.json [--driver B=ICD.json]
                          [--binary NAME=HRPP ...] [--scenes bunny,dragon,lamborghini]
                          [--rounds 2] [--repeat 5] [--results FILE [--block NAME]]
Example (Mesa 22.3 unpacked beside the system's Mesa 25, an old build beside this one):
  python3 -m study driver-ab --driver 22.3=/opt/mesa22/lvp_icd.json \\
      --driver 25.0=/usr/share/vulkan/icd.d/lvp_icd.json \\
      --binary e5dd7c2=/tmp/old/build/release/host/hrpp --binary new=build/release/host/hrpp
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

from common import DEFAULT_BIN, REPO, cpu_model, need_binary, repo_commit, rewrite_block, scene_arg

WHO = "study driver-ab"
KINDS = ("primary", "ao", "diffuse")
CLOSE_RAYS = 1 << 19  # per kind of the independent set


def fail(msg):
    print(f"{WHO}: {msg}", file=sys.stderr)
    sys.exit(1)


def pairs(values, flag):
    out = {}
    for v in values:
        if "=" not in v:
            fail(f"{flag} {v}: expected NAME=PATH")
        name, path = v.split("=", 1)
        if not os.path.isfile(path):
            fail(f"{flag} {v}: no such file")
        out[name] = path
    return out


def parse_args():
    p = argparse.ArgumentParser(prog=WHO, description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--driver", action="append", default=[], help="NAME=ICD_JSON (once or more)")
    p.add_argument("--binary", action="append", default=[],
                   help="NAME=HRPP (once or more; default: this build's, as 'hrpp')")
    p.add_argument("--scenes", default="bunny,dragon,lamborghini")
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--repeat", type=int, default=5, help="hrpp trace --repeat")
    p.add_argument("--results", help="rewrite the generated block --block of this Markdown file")
    p.add_argument("--block", default="driver_ab:trace", help="the block's name (with --results)")
    a = p.parse_args()
    if not a.driver:
        fail("--driver NAME=ICD_JSON is needed at least once")
    a.drivers = pairs(a.driver, "--driver")
    a.binaries = pairs(a.binary, "--binary") if a.binary else {"hrpp": DEFAULT_BIN}
    for path in a.binaries.values():
        need_binary(path, WHO, "--binary")
    if a.rounds < 1 or a.repeat < 1:
        fail("--rounds and --repeat: at least 1")
    return a


def cosine_rays(origin, normal, rng, tmin, tmax):
    """One cosine-distributed ray about each normal."""
    helper = np.where(np.abs(normal[:, :1]) > 0.9, [[0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0]])
    b1 = np.cross(normal, helper)
    b1 /= np.linalg.norm(b1, axis=1, keepdims=True)
    b2 = np.cross(normal, b1)
    phi, r2 = 2 * np.pi * rng.random(len(normal)), rng.random(len(normal))
    d = (np.sqrt(r2) * np.cos(phi))[:, None] * b1 + (np.sqrt(r2) * np.sin(phi))[:, None] * b2 + \
        np.sqrt(1 - r2)[:, None] * normal
    return records(origin, d, tmin, tmax)


def records(origin, d, tmin, tmax):
    r = np.empty((len(d), 8), dtype=np.float32)
    r[:, 0:3], r[:, 3], r[:, 4:7], r[:, 7] = origin, tmin, d / np.linalg.norm(d, axis=1, keepdims=True), tmax
    return r


def close_rays(triangles, n, seed=11):
    """The independent set from a triangle dump (9 floats a triangle): primary, ao, diffuse."""
    tri = np.fromfile(triangles, dtype=np.float32).reshape(-1, 3, 3).astype(np.float64)
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    cross = np.cross(e1, e2)
    area = np.linalg.norm(cross, axis=1)
    keep = (area > 0) & (area < 1000 * np.median(area))  # the mesh: not a manifest's floor
    tri, cross, area = tri[keep], cross[keep], area[keep]
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo) / 2
    rng = np.random.default_rng(seed)
    eye = centre + 1.2 * radius * np.array([0.48, 0.36, 0.8])

    def points():
        t = rng.choice(len(tri), size=n, p=area / area.sum())
        r1, r2 = np.sqrt(rng.random(n))[:, None], rng.random(n)[:, None]
        p = (1 - r1) * tri[t, 0] + r1 * (1 - r2) * tri[t, 1] + r1 * r2 * tri[t, 2]
        nrm = cross[t] / area[t][:, None]
        nrm *= np.where(((eye - p) * nrm).sum(axis=1) < 0, -1.0, 1.0)[:, None]  # toward the eye
        return p, nrm

    target, _ = points()
    primary = records(np.broadcast_to(eye, target.shape), target - eye, 0.0, np.inf)
    eps = 1e-4 * radius
    p, nrm = points()
    ao = cosine_rays(p + eps * nrm, nrm, rng, 0.0, 0.1 * radius)
    p, nrm = points()
    diffuse = cosine_rays(p + eps * nrm, nrm, rng, 0.0, np.inf)
    return {"primary": primary, "ao": ao, "diffuse": diffuse}


def ray_sets(a, scene, tmp):
    """scene's ray files by (set, kind): bench's batches and the independent close ones."""
    first = next(iter(a.binaries.values()))
    out = os.path.join(tmp, scene)
    run([first, "bench", scene_arg(scene), "--no-gpu", "--no-embree", "--check-rays", "1",
         "--repeat", "1", "--save-rays", out], dict(os.environ))
    files = {("bench", k): os.path.join(out, f"{k}.rays") for k in KINDS}
    for k, rays in close_rays(os.path.join(out, "triangles.bin"), CLOSE_RAYS).items():
        files[("close", k)] = os.path.join(out, f"close_{k}.rays")
        rays.tofile(files[("close", k)])
    return files


def run(cmd, env):
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        fail(f"{' '.join(cmd)} failed:\n{p.stdout[-1500:]}{p.stderr[-1500:]}")
    return p.stdout


def mrays(a, binary, icd, scene, rays, kind, hits):
    env = dict(os.environ, VK_DRIVER_FILES=icd)
    out = run([binary, "trace", scene_arg(scene), "--rays", rays, "--hits", hits, "--repeat",
               str(a.repeat)] + (["--any-hit"] if kind == "ao" else []), env)
    m = re.search(r"kernel\s+[0-9.]+ ms.*?, ([0-9.]+) Mrays/s", out)
    if not m:
        fail(f"{binary} trace: no Mrays/s in its output:\n{out[-800:]}")
    return float(m.group(1))


def driver_of(a, icd):
    out = run(["vulkaninfo", "--summary"], dict(os.environ, VK_DRIVER_FILES=icd))
    m = re.search(r"driverInfo\s*=\s*(.+)", out)
    return m.group(1).strip() if m else "?"


def main():
    a = parse_args()
    cells = [(b, d) for b in a.binaries for d in a.drivers]
    scenes = a.scenes.split(",")
    best, loads = {}, []
    with tempfile.TemporaryDirectory(prefix="hrpp_driver_ab_") as tmp:
        files = {s: ray_sets(a, s, tmp) for s in scenes}
        hits = os.path.join(tmp, "hits")
        for rnd in range(a.rounds):
            order = cells if rnd % 2 == 0 else cells[::-1]
            for scene in scenes:
                for (rset, kind), rays in files[scene].items():
                    for b, d in order:
                        loads.append(os.getloadavg()[0])
                        v = mrays(a, a.binaries[b], a.drivers[d], scene, rays, kind, hits)
                        best.setdefault((scene, rset, kind, b, d), []).append(v)
                print(f"{WHO}: round {rnd + 1}/{a.rounds} {scene}", file=sys.stderr, flush=True)
    spread = statistics.median(1 - min(v) / max(v) for v in best.values())
    best = {k: max(v) for k, v in best.items()}
    names = [f"{b} / {d}" for b, d in cells]
    drivers = "; ".join(f"{d}: {driver_of(a, icd)}" for d, icd in a.drivers.items())
    results = f" --results {a.results} --block {a.block}" if a.results else ""
    flags = " ".join([f"--driver {x}" for x in a.driver] + [f"--binary {x}" for x in a.binary])
    lines = [f"Made by `python3 -m study driver-ab {flags} --scenes {a.scenes} --rounds {a.rounds} "
             f"--repeat {a.repeat}{results}` at commit {repo_commit(REPO)}, "
             f"{time.strftime('%Y-%m-%d')}, {cpu_model()}; {drivers}; load "
             f"{min(loads):.1f}-{max(loads):.1f}. Mrays/s, best of the rounds (ratio to "
             f"{names[0]}); a cell's rounds differ by {spread:.0%} (median over the cells); bench: "
             f"`hrpp bench`'s batches (2^20 rays), close: the independent close-camera rays "
             f"(2^19):", "",
             "| scene | rays | kind | " + " | ".join(names) + " |",
             "|---|---|---|" + "---|" * len(names)]
    for scene in scenes:
        for rset in ("bench", "close"):
            for kind in KINDS:
                v = [best[(scene, rset, kind, b, d)] for b, d in cells]
                row = [f"{v[0]:.2f}"] + [f"{x:.2f} ({x / v[0]:.2f})" for x in v[1:]]
                lines.append(f"| {scene} | {rset} | {kind} | " + " | ".join(row) + " |")
    ratios = [[best[k + c] / best[k + cells[0]] for k in {key[:3] for key in best}]
              for c in cells[1:]]
    lines.append("| geometric mean | | | 1 | " +
                 " | ".join(f"{float(np.exp(np.mean(np.log(r)))):.3f}" for r in ratios) + " |")
    print("\n".join(lines))
    if a.results:
        rewrite_block(a.results, a.block, lines, "python3 -m study driver-ab")


if __name__ == "__main__":
    main()

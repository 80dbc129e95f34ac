"""The two published predictors on the same rays: MICRO'21's intersection predictor (Liu, Chang,
Demoullin et al., MICRO 2021; configs/hrpp/micro21.json reproduces its submitted simulator)
beside the paper's HRPP and hrpp's own keys.

Rays:
  - ao: rtao-benchmark's ambient-occlusion rays as its generator makes them (RayGenerator.cpp:
    one point on each triangle, in file order, up to --points; its vertex normal interpolated;
    10 cosine-weighted rays from it, in a row; tmin 0.1 on its bunny, whose largest extent is
    1.62: here 0.0617 of the mesh's largest extent; tmax unbounded), on the stand-ins of its
    scenes with the mesh alone, as its scenes have it; traced any-hit by `hrpp trace`;
  - camera, bounce, shadow: one path-traced frame of the stand-in scene (`hrpp render`).
Every predictor runs in the deterministic order (batches of 256 rays: a ray sees the inserts of
the batches before it, as a ray in MICRO'21's RT unit sees those of rays that finished) and
counts full traversals (savings, wrong closest hits).

Per row: probes; the share of rays that hit (or are occluded: no predictor can verify more);
predicted (a key found) and verified (its nodes held the hit) shares of the
probes; interior-node visits skipped net of verification; wrong closest hits (speculative
hit-all); table bytes (per SM where per SM); and the hardware projection: RT-unit cycles per ray
with the predictor over without, at MICRO'21's MOBILE latencies (HW_* below).
Writes the block micro21:MODE of --results (default results/MICRO21.md)."""
import argparse
import json
import os
import shlex
import sys
import tempfile

import numpy as np

import common
from common import DEFAULT_BIN, REPO, hrpp_settings, need_binary, repo_commit, rewrite_block, table

WHO = "study micro21"
SPP = 10                        # rtao's scene.toml: spp = 10 AO rays per point
TMIN_SHARE = 0.1 / 1.6208       # its t_min 0.1 over its bunny's largest extent
SCENES = ("bunny", "teapot", "dragon")  # its bunny, teapot and dragon; its others are not here
MODES = {  # points per AO scene, render size and spp
    "full": {"points": 32768, "size": "128x128", "spp": 2},
    "quick": {"points": 4096, "size": "64x64", "spp": 1},
    "test": {"points": 256, "size": "16x16", "spp": 1},
}
# MICRO'21's MOBILE configuration (configs/tested-cfgs/MOBILE/gpgpusim.config at its submission):
HW_NODE = 24      # -gpgpu_rt_latency: the RT unit's latency, charged per node or leaf visit
HW_TRIANGLE = 2   # -gpgpu_rt_intersection_latency: one ray-triangle test
HW_PROBE = 2      # -gpgpu_rt_predictor_config's latency: a predictor lookup (its per-thread
                  # -gpgpu_rt_predictor_lookup_latency is 1)
ORDER = {"batch": 256, "serial": True, "count_baseline": True, "adaptive": False}


def micro21_keys(**override):
    return {"hash": "micro21", "hash_bits": 5, "go_up": 3, "go_up_size": 0,
            "table_preset": "micro21", **override}


def paper_keys(**override):
    return {"hash": "hrpp", "hash_bits": 6, "go_up": 0, "go_up_size": 0,
            "table_preset": "unbounded", **override}


# name: (settings, what it is[, the order's settings over ORDER]). Every class keyed alike.
PREDICTORS = {
    "MICRO'21": (micro21_keys(), "as submitted: 2 SM tables, inserts after every 256 rays"),
    "MICRO'21, inserts every 16 rays": (micro21_keys(), "the same, a ray seeing the inserts of all "
                                        "but the last 15 before it", {"batch": 16}),
    "MICRO'21, one table": (micro21_keys(sm_tables=1, table_sets=512),
                            "its 2 SM tables' entries in one table that every ray probes"),
    "paper": (paper_keys(), "hrpp key N=6, leaves, unbounded table"),
    "paper key, MICRO'21 tables": (paper_keys(table_preset="micro21", go_up=3),
                                   "N=6, go-up 3, in MICRO'21's 2 SM tables"),
    "hrpp defaults": (None, "camera hrpp, bounce grid-spherical, shadow light-depth"),
}


def settings(name, mode):
    keys, _, *order = PREDICTORS[name]
    per_class = {} if keys is None else {c: keys for c in common.RAY_CLASSES}
    top = {"fallback": "root", "mode": mode, **ORDER, **(order[0] if order else {})}
    return hrpp_settings(None, top, **per_class)


def mesh_manifest(scene, work):
    """The stand-in's mesh alone (its first object: no floor, no light), as rtao's scenes are."""
    with open(os.path.join(REPO, "scenes", f"{scene}.scene.json")) as f:
        manifest = json.load(f)
    mesh = dict(manifest["objects"][0])
    mesh["gltf"] = os.path.join(REPO, "scenes", mesh["gltf"])
    if not os.path.exists(mesh["gltf"]):
        return None
    path = os.path.join(work, f"{scene}_mesh.scene.json")
    with open(path, "w") as f:
        json.dump({"name": f"{scene} (mesh)", "objects": [mesh]}, f)
    return path


def tangent_basis(n):
    """Duff et al.'s orthonormal basis around unit normals n (rtao's GetTangentBasis)."""
    sign = np.where(n[:, 2] >= 0, 1.0, -1.0)
    a = -1.0 / (sign + n[:, 2])
    b = n[:, 0] * n[:, 1] * a
    b1 = np.stack([1 + sign * n[:, 0] ** 2 * a, sign * b, -sign * n[:, 0]], axis=1)
    b2 = np.stack([b, sign + n[:, 1] ** 2 * a, -n[:, 1]], axis=1)
    return b1, b2


def ao_rays(export, points, seed):
    """rtao's AO rays (generatePointsAndNormals_spt, generate_detangled_spp) as 32-byte records."""
    with open(export) as f:
        scene = json.load(f)
    pos = np.asarray(scene["positions"], dtype=np.float64).reshape(-1, 3, 3)[:points]
    nrm = np.asarray(scene["normals"], dtype=np.float64).reshape(-1, 3, 3)[:points]
    rng = np.random.default_rng(seed)
    r1, r2 = np.sqrt(rng.random(len(pos)))[:, None], rng.random(len(pos))[:, None]
    w = np.concatenate([1 - r1, r1 * (1 - r2), r1 * r2], axis=1)[:, :, None]
    origin, normal = (w * pos).sum(axis=1), (w * nrm).sum(axis=1)
    flat = np.cross(pos[:, 1] - pos[:, 0], pos[:, 2] - pos[:, 0])  # where a mesh has no normals
    normal = np.where(np.linalg.norm(normal, axis=1, keepdims=True) > 1e-12, normal, flat)
    keep = np.linalg.norm(normal, axis=1) > 1e-12  # degenerate triangles: no normal, no rays
    pos, origin, normal = pos[keep], origin[keep], normal[keep]
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    b1, b2 = tangent_basis(normal)
    e1, e2 = rng.random((len(pos), SPP)), rng.random((len(pos), SPP))
    phi, cos_t = 2 * np.pi * e1, np.sqrt(e2)
    sin_t = np.sqrt(1 - cos_t ** 2)
    local = [sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t]
    d = sum(local[k][:, :, None] * basis[:, None, :] for k, basis in enumerate((b1, b2, normal)))
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    extent = np.ptp(pos.reshape(-1, 3), axis=0).max()
    rays = np.empty((len(pos), SPP, 8), dtype=np.float32)
    rays[:, :, 0:3] = origin[:, None, :]
    rays[:, :, 3] = TMIN_SHARE * extent
    rays[:, :, 4:7] = d
    rays[:, :, 7] = np.finfo(np.float32).max
    return rays.reshape(-1, 8)


def hw_cycles(interior, leaves, triangles, probes):
    return HW_NODE * (interior + leaves) + HW_TRIANGLE * triangles + HW_PROBE * probes


def row_figures(pc, counts, bytes_, sm_tables):
    """One row's figures from HRPP's counters and the run's traversal counts (verification
    included); HRPP off is the full traversal the run counted beside for every probed ray
    (count_baseline), in the same order: no second run."""
    probes = pc["probes"]
    n = max(probes, 1)
    hit = counts["hits"] / max(counts["rays"], 1)
    net = (pc["baseline_interior"] - counts["interior"]) / max(pc["baseline_interior"], 1)
    on = hw_cycles(counts["interior"], counts["leaves"], counts["triangles"], probes)
    off = hw_cycles(pc["baseline_interior"], pc["baseline_leaves"], pc["baseline_triangles"], 0)
    each = bytes_ // max(sm_tables, 1) // 1024
    per_sm = (f"{each} KiB" if each < 1024 else f"{each // 1024} MiB") + (
        f" x {sm_tables}" if sm_tables > 1 else "")
    return [probes, f"{100 * hit:.1f}%", f"{100 * pc['predictor_hits'] / n:.1f}%",
            f"{100 * pc['true_positives'] / n:.1f}%", f"{100 * net:.1f}%",
            pc.get("wrong_closest", 0), per_sm, f"{on / off:.3f}" if off > 0 else "-"]


def trace(hrpp, scene, rays_path, flags, out):
    common.run([hrpp, "trace", scene, "--rays", rays_path, "--hits", out + ".hits", "--any-hit",
                "--stats", out + ".json"] + flags, WHO)
    with open(out + ".json") as f:
        return json.load(f)


def trace_counts(j):
    return {"interior": j["interior_visited"], "leaves": j["leaves_visited"],
            "triangles": j["triangles_tested"], "rays": j["rays"], "hits": j["hits"]}


def ao_rows(a, scene, work):
    manifest = mesh_manifest(scene, work)
    if manifest is None:
        print(f"{WHO}: {scene}: its mesh is missing (tools/fetch-scenes.sh); skipped",
              file=sys.stderr)
        return []
    export = os.path.join(work, f"{scene}_mesh.json")
    common.run([a.hrpp, "scene", manifest, "--export-json", export], WHO)
    rays_path = os.path.join(work, f"{scene}_ao.rays")
    ao_rays(export, a.points, a.seed).tofile(rays_path)
    rows = []
    for name in PREDICTORS:
        out = os.path.join(work, f"{scene}_ao_{len(rows)}")
        flags = ["--hrpp", "on"] + common.settings_args([settings(name, "speculative")],
                                                          out + ".hrpp.json")
        j = trace(a.hrpp, manifest, rays_path, flags, out)
        s, keys = j["hrpp"]["summary"], j["hrpp"]["keys"]["shadow"]
        rows.append([scene, "ao", name] + row_figures(s, trace_counts(j), keys["table_bytes"],
                                                       keys["sm_tables"]))
    return rows


def render(a, scene, flags, out):
    common.run([a.hrpp, "render", scene, "--size", a.size, "--spp", str(a.spp), "--seed", "7",
                "--out", out + ".exr", "--stats", out + ".json"] + flags, WHO)
    with open(out + ".json") as f:
        return json.load(f)


def class_counts(j, c):
    k = j["classes"][c]
    return {"interior": k["interior_visited"], "leaves": k["leaves_visited"],
            "triangles": k["triangles_tested"], "rays": k["rays"], "hits": k["hits"]}


def path_rows(a, scene, work):
    scene_path = common.scene_arg(scene)
    if not os.path.exists(scene_path):
        return []
    rows = []
    for i, name in enumerate(PREDICTORS):
        out = os.path.join(work, f"{scene}_render_{i}")
        j = render(a, scene_path, ["--hrpp", "on"] + common.settings_args(
            [settings(name, "speculative")], out + ".hrpp.json"), out)
        for c in common.RAY_CLASSES:
            pc, keys = j["classes"][c]["hrpp"], j["hrpp_predictor"]["keys"][c]
            rows.append([scene, c, name] + row_figures(pc, class_counts(j, c), keys["table_bytes"],
                                                       keys["sm_tables"]))
    return rows


HEAD = ["scene", "rays", "predictor", "probes", "hit", "predicted", "verified",
        "interior visits skipped, net", "wrong closest", "table bytes", "hardware on/off"]


def block_lines(a, rows, device):
    command = shlex.join(["python3 -m study micro21"] + sys.argv[1:])
    lines = [f"`{command}` at commit {repo_commit(REPO)}; {common.machine_line(device)}. "
             f"AO: {a.points} points x {SPP} rays per stand-in mesh; paths: {a.size}, "
             f"{a.spp} spp, seed 7. Predictors:", ""]
    lines += [f"- {name}: {p[1]}" for name, p in PREDICTORS.items()]
    lines += ["", table(HEAD, rows), "",
              f"Hardware on/off: RT-unit cycles per ray, {HW_NODE} a node or leaf visit, "
              f"{HW_TRIANGLE} a triangle test, {HW_PROBE} a probe, verification included, "
              "no queue, no memory-system or repacking effects; below 1 the predictor saves."]
    return lines


def main():
    ap = argparse.ArgumentParser(prog="study micro21", description=__doc__.split("\n\n")[0])
    ap.add_argument("--mode", choices=sorted(MODES), default="quick")
    ap.add_argument("--hrpp", default=DEFAULT_BIN, help="the hrpp binary (default %(default)s)")
    ap.add_argument("--scenes", default=",".join(SCENES), help="stand-ins (default %(default)s)")
    ap.add_argument("--points", type=int, help="AO points per scene (default: the mode's)")
    ap.add_argument("--seed", type=int, default=1, help="the AO rays' seed")
    ap.add_argument("--no-paths", action="store_true", help="AO rays only")
    ap.add_argument("--results", help="rewrite the block micro21:MODE of this Markdown file "
                    "(default results/MICRO21.md; '-' prints it)")
    a = ap.parse_args()
    need_binary(a.hrpp, WHO)
    mode = MODES[a.mode]
    a.points = a.points or mode["points"]
    a.size, a.spp = mode["size"], mode["spp"]
    if a.points < 1:
        sys.exit(f"{WHO}: --points must be at least 1")
    rows, device = [], "?"
    with tempfile.TemporaryDirectory(prefix="hrpp_micro21_") as work:
        for scene in a.scenes.split(","):
            if scene not in SCENES:
                sys.exit(f"{WHO}: --scenes: {scene} is not one of {', '.join(SCENES)}")
            print(f"{WHO}: {scene}", file=sys.stderr, flush=True)
            rows += ao_rows(a, scene, work)
            if not a.no_paths:
                rows += path_rows(a, scene, work)
        for name in os.listdir(work):
            if name.endswith(".json") and "_ao_" in name and not name.endswith("hrpp.json"):
                with open(os.path.join(work, name)) as f:
                    device = common.device_name(json.load(f))
                break
    lines = block_lines(a, rows, device)
    if a.results == "-":
        print("\n".join(lines))
        return
    path = a.results or os.path.join(REPO, "results", "MICRO21.md")
    rewrite_block(path, f"micro21:{a.mode}", lines, "python3 -m study micro21")
    print(f"{WHO}: wrote the block micro21:{a.mode} of {path}")


if __name__ == "__main__":
    main()

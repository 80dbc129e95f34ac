"""Collects the limit study's runs into one CSV: every --stats JSON (configuration, per-class
predictor counters, table figures, wall and per-kernel times) joined with the job's grid
parameters (jobs.jsonl), plus image errors computed here from the EXR images:
  *_off  against the HRPP-off image of the same scene, size, spp, seed and estimator (exact
         mode: 0)
  *_ref  against the high-spp HRPP-off reference of the same scene, size and estimator
         (errtime grid)
RMSE over all pixels and channels; relMSE = mean((x - y)^2 / (y^2 + eps)), eps = 0.01, y the
image compared with. Needs python3-openimageio and numpy (Debian)."""
import argparse
import csv
import json
import os
import shlex
import subprocess
import sys

from common import device_name, image_errors, read_exr, run_line

META = ["id", "grid", "scene", "size", "spp", "seed", "variant", "bits", "goup", "hash", "kib",
        "policy", "ways", "ok"]
CONFIG = ["hrpp", "mode", "count_baseline", "hash_bits", "go_up", "hash_fn", "table_sets",
          "table_ways", "table_nodes", "table_policy", "triangles", "bvh_depth"]
CLASS_KEYS = ["probes", "predictor_hits", "hit_rate", "true_positives", "false_positives",
              "negatives", "true_positive_rate", "savings", "net_savings", "skipped_interior",
              "baseline_interior", "interior_visited", "leaves_visited", "verify_leaves",
              "verify_interior", "verify_triangles", "inserts", "insert_requests", "insert_drops",
              "evictions", "wrong_closest", "table_entries", "table_capacity", "table_nodes",
              "table_bytes"]
DERIVED = ["rays", "nodes_per_entry", "used_bytes", "compact_bytes", "occupancy",
           "interior_per_ray"]
TIMES = ["wall_s", "kernels_ms_total", "trace_ms"]
ERRORS = ["rmse_off", "relmse_off", "pixels_differ_off", "rmse_ref", "relmse_ref"]
TAIL = ["flags", "cmd", "run"]


def flatten(meta, stats, note):
    r = {k: meta.get(k, "") for k in META}
    r["flags"], r["cmd"] = meta.get("flags", ""), meta.get("cmd", "")
    r["run"] = run_line(note, device_name(stats))  # the render's provenance
    r["ok"] = 1
    h = stats.get("hrpp_predictor", {})
    on = bool(h.get("enabled"))
    r["hrpp"] = "on" if on else "off"
    r["triangles"] = stats.get("scene", {}).get("triangles", "")
    if on:
        r.update(mode=h.get("mode"), count_baseline=int(bool(h.get("count_baseline"))),
                 hash_bits=h.get("hash_bits"), go_up=h.get("go_up"), hash_fn=h.get("hash"),
                 table_sets=h.get("table_sets"), table_ways=h.get("table_ways"),
                 table_nodes=h.get("table_nodes"), table_policy=h.get("table_policy"))
    else:
        r.update(mode="off", count_baseline=0)
    r["wall_s"] = stats.get("wall_s")
    r["kernels_ms_total"] = stats.get("kernels_ms_total")
    km = stats.get("kernels_ms", {})
    for k, v in km.items():
        r["ms_" + k] = v
    r["trace_ms"] = sum(v for k, v in km.items() if k.startswith("trace") or k.startswith("hrpp"))
    for cls, src, pc in (("all", "closest", "hit_all"), ("any", "shadow", "hit_any")):
        c = stats.get(src, {})
        r[f"{cls}_rays"] = c.get("rays")
        r[f"{cls}_interior_per_ray"] = c.get("interior_visited", c.get("interior_nodes", 0)) / max(1, c.get("rays", 0))
        p = h.get(pc) if on else None
        if p is None:
            r[f"{cls}_interior_visited"] = c.get("interior_visited", c.get("interior_nodes"))
            continue
        for k in CLASS_KEYS:
            r[f"{cls}_{k}"] = p.get(k)
        e, n = p.get("table_entries", 0), p.get("table_nodes", 0)
        # Node slots per entry of the kind's table: per class in the stats (the default gives
        # shadow rays the beam table); hit-all figures use the camera rays' (the grids give
        # bounce rays the same table).
        slots = h.get("keys", {}).get("shadow" if pc == "hit_any" else "camera", {}).get(
            "table_nodes", h.get("table_nodes", 0))
        r[f"{cls}_nodes_per_entry"] = n / e if e else 0.0
        r[f"{cls}_used_bytes"] = e * (12 + 4 * slots)   # entries in use, this table's layout
        r[f"{cls}_compact_bytes"] = 8 * e + 4 * n        # a key and a 4-byte node id per node
        r[f"{cls}_occupancy"] = e / p["table_capacity"] if p.get("table_capacity") else 0.0
        if not r[f"{cls}_true_positive_rate"] and p.get("predictor_hits"):
            r[f"{cls}_true_positive_rate"] = p["true_positives"] / p["predictor_hits"]
    return r


def estimator(row):
    """The light sampling and sampler flags of a row's render: images compare only with HRPP
    off's of the same estimator (the grids pin different ones: study/sweep_jobs.py)."""
    words = row.get("cmd", "").split()
    return tuple(words[i + 1] for i, w in enumerate(words[:-1])
                 if w in ("--light-sampling", "--sampler"))


def kept_rows(path, grids):
    """The rows of `path` (if it exists) whose grid is not in `grids`, as read."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return [r for r in csv.DictReader(f) if r.get("grid") not in grids]


def bvh_depths(rows):
    """The BVH's maximum depth of each Table 1 scene (`hrpp scene SCENE --json`, the binary and
    scene argument of the row's own render command); the other grids' rows have none."""
    depth = {}
    for r in rows:
        if r.get("grid") != "table1" or not r.get("cmd"):
            continue
        hrpp, _, scene = shlex.split(r["cmd"])[:3]
        if scene not in depth:
            out = subprocess.run([hrpp, "scene", scene, "--json"], capture_output=True, text=True)
            depth[scene] = (json.loads(out.stdout)["bvh"]["max_depth"] if out.returncode == 0
                            else "")
        r["bvh_depth"] = depth[scene]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--jobs", required=True, help="jobs.jsonl from sweep_jobs.py")
    ap.add_argument("--runs", required=True, help="directory of ID.json / ID.exr")
    ap.add_argument("--csv", required=True, help="CSV to write")
    ap.add_argument("--no-images", action="store_true", help="skip the image errors")
    ap.add_argument("--keep-other-grids", action="store_true",
                    help="keep the rows of grids these jobs do not cover from the CSV's "
                         "previous contents (a run of some grids merged into a full CSV)")
    a = ap.parse_args()
    metas = [json.loads(l) for l in open(a.jobs) if l.strip()]
    note_path = os.path.join(os.path.dirname(os.path.abspath(a.runs)), "provenance.json")
    note = json.load(open(note_path)) if os.path.exists(note_path) else {}
    kept = kept_rows(a.csv, {m["grid"] for m in metas}) if a.keep_other_grids else []
    rows = []
    for m in metas:
        js = os.path.join(a.runs, m["id"] + ".json")
        try:
            with open(js) as f:
                stats = json.load(f)
            if stats.get("session", {}).get("interrupted"):
                raise ValueError("the render was interrupted: its passes are not the job's")
            if stats.get("session", {}).get("failed"):
                raise ValueError("the render failed: " + str(stats["session"].get("error")))
            rows.append(flatten(m, stats, note))
        except (OSError, ValueError) as e:
            r = {k: m.get(k, "") for k in META}
            r.update(ok=0, flags=m.get("flags", ""), cmd=m.get("cmd", ""))
            rows.append(r)
            print(f"study sweep-collect: {m['id']}: no stats ({e})", file=sys.stderr)

    bvh_depths(rows)
    if not a.no_images:
        cache = {}

        def img(rid):
            if rid not in cache:
                p = os.path.join(a.runs, rid + ".exr")
                cache[rid] = read_exr(p) if os.path.exists(p) else None
            return cache[rid]

        key = lambda r: (r["scene"], r["size"], r["spp"], r["seed"], estimator(r))
        offs, refs = {}, {}
        for r in rows:
            if r["ok"] and r.get("hrpp") == "off":
                if r.get("variant") == "reference":
                    refs.setdefault((r["scene"], r["size"], estimator(r)), r["id"])
                else:
                    offs.setdefault(key(r), r["id"])
        for r in rows:
            if not r["ok"]:
                continue
            x = img(r["id"])
            if x is None:
                continue
            o = offs.get(key(r))
            if o is not None and img(o) is not None:
                r["rmse_off"], r["relmse_off"], r["pixels_differ_off"] = image_errors(x, img(o))
            ref = refs.get((r["scene"], r["size"], estimator(r)))
            if ref is not None and ref != r["id"] and img(ref) is not None:
                r["rmse_ref"], r["relmse_ref"], _ = image_errors(x, img(ref))
            if len(cache) > 64:   # keep memory bounded (1024^2 images are 24 MiB each)
                for k in list(cache)[:32]:
                    if k not in offs.values() and k not in refs.values():
                        del cache[k]

    kernels = sorted({k for r in rows for k in r if k.startswith("ms_")})
    cols = META + CONFIG + TIMES + kernels
    for cls in ("all", "any"):
        cols += [f"{cls}_{k}" for k in CLASS_KEYS + DERIVED]
    cols += ERRORS + TAIL
    os.makedirs(os.path.dirname(os.path.abspath(a.csv)), exist_ok=True)
    kept_kernels = sorted({k for r in kept for k in r if k.startswith("ms_")} - set(kernels))
    cols[len(META + CONFIG + TIMES):len(META + CONFIG + TIMES)] = kept_kernels
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in kept + rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k, "")) for k in cols})
    ok = sum(1 for r in rows if r["ok"])
    print(f"study sweep-collect: {ok} of {len(rows)} runs -> {a.csv}"
          + (f" (and {len(kept)} kept rows of other grids)" if kept else ""))
    return 0 if ok == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main())

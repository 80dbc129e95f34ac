"""Writes the limit study's job list: one hrpp render per line (jobs.txt, for GNU parallel) and
its metadata (jobs.jsonl: grid, scene, the varied parameters; the collector joins on "id").

Grids (see results/LIMIT_STUDY.md):
  table1     stand-in scenes at the paper's Table 1 setup (N = 6, go-up 0, unbounded tables,
             speculative, --hrpp-count), plus HRPP off / speculative / exact without counting
             (their wall and kernel times, and the speculative image error)
  precision  hash precision N = 1..8 on the dragon (the Buddha stand-in)
  goup       go-up level 0..4 on the dragon
  spp        1, 2, 4, 8, 16 samples per pixel on the dragon
  bounded    bounded tables (4 KiB .. 16 MiB and unbounded, policy none | lru, ways 1 | 4 | 8)
             and the three hash functions, hit-all and hit-any in every run
  errtime    error against run time: spp ladders with HRPP off, speculative and exact (no
             counting: these runs are the timed ones) and a high-spp reference image
  paperscale the paper's Sportscar scale (--full only): the 52M-triangle random scene of
             study/big_scene.py at the Table 1 setup, with the unbounded and the tuned
             table, and its off / speculative / exact runs (results/LIMIT_STUDY.md shows it in Table 1)
  test       three configurations on the Cornell box (the pipeline test)

Every predicting run uses the paper's keys and, as the paper, traces a ray its prediction did not
answer from the root (--hrpp-fallback root).

Modes fix the image sizes and spp; "quick" fits minutes on 2 cores, "full" about 1.5 hours.
"""
import argparse
import json
import os
import shlex
import sys

from common import flags_text, hrpp_settings, scene_arg, settings_args

TABLE1_SCENES = ["teapot", "bunny", "bunny-complex", "dragon", "lamborghini", "cornell",
                 "killeroo-simple", "killeroo-gold"]
ERRTIME_SCENES = ["bunny", "lamborghini"]
# The paper-scale scene: python3 -m study big-scene --layout random at its defaults (sweep.sh writes
# it when missing; not committed).
PAPERSCALE_SCENE = "fetched/big_random"

# Entry bytes with 8 nodes: 8 (tag) + 4 (stamp) + 4 * 8 = 44; a table of S sets x W ways.
BOUNDED_NODES = 8
BOUNDED_KIB = [4, 16, 64, 256, 1024, 4096, 16384]
BOUNDED_WAYS = [1, 4, 8]
BOUNDED_POLICIES = ["none", "lru"]
# The estimator the limit study's HRPP grids were rendered with (light sampling alone, independent
# samples), pinned so that they reproduce. The error-against-time grid renders with hrpp
# render's own (MIS, Sobol samples: DEFAULT_ESTIMATOR), which its images' error depends on.
ESTIMATOR = ["--light-sampling", "light", "--sampler", "independent"]
DEFAULT_ESTIMATOR = []
HASHES = ["hrpp", "grid-spherical", "two-point"]

MODES = {
    # size: Table 1 / dragon grids; bsize: bounded-table grid; esize: error-vs-time grid
    "quick": dict(size=256, spp=4, bsize=256, bspp=2, bscenes=["bunny"], esize=192,
                  espp=[1, 2, 4, 8], eref=64, escenes=["bunny"], sppgrid=[1, 2, 4, 8, 16],
                  bkib=[4, 64, 1024, 16384], bways=[1, 8], t1scenes=TABLE1_SCENES),
    "full": dict(size=1024, spp=8, bsize=512, bspp=8, bscenes=["bunny"], esize=512,
                 espp=[1, 2, 4, 8, 16], eref=256, escenes=ERRTIME_SCENES,
                 sppgrid=[1, 2, 4, 8, 16], bkib=BOUNDED_KIB, bways=BOUNDED_WAYS,
                 t1scenes=TABLE1_SCENES, pscenes=[PAPERSCALE_SCENE]),
    # every grid at toy sizes: checks the pipeline end to end in a few minutes (dragon loads)
    "smoke": dict(size=64, spp=1, bsize=64, bspp=1, bscenes=["bunny"], esize=64,
                  espp=[1, 2], eref=8, escenes=["bunny"], sppgrid=[1, 2], bkib=[4, 1024],
                  bways=[1, 8], t1scenes=["teapot", "cornell"]),
    "test": dict(size=32, spp=1),
}


def pow2_floor(x):
    p = 1
    while p * 2 <= x:
        p *= 2
    return p


class Jobs:
    def __init__(self, args):
        self.args = args
        self.rows = []
        self.ids = set()

    def add(self, grid, scene, size, spp, flags, seed=0, estimator=None, **meta):
        parts = [grid, scene, f"{size}", f"s{spp}", f"seed{seed}"] + [
            f"{k}{v}" for k, v in sorted(meta.items())]
        jid = "-".join(str(p).replace("_", "").replace(" ", "").replace(":", "").replace("/", "")
                       for p in parts)
        if jid in self.ids:
            return
        self.ids.add(jid)
        out = os.path.join(self.args.runs, jid)
        os.makedirs(self.args.runs, exist_ok=True)  # the job's HRPP settings file goes there
        cmd = [self.args.hrpp, "render", scene_arg(scene), "--size", f"{size}x{size}", "--spp", str(spp),
               "--seed", str(seed), "--out", out + ".exr", "--stats", out + ".json"] + \
            (ESTIMATOR if estimator is None else estimator) + settings_args(flags, out + ".hrpp.json")
        line = " ".join(shlex.quote(c) for c in cmd) + " > " + shlex.quote(out + ".log") + " 2>&1"
        row = dict(id=jid, grid=grid, scene=scene, size=size, spp=spp, seed=seed,
                   flags=flags_text(flags), cmd=" ".join(shlex.quote(c) for c in cmd), **meta)
        self.rows.append((line, row))


def hrpp_flags(mode="speculative", preset="unbounded", count=True, bits=6, goup=0, hash_="hrpp",
               sets=None, ways=None, nodes=None, policy=None):
    """Every class predicting every ray with one key and table: the paper's setup (the root
    fallback), as --hrpp on and an --hrpp-config file."""
    every = {"hash": hash_, "hash_bits": bits, "go_up": goup, "table_preset": preset}
    if sets is not None:
        every.update(table_sets=sets, table_ways=ways, table_nodes=nodes, table_policy=policy)
    top = {"adaptive": False, "fallback": "root", "count_baseline": count}
    return ["--hrpp", "on", "--hrpp-rays", "camera,bounce,shadow", "--hrpp-mode", mode,
            hrpp_settings(every, top)]


OFF = ["--hrpp", "off"]


def grid_table1(J, m):
    for sc in m["t1scenes"]:
        s, n = m["size"], m["spp"]
        J.add("table1", sc, s, n, hrpp_flags(), variant="count")
        J.add("table1", sc, s, n, OFF, variant="off")
        J.add("table1", sc, s, n, hrpp_flags(count=False), variant="spec")
        J.add("table1", sc, s, n, hrpp_flags(mode="exact", count=False), variant="exact")


def grid_paperscale(J, m):
    for sc in m.get("pscenes", []):
        s, n = m["size"], m["spp"]
        J.add("paperscale", sc, s, n, hrpp_flags(), variant="count")
        J.add("paperscale", sc, s, n, hrpp_flags(preset="tuned"), variant="count-tuned")
        J.add("paperscale", sc, s, n, OFF, variant="off")
        J.add("paperscale", sc, s, n, hrpp_flags(count=False), variant="spec")
        J.add("paperscale", sc, s, n, hrpp_flags(mode="exact", count=False), variant="exact")


def grid_precision(J, m):
    J.add("precision", "dragon", m["size"], m["spp"], OFF, variant="off")
    for b in range(1, 9):
        J.add("precision", "dragon", m["size"], m["spp"], hrpp_flags(bits=b), bits=b)


def grid_goup(J, m):
    for g in range(0, 5):
        J.add("goup", "dragon", m["size"], m["spp"], hrpp_flags(goup=g), goup=g)


def grid_spp(J, m):
    for n in m["sppgrid"]:
        J.add("spp", "dragon", m["size"], n, hrpp_flags(), variant="count")
        J.add("spp", "dragon", m["size"], n, OFF, variant="off")


def bounded_flags(kib, ways, policy, hash_="hrpp"):
    entry = 12 + 4 * BOUNDED_NODES
    sets = pow2_floor(max(1, kib * 1024 // (entry * ways)))
    return hrpp_flags(hash_=hash_, preset="small", sets=sets, ways=ways, nodes=BOUNDED_NODES,
                      policy=policy)


def grid_bounded(J, m):
    for sc in m["bscenes"]:
        s, n = m["bsize"], m["bspp"]
        J.add("bounded", sc, s, n, OFF, variant="off")
        for h in HASHES:
            J.add("bounded", sc, s, n, hrpp_flags(hash_=h), hash=h, kib="unbounded",
                  policy="none", ways=16)
        for kib in m["bkib"]:
            for ways in m["bways"]:
                for pol in BOUNDED_POLICIES:
                    J.add("bounded", sc, s, n, bounded_flags(kib, ways, pol), hash="hrpp",
                          kib=kib, policy=pol, ways=ways)
            for h in HASHES[1:]:
                J.add("bounded", sc, s, n, bounded_flags(kib, 8, "lru", h), hash=h, kib=kib,
                      policy="lru", ways=8)


def grid_errtime(J, m):
    for sc in m["escenes"]:
        s = m["esize"]
        # The reference: HRPP off, many spp, another seed (independent of the compared images).
        est = DEFAULT_ESTIMATOR
        J.add("errtime", sc, s, m["eref"], OFF, seed=1, estimator=est, variant="reference")
        for n in m["espp"]:
            J.add("errtime", sc, s, n, OFF, estimator=est, variant="off")
            J.add("errtime", sc, s, n, hrpp_flags(count=False, preset="small"), estimator=est,
                  variant="spec-small")
            J.add("errtime", sc, s, n, hrpp_flags(mode="exact", count=False, preset="small"),
                  estimator=est, variant="exact-small")
            J.add("errtime", sc, s, n, hrpp_flags(count=False, preset="unbounded"),
                  estimator=est, variant="spec-unbounded")
            # What --hrpp on gives with no other flag: the tuned table, the adaptive predictor.
            J.add("errtime", sc, s, n, ["--hrpp", "on"], estimator=est, variant="default")


def grid_test(J, m):
    # Three configurations on the Cornell box (plus the HRPP-off image they are compared with).
    J.add("test", "builtin:cornell", m["size"], m["spp"], OFF, variant="off")
    J.add("test", "builtin:cornell", m["size"], m["spp"], hrpp_flags(preset="small"),
          variant="count")
    J.add("test", "builtin:cornell", m["size"], m["spp"],
          hrpp_flags(mode="exact", count=False, preset="tiny"), variant="exact")
    # The default: a table per class of its own size (as errtime's default runs).
    J.add("test", "builtin:cornell", m["size"], m["spp"], ["--hrpp", "on"], variant="default")


GRIDS = dict(table1=grid_table1, paperscale=grid_paperscale, precision=grid_precision,
             goup=grid_goup, spp=grid_spp, bounded=grid_bounded, errtime=grid_errtime,
             test=grid_test)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mode", choices=MODES, required=True)
    ap.add_argument("--grids", default="", help="comma-separated subset (default: all of the mode)")
    ap.add_argument("--hrpp", required=True, help="the hrpp binary (absolute path)")
    ap.add_argument("--repo", required=True, help="repository root (scenes/ under it)")
    ap.add_argument("--runs", required=True, help="directory for each run's .json/.exr/.log")
    ap.add_argument("--out", required=True, help="directory for jobs.txt and jobs.jsonl")
    a = ap.parse_args()
    m = MODES[a.mode]
    grids = [g for g in a.grids.split(",") if g] or (
        ["test"] if a.mode == "test" else [g for g in GRIDS if g != "test"])
    J = Jobs(a)
    for g in grids:
        if g not in GRIDS:
            sys.exit(f"study sweep-jobs: unknown grid '{g}' (known: {', '.join(GRIDS)})")
        GRIDS[g](J, m)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "jobs.txt"), "w") as f:
        for line, _ in J.rows:
            f.write(line + "\n")
    with open(os.path.join(a.out, "jobs.jsonl"), "w") as f:
        for _, row in J.rows:
            f.write(json.dumps(row) + "\n")
    print(f"study sweep-jobs: {len(J.rows)} jobs ({a.mode}: {', '.join(grids)})")


if __name__ == "__main__":
    main()

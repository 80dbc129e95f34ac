"""Keys per ray class: the HRPP study of keys for each ray class (results/KEYS.md).

Renders each stand-in once with HRPP off and once per key, predicting one class at a time
(--hrpp-adaptive off --hrpp-count, same seed), then at the study's setup (larger, both classes
predicted in one render, the default keys on two tables), and prints markdown tables (with
--results, as the block key_study:MODE of that file; study/sweep.sh runs it as its `keys`
grid):
  shadow: the occluded share of shadow rays, the share of the occluded ones that prediction
          answered (true positives / occluded), interior-node savings net of verification, and
          the goal (a quarter of the occluded share);
  bounce: savings net of verification, true positives and wrong closest hits per probe, and the
          image's relMSE against HRPP off (eps 0.01, as study/sweep_collect.py);
  study's setup: the same per scene for the default keys on the tuned and the beam table;
  the distance gate: bounce rays on a fine key at the study's setup, per gate (--hrpp-gate),
          on the Vulkan device or (--backend cpu, that table alone) the CPU renderer.

  python3 -m study keys [--mode full|quick|smoke|test] [--hrpp build/ci/host/hrpp] [--size WxH]
                     [--spp N] [--scenes a,b] [--classes shadow,bounce] [--runs DIR] [--reuse]
                     [--results MD] [--command TEXT] [--backend gpu|cpu]
"""
import argparse
import json
import os
import sys
import time

import numpy as np

import common
from common import REPO, image_errors, read_exr, repo_commit, rewrite_block, table

SCENES = ["teapot", "bunny", "lamborghini", "dragon"]
# Each key tried: the studied class's keys in an --hrpp-config file (host/app/hrpp_config_file.h);
# "fallback" goes to the file's top level, "mode" to --hrpp-mode.
N4 = {"table_preset": "beam"}  # 4096 x 2 x 4 lru: 224 KiB
# The distance gate's key: a finer origin grid, coarser direction bins, four times the tuned
# table's sets (65536 x 2 x 1 lru: 2 MiB, 2.5 MiB with the gate).
FINE = {"hash_bits": 7, "hash_dir_bits": 3, "table_sets": 65536}
# The distance gates of the gate table (python3 -m study keys --backend), 0: none.
GATES = [0, 1.1, 1.4, 2]
SHADOW = {
    "hrpp N=6 (paper)": {"hash": "hrpp", "hash_bits": 6},
    "grid-spherical N=3 go-up 4": {"hash": "grid-spherical", "hash_bits": 3, "go_up": 4},
    "light N=6 size 0.02": {"hash": "light", "hash_bits": 6, "go_up_size": 0.02},
    "light-depth N=6 size 0.02": {"hash": "light-depth", "hash_bits": 6, "go_up_size": 0.02},
    "light-depth N=6 size 0.02, beam, fallback root": {"hash": "light-depth", "hash_bits": 6,
                                                       "go_up_size": 0.02, "fallback": "root",
                                                       **N4},
    "light-depth N=6 size 0.02, beam (default)": {"hash": "light-depth", "hash_bits": 6,
                                                  "go_up_size": 0.02, **N4},
}
BOUNCE = {
    "hrpp N=6 (paper)": {"hash": "hrpp", "hash_bits": 6},
    "grid-spherical N=3": {"hash": "grid-spherical", "hash_bits": 3},
    "grid-spherical N=4": {"hash": "grid-spherical", "hash_bits": 4},
    "grid-spherical N=4 go-up 2": {"hash": "grid-spherical", "hash_bits": 4, "go_up": 2},
    "grid-spherical N=5": {"hash": "grid-spherical", "hash_bits": 5},
    "grid-spherical N=5 go-up 1": {"hash": "grid-spherical", "hash_bits": 5, "go_up": 1},
    "grid-spherical N=5, beam": {"hash": "grid-spherical", "hash_bits": 5, **N4},
    "grid-spherical N=6 (default)": {"hash": "grid-spherical", "hash_bits": 6},
    "two-point N=4 go-up 2": {"hash": "two-point", "hash_bits": 4, "go_up": 2},
    "two-point N=5 go-up 2": {"hash": "two-point", "hash_bits": 5, "go_up": 2},
    "grid-spherical N=4 exact": {"hash": "grid-spherical", "hash_bits": 4, "mode": "exact"},
    "grid-spherical N=7 D=3, 65536 sets": {"hash": "grid-spherical", **FINE},
    "grid-spherical N=7 D=3, 65536 sets, gate 1.4": {"hash": "grid-spherical", **FINE,
                                                      "gate": 1.4},
}
# Every ray of the named classes predicted, the full traversals counted (savings).
PREDICT_ALL = {"adaptive": False, "count_baseline": True}


def key_flags(cls, key):
    """The flags of a render predicting class `cls` alone with `key` (on the tuned table unless
    it names one)."""
    k = {"table_preset": "tuned", **key}
    top = {**PREDICT_ALL, **({"fallback": k.pop("fallback")} if "fallback" in k else {})}
    mode = ["--hrpp-mode", k.pop("mode")] if "mode" in k else []
    return ["--hrpp", "on", "--hrpp-rays", cls] + mode + [common.hrpp_settings(None, top,
                                                                                    **{cls: k})]


# The study's setup: both classes predicted in one render with the default keys, on
# the tuned table and on the beam table with bounce rays at N = 5.
STUDY_KEYS = {"bounce": {"hash": "grid-spherical"}, "shadow": {"hash": "light-depth",
                                                                "go_up_size": 0.02}}
STUDY_TABLES = {"tuned": {"bounce": {"hash_bits": 6}, "every": {"table_preset": "tuned"}},
                "beam": {"bounce": {"hash_bits": 5}, "every": {"table_preset": "beam"}}}


def study_flags(preset):
    """The flags of the study's setup on the table `preset`."""
    t = STUDY_TABLES[preset]
    keys = {c: {**t["every"], "hash_bits": 6, **STUDY_KEYS[c], **t.get(c, {})}
            for c in ("bounce", "shadow")}
    return ["--hrpp", "on", "--hrpp-rays", "bounce,shadow",
            common.hrpp_settings(None, PREDICT_ALL, **keys)]


STUDY = {p: study_flags(p) for p in STUDY_TABLES}
# The modes of study/sweep.sh: size, spp, scenes and the keys tried (None: every key) of the
# exploration tables, and size and spp of the study's setup.
MODES = {
    "full": dict(size="256x256", spp=4, scenes=SCENES, keys=None, study=("1024x1024", 8)),
    "quick": dict(size="64x64", spp=2, scenes=SCENES, keys=None, study=("256x256", 2)),
    "smoke": dict(size="32x32", spp=1, scenes=["teapot", "dragon"], keys=None,
                  study=("32x32", 1)),
    "test": dict(size="32x32", spp=1, scenes=["teapot"],
                 keys=["hrpp N=6 (paper)", "light-depth N=6 size 0.02, beam (default)",
                       "grid-spherical N=6 (default)"], study=("32x32", 1)),
}
HEADS = {"shadow": ["scene", "shadow key (tuned table unless named)", "occluded",
                    "answered (of occluded)", "net savings", "goal (occluded / 4)"],
         "bounce": ["scene", "bounce key (tuned table unless named)", "net savings",
                    "true positives / probe", "wrong closest / probe", "relMSE vs off"]}


def slug(name):
    return "".join(c if c.isalnum() else "_" for c in name)


def render(a, scene, name, flags, size=None):
    """The stats of one render (reused from --runs when --reuse and present); its image path.
    `size`: (WxH, spp) in place of --size and --spp."""
    size, spp = size or (a.size, a.spp)
    out = os.path.join(a.runs, f"{scene}-{size}-{spp}-{slug(name)}")
    present = os.path.exists(out + ".json") and os.path.exists(out + ".exr")
    reuse = a.reuse or out in a.made  # each render once per invocation
    if not (present and reuse):
        a.made.add(out)
    elif out not in a.made:
        a.reused.add(out)
    return common.render(a.hrpp, scene, out, size, spp, 5, flags, "study keys", reuse)


def pct(x):
    return f"{100 * x:.1f}%"


def shadow_shares(j):
    """Of a render's stats: the occluded share of its shadow rays and the share of the occluded
    ones that prediction answered (true positives / occluded)."""
    hits = j["shadow"]["hits"]
    return hits / max(j["shadow"]["rays"], 1), \
        j["hrpp_predictor"]["shadow"]["true_positives"] / max(hits, 1)


def study(a):
    """{class: rows of its table}, the keys of the mode predicting one class at a time."""
    # The tuned table unless a row names one (the shadow class's default is the beam table).
    rows = {cls: [] for cls in a.classes}
    for scene in a.scenes:
        _, off_exr = render(a, scene, "off", [])
        off_image = read_exr(off_exr)
        for cls in a.classes:
            for name, flags in (SHADOW if cls == "shadow" else BOUNCE).items():
                if a.keys is not None and name not in a.keys:
                    continue
                j, exr = render(a, scene, f"{cls}-{name}", key_flags(cls, flags))
                s = j["hrpp_predictor"][cls]
                if cls == "shadow":
                    occ, answered = shadow_shares(j)
                    rows[cls].append([scene, name, pct(occ), pct(answered),
                                      pct(s["net_savings"]), pct(occ / 4)])
                else:
                    probes = max(s["probes"], 1)
                    relmse = image_errors(read_exr(exr), off_image)[1]
                    rows[cls].append([scene, name, pct(s["net_savings"]),
                                      pct(s["true_positives"] / probes),
                                      f"{100 * s['wrong_closest'] / probes:.2f}%",
                                      f"{relmse:.2e}"])
                print(" | ".join(rows[cls][-1]), file=sys.stderr, flush=True)
    return rows


def study_setup(a):
    """One row per scene at the study's setup: the shadow class's occluded share, answered share
    and net savings on the tuned and the beam table, and the bounce class's on each."""
    rows = []
    for scene in a.scenes:
        _, off_exr = render(a, scene, "off", [], a.study)
        off_image = read_exr(off_exr)
        row = [scene]
        shadow, bounce = {}, {}
        for preset, flags in STUDY.items():
            j, exr = render(a, scene, f"study-{preset}", flags, a.study)
            b = j["hrpp_predictor"]["bounce"]
            shadow[preset] = (*shadow_shares(j), j["hrpp_predictor"]["shadow"]["net_savings"])
            bounce[preset] = (f"{pct(b['net_savings'])}, "
                              f"{100 * b['wrong_closest'] / max(b['probes'], 1):.2f}%, "
                              f"{image_errors(read_exr(exr), off_image)[1]:.2e}")
        occluded = shadow["tuned"][0]
        row += [pct(occluded), pct(shadow["tuned"][1]), pct(shadow["beam"][1]),
                pct(shadow["tuned"][2]), pct(shadow["beam"][2]), pct(occluded / 4),
                bounce["tuned"], bounce["beam"]]
        rows.append(row)
        print(" | ".join(row), file=sys.stderr, flush=True)
    return rows


STUDY_HEAD = ["scene", "occluded shadow rays", "answered, tuned table",
              "answered, beam table (default)", "net savings, tuned", "net savings, beam",
              "goal (occluded / 4)", "bounce grid-spherical N=6, tuned (default): net savings, "
              "wrong / probe, relMSE", "bounce grid-spherical N=5, beam table: net savings, "
              "wrong / probe, relMSE"]


def gate_study(a):
    """One row per scene at the study's setup, bounce rays alone on FINE: per distance gate the
    net savings, wrong closest hits per probe and relMSE against HRPP off."""
    rows = []
    on = {"hash": "grid-spherical", "table_preset": "tuned", **FINE}
    cpu = a.backend == "cpu"
    flags = ["--backend", "cpu"] if cpu else []
    prefix = "cpu-" if cpu else ""  # the device's renders of the same names share --runs
    for scene in a.scenes:
        _, off_exr = render(a, scene, prefix + "off", flags, a.study)
        off_image = read_exr(off_exr)
        row = [scene]
        for gate in GATES:
            j, exr = render(a, scene, f"{prefix}gate-{gate}",
                            flags + key_flags("bounce", {**on, "gate": gate}), a.study)
            b = j["hrpp_predictor"]["bounce"]
            a.device = common.device_name(j)
            relmse = image_errors(read_exr(exr), off_image)[1]
            row.append(f"{pct(b['net_savings'])}, "
                       f"{100 * b['wrong_closest'] / max(b['probes'], 1):.2f}%, {relmse:.2e}")
        rows.append(row)
        print(" | ".join(row), file=sys.stderr, flush=True)
    return rows


def gate_lines(a, rows):
    size, spp = a.study
    where = ("the CPU renderer, HRPP inline" if a.backend == "cpu"
             else "the Vulkan device's HRPP stage")
    head = ["scene"] + [f"gate {g}: net savings, wrong / probe, relMSE" if g else
                        "no gate: net savings, wrong / probe, relMSE" for g in GATES]
    return ["", f"The distance gate, {size}, {spp} spp, seed 5, on {where}: bounce rays alone on "
            "grid-spherical N = 7 with D = 3 direction bits and 65536 sets (`--hrpp-config` keys "
            "`" + json.dumps({"bounce": {**FINE, "gate": "G"}}) + "`):", "", table(head, rows)]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    keys = lambda v: "" if v["keys"] is None else f", {len(v['keys'])} keys"
    p.add_argument("--mode", choices=MODES, default="full",
                   help="; ".join(f"{k}: {v['size']}, {v['spp']} spp, {', '.join(v['scenes'])}"
                                  f"{keys(v)}" for k, v in MODES.items()))
    p.add_argument("--hrpp", default=os.path.join(REPO, "build/ci/host/hrpp"))
    p.add_argument("--size", help="WxH (default: the mode's)")
    p.add_argument("--spp", type=int, help="samples per pixel (default: the mode's)")
    p.add_argument("--classes", default="shadow,bounce")
    p.add_argument("--scenes", help="comma-separated stand-ins (default: the mode's)")
    p.add_argument("--runs", help="render directory (default build/key-study/MODE)")
    p.add_argument("--reuse", action="store_true", help="reuse the renders --runs holds")
    p.add_argument("--results", help="rewrite this Markdown file's block key_study:MODE")
    p.add_argument("--command", help="the command named in the block (default: this one)")
    p.add_argument("--backend", choices=["gpu", "cpu"], default="gpu",
                   help="cpu: only the distance gate's table, on the CPU renderer (block "
                        "key_study:MODE-cpu)")
    a = p.parse_args()
    m = MODES[a.mode]
    a.size, a.spp = a.size or m["size"], a.spp or m["spp"]
    a.scenes = a.scenes.split(",") if a.scenes else m["scenes"]
    a.classes = [c for c in a.classes.split(",") if c]
    a.keys = m["keys"]
    a.study = m["study"]
    a.runs = a.runs or os.path.join(REPO, "build", "key-study", a.mode)
    a.command = a.command or " ".join(["python3 -m study keys"] + sys.argv[1:])
    a.made, a.reused, a.device = set(), set(), "?"
    os.makedirs(a.runs, exist_ok=True)
    start = time.time()
    cpu = a.backend == "cpu"
    rows = {} if cpu else study(a)
    setup = [] if cpu else study_setup(a)
    gates = gate_study(a)
    elapsed = int(time.time() - start)
    size, spp = a.study if cpu else (a.size, a.spp)
    lines = [f"Made by `{a.command}` ({size}, {spp} spp, seed 5; {len(a.made)} renders"
             f"{f' and {len(a.reused)} reused' if a.reused else ''}, "
             f"this command {elapsed // 60} min {elapsed % 60} s; repository at "
             f"{repo_commit(REPO)}; {common.machine_line(a.device)}):"]
    if cpu:
        print("\n".join(lines + gate_lines(a, gates)))
        if a.results:
            rewrite_block(a.results, f"key_study:{a.mode}-cpu", lines + gate_lines(a, gates),
                          "python3 -m study keys")
        return
    for cls in a.classes:
        lines += ["", f"{cls} rays, {a.size}, {a.spp} spp, seed 5:", "",
                  table(HEADS[cls], rows[cls])]
    size, spp = a.study
    lines += ["", f"The study's setup, {size}, {spp} spp, seed 5: both classes predicted in one "
              "render, the default keys on the tuned table and on the beam table with bounce "
              "rays at N = 6 and N = 5 (`" + common.flags_text(STUDY["tuned"]) + "` or `"
              + common.flags_text(STUDY["beam"]) + "`):", "",
              table(STUDY_HEAD, setup)] + gate_lines(a, gates)
    print("\n".join(lines))
    if a.results:
        rewrite_block(a.results, f"key_study:{a.mode}", lines, "python3 -m study keys")


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()

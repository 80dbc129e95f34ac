#!/usr/bin/python3
"""Keys per ray class: the HRPP study of issue 27 (RESULTS.md, "Keys per ray class").

Renders each stand-in once with HRPP off and once per key, predicting one class at a time
(--hrpp-adaptive off --hrpp-count, same seed), and prints markdown tables:
  shadow: the occluded share of shadow rays, the share of the occluded ones that prediction
          answered (true positives / occluded), interior-node savings net of verification, and
          the goal (a quarter of the occluded share);
  bounce: savings net of verification, true positives and wrong closest hits per probe, and the
          image's relMSE against HRPP off (eps 0.01, as tools/sweep_collect.py).

  tools/key_study.py [--hrpp build/ci/host/hrpp] [--size 256x256] [--spp 4] [--classes shadow,bounce]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep_collect import errors, read_exr  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ["teapot", "bunny", "lamborghini", "dragon"]
N4 = ["--table-preset", "beam"]  # 4096 x 2 x 4 lru: 224 KiB
SHADOW = {
    "hrpp N=6 (paper)": ["--hash", "hrpp", "--hash-bits", "6"],
    "grid-spherical N=3 go-up 4": ["--hash", "grid-spherical", "--hash-bits", "3", "--go-up", "4"],
    "light N=6 size 0.02": ["--hash", "shadow=light", "--hash-bits", "6", "--go-up-size", "0.02"],
    "light-depth N=6 size 0.02": ["--hash", "shadow=light-depth", "--hash-bits", "6",
                                  "--go-up-size", "0.02"],
    "light-depth N=6 size 0.02, beam (default)": ["--hash", "shadow=light-depth", "--hash-bits",
                                                  "6", "--go-up-size", "0.02"] + N4,
}
BOUNCE = {
    "hrpp N=6 (paper)": ["--hash", "hrpp", "--hash-bits", "6"],
    "grid-spherical N=3": ["--hash", "grid-spherical", "--hash-bits", "3"],
    "grid-spherical N=4": ["--hash", "grid-spherical", "--hash-bits", "4"],
    "grid-spherical N=4 go-up 2": ["--hash", "grid-spherical", "--hash-bits", "4", "--go-up", "2"],
    "grid-spherical N=5": ["--hash", "grid-spherical", "--hash-bits", "5"],
    "grid-spherical N=5 go-up 1": ["--hash", "grid-spherical", "--hash-bits", "5", "--go-up", "1"],
    "grid-spherical N=5, beam": ["--hash", "grid-spherical", "--hash-bits", "5"] + N4,
    "grid-spherical N=6 (default)": ["--hash", "grid-spherical", "--hash-bits", "6"],
    "two-point N=4 go-up 2": ["--hash", "two-point", "--hash-bits", "4", "--go-up", "2"],
    "two-point N=5 go-up 2": ["--hash", "two-point", "--hash-bits", "5", "--go-up", "2"],
    "grid-spherical N=4 exact": ["--hash", "grid-spherical", "--hash-bits", "4",
                                 "--hrpp-mode", "exact"],
}


def render(a, scene, out, flags):
    cmd = [a.hrpp, "render", os.path.join(REPO, "scenes", scene + ".scene.json"), "--size", a.size,
           "--spp", str(a.spp), "--seed", "5", "--out", out + ".exr", "--stats", out + ".json"]
    subprocess.run(cmd + flags, check=True, stdout=subprocess.DEVNULL)
    with open(out + ".json") as f:
        return json.load(f)


def pct(x):
    return f"{100 * x:.1f}%"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--hrpp", default=os.path.join(REPO, "build/ci/host/hrpp"))
    p.add_argument("--size", default="256x256")
    p.add_argument("--spp", type=int, default=4)
    p.add_argument("--classes", default="shadow,bounce")
    p.add_argument("--scenes", default=",".join(SCENES))
    a = p.parse_args()
    # The tuned table unless a row names one (the shadow class's default is the beam table).
    on = ["--hrpp", "on", "--hrpp-adaptive", "off", "--hrpp-count"]
    rows = {"shadow": [], "bounce": []}
    with tempfile.TemporaryDirectory() as tmp:
        for scene in a.scenes.split(","):
            off = os.path.join(tmp, scene + "-off")
            render(a, scene, off, [])
            off_image = read_exr(off + ".exr")
            for cls in a.classes.split(","):
                for name, flags in (SHADOW if cls == "shadow" else BOUNCE).items():
                    out = os.path.join(tmp, scene + "-" + cls)
                    table = [] if "--table-preset" in flags else ["--table-preset", "tuned"]
                    j = render(a, scene, out, on + ["--hrpp-rays", cls] + table + flags)
                    s = j["hrpp_predictor"][cls]
                    if cls == "shadow":
                        occ = j["shadow"]["hits"] / j["shadow"]["rays"]
                        answered = s["true_positives"] / max(j["shadow"]["hits"], 1)
                        rows[cls].append([scene, name, pct(occ), pct(answered),
                                          pct(s["net_savings"]), pct(occ / 4)])
                    else:
                        probes = max(s["probes"], 1)
                        relmse = errors(read_exr(out + ".exr"), off_image)[1]
                        rows[cls].append([scene, name, pct(s["net_savings"]),
                                          pct(s["true_positives"] / probes),
                                          f"{100 * s['wrong_closest'] / probes:.2f}%",
                                          f"{relmse:.1e}"])
                    print(" | ".join(rows[cls][-1]), file=sys.stderr, flush=True)
    heads = {"shadow": ["scene", "shadow key (tuned table unless named)", "occluded",
                        "answered (of occluded)", "net savings", "goal (occluded / 4)"],
             "bounce": ["scene", "bounce key (tuned table unless named)", "net savings",
                        "true positives / probe", "wrong closest / probe", "relMSE vs off"]}
    for cls in a.classes.split(","):
        print(f"\n{cls} rays, {a.size}, {a.spp} spp, seed 5:\n")
        print("| " + " | ".join(heads[cls]) + " |")
        print("|" + "---|" * len(heads[cls]))
        for r in rows[cls]:
            print("| " + " | ".join(r) + " |")


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()

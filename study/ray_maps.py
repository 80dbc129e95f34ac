"""Pictures of where prediction works: `hrpp render --backend cpu --ray-stats` per scene (HRPP
inline in the CPU renderer, every ray probing: adaptive off, full traversals counted), and one
figure per scene of its EXR's layers (host/render/ray_stat_layers.h): per ray class (rows:
camera, bounce, shadow), the rays a sample (camera: the render itself), the share of probes
that found an entry (predicted) and whose nodes held the answer (verified), the interior-node
visits a ray saved net of verification (skipped) and those it made (interior, the traversal
cost). Writes results/figures/ray_maps_SCENE.png and the block ray_maps:MODE of --results
(default results/RAY_MAPS.md): the figures and each class's image means per scene."""
import argparse
import os
import shlex
import sys
import tempfile

import numpy as np

import common
from common import (DEFAULT_BIN, REPO, RAY_CLASSES, hrpp_settings, need_binary, repo_commit,
                    rewrite_block, table)

WHO = "study ray-maps"
SCENES = ("bunny", "teapot", "dragon", "killeroo-simple")  # the stand-ins and the paper's scene
MODES = {"full": {"size": "256x192", "spp": 4}, "test": {"size": "16x12", "spp": 1}}
# Every ray probes and its full traversal is counted (the skipped layer); hrpp's default keys.
SETTINGS = hrpp_settings(top={"adaptive": False, "count_baseline": True})
COLUMNS = (("predicted", "viridis"), ("verified", "viridis"), ("skipped", "RdBu"),
           ("interior", "magma"))


def draw(scene, layers, out, written):
    plt = common.pyplot()
    fig, axes = plt.subplots(len(RAY_CLASSES), 1 + len(COLUMNS), figsize=(15, 7.5))
    rgb = np.stack([layers[c] for c in "RGB"], axis=-1)
    rgb = np.clip(rgb, 0, 1)
    srgb = np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * np.power(rgb, 1 / 2.4) - 0.055)
    for row, cls in enumerate(RAY_CLASSES):
        first = axes[row][0]
        if cls == "camera":
            first.imshow(srgb)
            first.set_title(f"{scene}: the render")
        else:
            im = first.imshow(layers[f"{cls}.rays"], cmap="gray")
            first.set_title(f"{cls}: rays a sample")
            fig.colorbar(im, ax=first, fraction=0.046)
        for col, (stat, cmap) in enumerate(COLUMNS, start=1):
            ax, v = axes[row][col], layers[f"{cls}.{stat}"]
            if stat in ("predicted", "verified"):
                im = ax.imshow(v, cmap=cmap, vmin=0, vmax=1)
            elif stat == "skipped":
                lim = max(float(np.percentile(np.abs(v), 99)), 1e-6)
                im = ax.imshow(v, cmap=cmap, vmin=-lim, vmax=lim)
            else:
                im = ax.imshow(v, cmap=cmap, vmin=0)
            ax.set_title(f"{cls} {stat}")
            fig.colorbar(im, ax=ax, fraction=0.046)
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
    common.save_figure(fig, out, f"ray_maps_{scene}.png", written)


def means(layers):
    """Each class's image means: verified share and skipped, interior visits a ray."""
    return {cls: {s: float(np.mean(layers[f"{cls}.{s}"])) for s in ("verified", "skipped", "interior")}
            for cls in RAY_CLASSES}


def block_lines(args, mode, results, figures, device):
    """The generated block: provenance, a table of each scene's class means, the figures."""
    command = "python3 -m study ray-maps " + " ".join(shlex.quote(a) for a in sys.argv[1:])
    lines = [f"`{command.strip()}` at commit {repo_commit(REPO)}; {common.machine_line(device)}. "
             f"{mode['size']}, {mode['spp']} spp, seed 7; HRPP's default keys, every ray "
             "probing (adaptive off), full traversals counted. Image means over the pixels:", ""]
    body = [[scene, cls, f"{m['verified']:.1%}", f"{m['skipped']:.2f}", f"{m['interior']:.1f}"]
            for scene, per_class in results for cls, m in per_class.items()]
    lines.append(table(["scene", "rays", "verified", "interior visits skipped a ray, net",
                        "interior visits a ray"], body))
    here = os.path.dirname(os.path.abspath(args.results))
    lines.append("")
    lines += [f"![{scene}]({os.path.relpath(os.path.abspath(f), here)})"
              for (scene, _), f in zip(results, figures)]
    return lines


def main():
    ap = argparse.ArgumentParser(prog=WHO, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hrpp", default=DEFAULT_BIN, help="the hrpp binary")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated scene names")
    ap.add_argument("--mode", choices=MODES, default="full",
                    help="full: 256x192, 4 spp; test: 16x12, 1 spp")
    ap.add_argument("--out", default=os.path.join(REPO, "results", "figures"),
                    help="where the figures go")
    ap.add_argument("--results", default=os.path.join(REPO, "results", "RAY_MAPS.md"),
                    help="the Markdown file of the generated block")
    args = ap.parse_args()
    need_binary(args.hrpp, WHO)
    os.makedirs(args.out, exist_ok=True)
    mode, written, results, device = MODES[args.mode], [], [], "?"
    with tempfile.TemporaryDirectory(prefix="hrpp_ray_maps_") as tmp:
        for scene in args.scenes.split(","):
            print(f"{WHO}: rendering {scene}", file=sys.stderr, flush=True)
            stats, exr = common.render(args.hrpp, scene, os.path.join(tmp, scene), mode["size"],
                                       mode["spp"], 7, ["--backend", "cpu", "--ray-stats", SETTINGS],
                                       who=WHO)
            device = common.device_name(stats)
            layers = common.read_exr_channels(exr)
            draw(scene, layers, args.out, written)
            results.append((scene, means(layers)))
            for cls, m in results[-1][1].items():
                print(f"{scene:16} {cls:7} verified {m['verified']:6.1%}  skipped "
                      f"{m['skipped']:7.2f}  interior {m['interior']:6.1f} a ray")
    rewrite_block(args.results, f"ray_maps:{args.mode}",
                  block_lines(args, mode, results, written, device), "python3 -m study ray-maps")
    for path in written + [args.results]:
        print(f"wrote {os.path.relpath(path)}")


if __name__ == "__main__":
    main()

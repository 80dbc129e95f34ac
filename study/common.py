"""The study's shared library (not a command): the stand-in scenes, the scene argument, running
an hrpp command, one `hrpp render` wrapper, HRPP's settings files, reading EXR images and the
image error metrics; the paper's numbers, each run's provenance, the sweep CSV's reader and the
generated blocks' tables and rewriting. Every command computes them the same way by importing
it (study/__main__.py puts study/ on sys.path)."""
import csv
import datetime
import glob
import json
import os
import platform
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, ".."))
DEFAULT_BIN = os.path.join(REPO, "build", "release", "host", "hrpp")
# The paper's Table 1 stand-ins (scenes/SCENES.md), smallest first.
STAND_INS = ["cornell", "teapot", "bunny", "bunny-complex", "lamborghini", "dragon"]
# The estimator scripts' scenes: the Cornell boxes, two stand-ins, two lights near surfaces.
ESTIMATOR_SCENES = "builtin:cornell,cornell,bunny,teapot,wall-lamp,floor-panel"
EPS = 1e-2  # relMSE's guard: (x - ref)^2 / (ref^2 + EPS)
RAY_CLASSES = ("camera", "bounce", "shadow")


def hrpp_settings(every=None, top=None, **per_class):
    """HRPP's settings as an --hrpp-config file holds them (host/app/hrpp_config_file.h; HRPP on):
    `top`'s keys at the top level (adaptive, fallback, batch, count_baseline, ...) and, under
    "keys", each ray class's keys from `every` and then from per_class[CLASS], e.g.
    hrpp_settings({"hash_bits": 4}, {"adaptive": False}, shadow={"go_up": 3})."""
    cfg = {"enabled": True, **(top or {})}
    keys = {c: {**(every or {}), **per_class.get(c, {})} for c in RAY_CLASSES}
    keys = {c: k for c, k in keys.items() if k}
    if keys:
        cfg["keys"] = keys
    return cfg


def settings_args(flags, path):
    """`flags` with their HRPP settings (the dicts among them: hrpp_settings, merged in order)
    written to the file `path` and given as --hrpp-config PATH; the strings kept in order."""
    settings = [f for f in flags if isinstance(f, dict)]
    args = [f for f in flags if not isinstance(f, dict)]
    if not settings:
        return args
    merged = {}
    for cfg in settings:
        keys = {**merged.get("keys", {})}
        for c, k in cfg.get("keys", {}).items():
            keys[c] = {**keys.get(c, {}), **k}
        merged = {**merged, **cfg, **({"keys": keys} if keys else {})}
    with open(path, "w") as f:
        json.dump(merged, f, indent=1, sort_keys=True)
    return args + ["--hrpp-config", path]


def flags_text(flags):
    """A flag list as one line, its settings as JSON (a table's or a log's record of a run)."""
    return " ".join(json.dumps(f, sort_keys=True) if isinstance(f, dict) else f for f in flags)


def cpu_model():
    """The CPU's model name (/proc/cpuinfo), for the headers of generated blocks."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "?"


def device_name(stats):
    """A render's device as its stats name it: "NAME (DRIVER)"."""
    d = stats.get("device", {})
    return f"{d.get('name', '?')} ({d.get('driver', '?')})"


def machine_line(device):
    """The device, CPU, date and load, for the headers of generated blocks."""
    return (f"{device}, {cpu_model()}, {datetime.date.today()}, "
            f"load {os.getloadavg()[0]:.1f}")


def need_binary(path, who, flag="--hrpp"):
    """Exits with one line naming `who`, the path and the flag that sets it unless `path` is an
    executable."""
    if not os.access(path, os.X_OK):
        sys.exit(f"{who}: no binary at {path} ({flag}; tools/build.sh builds it)")


def scene_arg(name):
    """builtin:cornell and file paths as they are; any other name: scenes/NAME.scene.json, or
    the pbrt scene of that name that tools/fetch-scenes.sh fetched (scenes/fetched/*/NAME.pbrt)."""
    if name.startswith("builtin:") or name.endswith((".glb", ".gltf", ".json", ".obj", ".ply",
                                                     ".pbrt")):
        return name
    manifest = os.path.join(REPO, "scenes", f"{name}.scene.json")
    if "/" in name or os.path.exists(manifest):
        return manifest if os.path.exists(manifest) else name
    fetched = sorted(glob.glob(os.path.join(REPO, "scenes", "fetched", "*", f"{name}.pbrt")))
    return fetched[0] if fetched else manifest


def run(cmd, who, echo=False):
    """Runs cmd (echoed to stderr when `echo`); exits naming `who` and the command when it fails."""
    if echo:
        print(f"  {' '.join(cmd)}", file=sys.stderr, flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{who}: {' '.join(cmd)} failed:\n{(r.stderr or r.stdout).strip()}")


def render(hrpp, scene, out, size, spp, seed, flags=(), who="hrpp", reuse=False, echo=False):
    """`hrpp render SCENE --size --spp --seed FLAGS` into OUT.exr and OUT.json (FLAGS' HRPP
    settings into OUT.hrpp.json: settings_args); returns the stats and the image's path. With `reuse`, a render already there is read instead."""
    exr, stats = out + ".exr", out + ".json"
    if not (reuse and os.path.exists(exr) and os.path.exists(stats)):
        run([hrpp, "render", scene_arg(scene), "--size", size, "--spp", str(spp), "--seed",
             str(seed), "--out", exr, "--stats", stats] + settings_args(flags, out + ".hrpp.json"),
            who, echo)
    with open(stats) as f:
        j = json.load(f)
    if j.get("session", {}).get("interrupted"):  # a stopped render's passes are not the job's
        sys.exit(f"{who}: {stats}: the render was interrupted; render it again")
    if j.get("session", {}).get("failed"):  # nor are a failed one's
        sys.exit(f"{who}: {stats}: the render failed ({j['session'].get('error')}); render it again")
    return j, exr


def read_exr(path):
    """An EXR's RGB as float64: OpenImageIO (Debian's python3-openimageio), else, for an
    uncompressed file (what hrpp writes when built without OpenImageIO), numpy alone."""
    import numpy as np
    try:
        import OpenImageIO as oiio
    except ImportError:
        return read_uncompressed_exr(path)
    channels = read_exr_channels(path, oiio)
    return np.stack([channels[c] for c in "RGB"], axis=-1)


def read_exr_channels(path, oiio=None):
    """An EXR's channels by name, each a height × width float64 array (OpenImageIO): R, G, B and
    the layers hrpp writes beside them (`hrpp render --ray-stats`)."""
    import numpy as np
    if oiio is None:
        import OpenImageIO as oiio
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise RuntimeError(f"cannot read {path}")
    names = list(inp.spec().channelnames)
    px = np.asarray(inp.read_image("float"), dtype=np.float64)
    inp.close()
    return {n: px[..., i] for i, n in enumerate(names)}


def read_uncompressed_exr(path):
    """R, G, B of a single-part scanline EXR without compression and with float channels."""
    import numpy as np
    data = open(path, "rb").read()
    if data[:4] != b"\x76\x2f\x31\x01":
        raise RuntimeError(f"{path}: not an OpenEXR file")
    pos, attrs = 8, {}
    while data[pos] != 0:  # attributes: name, type, size, value; an empty name ends them
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        size = int.from_bytes(data[type_end + 1:type_end + 5], "little")
        attrs[data[pos:name_end].decode()] = data[type_end + 5:type_end + 5 + size]
        pos = type_end + 5 + size
    if attrs.get("compression") != b"\0":
        raise RuntimeError(f"{path}: a compressed EXR needs python3-openimageio")
    x0, y0, x1, y1 = (int(v) for v in np.frombuffer(attrs["dataWindow"], "<i4"))
    width, height = x1 - x0 + 1, y1 - y0 + 1
    names, chlist = [], attrs["channels"]
    i = 0
    while chlist[i] != 0:  # name, pixel type, pLinear + 3 reserved, x and y sampling
        end = chlist.index(b"\0", i)
        if int.from_bytes(chlist[end + 1:end + 5], "little") != 2:
            raise RuntimeError(f"{path}: channel {chlist[i:end].decode()} is not 32-bit float")
        names.append(chlist[i:end].decode())
        i = end + 17
    img = np.empty((height, width, len(names)))
    for off in np.frombuffer(data, "<u8", height, pos + 1).tolist():  # a block per scanline
        y = int.from_bytes(data[off:off + 4], "little", signed=True) - y0
        line = np.frombuffer(data, "<f4", width * len(names), off + 8)
        img[y] = line.reshape(len(names), width).T  # each channel's whole line in turn
    return np.stack([img[..., names.index(c)] for c in "RGB"], axis=-1)


def image_errors(x, ref):
    """x against ref: RMSE, relMSE (guarded by EPS) and the share of pixels that differ at all."""
    import numpy as np
    d = x - ref
    rmse = float(np.sqrt(np.mean(d * d)))
    relmse = float(np.mean(d * d / (ref * ref + EPS)))
    differ = float(np.mean(np.any(d != 0, axis=-1)))
    return rmse, relmse, differ


# The paper's Table 1 (Demoullin, Gubran, Aamodt, EG 2019): 1024x1024, 8 spp, go-up 0,
# precision 6. Savings in %, table sizes in MB. "<1" is entered as 0.5. Our stand-in scenes:
PAPER_TABLE1 = {
    # ours: (paper scene, triangles, hit-any %, hit-any MB, hit-all %, hit-all MB)
    "teapot": ("Teapot", "2k", 4, 16, 69, 2),
    "bunny": ("Killeroo simple", "60k", 48, 10.8, 52, 84),
    "bunny-complex": ("Killeroo metal", "500k", 0.5, 31, 30, 47),
    "dragon": ("Buddha", "1M", 23, 18, 41, 18),
    "lamborghini": ("Sportscar", "53M", 0.5, 21, 32, 18),
    # the paper's own scenes (pbrt-v4's scene collection, tools/fetch-scenes.sh)
    "killeroo-simple": ("Killeroo simple", "60k", 48, 10.8, 52, 84),
    "killeroo-gold": ("Killeroo metal", "500k", 0.5, 31, 30, 47),
    # the paperscale grid's scene: the Sportscar's triangle count, not its model
    "fetched/big_random": ("Sportscar", "53M", 0.5, 21, 32, 18),
}
# The paper's own scenes among ours (the others are stand-ins).
PAPER_OWN = {"killeroo-simple", "killeroo-gold"}
# The paper's Table 1 "max BVH depth" row, by our scene.
PAPER_DEPTH = {"teapot": 16, "bunny": 24, "killeroo-simple": 24, "bunny-complex": 27,
               "killeroo-gold": 27, "dragon": 30, "lamborghini": 32, "fetched/big_random": 32}
PAPER_LT1 = {("bunny-complex", "any"), ("lamborghini", "any"), ("fetched/big_random", "any"),
             ("killeroo-gold", "any")}


def num(v):
    if v is None or v == "":
        return None
    try:
        f = float(v)
    except ValueError:
        return v
    return int(f) if f.is_integer() and "." not in str(v) and "e" not in str(v) else f


def read_csv(path):
    with open(path, newline="") as f:
        return [{k: num(v) for k, v in r.items()} for r in csv.DictReader(f)]


def rows(data, grid, **eq):
    out = [r for r in data if r.get("grid") == grid and r.get("ok") == 1]
    for k, v in eq.items():
        out = [r for r in out if r.get(k) == v]
    return out


def table(head, body):
    """A Markdown table: the header row, its rule and one row per item of `body`."""
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in body]
    return "\n".join(out)


def repo_commit(repo):
    """The repository's HEAD as a short hash ("?" without git)."""
    try:
        return subprocess.run(["git", "-C", repo, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True).stdout.strip() or "?"
    except OSError:
        return "?"


def note_run(out_dir, when):
    """OUT/provenance.json of a sweep's renders: before them the repository's commit, the CPU,
    the date and the load; after them (when = "after") the load again. sweep_collect.py stamps
    every row it collects from that run directory with it."""
    path = os.path.join(out_dir, "provenance.json")
    load = f"{os.getloadavg()[0]:.1f}"
    if when == "before":
        note = {"commit": repo_commit(REPO),
                "cpu": cpu_model(), "date": str(datetime.date.today()), "load_before": load}
    else:
        with open(path) as f:
            note = json.load(f)
        note["load_after"] = load
    with open(path, "w") as f:
        json.dump(note, f)


def run_line(note, device):
    """A grid's provenance as the report prints it: commit, device, CPU, date and load."""
    return (f"commit {note.get('commit', '?')}, {device}, {note.get('cpu', '?')}, "
            f"{note.get('date', '?')}, load {note.get('load_before', '?')} before and "
            f"{note.get('load_after', '?')} after")


def rewrite_block(path, name, lines, generator):
    """Replaces the generated block NAME of the Markdown file at `path` (everything between
    <!-- BEGIN NAME --> and <!-- END NAME -->) with `lines`, headed by a comment naming the
    `generator`; appends the block when the file has none. Text outside the blocks is kept."""
    begin, end = f"<!-- BEGIN {name} -->", f"<!-- END {name} -->"
    block = "\n".join([begin, f"<!-- generated by {generator}; edits inside this block are "
                       "overwritten -->", *lines, end])
    text = open(path).read() if os.path.exists(path) else "# Results\n"
    if begin in text and end in text:
        text = text[:text.index(begin)] + block + text[text.index(end) + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    with open(path, "w") as f:
        f.write(text)



def provenance_main(args):
    """`study sweep-provenance OUT_DIR before|after` (study/sweep.sh, around its renders)."""
    if len(args) != 2 or args[1] not in ("before", "after"):
        sys.exit("usage: study sweep-provenance OUT_DIR before|after")
    note_run(args[0], args[1])


def pyplot():
    """matplotlib's pyplot drawing without a display, imported on first use (only the figures
    need matplotlib)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save_figure(fig, out, name, written):
    """Writes `fig` as OUT/NAME (a PNG), closes it and appends the path to `written`."""
    path = os.path.join(out, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    pyplot().close(fig)
    written.append(path)

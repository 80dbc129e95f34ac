#!/usr/bin/env bash
# The limit study in one command: writes the job list (study/sweep_jobs.py), runs it with GNU
# parallel (locally, one render at a time by default; across machines with --sshloginfile),
# collects every --stats JSON and the image errors into one CSV (study/sweep_collect.py), draws
# the figures (study/figures.py) and rewrites the generated tables (results/, RESULTS.md)
# (study/sweep_report.py); its two other grids run their own tools, which render and rewrite
# their own blocks: keys (study/keys.py) and model (study/model.py). One command thus
# rewrites every generated block of a mode. See results/LIMIT_STUDY.md.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY=/usr/bin/python3   # Debian's python3 (python3-matplotlib, python3-openimageio, numpy)
MODE=quick
GRIDS=""
JOBS=1
SSHLOGINFILE=""
RESUME=0
RUN=1
REPORT=1
OUT=""
CSV=""
FIGS=""
RESULTS=""
HRPP="${HRPP_BIN:-}"

usage() {
    cat <<EOF
Usage: python3 -m study sweep [--quick | --full | --test] [options]

Runs hrpp render over the limit study's grids, collects one CSV, draws the figures and updates
every generated block of the mode: --full's limit study in results/LIMIT_STUDY.md, its keys in
results/KEYS.md and its cost model in RESULTS.md; --quick's three in results/QUICK.md.

  --quick            small images and spp: minutes on 2 cores (default)
  --full             the paper's 1024x1024 8 spp for Table 1, paperscale and the dragon grids,
                     512x512 for the bounded-table, error-vs-time and model grids, 256x256 for
                     the keys grid (the study's setup at 1024x1024): about 2 hours on 2 cores
  --test             three configurations on the Cornell box at 32x32, the keys and model grids
                     at 32x32 (the pipeline test; RESULTS.md is not touched: --results
                     defaults to OUT/RESULTS.md)
  --smoke            every grid at toy sizes (checks the pipeline in a few minutes)
  --grids LIST       comma-separated subset of table1,paperscale,precision,goup,spp,bounded,
                     errtime (the CSV's grids: their rows replace those grids' rows of the CSV;
                     the other rows stay; paperscale, the 52M-triangle scene at Table 1's
                     setup, runs in --full only: about 10 GiB of memory and 15 minutes) and
                     keys (study/keys.py: keys per ray class, block key_study:MODE) and
                     model (study/model.py: the cost model, block hrpp_model:MODE);
                     default: all of them
  --hrpp PATH        the hrpp binary (default: \$HRPP_BIN, else build/release/host/hrpp,
                     build/sweep/host/hrpp or build/ci/host/hrpp, the first that exists)
  --out DIR          run directory: jobs, joblog, each run's .json/.exr/.log, the keys and
                     model grids' renders in keys/ and model/ (default: build/limit-study/MODE)
  --csv FILE         the CSV (default: results/csv/MODE.csv)
  --figures DIR      figure directory (default: results/figures for --full, results/figures/MODE
                     otherwise)
  --results FILE     one Markdown file for every generated block of the run (default: the
                     files above; --test: OUT/RESULTS.md)
  --no-report        do not touch the results' Markdown files
  --jobs N           renders at once per machine (GNU parallel -j; default 1: the renderer
                     already uses every core)
  --sshloginfile F   run the CSV grids' jobs on the machines listed in F (GNU parallel
                     --sshloginfile; the keys and model grids render here);
                     they need this repository, the binary and the run directory at the same
                     absolute paths (a shared file system); one line per machine, e.g.
                     "1/ssh -p 2222 -i KEY user@host" (1 render at a time, another port/key)
  --resume           skip the jobs the joblog records as done (GNU parallel --resume) and the
                     keys and model grids' renders that their directories hold
  --collect-only     do not render the CSV grids: collect, plot and report what the run
                     directory holds (the keys and model grids reuse their renders and make
                     only those missing)
  --help             this text
EOF
}

while [[ $# -gt 0 ]]; do
    case "$1" in
        --quick) MODE=quick; shift ;;
        --full) MODE=full; shift ;;
        --test) MODE=test; shift ;;
        --smoke) MODE=smoke; shift ;;
        --grids) GRIDS="${2:?--grids needs a list}"; shift 2 ;;
        --hrpp) HRPP="${2:?--hrpp needs a path}"; shift 2 ;;
        --out) OUT="${2:?--out needs a directory}"; shift 2 ;;
        --csv) CSV="${2:?--csv needs a file}"; shift 2 ;;
        --figures) FIGS="${2:?--figures needs a directory}"; shift 2 ;;
        --results) RESULTS="${2:?--results needs a file}"; shift 2 ;;
        --no-report) REPORT=0; shift ;;
        --jobs|-j) JOBS="${2:?--jobs needs a number}"; shift 2 ;;
        --sshloginfile) SSHLOGINFILE="${2:?--sshloginfile needs a file}"; shift 2 ;;
        --resume) RESUME=1; shift ;;
        --collect-only) RUN=0; shift ;;
        --help|-h) usage; exit 0 ;;
        *) echo "sweep: unknown option '$1' (see --help)" >&2; exit 1 ;;
    esac
done

if [[ -z "$HRPP" ]]; then
    for c in build/release/host/hrpp build/sweep/host/hrpp build/ci/host/hrpp; do
        if [[ -x "$REPO/$c" ]]; then HRPP="$REPO/$c"; break; fi
    done
fi
[[ -n "$HRPP" && -x "$HRPP" ]] || { echo "sweep: no hrpp binary (--hrpp PATH or build first)" >&2; exit 1; }
HRPP="$(cd "$(dirname "$HRPP")" && pwd)/$(basename "$HRPP")"
[[ -n "$OUT" ]] || OUT="$REPO/build/limit-study/$MODE"
[[ -n "$CSV" ]] || CSV="$REPO/results/csv/$MODE.csv"
if [[ -z "$FIGS" ]]; then
    if [[ "$MODE" == full ]]; then FIGS="$REPO/results/figures"; else FIGS="$REPO/results/figures/$MODE"; fi
fi
mkdir -p "$OUT/runs"
OUT="$(cd "$OUT" && pwd)"
# Where each grid's block goes: --results takes them all; else by mode.
[[ -z "$RESULTS" && "$MODE" == test ]] && RESULTS="$OUT/RESULTS.md"
if [[ -n "$RESULTS" ]]; then
    SWEEP_RESULTS="$RESULTS"; KEYS_RESULTS="$RESULTS"; MODEL_RESULTS="$RESULTS"
elif [[ "$MODE" == full ]]; then
    SWEEP_RESULTS="$REPO/results/LIMIT_STUDY.md"; KEYS_RESULTS="$REPO/results/KEYS.md"
    MODEL_RESULTS="$REPO/RESULTS.md"
else
    SWEEP_RESULTS="$REPO/results/QUICK.md"
    KEYS_RESULTS="$SWEEP_RESULTS"; MODEL_RESULTS="$SWEEP_RESULTS"
fi

# The grids: the CSV's (study/sweep_jobs.py) and the two run by their own tools.
CSV_GRIDS=""
TOOL_GRIDS=""
if [[ -z "$GRIDS" ]]; then
    TOOL_GRIDS="keys,model"
else
    IFS=, read -r -a grid_list <<< "$GRIDS"
    for g in "${grid_list[@]}"; do
        case "$g" in
            keys|model) TOOL_GRIDS+="${TOOL_GRIDS:+,}$g" ;;
            "") ;;
            *) CSV_GRIDS+="${CSV_GRIDS:+,}$g" ;;
        esac
    done
fi
RUN_CSV=0
[[ -z "$GRIDS" || -n "$CSV_GRIDS" ]] && RUN_CSV=1

for m in matplotlib OpenImageIO numpy; do
    "$PY" -c "import $m" 2>/dev/null || { echo "sweep: $PY lacks $m (run tools/setup.sh)" >&2; exit 1; }
done
command -v parallel >/dev/null || { echo "sweep: GNU parallel missing (run tools/setup.sh)" >&2; exit 1; }
if [[ ( "$MODE" == full || "$MODE" == quick ) && ( ! -f "$REPO/scenes/fetched/stanford_dragon.glb" ||
      ! -f "$REPO/scenes/fetched/killeroos/killeroo-gold.pbrt" ) ]]; then
    "$REPO/tools/fetch-scenes.sh"
fi
# The paperscale grid's 52M-triangle scene (--full): written from the fetched meshes.
if [[ "$MODE" == full && ( -z "$GRIDS" || ",$GRIDS," == *,paperscale,* ) &&
      ! -f "$REPO/scenes/fetched/big_random.scene.json" ]]; then
    "$PY" "$REPO/study" big-scene --layout random
fi

start=$(date +%s)
desc="python3 -m study sweep --$MODE${GRIDS:+ --grids $GRIDS}"
[[ "$RESUME" == 1 ]] && desc+=" --resume"
[[ "$RUN" == 1 ]] || desc+=" --collect-only"
status=0
if [[ "$RUN_CSV" == 1 ]]; then
    "$PY" "$REPO/study" sweep-jobs --mode "$MODE" --grids "$CSV_GRIDS" --hrpp "$HRPP" \
        --repo "$REPO" --runs "$OUT/runs" --out "$OUT"

    if [[ "$RUN" == 1 ]]; then
        par=(parallel --will-cite -j "$JOBS" --joblog "$OUT/joblog")
        [[ "$RESUME" == 1 ]] && par+=(--resume)
        [[ -n "$SSHLOGINFILE" ]] && par+=(--sshloginfile "$SSHLOGINFILE" --workdir "$REPO")
        echo "sweep: $(wc -l < "$OUT/jobs.txt") jobs, ${par[*]} < $OUT/jobs.txt"
        [[ "$RESUME" == 1 && -f "$OUT/provenance.json" ]] ||
            "$PY" "$REPO/study" sweep-provenance "$OUT" before
        "${par[@]}" < "$OUT/jobs.txt" || status=$?
        "$PY" "$REPO/study" sweep-provenance "$OUT" after
        [[ "$status" == 0 ]] || echo "sweep: $status jobs failed (see $OUT/joblog and runs/*.log)" >&2
    fi
    # A subset of grids (--grids) replaces those grids' rows of the CSV and keeps the others.
    "$PY" "$REPO/study" sweep-collect --jobs "$OUT/jobs.jsonl" --runs "$OUT/runs" --csv "$CSV" \
        ${GRIDS:+--keep-other-grids} || status=1
    "$PY" "$REPO/study" figures --csv "$CSV" --out "$FIGS"
    if [[ "$REPORT" == 1 ]]; then
        "$PY" "$REPO/study" sweep-report --csv "$CSV" --figures "$FIGS" \
            --results "$SWEEP_RESULTS" \
            --mode "$MODE" --command "$desc" \
            --elapsed $(( $(date +%s) - start )) --joblog "$OUT/joblog"
    fi
fi

# The keys and model grids: their tools render (on this machine) and rewrite their blocks.
tool_args=(--mode "$MODE" --hrpp "$HRPP" --command "$desc")
[[ "$RESUME" == 1 || "$RUN" == 0 ]] && tool_args+=(--reuse)
keys_args=(); model_args=()
[[ "$REPORT" == 1 ]] && keys_args=(--results "$KEYS_RESULTS") && model_args=(--results "$MODEL_RESULTS")
if [[ ",$TOOL_GRIDS," == *,keys,* ]]; then
    echo "sweep: keys grid: python3 -m study keys ${tool_args[*]} ${keys_args[*]} --runs $OUT/keys"
    "$PY" "$REPO/study" keys "${tool_args[@]}" "${keys_args[@]}" --runs "$OUT/keys" > "$OUT/keys.md" \
        || { echo "sweep: study/keys.py failed" >&2; status=1; }
fi
if [[ ",$TOOL_GRIDS," == *,model,* ]]; then
    echo "sweep: model grid: python3 -m study model ${tool_args[*]} ${model_args[*]} --runs $OUT/model"
    "$PY" "$REPO/study" model "${tool_args[@]}" "${model_args[@]}" --runs "$OUT/model" \
        --figure "$FIGS/hrpp_model.png" > "$OUT/model.md" \
        || { echo "sweep: study/model.py failed" >&2; status=1; }
    tail -n 1 "$OUT/model.md"
fi
wrote="$FIGS"
[[ "$RUN_CSV" == 1 ]] && wrote="$CSV, $wrote"
[[ "$REPORT" == 1 ]] && wrote+=", $SWEEP_RESULTS"
[[ "$REPORT" == 1 && -n "$TOOL_GRIDS" ]] && wrote+=", $KEYS_RESULTS, $MODEL_RESULTS"
echo "sweep: $MODE done in $(( $(date +%s) - start )) s: $wrote"
exit "$status"

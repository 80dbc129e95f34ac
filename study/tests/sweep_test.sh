#!/usr/bin/env bash
# The limit study's pipeline on the Cornell box (python3 -m study sweep --test: three HRPP configurations
# and the HRPP-off image they are compared with, 32x32): jobs run through GNU parallel, the CSV
# has the expected columns and one successful row per job, image errors are filled in and the
# plots are written. The same command runs the keys grid (study/keys.py: three keys on the
# teapot, and the study's setup at 32x32) and the model grid (study/model.py: Cornell box and teapot, one render of each
# setting), and every grid rewrites its block of the run's RESULTS.md.
# Usage: sweep_test.sh HRPP_BINARY WORK_DIR
set -euo pipefail
HRPP="${1:?usage: sweep_test.sh HRPP_BINARY WORK_DIR}"
WORK="${2:?usage: sweep_test.sh HRPP_BINARY WORK_DIR}"
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
rm -rf "$WORK"
mkdir -p "$WORK"
/usr/bin/python3 "$REPO/study" sweep --test --hrpp "$HRPP" --out "$WORK/run" --csv "$WORK/test.csv" \
    --figures "$WORK/figures"
/usr/bin/python3 - "$WORK" <<'PY'
import csv, os, re, sys
work = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(work, "test.csv"))))
need = ["id", "grid", "scene", "size", "spp", "seed", "variant", "ok", "hrpp", "mode", "wall_s",
        "kernels_ms_total", "trace_ms", "all_savings", "any_savings", "all_table_entries",
        "all_table_bytes", "all_nodes_per_entry", "any_table_bytes", "all_wrong_closest",
        "rmse_off", "relmse_off", "rmse_ref", "relmse_ref", "cmd", "run"]
missing = [c for c in need if c not in rows[0]]
assert not missing, f"CSV lacks columns {missing}"
assert len(rows) == 4, f"{len(rows)} rows, expected 4"
assert all(r["ok"] == "1" and r["scene"] == "builtin:cornell" for r in rows), rows
v = {r["variant"]: r for r in rows}
assert v["off"]["hrpp"] == "off" and v["count"]["mode"] == "speculative", v
assert v["exact"]["mode"] == "exact" and float(v["exact"]["relmse_off"]) == 0.0, v["exact"]
# The default's tables differ per class (shadow rays: the beam table's 4 node slots).
assert v["default"]["hrpp"] == "on" and v["default"]["table_nodes"] != "", v["default"]
assert float(v["count"]["all_probes"]) > 0 and v["count"]["all_savings"] != "", v["count"]
assert float(v["count"]["wall_s"]) > 0 and v["count"]["relmse_off"] != "", v["count"]
for f in ("test_savings.png", "error_vs_off.png"):
    p = os.path.join(work, "figures", f)
    assert os.path.getsize(p) > 1000, p
    assert open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n", p
results = open(os.path.join(work, "run", "RESULTS.md")).read()
for block in ("sweep:test", "key_study:test", "hrpp_model:test"):
    assert results.count(f"<!-- BEGIN {block} -->") == 1, (block, results)
    assert results.count(f"<!-- END {block} -->") == 1, (block, results)
# Every row and the sweep's block name where the renders ran: commit, device, CPU, date, load.
sweep = results.split("<!-- BEGIN sweep:test -->")[1].split("<!-- END")[0]
run = rows[0]["run"]
assert re.match(r"commit [0-9a-f]{7,}, .+ \(.+\), .+, \d{4}-\d\d-\d\d, load \d+\.\d before and "
                r"\d+\.\d after$", run), run
assert all(r["run"] == run for r in rows), [r["run"] for r in rows]
assert f"- test: {run}" in sweep, sweep  # one run, one line
keys = results.split("<!-- BEGIN key_study:test -->")[1].split("<!-- END")[0]
assert "Made by `python3 -m study sweep --test`" in keys, keys
for row in ("| teapot | hrpp N=6 (paper) |",
            "| teapot | light-depth N=6 size 0.02, beam (default) |",
            "| teapot | grid-spherical N=6 (default) |"):
    assert row in keys, (row, keys)
# The paper's key for both classes, each default, a row of the study's setup and one of the
# distance gate's table.
assert keys.count("| teapot |") == 6, keys
study, gates = keys.split("The study's setup, 32x32, 1 spp")[1].split("The distance gate, ")
assert study.count("| teapot |") == 1 and "answered, beam table (default)" in study, study
assert gates.count("| teapot |") == 1 and "gate 1.4: net savings" in gates, gates
model = results.split("<!-- BEGIN hrpp_model:test -->")[1].split("<!-- END")[0]
assert "Made by `python3 -m study sweep --test`" in model and "| teapot | camera |" in model, model
assert re.search(r"\) at commit [0-9a-f]{7,}, .+, \d{4}-\d\d-\d\d, load \d+\.\d before", model), model
last = open(os.path.join(work, "run", "model.md")).read().strip().splitlines()[-1]
assert re.fullmatch(r"model: max relative error \d+\.\d+ on 10 held-out runs", last), last
p = os.path.join(work, "figures", "hrpp_model.png")
assert open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n", p
print("sweep_test: CSV columns, rows, figures and the three grids' blocks as expected")
PY

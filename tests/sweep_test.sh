#!/usr/bin/env bash
# The limit study's pipeline on the Cornell box (tools/sweep.sh --test: two HRPP configurations
# and the HRPP-off image they are compared with, 32x32): jobs run through GNU parallel, the CSV
# has the expected columns and one successful row per job, image errors are filled in and the
# plots are written. Usage: sweep_test.sh HRPP_BINARY WORK_DIR
set -euo pipefail
HRPP="${1:?usage: sweep_test.sh HRPP_BINARY WORK_DIR}"
WORK="${2:?usage: sweep_test.sh HRPP_BINARY WORK_DIR}"
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rm -rf "$WORK"
mkdir -p "$WORK"
"$REPO/tools/sweep.sh" --test --hrpp "$HRPP" --out "$WORK/run" --csv "$WORK/test.csv" \
    --figures "$WORK/figures"
/usr/bin/python3 - "$WORK" <<'PY'
import csv, os, sys
work = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(work, "test.csv"))))
need = ["id", "grid", "scene", "size", "spp", "seed", "variant", "ok", "hrpp", "mode", "wall_s",
        "kernels_ms_total", "trace_ms", "all_savings", "any_savings", "all_table_entries",
        "all_table_bytes", "all_nodes_per_entry", "any_table_bytes", "all_wrong_closest",
        "rmse_off", "relmse_off", "rmse_ref", "relmse_ref", "cmd"]
missing = [c for c in need if c not in rows[0]]
assert not missing, f"CSV lacks columns {missing}"
assert len(rows) == 3, f"{len(rows)} rows, expected 3"
assert all(r["ok"] == "1" and r["scene"] == "builtin:cornell" for r in rows), rows
v = {r["variant"]: r for r in rows}
assert v["off"]["hrpp"] == "off" and v["count"]["mode"] == "speculative", v
assert v["exact"]["mode"] == "exact" and float(v["exact"]["relmse_off"]) == 0.0, v["exact"]
assert float(v["count"]["all_probes"]) > 0 and v["count"]["all_savings"] != "", v["count"]
assert float(v["count"]["wall_s"]) > 0 and v["count"]["relmse_off"] != "", v["count"]
for f in ("test_savings.png", "error_vs_off.png"):
    p = os.path.join(work, "figures", f)
    assert os.path.getsize(p) > 1000, p
    assert open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n", p
print("sweep_test: CSV columns, rows and figures as expected")
PY

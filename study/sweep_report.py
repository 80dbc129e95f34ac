"""Rewrites the generated block of one sweep mode in RESULTS.md from the sweep CSV: the tables
(Table 1 beside the paper's, hash precision, go-up, spp, bounded tables, hash functions, error
against time, equal-time comparisons) and links to the figures. Everything between
<!-- BEGIN sweep:MODE --> and <!-- END sweep:MODE --> is replaced; the block is appended when
the file has none. Text outside the blocks (the discussion) is left alone."""
import argparse
import math
import os
import sys

from common import (PAPER_DEPTH, PAPER_OWN, PAPER_TABLE1, PAPER_LT1, read_csv, repo_commit,
                          rewrite_block, rows, table)


def f1(x, d=1):
    return "" if x is None else f"{x:.{d}f}"


def pc(x):
    return "–" if x is None else f"{100 * x:.1f}"


def mb(b):
    return "" if b is None else f"{b / 1e6:.1f}"


def sci(x):
    return "" if x is None else ("0" if x == 0 else f"{x:.2e}")


def fig(figdir, results, name, alt):
    p = os.path.join(figdir, name)
    if not os.path.exists(p):
        return ""
    return f"![{alt}]({os.path.relpath(p, os.path.dirname(os.path.abspath(results)))})\n"


def section_table1(data, out, figdir, results):
    cnt = rows(data, "table1", variant="count")
    if not cnt:
        return
    r0 = cnt[0]
    out.append(f"### Table 1 ({r0['size']}x{r0['size']}, {r0['spp']} spp, hash precision 6, "
               "go-up 0, unbounded tables, speculative)\n")
    out.append("Savings: interior nodes skipped, % of what full traversals of the same rays "
               "visit (`--hrpp-count`). Table MB: entries in use × (8-byte key + 4 bytes per "
               "node id held), the size an unbounded map like the paper's would need; the GPU "
               "table allocates 152 MiB per class (131072 sets × 16 ways × 16 node slots). "
               "Paper: its scene, pbrt.\n")
    # The paperscale grid's scene at the same setup, with the unbounded and the tuned table.
    big = rows(data, "paperscale", variant="count") + rows(data, "paperscale",
                                                           variant="count-tuned")
    body = []
    for r in cnt + big:
        s = r["scene"]
        p = PAPER_TABLE1.get(s)
        pall = f"{p[4]}" if p else ""
        pany = ("<1" if (s, "any") in PAPER_LT1 else f"{p[2]}") if p else ""
        name = s + (" (tuned 512 KiB table)" if r["variant"] == "count-tuned" else "")
        ours = "" if r.get("bvh_depth") is None else f"{r['bvh_depth']}"
        depth = ours + (f" / {PAPER_DEPTH[s]}" if s in PAPER_DEPTH else "")
        paper = (p[0] + (" (its own)" if s in PAPER_OWN else "")) if p else "(not in the paper)"
        body.append([name, paper, f"{r.get('triangles', '')}"
                     + (f" / {p[1]}" if p else ""), depth,
                     pc(r.get("all_savings")), pall, pc(r.get("any_savings")), pany,
                     mb(r.get("all_compact_bytes")), p[5] if p else "",
                     mb(r.get("any_compact_bytes")), p[3] if p else "",
                     f"{r.get('all_table_entries')} / {r.get('any_table_entries')}",
                     f"{r.get('all_insert_drops')} / {r.get('any_insert_drops')}"])
    out.append(table(["scene (ours)", "paper scene", "triangles ours / paper",
                      "BVH depth ours / paper", "hit-all % ours", "paper", "hit-any % ours", "paper",
                      "hit-all MB ours", "paper", "hit-any MB ours", "paper",
                      "entries all / any", "insert drops all / any"], body))
    ok = [r for r in cnt if r["scene"] in PAPER_TABLE1 and r["scene"] not in PAPER_OWN]
    if ok:
        ma = sum(r.get("all_savings") or 0 for r in ok) / len(ok)
        pa = sum(PAPER_TABLE1[r["scene"]][4] for r in ok) / len(ok)
        out.append(f"\nMean hit-all savings over the {len(ok)} stand-ins: {100 * ma:.1f}% "
                   f"(paper, its 5 scenes: {pa:.1f}%).\n")
    own = [r for r in cnt if r["scene"] in PAPER_OWN]
    if own:
        out.append("The paper's own scenes (pbrt-v4's Killeroos, tools/fetch-scenes.sh), hit-all "
                   "savings: " + "; ".join(
                       f"{r['scene']} {pc(r.get('all_savings'))}% (paper's "
                       f"{PAPER_TABLE1[r['scene']][0]}: {PAPER_TABLE1[r['scene']][4]}%)"
                       for r in own) + ".\n")
    # Times and speculative error
    body = []
    for r in cnt + [r for r in big if r["variant"] == "count"]:
        s = r["scene"]
        v = {x["variant"]: x for x in rows(data, r["grid"], scene=s)}
        off, sp, ex = v.get("off"), v.get("spec"), v.get("exact")
        if not off:
            continue
        body.append([s, f1(off.get("wall_s")), f1(sp and sp.get("wall_s")),
                     f1(ex and ex.get("wall_s")), f1(off.get("trace_ms"), 0),
                     f1(sp and sp.get("trace_ms"), 0), f1(ex and ex.get("trace_ms"), 0),
                     sci(sp and sp.get("relmse_off")),
                     pc(sp and sp.get("pixels_differ_off")), sci(ex and ex.get("relmse_off"))])
    if body:
        out.append("\nRun time of the same setup without `--hrpp-count` (one run each, "
                   "lavapipe on a shared 2-core CPU: noisy), and the image error each mode adds "
                   "against HRPP off (same seed and spp):\n")
        out.append(table(["scene", "wall off (s)", "wall spec (s)", "wall exact (s)",
                          "trace ms off", "trace ms spec", "trace ms exact",
                          "relMSE spec vs off", "pixels differ (spec)", "relMSE exact vs off"],
                         body))
    out.append("\n" + fig(figdir, results, "table1_savings.png", "Table 1 savings"))
    out.append(fig(figdir, results, "kernels_table1.png", "kernel times at the Table 1 setup"))


def section_precision(data, out, figdir, results):
    rs = sorted((r for r in rows(data, "precision") if r.get("bits") is not None),
                key=lambda r: r["bits"])
    if not rs:
        return
    out.append(f"### Hash precision (paper Fig. 3; dragon, {rs[0]['size']}x{rs[0]['size']}, "
               f"{rs[0]['spp']} spp, go-up 0, unbounded)\n")
    body = [[r["bits"], pc(r.get("all_savings")), pc(r.get("any_savings")),
             r.get("all_table_entries"), r.get("any_table_entries"),
             mb(r.get("all_compact_bytes")), mb(r.get("any_compact_bytes")),
             f1(r.get("all_nodes_per_entry"), 2), f1(r.get("any_nodes_per_entry"), 2),
             pc(r.get("all_true_positive_rate")),
             f1((r.get("all_verify_leaves") or 0) / max(1, r.get("all_predictor_hits") or 0), 2),
             pc((r.get("all_wrong_closest") or 0) / max(1, r.get("all_probes") or 0)),
             sci(r.get("relmse_off")), r.get("all_insert_drops")] for r in rs]
    out.append(table(["N bits", "hit-all %", "hit-any %", "entries all", "entries any",
                      "MB all", "MB any", "nodes/entry all", "nodes/entry any",
                      "TP rate all", "leaves tested per predictor hit (all)",
                      "wrong closest hits % (all)", "relMSE vs off", "drops all"], body))
    best = max(rs, key=lambda r: r.get("all_savings") or 0)
    best2 = max((r for r in rs if r["bits"] >= 2), key=lambda r: r.get("all_savings") or 0,
                default=best)
    out.append(f"\nHit-all savings peak at N = {best['bits']} "
               f"({pc(best.get('all_savings'))}%; for N >= 2 at N = {best2['bits']}, "
               f"{pc(best2.get('all_savings'))}%; paper, Buddha: 5). Savings count interior "
               "nodes only: the leaves a predictor hit tests and the wrong closest hits of "
               "speculative mode are the price of a loose hash (columns). Node lists hold at "
               "most 16 nodes here (the paper's grew to 600 leaves per entry at N = 4): a full "
               "list, or a full table, drops further inserts (`drops`).\n")
    out.append(fig(figdir, results, "precision.png", "hash precision"))


def section_goup(data, out, figdir, results):
    rs = sorted(rows(data, "goup"), key=lambda r: r["goup"])
    if not rs:
        return
    out.append(f"### Go-up level (paper Fig. 4; dragon, {rs[0]['size']}x{rs[0]['size']}, "
               f"{rs[0]['spp']} spp, N = 6, unbounded)\n")
    body = [[r["goup"], r.get("all_table_entries"), r.get("any_table_entries"),
             r.get("all_table_nodes"), r.get("any_table_nodes"), pc(r.get("all_savings")),
             pc(r.get("all_net_savings")), pc(r.get("any_savings")), mb(r.get("all_compact_bytes")),
             f1(r.get("all_nodes_per_entry"), 2), r.get("all_verify_interior")] for r in rs]
    out.append(table(["go-up", "entries all", "entries any", "node ids all", "node ids any",
                      "hit-all %", "hit-all net %", "hit-any %",
                      "MB all", "nodes/entry all", "verify interior nodes all"], body))
    out.append("\n" + fig(figdir, results, "goup.png", "go-up level"))


def section_spp(data, out, figdir, results):
    rs = sorted(rows(data, "spp", variant="count"), key=lambda r: r["spp"])
    if not rs:
        return
    out.append(f"### Samples per pixel (paper Fig. 5; dragon, {rs[0]['size']}x{rs[0]['size']}, "
               "N = 6, go-up 0, unbounded)\n")
    body = [[r["spp"], pc(r.get("all_savings")), pc(r.get("any_savings")),
             r.get("all_table_entries"), r.get("any_table_entries"),
             mb(r.get("all_compact_bytes")), r.get("all_insert_drops")] for r in rs]
    out.append(table(["spp", "hit-all %", "hit-any %", "entries all", "entries any", "MB all",
                      "drops all"], body))
    out.append("\n" + fig(figdir, results, "spp.png", "samples per pixel"))


def section_bounded(data, out, figdir, results):
    rs = [r for r in rows(data, "bounded") if r.get("hrpp") == "on"]
    if not rs:
        return
    for sc in sorted({r["scene"] for r in rs}):
        srs = [r for r in rs if r["scene"] == sc]
        hr = sorted((r for r in srs if r.get("hash") == "hrpp"),
                    key=lambda r: (r["all_table_bytes"], str(r.get("ways")), str(r.get("policy"))))
        out.append(f"### Bounded tables ({sc}, {srs[0]['size']}x{srs[0]['size']}, "
                   f"{srs[0]['spp']} spp, hash hrpp N = 6, 8 node slots per entry; "
                   "hit-all and hit-any in every run)\n")
        body = []
        for r in hr:
            kb = r["all_table_bytes"] / 1024
            body.append([f1(kb, 1), r.get("ways"), r.get("policy"),
                         pc(r.get("all_savings")), pc(r.get("any_savings")),
                         f"{100 * (r.get('all_savings') or 0) / kb:.3f}",
                         pc(r.get("all_occupancy")), r.get("all_evictions"),
                         r.get("all_insert_drops"), sci(r.get("relmse_off"))])
        out.append(table(["KiB per class", "ways", "policy", "hit-all %", "hit-any %",
                          "hit-all %-points per KiB", "occupancy all", "evictions all",
                          "drops all", "relMSE vs off"], body))
        bnd = [r for r in hr if r.get("kib") != "unbounded"]
        unb = [r for r in hr if r.get("kib") == "unbounded"]
        if bnd:
            spk = max(bnd, key=lambda r: (r.get("all_savings") or 0) / r["all_table_bytes"])
            lines = [f"\nBest savings per KiB (hit-all): {f1(spk['all_table_bytes'] / 1024)} KiB, "
                     f"{spk['ways']} way{'s' if spk['ways'] > 1 else ''}, {spk['policy']}: {pc(spk.get('all_savings'))}% "
                     f"({100 * (spk.get('all_savings') or 0) / (spk['all_table_bytes'] / 1024):.3f}"
                     " %-points per KiB)."]
            if unb and unb[0].get("all_savings"):
                u = unb[0]["all_savings"]
                for frac in (0.5, 0.9):
                    good = [r for r in bnd if (r.get("all_savings") or 0) >= frac * u]
                    if good:
                        g = min(good, key=lambda r: (r["all_table_bytes"],
                                                     -(r.get("all_savings") or 0)))
                        lines.append(f"Smallest table reaching {int(frac * 100)}% of the "
                                     f"unbounded table's hit-all savings ({pc(u)}%): "
                                     f"{f1(g['all_table_bytes'] / 1024)} KiB, {g['ways']} way{'s' if g['ways'] > 1 else ''}, "
                                     f"{g['policy']} ({pc(g.get('all_savings'))}%).")
            out.append(" ".join(lines) + "\n")
        out.append(fig(figdir, results, f"bounded_{sc}.png", f"bounded tables, {sc}"))
        hs = sorted((r for r in srs if r.get("ways") in (8, 16) and r.get("policy") in
                     ("lru", "none") and (r.get("policy") == "lru" or r.get("kib") == "unbounded")),
                    key=lambda r: (r.get("hash"), r["all_table_bytes"]))
        out.append(f"\nHash functions ({sc}; 8 ways LRU, and unbounded):\n")
        out.append(table(["hash", "KiB per class", "hit-all %", "hit-any %", "entries all",
                          "nodes/entry all", "TP rate all", "relMSE vs off"],
                         [[r.get("hash"), f1(r["all_table_bytes"] / 1024, 1),
                           pc(r.get("all_savings")), pc(r.get("any_savings")),
                           r.get("all_table_entries"), f1(r.get("all_nodes_per_entry"), 2),
                           pc(r.get("all_true_positive_rate")), sci(r.get("relmse_off"))]
                          for r in hs]))
        out.append("\n" + fig(figdir, results, f"hashes_{sc}.png", f"hash functions, {sc}"))


def section_errtime(data, out, figdir, results):
    rs = rows(data, "errtime")
    if not rs:
        return
    out.append(f"### Error against run time ({rs[0]['size']}x{rs[0]['size']}; runs without "
               "`--hrpp-count`; relMSE with ε = 0.01)\n")
    out.append("`ref`: against the HRPP-off reference of the same scene (high spp, seed 1); "
               "`off`: against the HRPP-off image of the same seed and spp (what the predictor "
               "itself changes). Times: one run each on a shared 2-core CPU (lavapipe), "
               "so noisy; compare within a scene.\n")
    body = []
    for r in sorted(rs, key=lambda r: (r["scene"], r["variant"], r["spp"])):
        if r["variant"] == "reference":
            continue
        body.append([r["scene"], r["variant"], r["spp"], f1(r.get("wall_s"), 2),
                     f1(r.get("trace_ms"), 0), f1(r.get("kernels_ms_total"), 0),
                     sci(r.get("relmse_ref")), sci(r.get("relmse_off")),
                     pc(r.get("pixels_differ_off"))])
    out.append(table(["scene", "variant", "spp", "wall s", "trace ms", "all kernels ms",
                      "relMSE ref", "relMSE off", "pixels differ"], body))
    out.append("\nEqual time. HRPP off's cost per sample pass is fitted on its spp ladder "
               "(least squares through the origin, time = c·spp) and its error interpolated "
               "between its ladder's points, linearly in log relMSE against log spp (no model: "
               "with Sobol samples the error falls faster than 1/spp; beyond the ladder the end "
               "segment's slope); for each HRPP run, the spp HRPP off reaches in the same time "
               "and the error it has there. Ratio > 1: HRPP is worse at equal time. Device time "
               "(all kernels, summed timestamps) is less disturbed by host hiccups than wall "
               "time; both are given.\n")
    body = []
    for sc in sorted({r["scene"] for r in rs}):
        off = [r for r in rs if r["scene"] == sc and r["variant"] == "off"
               and r.get("wall_s") and r.get("relmse_ref")]
        if len(off) < 2:
            continue
        n = [o["spp"] for o in off]
        cw = sum(o["wall_s"] * k for o, k in zip(off, n)) / sum(k * k for k in n)
        ck = sum(o["kernels_ms_total"] * k for o, k in zip(off, n)) / sum(k * k for k in n)
        ladder = sorted((o["spp"], o["relmse_ref"]) for o in off)
        for r in sorted((r for r in rs if r["scene"] == sc and r["variant"] not in
                         ("off", "reference")), key=lambda r: (r["variant"], r["spp"])):
            if not r.get("wall_s") or not r.get("relmse_ref"):
                continue
            sk = r["kernels_ms_total"] / ck
            sw = r["wall_s"] / cw
            off_err = log_interpolate(ladder, sk)
            body.append([sc, r["variant"], r["spp"], f1(r["kernels_ms_total"], 0),
                         f1(sk, 1), f1(r["wall_s"], 2), f1(sw, 1), sci(r["relmse_ref"]),
                         sci(off_err), f1(r["relmse_ref"] / off_err, 2)])
    out.append(table(["scene", "HRPP variant", "spp", "kernels ms", "off spp, same kernel time",
                      "wall s", "off spp, same wall time", "relMSE ref (HRPP)",
                      "relMSE ref (off, same kernel time)", "ratio"], body))
    out.append("")
    for sc in sorted({r["scene"] for r in rs}):
        out.append(fig(figdir, results, f"error_time_{sc}.png", f"error vs time, {sc}"))
    out.append(fig(figdir, results, "error_vs_off.png", "error added by the predictor"))


def log_interpolate(points, x):
    """y at x on the polyline through `points` (x, y > 0, sorted by x, at least two), linear in
    log y against log x; beyond either end, the end segment's line."""
    i = next((k for k in range(1, len(points) - 1) if x < points[k][0]), len(points) - 1)
    (x0, y0), (x1, y1) = points[i - 1], points[i]
    t = (math.log(x) - math.log(x0)) / (math.log(x1) - math.log(x0))
    return math.exp(math.log(y0) + t * (math.log(y1) - math.log(y0)))


def span(joblog):
    """'renders: N jobs over M min (first start to last end), ' from a GNU parallel joblog."""
    try:
        with open(joblog) as f:
            rs = [l.rstrip("\n").split("\t") for l in f][1:]
        st = [(float(r[2]), float(r[2]) + float(r[3])) for r in rs if len(r) > 3]
    except (OSError, ValueError, TypeError):
        return ""
    if not st:
        return ""
    t = max(e for _, e in st) - min(b for b, _ in st)
    return f"renders: {len(st)} jobs over {int(t) // 60} min {int(t) % 60} s; "


def grid_runs(data):
    """Where and when the renders ran (the CSV's `run` column): one line per run, naming its
    grids (a grid merged from several runs is named under each)."""
    grids = {}
    for r in data:
        grids.setdefault(r.get("run") or "not recorded", {})[r["grid"]] = None
    return [f"- {', '.join(g)}: {run}" for run, g in grids.items()]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--figures", required=True)
    ap.add_argument("--results", required=True)
    ap.add_argument("--mode", required=True)
    ap.add_argument("--command", required=True)
    ap.add_argument("--elapsed", type=int, default=0)
    ap.add_argument("--joblog", help="GNU parallel's joblog: the renders' span is reported")
    a = ap.parse_args()
    data = read_csv(a.csv)
    ok = sum(1 for r in data if r.get("ok") == 1)
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = [f"Made by `{a.command}` ({ok} of {len(data)} runs succeeded, "
           f"{span(a.joblog)}this command {a.elapsed // 60} min {a.elapsed % 60} s, "
           f"repository at {repo_commit(repo)}; "
           f"CSV: `{os.path.relpath(a.csv, repo)}`, figures: "
           f"`{os.path.relpath(a.figures, repo)}/`). The grids' renders ran at:\n"]
    out += grid_runs(data) + [""]
    for s in (section_table1, section_precision, section_goup, section_spp, section_bounded,
              section_errtime):
        s(data, out, a.figures, a.results)
        out.append("")
    rewrite_block(a.results, f"sweep:{a.mode}", out,
                  f"study/sweep_report.py from {os.path.relpath(a.csv, repo)}")
    print(f"study sweep-report: {a.results} (block sweep:{a.mode})")


if __name__ == "__main__":
    main()

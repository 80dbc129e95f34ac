"""The limit study's error figures (study figures): per scene of the errtime grid,
relMSE against the high-spp reference versus wall time and versus trace-kernel time for HRPP
off, speculative and exact (spp ladders; runs without --hrpp-count), and the error each HRPP
configuration adds against the HRPP-off image of the same seed and spp."""
from common import pyplot, rows, save_figure as save

plt = pyplot()

VARIANTS = (("off", "HRPP off", "k", "o-"), ("exact-small", "exact, small table", "tab:green", "s--"),
            ("spec-small", "speculative, small table", "tab:red", "^-"),
            ("spec-unbounded", "speculative, unbounded", "tab:purple", "v-"),
            ("default", "--hrpp on (tuned, adaptive)", "tab:orange", "D-"))


def errtime(data, out, w):
    rs = rows(data, "errtime")
    for sc in sorted({r["scene"] for r in rs}):
        srs = [r for r in rs if r["scene"] == sc]
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
        for ax, key, xl in ((axes[0], "wall_s", "render wall time (s)"),
                            (axes[1], "trace_ms", "trace kernels, device time (ms)")):
            for v, name, col, st in VARIANTS:
                p = sorted((r for r in srs if r.get("variant") == v and r.get("relmse_ref")),
                           key=lambda r: r["spp"])
                if not p:
                    continue
                ax.plot([r[key] for r in p], [r["relmse_ref"] for r in p], st, color=col,
                        label=name, ms=5)
                for r in p:
                    ax.annotate(str(r["spp"]), (r[key], r["relmse_ref"]), fontsize=7,
                                xytext=(3, 3), textcoords="offset points", color=col)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel(xl)
            ax.set_ylabel("relMSE vs high-spp reference (eps 0.01)")
            ax.grid(alpha=0.3, which="both")
            ax.legend(fontsize=8)
        ref = [r for r in srs if r.get("variant") == "reference"]
        t = f"{sc}, {srs[0]['size']}x{srs[0]['size']}, labels: spp"
        if ref:
            t += f"; reference: HRPP off, {ref[0]['spp']} spp, seed 1"
        fig.suptitle("Error against time - " + t + " (lavapipe, shared 2-core CPU: noisy times)",
                     fontsize=10)
        save(fig, out, f"error_time_{sc}.png", w)


def error_off(data, out, w):
    rs = [r for r in data if r.get("ok") == 1 and r.get("hrpp") == "on"
          and r.get("relmse_off") is not None]
    if not rs:
        return
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    ax = axes[0]
    for mode, col in (("speculative", "tab:red"), ("exact", "tab:green")):
        # wrong closest hits are only counted with --hrpp-count (exact mode has none)
        p = [r for r in rs if r.get("mode") == mode and (mode == "exact" or
                                                         r.get("count_baseline") == 1)]
        if p:
            ax.scatter([100 * (r.get("all_wrong_closest") or 0) / max(1, r.get("all_probes") or 1)
                        for r in p],
                       [r["relmse_off"] for r in p], color=col, s=14, label=mode, alpha=0.7)
    ax.set_yscale("symlog", linthresh=1e-6)
    ax.set_xlabel("wrong closest hits (% of hit-all rays)")
    ax.set_ylabel("relMSE vs HRPP off, same seed and spp")
    ax.set_title("runs with --hrpp-count (and exact runs): error added by the predictor")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[1]
    b = [r for r in rs if r.get("grid") == "bounded" and r.get("hash") == "hrpp"
         and r.get("policy") == "lru" or (r.get("grid") == "bounded" and r.get("kib") == "unbounded"
                                          and r.get("hash") == "hrpp")]
    for ways in sorted({r["ways"] for r in b}):
        p = sorted((r for r in b if r["ways"] == ways), key=lambda r: r["all_table_bytes"])
        ax.plot([r["all_table_bytes"] / 1024 for r in p], [r["relmse_off"] for r in p], "o-",
                label=f"{ways} way{'s' if ways > 1 else ''}" + (" (unbounded, none)" if ways == 16 else ", lru"), ms=4)
    if b:
        ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=1e-6)
        ax.set_ylim(bottom=0)
        ax.set_xlabel("hit-all table bytes (KiB)")
        ax.set_ylabel("relMSE vs HRPP off")
        ax.set_title(f"speculative error against table size ({b[0]['scene']}, bounded grid)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    save(fig, out, "error_vs_off.png", w)


def kernels(data, out, w):
    """Per-kernel device time of HRPP off / speculative / exact at the Table 1 setup."""
    rs = rows(data, "table1")
    scenes = []
    for r in rs:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    var = ("off", "spec", "exact")
    ks = sorted({k for r in rs for k in r if k.startswith("ms_") and r.get(k) is not None})
    if not rs or not ks:
        return
    fig, ax = plt.subplots(figsize=(14, 5))
    x, labels = 0, []
    xs = []
    for sc in scenes:
        for v in var:
            r = next((r for r in rs if r["scene"] == sc and r.get("variant") == v), None)
            if r is None:
                continue
            bottom = 0.0
            for i, k in enumerate(ks):
                val = (r.get(k) or 0) / 1000
                ax.bar(x, val, 0.8, bottom=bottom, color=f"C{i}",
                       label=k[3:] if not xs else None)
                bottom += val
            xs.append(x)
            labels.append(f"{v} {sc}")
            x += 1
        x += 0.6
    ax.set_xticks(xs)
    ax.set_xticklabels(labels, fontsize=7, rotation=35, ha="right")
    ax.set_ylabel("device time per kernel, summed over the frame (s)")
    r0 = rs[0]
    ax.set_title(f"Kernel times, HRPP off / speculative / exact (unbounded), {r0['size']}x"
                 f"{r0['size']}, {r0['spp']} spp, no --hrpp-count; one run each, shared CPU")
    ax.legend(fontsize=8)
    save(fig, out, "kernels_table1.png", w)


PLOTTERS = [errtime, error_off, kernels]

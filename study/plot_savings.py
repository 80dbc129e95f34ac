"""The limit study's savings figures (study figures): Table 1 against the paper, hash
precision, go-up level, spp, bounded tables and hash functions."""
from common import PAPER_TABLE1, pyplot, rows, save_figure as save

plt = pyplot()
CLS = (("all", "hit-all"), ("any", "hit-any"))


def plot_savings_by_bytes(ax, c, rs, style, label):
    """One curve of a ray class's (c: "all" or "any") savings % against its table KiB."""
    ax.plot([r[f"{c}_table_bytes"] / 1024 for r in rs],
            [100 * (r.get(f"{c}_savings") or 0) for r in rs], style, label=label, ms=4)


def finish_bytes_axes(ax, xlabel, title, legend_size):
    ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("interior nodes skipped (%)")
    ax.set_title(title)
    ax.legend(fontsize=legend_size)
    ax.grid(alpha=0.3)

def res_of(rs):
    r = rs[0]
    return f"{r['size']}x{r['size']}, {r['spp']} spp" if "spp" not in r.get("grid", "") else \
        f"{r['size']}x{r['size']}"


def table1(data, out, w):
    rs = rows(data, "table1", variant="count")
    if not rs:
        return
    scenes = [r["scene"] for r in rs]
    fig, axes = plt.subplots(1, 2, figsize=(14, 4.5))
    x = range(len(scenes))
    for ax, (c, name), pi in zip(axes, CLS, (4, 2)):
        ours = [100 * (r.get(f"{c}_savings") or 0) for r in rs]
        paper = [PAPER_TABLE1[s][pi] if s in PAPER_TABLE1 else float("nan") for s in scenes]
        ax.bar([i - 0.2 for i in x], ours, 0.4, label="ours (stand-in scene)")
        ax.bar([i + 0.2 for i in x], paper, 0.4, label="paper (its scene)")
        ax.set_xticks(list(x))
        ax.set_xticklabels([s + ("\n(" + PAPER_TABLE1[s][0] + ")" if s in PAPER_TABLE1 else "")
                            for s in scenes], fontsize=7)
        ax.set_ylabel("interior nodes skipped (%)")
        ax.set_title(f"{name} savings, N=6, go-up 0, unbounded ({res_of(rs)})")
        ax.legend(fontsize=8)
    save(fig, out, "table1_savings.png", w)


def precision(data, out, w):
    rs = sorted((r for r in rows(data, "precision") if r.get("bits") is not None),
                key=lambda r: r["bits"])
    if not rs:
        return
    b = [r["bits"] for r in rs]
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    for c, name in CLS:
        axes[0].plot(b, [100 * (r.get(f"{c}_savings") or 0) for r in rs], "o-", label=name)
        axes[1].plot(b, [(r.get(f"{c}_compact_bytes") or 0) / 2**20 for r in rs], "o-",
                     label=f"{name} (key + node ids)")
        axes[2].plot(b, [r.get(f"{c}_nodes_per_entry") or 0 for r in rs], "o-", label=name)
    axes[0].set_ylabel("interior nodes skipped (%)")
    axes[1].set_ylabel("table in use (MiB)")
    axes[1].set_yscale("log")
    axes[2].set_ylabel("mean nodes per entry (cap: 16 slots)")
    for ax, t in zip(axes, ("savings", "table size", "nodes per entry (tight vs loose)")):
        ax.set_xlabel("hash precision N (bits)")
        ax.set_title(f"dragon, {t}")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(f"Hash precision (paper Fig. 3, Buddha: peak at 5 bits) - {res_of(rs)}",
                 fontsize=10)
    save(fig, out, "precision.png", w)


def goup(data, out, w):
    rs = sorted(rows(data, "goup"), key=lambda r: r["goup"])
    if not rs:
        return
    g = [r["goup"] for r in rs]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for c, name in CLS:
        axes[0].plot(g, [r.get(f"{c}_table_entries") or 0 for r in rs], "o-",
                     label=f"{name}: entries (keys)")
        axes[0].plot(g, [r.get(f"{c}_table_nodes") or 0 for r in rs], "s--",
                     label=f"{name}: node ids held")
        axes[1].plot(g, [100 * (r.get(f"{c}_savings") or 0) for r in rs], "o-", label=name)
        axes[1].plot(g, [100 * (r.get(f"{c}_net_savings") or 0) for r in rs], "s--",
                     label=f"{name}, net of verification")
    axes[0].set_ylabel("table entries / node ids")
    axes[1].set_ylabel("interior nodes skipped (%)")
    for ax, loc in zip(axes, ("center", "best")):
        ax.set_xlabel("go-up level")
        ax.set_xticks(g)
        ax.legend(fontsize=8, loc=loc)
        ax.grid(alpha=0.3)
    fig.suptitle(f"Go-up level (paper Fig. 4) - dragon, N=6, {res_of(rs)}", fontsize=10)
    save(fig, out, "goup.png", w)


def spp(data, out, w):
    rs = sorted(rows(data, "spp", variant="count"), key=lambda r: r["spp"])
    if not rs:
        return
    s = [r["spp"] for r in rs]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for c, name in CLS:
        axes[0].plot(s, [100 * (r.get(f"{c}_savings") or 0) for r in rs], "o-", label=name)
        axes[1].plot(s, [r.get(f"{c}_table_entries") or 0 for r in rs], "o-", label=name)
    cap = rs[0].get("all_table_capacity")
    if cap:
        axes[1].axhline(cap, color="grey", ls=":", label="table capacity")
    axes[0].set_ylabel("interior nodes skipped (%)")
    axes[1].set_ylabel("table entries")
    for ax in axes:
        ax.set_xlabel("samples per pixel")
        ax.set_xscale("log", base=2)
        ax.set_xticks(s)
        ax.set_xticklabels([str(v) for v in s])
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(f"Samples per pixel (paper Fig. 5) - dragon, N=6, {res_of(rs)}", fontsize=10)
    save(fig, out, "spp.png", w)


def bounded(data, out, w):
    rs = [r for r in rows(data, "bounded") if r.get("hrpp") == "on"]
    if not rs:
        return
    for sc in sorted({r["scene"] for r in rs}):
        srs = [r for r in rs if r["scene"] == sc]
        unb = [r for r in srs if r.get("kib") == "unbounded" and r.get("hash") == "hrpp"]
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
        for ax, (c, name) in zip(axes, CLS):
            for ways in sorted({r["ways"] for r in srs if r.get("kib") != "unbounded"}):
                for pol, ls in (("none", "--"), ("lru", "-")):
                    p = sorted((r for r in srs if r.get("hash") == "hrpp" and r.get("ways") == ways
                                and r.get("policy") == pol and r.get("kib") != "unbounded"),
                               key=lambda r: r[f"{c}_table_bytes"])
                    if p:
                        plot_savings_by_bytes(ax, c, p, "o" + ls,
                                              f"{ways} way{'s' if ways > 1 else ''}, {pol}")
            if unb:
                u = unb[0]
                ax.scatter([u[f"{c}_table_bytes"] / 1024], [100 * (u.get(f"{c}_savings") or 0)],
                           marker="*", s=150, color="k", zorder=5, label="unbounded (16 ways)")
            finish_bytes_axes(ax, "table bytes per ray class (KiB, allocated)",
                              f"{name}: {sc}, {res_of(srs)}, hash hrpp N=6, 8 nodes/entry", 7)
        save(fig, out, f"bounded_{sc}.png", w)

        fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
        for ax, (c, name) in zip(axes, CLS):
            for h in ("hrpp", "grid-spherical", "two-point"):
                p = sorted((r for r in srs if r.get("hash") == h and r.get("kib") != "unbounded"
                            and r.get("ways") == 8 and r.get("policy") == "lru"),
                           key=lambda r: r[f"{c}_table_bytes"])
                u = [r for r in srs if r.get("hash") == h and r.get("kib") == "unbounded"]
                p = p + u
                if p:
                    plot_savings_by_bytes(ax, c, p, "o-", h)
            finish_bytes_axes(ax, "table bytes per ray class (KiB; last point: unbounded)",
                              f"{name}: hash functions, {sc}, 8 ways LRU, N=6", 8)
        save(fig, out, f"hashes_{sc}.png", w)


def test(data, out, w):
    rs = [r for r in rows(data, "test") if r.get("hrpp") == "on"]
    if not rs:
        return
    fig, ax = plt.subplots(figsize=(7, 3.5))
    x = range(len(rs))
    for off, (c, name) in zip((-0.2, 0.2), CLS):
        ax.bar([i + off for i in x], [100 * (r.get(f"{c}_savings") or 0) for r in rs], 0.4,
               label=name)
    ax.set_xticks(list(x))
    ax.set_xticklabels([r["variant"] for r in rs])
    ax.set_ylabel("interior nodes skipped (%)")
    ax.set_title("pipeline test (Cornell box); exact runs do not count savings")
    ax.legend(fontsize=8)
    save(fig, out, "test_savings.png", w)


PLOTTERS = [table1, precision, goup, spp, bounded, test]

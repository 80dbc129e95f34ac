"""Shared by tools/plot_*.py: matplotlib without a display, saving a figure, the savings-against-
table-bytes curves, and the command line (--csv, --out)."""
import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401  (the plot scripts draw with it)

from sweep_common import read_csv  # noqa: E402


def save(fig, out, name, written):
    p = os.path.join(out, name)
    fig.tight_layout()
    fig.savefig(p, dpi=110)
    plt.close(fig)
    written.append(p)


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


def main(prog, description, plotters):
    """Reads --csv, lets each plotter write its PNGs into --out, prints their paths."""
    ap = argparse.ArgumentParser(prog=prog, description=description)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    data = read_csv(a.csv)
    written = []
    for f in plotters:
        f(data, a.out, written)
    for p in written:
        print(f"{prog}: {p}")

"""`study figures --csv FILE --out DIR`: the limit study's figures from the sweep CSV (study
sweep's step after collecting): plot_savings.py's (Table 1 against the paper, hash precision,
go-up level, spp, bounded tables, hash functions) and plot_error_time.py's (error against run
time, error against HRPP off, kernel times). Writes PNGs into --out; a grid the CSV lacks is
skipped. matplotlib draws without a display (common.pyplot)."""
import argparse
import os

import plot_error_time
import plot_savings
from common import read_csv


def main():
    ap = argparse.ArgumentParser(prog="study figures", description=__doc__)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    data = read_csv(a.csv)
    written = []
    for f in plot_savings.PLOTTERS + plot_error_time.PLOTTERS:
        f(data, a.out, written)
    for p in written:
        print(f"study figures: {p}")

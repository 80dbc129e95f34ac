"""Shared by the limit study's plot and report scripts: the CSV reader and the paper's numbers."""
import csv

# The paper's Table 1 (Demoullin, Gubran, Aamodt, EG 2019): 1024x1024, 8 spp, go-up 0,
# precision 6. Savings in %, table sizes in MB. "<1" is entered as 0.5. Our stand-in scenes:
PAPER_TABLE1 = {
    # ours: (paper scene, triangles, hit-any %, hit-any MB, hit-all %, hit-all MB)
    "teapot": ("Teapot", "2k", 4, 16, 69, 2),
    "bunny": ("Killeroo simple", "60k", 48, 10.8, 52, 84),
    "bunny-complex": ("Killeroo metal", "500k", 0.5, 31, 30, 47),
    "dragon": ("Buddha", "1M", 23, 18, 41, 18),
    "lamborghini": ("Sportscar", "53M", 0.5, 21, 32, 18),
    # the paperscale grid's scene: the Sportscar's triangle count, not its model
    "fetched/big_random": ("Sportscar", "53M", 0.5, 21, 32, 18),
}
PAPER_LT1 = {("bunny-complex", "any"), ("lamborghini", "any"), ("fetched/big_random", "any")}


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


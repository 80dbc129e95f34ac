#!/usr/bin/python3
"""study/cost_model.py, the fit of study/model.py, on synthetic renders whose costs are
known: stats JSON files built from random operation counts and chosen costs per operation, with
1% multiplicative noise on every kernel time. The fit must recover every cost that carries
weight within 10% (the subgroup steps with a predictor hit of both predict kernels among them), predict held-out runs' class times within 5%, and the break-even answers
must solve their closed forms (the modelled on/off is 1 there), and of renders repeated with
disturbed frames the fit must see each frame's undisturbed time (and the renders' spread, one
against another, comes out as their time ratios). study/model.py end to end
on tiny renders is the model grid of study/tests/sweep_test.sh (python3 -m study sweep --test).
Usage: hrpp_model_test.py"""
import copy
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(HERE, ".."))  # study/
import cost_model as cm  # noqa: E402
import model as hm  # noqa: E402

NS = 1e-6  # ms per ns
TRUE = {
    "trace:camera": {"dispatch": 20000 * NS, "ray": 90 * NS, "interior": 60 * NS,
                     "leaf": 40 * NS, "triangle": 25 * NS, "queued_interior": 10 * NS, "interior_memory": 4 * NS},
    "trace:bounce": {"dispatch": 20000 * NS, "ray": 120 * NS, "interior": 95 * NS,
                     "leaf": 55 * NS, "triangle": 30 * NS, "queued_interior": 15 * NS, "interior_memory": 6 * NS},
    "trace:shadow": {"dispatch": 15000 * NS, "ray": 80 * NS, "interior": 75 * NS,
                     "leaf": 45 * NS, "triangle": 20 * NS, "queued_interior": 5 * NS, "interior_memory": 5 * NS},
    "hrpp_predict": {"dispatch": 30000 * NS, "probe": 150 * NS, "verify_interior": 70 * NS,
                     "verify_leaf": 60 * NS, "verify_triangle": 30 * NS, "hit_steps": 300 * NS,
                     "hit_steps_any": 500 * NS},
    "hrpp_resolve": {"dispatch": 25000 * NS, "queue_entry": 60 * NS, "insert": 110 * NS},
}


def synthetic_class(rng, on, dispatches):
    rays = int(np.exp(rng.uniform(np.log(2000), np.log(400000))))
    interior, leaf, tri = rng.uniform(2, 20), rng.uniform(0.5, 6), rng.uniform(1, 12)
    c = {"rays": rays, "trace_dispatches": dispatches}
    answered = int(rays * rng.uniform(0, 0.5)) if on else 0
    traced = rays - answered
    # Hit rates from a few percent (few subgroup steps verify) to 60% (nearly all do).
    hits = answered + int(rays * rng.uniform(0, 0.1)) if on else 0
    v_int, v_leaf, v_tri = (int(hits * rng.uniform(0, 5)), hits, int(hits * rng.uniform(1, 3))) \
        if on else (0, 0, 0)
    c["interior_visited"] = int(traced * interior) + v_int
    c["leaves_visited"] = int(traced * leaf) + v_leaf
    c["triangles_tested"] = int(traced * tri) + v_tri
    if on:
        c["hrpp"] = {"probes": rays, "traced": traced, "predictor_hits": hits,
                     "verify_interior": v_int, "verify_leaves": v_leaf,
                     "verify_triangles": v_tri, "predicted_traces": dispatches,
                     "insert_requests": int(traced * rng.uniform(0.3, 1.0))}
    return c


SUBGROUP = 8


def synthetic_stats(rng, on, frames=6):
    """A stats JSON's "frames" with random counts and kernel times from TRUE (1% noise)."""
    node_bytes = int(2**rng.uniform(16, 28))
    out = {"frames": [], "memory": {"buffers": {"BVH node array": node_bytes}},
           "device": {"subgroup_size": SUBGROUP}}
    for _ in range(frames):
        classes = {}
        for cls in cm.CLASSES:
            c = synthetic_class(rng, on, int(rng.integers(1, 16)))
            obs = {"class": cls, "counts": cm.class_counts(c, node_bytes, SUBGROUP,
                                                           cm.TRACE_KERNEL[cls] == "trace_any")}
            ms = {cm.TRACE_KERNEL[cls]: cm.predict_kernel(TRUE, obs, f"trace:{cls}")}
            if on:
                for k in cm.STAGE_KERNELS:
                    ms[k] = cm.predict_kernel(TRUE, obs, k)
            c["kernels_ms"] = {k: v * rng.normal(1, 0.01) for k, v in ms.items()}
            classes[cls] = c
        out["frames"].append({"classes": classes})
    return out


def weight(obs, model, op):
    """The median share of its kernel's time that one operation takes where it occurs (the
    hit-any steps only in the shadow class's predict kernel, for one)."""
    i = cm.model_features(model).index(op)
    shares = [cm.feature_row(o, model)[i] * TRUE[model][op] / t for o in obs
              if (t := cm.predict_kernel(TRUE, o, model)) > 0 and model in o["ms"]
              and cm.feature_row(o, model)[i] > 0]
    return float(np.median(shares)) if shares else 0.0


def check_fit():
    rng = np.random.default_rng(7)
    runs = {(f"scene{i}", s): synthetic_stats(rng, s == "on") for i in range(12)
            for s in ("off", "on")}
    obs = [o for key, st in runs.items() for o in cm.observations(st, key)]
    fitted = cm.fit([o for o in obs if o["run"][0] != "scene11"])
    checked = []
    for model, costs in TRUE.items():
        for op, c in costs.items():
            if weight(obs, model, op) < 0.05:
                continue  # under 5% of the kernel's time somewhere: not identifiable
            got = fitted[model][op]
            assert abs(got / c - 1) < 0.10, f"{model} {op}: fitted {got / NS:.1f} ns, true {c / NS:.1f}"
            checked.append((model, op))
    assert len(checked) >= 12, \
        f"only {len(checked)} costs carry weight: the synthetic data is too narrow"
    # The subgroup steps with a hit grow with the hit rate but not in proportion to the hits, so
    # they are told apart from the per-hit costs, for each predict kernel.
    for op in ("hit_steps", "hit_steps_any"):
        assert ("hrpp_predict", op) in checked, f"hrpp_predict {op} carries no weight: not checked"
    checked = len(checked)
    held = cm.class_totals([o for o in obs if o["run"][0] == "scene11"], fitted)
    worst = max(abs(t["modelled"] / t["measured"] - 1) for t in held.values())
    assert worst < 0.05, f"held-out class times off by {worst:.3f}"
    print(f"hrpp_model_test: fit recovers {checked} costs within 10%, held out within {worst:.3f}")
    return obs


def check_break_even(obs):
    pick = lambda run, cls: [o for o in obs if o["run"] == run and o["class"] == cls]
    for cls in cm.CLASSES:
        cc = cm.ClassCosts(TRUE, cm.per_ray_rates(pick(("scene0", "off"), cls)),
                           cm.per_ray_rates(pick(("scene0", "on"), cls)), f"trace:{cls}")
        a = cc.break_even_answered()
        if np.isfinite(a):
            assert abs(cc.ratio(a=a) - 1) < 1e-9, (cls, a, cc.ratio(a=a))
        s = cc.break_even_probe() * cc.interior_cost
        assert abs(cc.ratio(s=s) - 1) < 1e-9, (cls, s, cc.ratio(s=s))
        # More answered rays and cheaper probes can only lower the modelled on/off.
        assert cc.ratio(a=0.9) < cc.ratio(a=0.1) and cc.ratio(s=0) < cc.ratio()
        # With no queue costs and a free probe, answering every ray costs only verification.
        assert abs(cc.ratio(a=1.0, s=0.0, queue=False) - (1 + cc.f) * cc.v / cc.trace_only) < 1e-9
    print("hrpp_model_test: break-even answers solve on/off = 1")


def check_least_disturbed():
    """Three renders of one run, each disturbed (+30%) in other frames and classes: the
    observations hrpp_model fits are the undisturbed ones, which no whole render holds."""
    clean = synthetic_stats(np.random.default_rng(3), True, frames=3)
    repeats = []
    for r in range(3):
        stats = copy.deepcopy(clean)
        for i, frame in enumerate(stats["frames"]):
            for j, cls in enumerate(cm.CLASSES):
                if (i + j) % 3 == r:
                    ms = frame["classes"][cls]["kernels_ms"]
                    for k in ms:
                        ms[k] *= 1.3
        repeats.append(stats)
    got = hm.least_disturbed(repeats, ("scene", "on"))
    want = cm.observations(clean, ("scene", "on"))
    assert [(o["frame"], o["class"]) for o in got] == [(o["frame"], o["class"]) for o in want]
    assert all(abs(g["class_ms"] - w["class_ms"]) < 1e-12 for g, w in zip(got, want)), \
        "a disturbed frame was fitted"
    print("hrpp_model_test: each frame and class timed by its least disturbed render")
    # The device's own spread: renders 10% and 20% slower than the first, pair by pair.
    scaled = []
    for k in range(3):
        stats = copy.deepcopy(clean)
        for frame in stats["frames"]:
            for c in frame["classes"].values():
                c["kernels_ms"] = {n: v * (1 + 0.1 * k) for n, v in c["kernels_ms"].items()}
        scaled.append(stats)
    # ("default" is the adaptive predictor's setting, which the model does not fit.)
    twins = hm.twin_rows({("scene", "keys"): scaled, ("scene", "default"): scaled})
    got = sorted(round(r["error"], 9) for r in twins)
    assert got == sorted([0.1, 0.2, round(1.2 / 1.1 - 1, 9)] * len(cm.CLASSES)), got
    assert hm.twin_rows({("scene", "keys"): scaled[:1]}) is None
    print("hrpp_model_test: the renders' own spread, pair by pair")


if __name__ == "__main__":
    check_break_even(check_fit())
    check_least_disturbed()

"""The cost model, the library of study/model.py (not a command): a device's cost per
operation, fitted from the kernels' timestamps and counters of `hrpp render --stats` files, and
what it says about where prediction pays.

Every kernel of a ray class is modelled as a sum of operations times their costs (ms each):

  trace (trace_closest, trace_any): dispatch, ray traced, interior node, leaf, triangle test,
                                    interior node of a ray the HRPP queue compacted (extra)
  hrpp_predict:                     dispatch, probe, verified interior node, leaf, triangle,
                                    subgroup step with a predictor hit (hit-all, hit-any)
  hrpp_resolve:                     dispatch, queue entry (a ray the prediction did not answer),
                                    insert (a queued ray's hit offered to the table)

The counts come from the stats of each frame and class ("frames"[i]["classes"][class]); the
trace kernel's share of the counters is the class's minus what verification spent. Each kernel's
costs are fitted by non-negative least squares on relative error (every observation weighs the
same whatever its size), one set per device and, for the trace kernels, per ray class: camera
rays are coherent and bounce rays are not, so a node visit costs each class its own time on a
SIMD device (lavapipe: 55-70 ns for camera rays, 75-120 ns for bounce rays). For the same
reason a verification costs a subgroup the longest of its lanes' verifications: hrpp_predict
pays, besides the work each verifying lane does, for every subgroup step (the subgroup's lanes
probing one ray each) in which some lane verifies, with its own cost for the hit-all kernel
(hrpp_predict) and the hit-any one (hrpp_predict_any, whose entries hold subtrees). Used by
study/model.py (the command) and study/tests/hrpp_model_test.py.
"""
import numpy as np

CLASSES = ["camera", "bounce", "shadow"]
TRACE_KERNEL = {"camera": "trace_closest", "bounce": "trace_closest", "shadow": "trace_any"}
STAGE_KERNELS = ["hrpp_predict", "hrpp_resolve"]
FEATURES = {
    "trace": ["dispatch", "ray", "interior", "leaf", "triangle", "queued_interior",
              "interior_memory"],
    "hrpp_predict": ["dispatch", "probe", "verify_interior", "verify_leaf", "verify_triangle",
                     "hit_steps", "hit_steps_any"],
    "hrpp_resolve": ["dispatch", "queue_entry", "insert"],
}
MODELS = [f"trace:{c}" for c in CLASSES] + STAGE_KERNELS


def trace_ms(kernels_ms, cls):
    """A class's trace time: its trace kernel's, and the skipping variant's that traces HRPP's
    queue with --hrpp-fallback skip."""
    kernel = TRACE_KERNEL[cls]
    return kernels_ms.get(kernel, 0.0) + kernels_ms.get(kernel + "_skipping", 0.0)


def model_features(model):
    return FEATURES["trace" if model.startswith("trace") else model]


def memory_depth(node_bytes):
    """log2 of the BVH node array over 1 MiB (0 below): how far beyond a cache the node fetches
    reach. A node visit is modelled to cost k_interior + k_interior_memory * memory_depth."""
    return max(0.0, np.log2(max(node_bytes, 1) / 2**20))


def hit_steps(probes, hits, subgroup):
    """Subgroup steps (`subgroup` consecutive probes) in which at least one probe hit the table,
    for `hits` hits among `probes` probes spread over the lanes independently."""
    if probes <= 0 or hits <= 0:
        return 0.0
    return probes / subgroup * (1.0 - (1.0 - min(hits / probes, 1.0))**subgroup)


def class_counts(c, node_bytes=0, subgroup=1, any_hit=False):
    """Operation counts of one class in one frame (a "classes" entry of the stats JSON) in a
    scene whose BVH node array holds `node_bytes`, on a device of `subgroup` lanes; `any_hit`:
    the class's rays are hit-any (hrpp_predict_any)."""
    h = c.get("hrpp")
    probes = h["probes"] if h else 0
    queued = h["traced"] if h else 0
    v_int = h["verify_interior"] if h else 0
    v_leaf = h["verify_leaves"] if h else 0
    v_tri = h["verify_triangles"] if h else 0
    steps = hit_steps(probes, h["predictor_hits"], subgroup) if h else 0.0
    trace_rays = c["rays"] - (probes - queued)
    trace_interior = c["interior_visited"] - v_int
    return {
        "rays": c["rays"],
        "probes": probes,
        "answered": probes - queued,
        "predictor_hits": h["predictor_hits"] if h else 0,
        "trace": {"dispatch": c["trace_dispatches"], "ray": trace_rays,
                  "interior": trace_interior, "leaf": c["leaves_visited"] - v_leaf,
                  "triangle": c["triangles_tested"] - v_tri,
                  # the share of the visits made by rays the HRPP queue compacted
                  "queued_interior": trace_interior * queued // max(trace_rays, 1),
                  "interior_memory": trace_interior * memory_depth(node_bytes)},
        "hrpp_predict": {"dispatch": h["predicted_traces"] if h else 0, "probe": probes,
                         "verify_interior": v_int, "verify_leaf": v_leaf,
                         "verify_triangle": v_tri,
                         "hit_steps": 0.0 if any_hit else steps,
                         "hit_steps_any": steps if any_hit else 0.0},
        "hrpp_resolve": {"dispatch": h["predicted_traces"] if h else 0, "queue_entry": queued,
                         "insert": h["insert_requests"] if h else 0},
    }


def observations(stats, run):
    """One observation per frame and class of a stats JSON: counts and kernel times (ms)."""
    out = []
    node_bytes = stats.get("memory", {}).get("buffers", {}).get("BVH node array", 0)
    subgroup = stats.get("device", {}).get("subgroup_size", 1)
    for i, frame in enumerate(stats["frames"]):
        for cls in CLASSES:
            c = frame["classes"][cls]
            if c["rays"] == 0:
                continue
            ms = c["kernels_ms"]
            out.append({"run": run, "frame": i, "class": cls,
                        "counts": class_counts(c, node_bytes, subgroup,
                                               TRACE_KERNEL[cls] == "trace_any"),
                        "ms": {f"trace:{cls}": trace_ms(ms, cls),
                               "hrpp_predict": ms.get("hrpp_predict", 0.0),
                               "hrpp_resolve": ms.get("hrpp_resolve", 0.0)},
                        "class_ms": sum(ms.values())})
    return out


def feature_row(obs, model):
    counts = obs["counts"]["trace" if model.startswith("trace") else model]
    return [float(counts[f]) for f in model_features(model)]


def rows_for(obs_list, model):
    """The observations that ran `model`, as a feature matrix and the measured times."""
    chosen = [o for o in obs_list if model in o["ms"] and any(feature_row(o, model))]
    x = np.array([feature_row(o, model) for o in chosen]).reshape(-1, len(model_features(model)))
    y = np.array([o["ms"][model] for o in chosen])
    return x, y


def nnls(a, b):
    """min |a x - b| with x >= 0: Lawson and Hanson's active-set method (numpy alone, so the
    model also runs where SciPy is not installed, e.g. a GPU machine's bare Python)."""
    n = a.shape[1]
    tol = 10 * np.finfo(float).eps * np.abs(a).sum(axis=0).max() * max(a.shape)
    active, x = np.zeros(n, bool), np.zeros(n)
    for _ in range(3 * n):
        w = a.T @ (b - a @ x)
        if active.all() or np.where(active, -np.inf, w).max() <= tol:
            break
        active[np.argmax(np.where(active, -np.inf, w))] = True
        while True:  # least squares on the active set, stepping back while it leaves x >= 0
            z = np.zeros(n)
            z[active] = np.linalg.lstsq(a[:, active], b, rcond=None)[0]
            if (z[active] > tol).all():
                x = z
                break
            neg = active & (z <= tol)
            x = x + np.min(x[neg] / (x[neg] - z[neg])) * (z - x)
            active &= x > tol
            x[~active] = 0.0
    return x


def fit(obs_list):
    """Costs per operation, {model: {feature: ms}}, fitted on relative error."""
    costs = {}
    for model in MODELS:
        x, y = rows_for(obs_list, model)
        if len(y) == 0:
            continue
        keep = y > 0
        x, y = x[keep], y[keep]
        scale = x.max(axis=0)
        scale[scale == 0] = 1.0
        w = 1.0 / y  # relative error: each row divided by its measured time
        c = nnls(x / scale * w[:, None], np.ones_like(y)) / scale
        costs[model] = dict(zip(model_features(model), c.tolist()))
    return costs


def predict_kernel(costs, obs, model):
    if model not in costs:
        return 0.0
    return float(np.dot(feature_row(obs, model), [costs[model][f] for f in model_features(model)]))


def predict_class_ms(costs, obs):
    """The class's modelled kernel time in one frame: its trace kernel plus, when it probed,
    the HRPP stage's kernels."""
    models = [f"trace:{obs['class']}"]
    if obs["counts"]["probes"] > 0:
        models += STAGE_KERNELS
    return sum(predict_kernel(costs, obs, m) for m in models)


def class_totals(obs_list, costs):
    """Per (run, class): measured and modelled time summed over the frames."""
    totals = {}
    for o in obs_list:
        t = totals.setdefault((o["run"], o["class"]), {"measured": 0.0, "modelled": 0.0})
        t["measured"] += o["class_ms"]
        t["modelled"] += predict_class_ms(costs, o)
    return totals


def per_ray_rates(obs_list):
    """A class's operations per ray summed over frames: {name: count per ray or per probe}."""
    rays = sum(o["counts"]["rays"] for o in obs_list)
    probes = sum(o["counts"]["probes"] for o in obs_list)
    hits = sum(o["counts"]["predictor_hits"] for o in obs_list)
    total = lambda m, f: sum(o["counts"][m][f] for o in obs_list)
    r = {"rays": rays, "probes": probes}
    r["trace"] = {f: total("trace", f) / rays for f in FEATURES["trace"]}
    if probes:
        r["answered"] = sum(o["counts"]["answered"] for o in obs_list) / probes
        r["hit_rate"] = hits / probes
        r["verify"] = {f: total("hrpp_predict", f) / max(hits, 1)
                       for f in FEATURES["hrpp_predict"][2:]}
        queued = total("hrpp_resolve", "queue_entry")
        r["insert_per_queued"] = total("hrpp_resolve", "insert") / max(queued, 1)
        r["predict_dispatch"] = total("hrpp_predict", "dispatch") / probes
    return r


class ClassCosts:
    """A class's costs per ray on one device, from the fitted costs and the counts of an
    HRPP-off run (its traversal) and an HRPP-on run (its prediction rates):
      C   trace cost per ray of HRPP off (traversal + dispatch share); an "interior-node
          visit", the unit of probe costs, is the traversal's cost per interior node visited
      s   probe: hrpp_predict's cost per probed ray, verification excluded
      v   verification per predictor hit, its subgroup steps' cost included at the measured
          hit rate (a linear stand-in for the steps, which grow less than the hits do)
      r   per queued ray: its extra trace cost (its interior visits cost more once the queue
          has taken its neighbours away) + hrpp_resolve's queue entry and insert share
      d   the stage's dispatches per probed ray
    On/off time of the class at answered share a and predictor-hit share h = a + f:
      (s + d + h v + (1 - a) (C' + r) + (C - C')) / C,   C' = C without its dispatch share
    (the trace's dispatches stay when HRPP is on)."""

    def __init__(self, costs, off_rates, on_rates, trace_model):
        k = costs[trace_model]
        t = off_rates["trace"]
        self.trace_only = sum(k[f] * t[f] for f in ("ray", "interior", "leaf", "triangle",
                                                     "interior_memory"))
        self.C = self.trace_only + k["dispatch"] * t["dispatch"]
        # The unit of probe costs: the traversal's time per interior node visited, its leaves,
        # triangles and ray set-up included (robust where the fit trades those costs off).
        self.interior_cost = self.trace_only / t["interior"] if t["interior"] > 0 else 0.0
        self.q = k["queued_interior"] * t["interior"]
        p, res = costs["hrpp_predict"], costs["hrpp_resolve"]
        self.s = p["probe"]
        self.v = sum(p[f] * on_rates["verify"][f] for f in on_rates["verify"])
        self.r = self.q + res["queue_entry"] + res["insert"] * on_rates["insert_per_queued"]
        self.d = (p["dispatch"] + res["dispatch"]) * on_rates["predict_dispatch"]
        self.a = on_rates["answered"]
        self.f = max(on_rates["hit_rate"] - self.a, 0.0)

    def ratio(self, a=None, s=None, queue=True):
        """Modelled on/off time; `queue=False` drops the queue's costs (resolve, dispatches,
        the compacted trace's own dispatches), as a hardware predictor would."""
        a = self.a if a is None else a
        s = self.s if s is None else s
        h = a + self.f
        if self.trace_only <= 0:
            return float("nan")  # the fit gave this class's trace no cost: nothing to compare
        if queue:
            dispatch = self.C - self.trace_only
            return (s + self.d + h * self.v + (1 - a) * (self.trace_only + self.r) +
                    dispatch) / self.C
        return (s + h * self.v + (1 - a) * self.trace_only) / self.trace_only

    def break_even_answered(self):
        """The answered share at which on/off = 1 at today's probe cost (>1: never)."""
        denom = self.trace_only + self.r - self.v
        if denom <= 0:
            return float("inf")
        return (self.s + self.d + self.f * self.v + self.r) / denom

    def break_even_probe(self):
        """The probe cost, in interior-node visits, at which on/off = 1 at the measured answered
        share (<0: no probe cost is cheap enough)."""
        h = self.a + self.f
        s = self.trace_only - self.d - h * self.v - (1 - self.a) * (self.trace_only + self.r)
        return s / self.interior_cost if self.interior_cost > 0 else float("nan")

    def probe_in_interior_visits(self):
        return self.s / self.interior_cost if self.interior_cost > 0 else float("nan")

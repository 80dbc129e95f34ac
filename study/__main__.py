"""The study's one entry point: `python3 -m study COMMAND [options]` at the repository's root, or
`python3 PATH/TO/study COMMAND` from anywhere. `COMMAND --help` tells each command's options."""
import importlib
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the repository
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # the commands import common

# command: (module, what it does). One name table: the help below and the dispatch read it.
COMMANDS = {
    "sweep": (None, "the limit study in one command: render, collect, draw, report"),
    "bench": ("bench", "is HRPP faster? on against off per ray class and frame"),
    "model": ("model", "where would HRPP pay? a device's fitted cost per operation"),
    "cpu-model": ("cpu_model", "where would HRPP pay on the CPU? the inline predictor's model"),
    "cpu-table": ("cpu_table", "HRPP inline on the CPU against the same traversal without it"),
    "keys": ("keys", "the keys per ray class (results/KEYS.md)"),
    "micro21": ("micro21", "MICRO'21's predictor beside HRPP's on the same rays"),
    "ray-maps": ("ray_maps", "per-pixel pictures of where prediction works, per ray class"),
    "figures": ("figures", "the limit study's figures from the sweep CSV"),
    "error": ("estimator_error", "how fast hrpp's estimator converges, per strategy and sampler"),
    "cycles": ("cycles", "hrpp render against Blender's Cycles on the same integral"),
    "embree-check": ("embree_check", "hrpp bench's Embree figure against an independent harness"),
    "rayquery-table": ("rayquery_table", "the driver's ray queries beside the kernels and Embree"),
    "driver-ab": ("driver_ab", "Vulkan drivers and hrpp binaries on the same rays, interleaved"),
    "render-ab": ("render_ab", "hrpp binaries rendering the same frames, interleaved"),
    "build-scaling": ("build_scaling", "BVH build time and memory across scene sizes"),
    "render-session": ("render_session", "what stopping, limiting and sharing a render cost"),
    "big-scene": ("big_scene", "writes a big scene manifest of many meshes"),
    "sweep-jobs": ("sweep_jobs", "(sweep's step) the job list of a mode's grids"),
    "sweep-collect": ("sweep_collect", "(sweep's step) the runs' stats and errors as one CSV"),
    "sweep-report": ("sweep_report", "(sweep's step) the CSV's generated blocks"),
    "sweep-provenance": ("common", "(sweep's step) OUT/provenance.json before|after the renders"),
}
HERE = os.path.dirname(os.path.abspath(__file__))


def usage():
    width = max(len(c) for c in COMMANDS)
    lines = [f"  {c.ljust(width)}  {what}" for c, (_, what) in COMMANDS.items()]
    return "usage: python3 -m study COMMAND [options]\n\ncommands:\n" + "\n".join(lines)


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(usage())
        return 0 if len(sys.argv) >= 2 else 2
    command, args = sys.argv[1], sys.argv[2:]
    if command not in COMMANDS:
        print(f"study: unknown command '{command}'\n{usage()}", file=sys.stderr)
        return 2
    if command == "sweep":  # a shell pipeline around GNU parallel
        os.execv("/bin/bash", ["bash", os.path.join(HERE, "sweep.sh"), *args])
    module = importlib.import_module(COMMANDS[command][0])
    sys.argv = [f"study {command}", *args]
    if command == "sweep-provenance":
        return module.provenance_main(args)
    return module.main() or 0


if __name__ == "__main__":
    sys.exit(main())

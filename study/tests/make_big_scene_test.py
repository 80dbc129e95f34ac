#!/usr/bin/env python3
"""python3 -m study big-scene --layout random: a small variant from the committed meshes loads in
hrpp with the triangle count the tool prints (witness: hrpp scene --json), the same seed writes
the same manifest and another seed another, and bad flags are one-line errors.

Usage: study/tests/make_big_scene_test.py HRPP WORKDIR
"""
import json
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STUDY = os.path.join(REPO, "study")


def make(out, *flags):
    r = subprocess.run([sys.executable, STUDY, "big-scene", "--layout", "random", "--out", out, *flags],
                       capture_output=True, text=True)
    return r


def main():
    hrpp, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    a, b, c = (os.path.join(work, f"{n}.scene.json") for n in "abc")
    flags = ["--triangles", "300000", "--meshes", "bunny,teapot"]
    r = make(a, *flags, "--seed", "7")
    assert r.returncode == 0, r.stderr
    printed = int(r.stdout.split(",")[-1].split()[0])
    assert make(b, *flags, "--seed", "7").returncode == 0
    assert make(c, *flags, "--seed", "8").returncode == 0
    assert open(a).read() == open(b).read(), "the same seed wrote another manifest"
    assert open(a).read() != open(c).read(), "another seed wrote the same manifest"
    doc = json.load(open(a))
    meshes = [o for o in doc["objects"] if "gltf" in o]
    assert len(meshes) >= 3, len(meshes)
    sizes = {o["fit"]["size"] for o in meshes}
    assert len(sizes) == len(meshes), "sizes should differ"
    stats = json.loads(subprocess.run([hrpp, "scene", a, "--json"], capture_output=True,
                                      text=True, check=True).stdout)
    assert stats["triangles"] == printed, (stats["triangles"], printed)
    assert printed >= 300000 + 4, printed
    for bad, word in ((["--triangles", "0"], "--triangles"), (["--meshes", "cube"], "--meshes")):
        r = make(os.path.join(work, "bad.scene.json"), *bad)
        assert r.returncode != 0 and word in r.stderr and r.stderr.count("\n") == 1, r.stderr
        assert not os.path.exists(os.path.join(work, "bad.scene.json"))
    print("make_big_scene_test: ok,", printed, "triangles")


if __name__ == "__main__":
    main()

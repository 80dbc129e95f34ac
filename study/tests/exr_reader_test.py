#!/usr/bin/python3
"""study/common.py's numpy EXR reader (for a Python without OpenImageIO, reading what a
portable build writes) against OpenImageIO on the same files: a small hrpp render, rewritten
by oiiotool as an uncompressed float EXR, reads back equal value for value; a compressed file is
refused with a message that says so. Usage: exr_reader_test.py HRPP_BINARY WORK_DIR"""
import os
import subprocess
import sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import numpy as np  # noqa: E402
import common  # noqa: E402


def main():
    hrpp, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    compressed = os.path.join(work, "render.exr")
    plain = os.path.join(work, "plain.exr")
    subprocess.run([hrpp, "render", "--size", "24x16", "--spp", "2", "--out", compressed],
                   check=True, capture_output=True)
    subprocess.run(["oiiotool", compressed, "-d", "float", "--compression", "none", "-o", plain],
                   check=True)
    mine = common.read_uncompressed_exr(plain)
    assert mine.shape == (16, 24, 3), mine.shape
    assert mine.max() > 0, "the render is black: the comparison would prove little"
    assert np.array_equal(mine, common.read_exr(plain)), "differs from OpenImageIO's read"
    assert np.array_equal(mine, common.read_exr(compressed)), "differs from the render"
    try:
        common.read_uncompressed_exr(compressed)
    except RuntimeError as e:
        assert "compressed" in str(e), e
    else:
        raise AssertionError("a compressed EXR was read as if uncompressed")
    print("exr_reader_test: the numpy reader equals OpenImageIO on", plain)


if __name__ == "__main__":
    main()

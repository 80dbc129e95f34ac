#!/usr/bin/python3
"""The stages' include graph: which folder of host/ includes which, and whether it has a cycle.

Each folder of host/ is a stage (docs/ARCHITECTURE.md, "Stages and data flow"); a file's
`#include "FOLDER/..."` of another stage is an edge from its stage to that one. Prints the edges
and every cycle; exits 1 when there is one (the test suite's include_graph_test), so that the
stages keep their one-way order.

Usage: tests/code_checks/include_graph.py [REPO]
"""
import os
import re
import sys

INCLUDE = re.compile(r'#include "([a-z_]+)/')


def edges(host):
    """{stage: set of the stages its files include}."""
    stages = {d for d in os.listdir(host) if os.path.isdir(os.path.join(host, d))}
    out = {s: set() for s in stages}
    for stage in stages:
        for folder, _, files in os.walk(os.path.join(host, stage)):
            for name in files:
                if not name.endswith((".h", ".cpp")):
                    continue
                with open(os.path.join(folder, name), errors="replace") as f:
                    for line in f:
                        m = INCLUDE.match(line)
                        if m and m.group(1) in stages and m.group(1) != stage:
                            out[stage].add(m.group(1))
    return out


def cycles(graph):
    """Every cycle, once each, as a list of stages that ends where it starts."""
    found = set()
    def visit(node, path):
        for nxt in sorted(graph[node]):
            if nxt in path:
                cycle = path[path.index(nxt):]
                start = cycle.index(min(cycle))
                found.add(tuple(cycle[start:] + cycle[:start]))
            else:
                visit(nxt, path + [nxt])
    for n in sorted(graph):
        visit(n, [n])
    return [list(c) + [c[0]] for c in sorted(found)]


def main():
    repo = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
    graph = edges(os.path.join(repo, "host"))
    for stage in sorted(graph):
        print(f"{stage:11s} -> {', '.join(sorted(graph[stage])) or '(none)'}")
    found = cycles(graph)
    for c in found:
        print("cycle: " + " -> ".join(c))
    sys.exit(1 if found else 0)


if __name__ == "__main__":
    main()

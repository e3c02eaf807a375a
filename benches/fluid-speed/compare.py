#!/usr/bin/env python3
"""Compares two runs of one case (the native fluid's and pisoFoam's) for the speed benchmark.

    compare.py fields OURS THEIRS TIME     max |a − b| / max |b| of U, p, k, epsilon, nut at TIME
    compare.py iters LOG                   linear-solver iterations per equation in a log

Both logs have OpenFOAM's lines `…: Solving for Ux, Initial residual = …, No Iterations N`
(pisoFoam) or `Ux: Initial residual = …, No Iterations N` (`foamgrain fluid --log`); the
iterations are summed per equation over the run, and the number of solves is given too.
The fields are read from ASCII `internalField nonuniform List<…>` (uniform fields compare as
their one value)."""
import re
import sys
from pathlib import Path


def internal(path):
    text = Path(path).read_text()
    m = re.search(r"internalField\s+uniform\s+(\([^)]*\)|[^;]+);", text)
    if m:
        v = m.group(1).strip("() ").split()
        return [float(x) for x in v]
    m = re.search(r"internalField\s+nonuniform\s+List<\w+>\s*(\d+)\s*\(", text)
    if not m:
        raise SystemExit(f"{path}: no internalField")
    n = int(m.group(1))
    body = text[m.end():]
    depth, end = 1, 0
    for i, ch in enumerate(body):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                end = i
                break
    vals = [float(x) for x in body[:end].replace("(", " ").replace(")", " ").split()]
    if len(vals) % n:
        raise SystemExit(f"{path}: {len(vals)} numbers for {n} values")
    return vals


def fields(ours, theirs, time):
    for name in ["U", "p", "k", "epsilon", "nut"]:
        a_path, b_path = Path(ours) / time / name, Path(theirs) / time / name
        if not b_path.exists():
            continue
        a, b = internal(a_path), internal(b_path)
        if len(a) != len(b):
            raise SystemExit(f"{name}: {len(a)} against {len(b)} values")
        scale = max(abs(x) for x in b) or 1.0
        diff = max(abs(x - y) for x, y in zip(a, b))
        print(f"{name:8s} max|diff|/max|ref| = {diff / scale:.2e}")


def iters(log):
    tot, n = {}, {}
    pat = re.compile(r"(?:Solving for |^)(\w+)(?:,|:) Initial residual = .*No Iterations (\d+)")
    for line in Path(log).read_text().splitlines():
        m = pat.search(line)
        if m:
            k = m.group(1)
            tot[k] = tot.get(k, 0) + int(m.group(2))
            n[k] = n.get(k, 0) + 1
    for k in ["Ux", "Uy", "Uz", "p", "epsilon", "k"]:
        if k in tot:
            print(f"{k:8s} {tot[k]:7d} iterations in {n[k]:5d} solves")


if __name__ == "__main__":
    if sys.argv[1] == "fields":
        fields(*sys.argv[2:5])
    elif sys.argv[1] == "iters":
        iters(sys.argv[2])
    else:
        raise SystemExit(__doc__)

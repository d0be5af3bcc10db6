#!/usr/bin/env python3
"""How much of a skeleton's wood volume lies in the flare of the edges that leave its forks.

The wood volume (`measure_tree`, the summary's "wood volume") sums a frustum per edge, each from its
two nodes' radii. An edge that leaves a fork starts at the fork's node, whose radius is the parent
branch's, so a side branch's first frustum flares from the parent's radius to its own. This prints,
for each skeleton JSON (as `treeskel model CLOUD --skeleton FILE.json` writes it), the wood volume,
the share of it in edges that leave a fork, and the volume when each such edge starts at the smaller
of its two radii, over the volume as it is.

Usage: python3 bench/fork_flare.py SKELETON.json...
"""
import json
import math
import sys
from collections import defaultdict


def frustum(r1, r2, length):
    return math.pi * length / 3.0 * (r1 * r1 + r1 * r2 + r2 * r2)


def flare(path):
    skeleton = json.load(open(path))
    nodes = {n["id"]: n for n in skeleton["nodes"]}
    around = defaultdict(list)
    for a, b in skeleton["edges"]:
        around[a].append(b)
        around[b].append(a)
    parent = {skeleton["root"]: None}
    order = [skeleton["root"]]
    for u in order:  # breadth first from the root: parents before children
        for v in around[u]:
            if v not in parent:
                parent[v] = u
                order.append(v)
    volume = from_fork = capped = 0.0
    for v in order[1:]:
        p = parent[v]
        length = math.dist(nodes[p]["position"], nodes[v]["position"])
        rp, rv = nodes[p]["radius"], nodes[v]["radius"]
        x = frustum(rp, rv, length)
        volume += x
        children = [w for w in around[p] if w != parent[p]]
        if len(children) >= 2:
            from_fork += x
            capped += frustum(min(rp, rv), rv, length)
        else:
            capped += x
    return volume, from_fork, capped


def main(paths):
    if not paths:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    print("| skeleton | wood volume | in edges leaving a fork | volume with those edges from the smaller radius / as it is |")
    print("|---|---:|---:|---:|")
    for path in paths:
        volume, from_fork, capped = flare(path)
        share = from_fork / volume if volume > 0 else 0.0
        ratio = capped / volume if volume > 0 else 1.0
        print(f"| {path} | {volume:.5g} | {share:.3f} | {ratio:.4f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

#!/usr/bin/python3
"""Renders a triangle mesh (OBJ) to a PNG with matplotlib: flat shading, one light, orthographic.

Usage: docs/render_mesh.py MESH.obj OUT.png [--up z|y] [--azimuth DEG] [--elevation DEG] [--title TEXT]
Needs python3-matplotlib and python3-numpy (Debian packages).
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append([idx[0], idx[k], idx[k + 1]])
    return np.array(vertices), np.array(faces, dtype=int)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh")
    ap.add_argument("out")
    ap.add_argument("--up", default="z", choices=["z", "y"])
    ap.add_argument("--azimuth", type=float, default=-60.0)
    ap.add_argument("--elevation", type=float, default=12.0)
    ap.add_argument("--title", default="")
    args = ap.parse_args()

    v, f = read_obj(args.mesh)
    if args.up == "y":
        v = v[:, [0, 2, 1]] * np.array([1.0, -1.0, 1.0])
        f = f[:, [0, 2, 1]]
    v = v - v.min(axis=0)
    tri = v[f]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
    light = np.array([0.4, -0.6, 0.7])
    light /= np.linalg.norm(light)
    shade = 0.35 + 0.65 * np.clip(normals @ light, 0.0, 1.0)
    bark = np.array([0.55, 0.40, 0.27])
    colours = np.clip(shade[:, None] * bark[None, :], 0.0, 1.0)

    extent = v.max(axis=0)
    fig = plt.figure(figsize=(5, 7), dpi=120)
    ax = fig.add_subplot(111, projection="3d", proj_type="ortho")
    ax.add_collection3d(Poly3DCollection(tri, facecolors=colours, edgecolors="none", linewidths=0))
    half = max(extent[0], extent[1]) / 2.0
    centre = extent / 2.0
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(0.0, extent[2])
    ax.set_box_aspect((2 * half, 2 * half, extent[2]))
    ax.view_init(elev=args.elevation, azim=args.azimuth)
    ax.set_axis_off()
    if args.title:
        ax.set_title(args.title)
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.95 if args.title else 1)
    fig.savefig(args.out)


if __name__ == "__main__":
    main()

"""treeskel: curve skeletons and tree models from raw point clouds.

The same method, options and defaults as the ``treeskel`` command (Fu et al., IEEE Access 2020, with
radii by the pipe model and one closed mesh of the wood). Options are keyword arguments named as the
command's, with dashes as underscores: ``cell_points=3`` for ``--cell-points 3``, ``no_cpc=True`` for
``--no-cpc``. Errors of the input or the options raise ``ValueError`` with the library's message. The
work runs without the GIL, so threads convert trees in parallel.

    import treeskel
    skeleton, mesh, measurements = treeskel.model("scan.las")
    mesh.save("tree.glb")

    trees = treeskel.plot("plot.laz", "out/")             # a plot: one model per tree, as `treeskel plot`
    labels = treeskel.segment_plot(points)["tree"]         # the plot's trees, point by point
    wood, score = treeskel.separate_wood(points)           # wood and leaves, point by point
    skeleton = treeskel.extract_skeleton(points, wood_only=True)  # the skeleton of the wood alone

    skeleton = treeskel.extract_skeleton(points)          # an (N, 3) numpy array; pruned as skeletonize
                                                           # prunes (prune_radius=1, prune_point_radius=0,
                                                           # prune_bands=1, close_forks=0 as model() does)
    skeleton = treeskel.fit_radii(skeleton)                # radii by the pipe model
    mesh = treeskel.tree_mesh(skeleton)                    # vertices, faces as numpy arrays
    print(treeskel.measure(skeleton)["dbh"])
"""

from ._treeskel import (  # noqa: F401
    Cloud,
    Mesh,
    Skeleton,
    __version__,
    extract_skeleton,
    fit_radii,
    measure,
    model,
    read_cloud,
    read_skeleton,
    segment_plot,
    separate_wood,
    tree_mesh,
)

__all__ = [
    "Cloud",
    "Mesh",
    "Skeleton",
    "extract_skeleton",
    "fit_radii",
    "measure",
    "model",
    "read_cloud",
    "read_skeleton",
    "segment_plot",
    "separate_wood",
    "tree_mesh",
    "plot",
]


def plot(path, out_dir, **options):
    """Runs ``treeskel plot PATH -o OUT_DIR`` and returns its ``trees.json`` as a dict (one entry per
    tree in ``["trees"]``: stem position, height, crown base, DBH, volume, status, model). Options are
    the command's, as keyword arguments: ``segment_only=True``, ``jobs=2``, ``stem_slice=(0.5, 2.0)``,
    ``model="obj"``, ``keep_leaves=True`` (a tree that looks leafy is otherwise modelled from its wood,
    its ``leaf_points`` counted in its row), and every option of ``model``. A failed tree is a row with its error; a run that
    fails as a whole (no stem found, a bad option, an unreadable file) raises ``ValueError`` with the
    command's message."""
    import json
    import os
    import subprocess

    from .dask import _error_from, executable

    cmd = [executable(), "plot", os.fspath(path), "-o", os.fspath(out_dir), "-q"]
    for key, value in options.items():
        flag = ("-" if len(key) == 1 else "--") + key.replace("_", "-")
        if value is True:
            cmd.append(flag)
        elif value is False or value is None:
            continue
        elif isinstance(value, (tuple, list)):
            cmd += [flag, ",".join(str(v) for v in value)]
        else:
            cmd += [flag, str(value)]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, errors="replace")
    trees = os.path.join(os.fspath(out_dir), "trees.json")
    if done.returncode != 0 and (done.returncode == 2 or not os.path.exists(trees)):
        raise ValueError(_error_from(done.stderr, done.returncode))
    with open(trees) as f:
        result = json.load(f)
    if done.returncode != 0 and not result["trees"]:
        raise ValueError(_error_from(done.stderr, done.returncode))
    return result

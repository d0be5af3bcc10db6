"""treeskel: curve skeletons and tree models from raw point clouds.

The same method, options and defaults as the ``treeskel`` command (Fu et al., IEEE Access 2020, with
radii by the pipe model and one closed mesh of the wood). Options are keyword arguments named as the
command's, with dashes as underscores: ``cell_points=3`` for ``--cell-points 3``, ``no_cpc=True`` for
``--no-cpc``. Errors of the input or the options raise ``ValueError`` with the library's message. The
work runs without the GIL, so threads convert trees in parallel.

    import treeskel
    skeleton, mesh, measurements = treeskel.model("scan.las")
    mesh.save("tree.glb")

    skeleton = treeskel.extract_skeleton(points)          # an (N, 3) numpy array
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
    "tree_mesh",
]

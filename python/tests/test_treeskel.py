"""The Python package against the command line, on the bundled clouds: the same results for the same
options, errors as Python exceptions, no leak, the GIL released during the work."""
import json
import subprocess
import threading
import time
import warnings

import numpy as np
import pytest

import treeskel


def run(exe, *args):
    done = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


def test_skeleton_from_numpy_equals_the_commands(exe, data, tmp_path):
    points = np.loadtxt(data / "tree_rtwig.txt")
    skeleton = treeskel.extract_skeleton(points, cell_points=3, up="z")
    skeleton.save(tmp_path / "py.json")
    run(exe, "skeletonize", data / "tree_rtwig.txt", "-o", tmp_path / "cli.json", "--cell-points", 3, "-q")
    assert json.loads((tmp_path / "py.json").read_text()) == json.loads((tmp_path / "cli.json").read_text())
    # Arrays as the file says: positions in the input's frame, edges, every point labelled.
    assert skeleton.positions.shape == (len(skeleton), 3)
    assert skeleton.edges.shape == (len(skeleton) - 1, 2)
    labels = skeleton.labels
    assert labels.shape == (len(points),)
    assert (labels >= -1).all() and labels.max() < len(skeleton)
    assert (labels >= 0).sum() + skeleton.left_out["total"] == len(points)
    assert np.abs(skeleton.positions.mean(axis=0) - points.mean(axis=0)).max() < 0.5


def test_model_equals_the_commands(exe, data, tmp_path):
    # Swept in the floats of the local frame, as the command with --local sweeps it.
    skeleton, mesh, measured = treeskel.model(str(data / "tree_rtwig.txt"), exponent=2.2, local=True)
    mesh.save(str(tmp_path / "py.ply"), local=True)
    report = tmp_path / "cli.json"
    run(exe, "model", data / "tree_rtwig.txt", "-o", tmp_path / "cli.ply", "--local", "--exponent", 2.2,
        "--report", report, "-q")
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    cli = json.loads(report.read_text())
    assert measured == cli["measurements"]
    check = mesh.check()
    assert check["ok"] and check["closed"] and check["manifold"] and check["components"] == 1
    assert check["triangles"] == cli["mesh"]["triangles"] == len(mesh.faces)
    assert mesh.vertices.shape == (check["vertices"], 3)
    assert mesh.faces.max() < len(mesh.vertices)
    # The stages one at a time give the same as model(), the skeleton pruned as a model prunes.
    fitted = treeskel.fit_radii(
        treeskel.extract_skeleton(treeskel.read_cloud(str(data / "tree_rtwig.txt")), prune_radius=1, prune_point_radius=0, prune_bands=1, close_forks=0), exponent=2.2)
    again = treeskel.tree_mesh(fitted, local=True)
    assert np.array_equal(again.faces, mesh.faces) and np.array_equal(again.vertices, mesh.vertices)
    assert np.array_equal(skeleton.radii, fitted.radii) and np.array_equal(skeleton.positions, fitted.positions)


@pytest.mark.parametrize("option, value, bad",
                         [("stem_share_bound", 2, 0.5), ("stub_length", 0, -1), ("fork_margin", 0, -1)])
def test_radius_options_as_the_command(exe, data, tmp_path, option, value, bad):
    # The bound on a stem fork's shares, the stubs' length (0: every tip a twig) and the margin before
    # a fork (0: every fit counts) reach the radii as `model --stem-share-bound`, `--stub-length` and
    # `--fork-margin` do.
    flag = "--" + option.replace("_", "-")
    cloud = str(data / "tree_adtree1.xyz")
    skeleton = treeskel.extract_skeleton(cloud)
    changed = treeskel.fit_radii(skeleton, **{option: value})
    assert not np.array_equal(changed.radii, treeskel.fit_radii(skeleton).radii)
    _, mesh, _ = treeskel.model(cloud, local=True, **{option: value})
    mesh.save(str(tmp_path / "py.ply"), local=True)
    run(exe, "model", cloud, "-o", tmp_path / "cli.ply", "--local", flag, value, "-q")
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    with pytest.raises(ValueError, match=flag[2:]):
        treeskel.fit_radii(skeleton, **{option: bad})


def test_model_warns_as_the_command_does(data):
    points = np.loadtxt(data / "tree_rtwig.txt")[:, :3]
    # The bundled tree as it is: nothing to warn about.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        treeskel.model(points)
    # At a fifth of its size it is 0.74 tall, shorter than breast height: the command's warning.
    with pytest.warns(UserWarning, match="shorter than breast height"):
        treeskel.model(points * 0.2)


def test_tree_mesh_warns_of_limbs_left_out(data):
    # Far bridging of parts of ten points or more, as the default was until 5 December 2026: its
    # skeleton has a limb (15% of its length) that finds no room at its fork. (With the default of 3
    # the limbs left out hold 3.5% of the length, under what the summary warns of; and with the limbs
    # straightened, as `fit_radii` does by default since 6 December 2026, 1%: stiffness=0 keeps the
    # skeleton's path; the spurs judged on the nodes' radii, as until 6 December 2026, with
    # prune_point_radius=0.)
    skeleton = treeskel.fit_radii(
        treeskel.extract_skeleton(str(data / "tree_adtree1.xyz"), far_bridge_points=10, prune_point_radius=0),
        stiffness=0)
    # Limbs not united (no_unite) are left out, and with them much of the skeleton: said, as the
    # command says it, though tree_mesh measures nothing.
    with pytest.warns(UserWarning) as said:
        treeskel.tree_mesh(skeleton, no_unite=True)
    texts = [str(w.message) for w in said]
    assert any("found no room at their forks" in t for t in texts), texts
    assert any("of the skeleton's length" in t for t in texts), texts
    # United, they are in the mesh: nothing to say.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        treeskel.tree_mesh(skeleton)


def modelled_as_the_command(exe, cloud, tmp_path, flag, **options):
    """treeskel.model(cloud, **options), asserting that its mesh is the command's with `flag`, byte for byte."""
    skeleton, mesh, _ = treeskel.model(cloud, **options)
    mesh.save(str(tmp_path / "py.ply"), local=True)
    run(exe, "model", cloud, "-o", tmp_path / "cli.ply", "--local", flag, "-q")
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    return skeleton


def test_complete_equals_the_commands(exe, data, tmp_path):
    cloud = str(data / "tree_adtree1.xyz")
    skeleton = modelled_as_the_command(exe, cloud, tmp_path, "--complete", complete=True)
    plain = treeskel.fit_radii(treeskel.extract_skeleton(cloud, prune_radius=1, prune_point_radius=0, prune_bands=1, close_forks=0))
    assert len(skeleton) > len(plain)  # the grown branches
    assert len(treeskel.fit_radii(treeskel.extract_skeleton(cloud, prune_radius=1, prune_point_radius=0, prune_bands=1, close_forks=0), complete=True)) == len(skeleton)
    # extract_skeleton prunes as skeletonize does, more than a model: fewer nodes.
    assert len(treeskel.extract_skeleton(cloud)) < len(treeskel.extract_skeleton(cloud, prune_radius=1, prune_point_radius=0, prune_bands=1, close_forks=0))


def test_complete_all_equals_the_command(exe, data, tmp_path):
    cloud = str(data / "tree_adtree1.xyz")
    skeleton = modelled_as_the_command(exe, cloud, tmp_path, "--complete-all", complete_all=True)
    some, _, _ = treeskel.model(cloud, complete=True)
    assert len(skeleton) > len(some)  # the tufts and bushes grown too


def test_bad_input_raises_value_error_with_the_message(tmp_path):
    with pytest.raises(ValueError, match=r"\(N, 3\) array.*got shape \(5, 2\)"):
        treeskel.extract_skeleton(np.zeros((5, 2)))
    with pytest.raises(ValueError, match="row 7 is not finite"):
        bad = np.random.default_rng(1).random((50, 3))
        bad[7, 2] = np.nan
        treeskel.extract_skeleton(bad)
    with pytest.raises(ValueError, match="needs at least 10"):
        treeskel.extract_skeleton(np.random.default_rng(2).random((5, 3)))
    with pytest.raises(ValueError, match="lie on one straight line"):
        treeskel.extract_skeleton(np.outer(np.arange(100.0), [1.0, 1.0, 1.0]))
    with pytest.raises(TypeError, match="unexpected keyword argument 'cellpoints'"):
        treeskel.extract_skeleton(np.zeros((20, 3)), cellpoints=3)
    with pytest.raises(ValueError, match="--cell-points"):
        treeskel.extract_skeleton(np.zeros((20, 3)), cell_points=-1)
    with pytest.raises(TypeError, match="switch"):
        treeskel.extract_skeleton(np.zeros((20, 3)), no_cpc=1)
    (tmp_path / "empty.xyz").write_text("")
    with pytest.raises(ValueError, match="empty"):
        treeskel.extract_skeleton(str(tmp_path / "empty.xyz"))
    with pytest.raises(ValueError, match="unknown mesh extension"):
        _, mesh, _ = treeskel.model(np.loadtxt(pathlib_data() / "tree_rtwig.txt"))
        mesh.save(str(tmp_path / "tree.abc"))


def pathlib_data():
    import os
    import pathlib

    return pathlib.Path(os.environ.get("TREESKEL_TEST_DATA", pathlib.Path(__file__).parents[2] / "data"))


def resident_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096 / 2**20


def test_no_leak_over_a_thousand_calls():
    rng = np.random.default_rng(3)
    # A small trunk: 2000 points on a cylinder of radius 0.1, 2 tall (a copy of them, 48 kB, left
    # behind by each call would add 48 MB).
    a = rng.uniform(0, 2 * np.pi, 2000)
    z = rng.uniform(0, 2, 2000)
    points = np.c_[0.1 * np.cos(a), 0.1 * np.sin(a), z]

    def calls(n):
        for _ in range(n):
            s = treeskel.fit_radii(treeskel.extract_skeleton(points))
            treeskel.measure(s)
            _ = s.positions, s.labels, s.edges
            try:
                treeskel.extract_skeleton(points[:3])
            except ValueError:
                pass

    calls(100)
    before = resident_mb()
    calls(1000)
    grown = resident_mb() - before
    assert grown < 10.0, "resident memory grew by %.1f MB over 1000 calls" % grown


def test_the_gil_is_released_during_the_work(data):
    cloud = treeskel.read_cloud(str(data / "tree_adtree1.xyz"))
    ticks = 0
    worker = threading.Thread(target=lambda: treeskel.model(cloud))
    start = time.monotonic()
    worker.start()
    while worker.is_alive():
        time.sleep(0.001)
        ticks += 1
    seconds = time.monotonic() - start
    # Held, this thread would not have run until the model was done.
    assert seconds > 0.2 and ticks > 50, (seconds, ticks)


def two_trees(data):
    """The bundled AdTree tree twice, 10 m apart: a plot of two trees."""
    tree = np.loadtxt(data / "tree_adtree1.xyz")
    return np.vstack([tree, tree + [10.0, 0.0, 0.0]])


def test_segment_plot_finds_both_trees_point_by_point(data):
    points = two_trees(data)
    found = treeskel.segment_plot(points)
    assert [t["id"] for t in found["trees"]] == [1, 2]
    assert abs(found["trees"][1]["x"] - found["trees"][0]["x"] - 10.0) < 0.05
    tree = found["tree"]
    assert tree.shape == (len(points),) and found["ground"].shape == (len(points),)
    half = len(points) // 2
    # Each copy is (nearly all) its own tree, and no point is in both a tree and the ground.
    assert (tree[:half] == 1).mean() > 0.95 and (tree[half:] == 2).mean() > 0.95
    assert not (found["ground"] & (tree > 0)).any()
    assert found["trees"][0]["points"] == (tree == 1).sum()
    with pytest.raises(ValueError, match="slice"):
        treeskel.segment_plot(points, stem_slice=(2.0, 1.0))


def trunk_with_leaves():
    """An upright trunk's bark (6,000 points) and a cluster of 1,500 leaf points touching its top."""
    rng = np.random.default_rng(7)
    a = rng.uniform(0, 2 * np.pi, 6000)
    z = rng.uniform(0, 3, 6000)
    bark = np.c_[0.15 * np.cos(a), 0.15 * np.sin(a), z] + rng.normal(0, 0.002, (6000, 3))
    leaves = rng.normal(0, 0.1, (1500, 3)) + [0.4, 0.0, 2.5]
    return np.vstack([bark, leaves]), 6000


def test_separate_wood_tells_bark_from_leaves():
    points, bark = trunk_with_leaves()
    wood, score = treeskel.separate_wood(points)
    assert wood.shape == (len(points),) and wood.dtype == bool and score.shape == (len(points),)
    assert wood[:bark].mean() > 0.95 and (~wood[bark:]).mean() > 0.85
    # Wood: every point scoring above -0.4, and the few joining cut-off wood back through the leaves.
    assert wood[score > -0.4].all() and (wood & (score <= -0.4)).sum() < 50
    # The same cloud lying on its side, told its up axis: the same labels.
    assert (treeskel.separate_wood(points[:, [0, 2, 1]], up="y")[0] == wood).mean() > 0.99


def test_wood_only_skeleton_is_the_skeleton_of_the_wood():
    points, _ = trunk_with_leaves()
    wood, _ = treeskel.separate_wood(points)
    only = treeskel.extract_skeleton(points, wood_only=True)
    np.testing.assert_allclose(only.positions, treeskel.extract_skeleton(points[wood]).positions, atol=1e-9)
    # The leafy cloud's skeleton reaches out into the leaves; the wood's much less far. Only the
    # leafy cloud's is warned about, naming Python's way to set the leaves aside.
    with pytest.warns(UserWarning, match="looks leafy.*wood_only=True sets them aside"):
        whole = treeskel.extract_skeleton(points)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        treeskel.extract_skeleton(points[wood])
    assert whole.positions[:, 0].max() > only.positions[:, 0].max() + 0.1


def test_wood_if_leafy_sets_aside_the_leaves_of_a_leafy_cloud_alone(data):
    points, _ = trunk_with_leaves()
    only = treeskel.extract_skeleton(points, wood_only=True)
    with warnings.catch_warnings():  # no leafy warning: the leaves were set aside
        warnings.simplefilter("error")
        leafy = treeskel.extract_skeleton(points, wood_if_leafy=True)
    np.testing.assert_allclose(leafy.positions, only.positions, atol=1e-9)
    # A leafless tree is kept whole: the same skeleton as without the option.
    bare = np.loadtxt(data / "tree_adtree1.xyz")[:, :3]
    np.testing.assert_allclose(treeskel.extract_skeleton(bare, wood_if_leafy=True).positions,
                               treeskel.extract_skeleton(bare).positions, atol=1e-9)
    with pytest.raises(ValueError, match="give one"):
        treeskel.extract_skeleton(points, wood_only=True, wood_if_leafy=True)


def tree_on_ground(data):
    """The bundled AdTree tree standing on a disc of ground 6 m across (points every 4 cm, 1 cm noise)."""
    tree = np.loadtxt(data / "tree_adtree1.xyz")[:, :3]
    base = tree[tree[:, 2] < tree[:, 2].min() + 0.3].mean(axis=0)
    g = np.arange(-3.0, 3.0001, 0.04)
    x, y = np.meshgrid(g, g)
    keep = (np.hypot(x, y) > 0.12) & (np.hypot(x, y) < 3.0)
    noise = np.random.default_rng(1).normal(0.0, 0.01, keep.sum())
    ground = np.column_stack([base[0] + x[keep], base[1] + y[keep], tree[:, 2].min() + noise])
    return np.vstack([ground, tree]), len(ground)


def test_set_ground_aside_roots_the_skeleton_in_the_stem(data):
    points, ground = tree_on_ground(data)
    with pytest.warns(UserWarning, match="set aside .* points of ground .*set_ground_aside=True"):
        aside = treeskel.extract_skeleton(points, set_ground_aside=True)
    kept = treeskel.extract_skeleton(points)  # off by default: the ground is in the skeleton
    alone = treeskel.extract_skeleton(points[ground:])
    assert abs(len(aside) - len(alone)) < 0.05 * len(alone)
    assert len(kept) > 1.1 * len(alone)  # 1.18: the disc of ground's nodes


def test_plot_runs_the_command(data, tmp_path):
    np.savetxt(tmp_path / "two.xyz", two_trees(data))
    result = treeskel.plot(tmp_path / "two.xyz", tmp_path / "out", segment_only=True, stem_slice=(0.3, 1.8))
    assert [t["status"] for t in result["trees"]] == ["segmented", "segmented"]
    assert (tmp_path / "out" / "trees" / "tree_002.ply").exists()
    with pytest.raises(ValueError, match="stem-slice"):
        treeskel.plot(tmp_path / "two.xyz", tmp_path / "bad", stem_slice=(2, 1))

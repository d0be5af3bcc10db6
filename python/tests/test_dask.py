"""treeskel.dask on a real cluster: a dask-scheduler and two dask-worker processes on the loopback
address. Every tree converted once, a worker killed mid-run loses nothing, a corrupt input fails alone."""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

import pytest

distributed = pytest.importorskip("distributed")

import treeskel.dask  # noqa: E402


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def dask_command(name):
    """The Dask command of the interpreter running the tests (Debian's: dask-scheduler, dask-worker)."""
    found = shutil.which(name)
    if found:
        return [found]
    return [sys.executable, "-m", "distributed.cli." + name.replace("-", "_")]


@pytest.fixture
def cluster(tmp_path):
    port = free_port()
    address = "tcp://127.0.0.1:%d" % port
    log = open(tmp_path / "dask.log", "w")
    procs = [subprocess.Popen(dask_command("dask-scheduler") + ["--host", "127.0.0.1", "--port", str(port),
                                                                "--dashboard-address", ":0"],
                              stdout=log, stderr=subprocess.STDOUT)]
    workers = {}
    for name in ("w1", "w2"):
        p = subprocess.Popen(dask_command("dask-worker") + [address, "--name", name, "--nthreads", "1", "--no-nanny",
                                                            "--no-dashboard", "--local-directory", str(tmp_path / name)],
                             stdout=log, stderr=subprocess.STDOUT)
        procs.append(p)
        workers[name] = p
    client = distributed.Client(address, timeout=60)
    client.wait_for_workers(2, timeout=60)
    try:
        yield client, workers
    finally:
        client.close()
        for p in procs:
            if p.poll() is None:
                p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
        log.close()


def inputs(data, folder):
    folder.mkdir()
    shutil.copy(data / "tree_rtwig.txt", folder / "rtwig.txt")
    for i in range(4):
        shutil.copy(data / "tree_adtree1.xyz", folder / ("adtree_%d.xyz" % i))
    (folder / "corrupt.xyz").write_text("1.0 2.0 3.0\n4.0 five 6.0\n")
    return folder


def check_rows(rows, out):
    names = sorted(r["name"] for r in rows)
    assert names == sorted(["rtwig", "adtree_0", "adtree_1", "adtree_2", "adtree_3", "corrupt"])  # each once
    for r in rows:
        if r["name"] == "corrupt":
            assert r["status"] == "failed" and "line 2" in r["error"], r
            assert not (out / "corrupt.glb").exists()
            continue
        assert r["status"] == "ok", r
        assert r["points"] == (14667 if r["name"] == "rtwig" else 11855)
        for path in r["outputs"]:
            assert os.path.getsize(path) > 0
        report = json.loads((out / (r["name"] + "_report.json")).read_text())
        assert report["mesh"]["closed"] and report["mesh"]["triangles"] == r["triangles"]
        glb = (out / (r["name"] + ".glb")).read_bytes()
        assert glb[:4] == b"glTF" and int.from_bytes(glb[8:12], "little") == len(glb)  # whole
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converted"] == 5 and summary["failed"] == 1
    assert len((out / "summary.csv").read_text().splitlines()) == 7


def test_every_tree_once_and_a_corrupt_one_alone(cluster, data, tmp_path):
    client, _ = cluster
    folder = inputs(data, tmp_path / "in")
    rows = treeskel.dask.convert([folder], tmp_path / "out", client=client)
    check_rows(rows, tmp_path / "out")
    # Run again with resume: nothing is converted twice.
    again = treeskel.dask.convert([folder], tmp_path / "out", client=client, resume=True)
    assert [r["resumed"] for r in again if r["status"] == "ok"] == [True] * 5
    # Leaves set aside are written beside each model, as batch writes them: the leafy tree's, and for
    # the leafless one (kept whole by wood_if_leafy) a cloud of no points.
    wood = treeskel.dask.convert([data / "tree_arbor_leafy.xyz", data / "tree_adtree1.xyz"], tmp_path / "wood",
                                 client=client, wood_if_leafy=True)
    row = {r["name"]: r for r in wood}
    assert [r["status"] for r in wood] == ["ok", "ok"], wood
    leafy = json.loads((tmp_path / "wood" / "tree_arbor_leafy_report.json").read_text())
    assert leafy["wood_if_leafy"]["leaves_set_aside"]
    assert row["tree_arbor_leafy"]["points"] == leafy["wood_only"]["wood_points"]
    assert row["tree_arbor_leafy"]["leaf_points"] == leafy["wood_only"]["leaf_points"]
    assert row["tree_adtree1"]["leaf_points"] == 0 and rows[0]["leaf_points"] is None
    header = (tmp_path / "wood" / "tree_arbor_leafy_leaves.ply").read_bytes()[:300]
    assert b"element vertex %d\n" % leafy["wood_only"]["leaf_points"] in header
    assert b"element vertex 0\n" in (tmp_path / "wood" / "tree_adtree1_leaves.ply").read_bytes()
    assert str(tmp_path / "wood" / "tree_arbor_leafy_leaves.ply") in row["tree_arbor_leafy"]["outputs"]


def test_a_worker_killed_mid_run_loses_nothing(cluster, data, tmp_path):
    client, workers = cluster
    folder = inputs(data, tmp_path / "in")
    out = tmp_path / "out"
    result = {}
    run = threading.Thread(target=lambda: result.update(rows=treeskel.dask.convert([folder], out, client=client)))
    run.start()
    # Once w1 is working on a tree, kill it outright.
    w1 = [a for a, w in client.scheduler_info()["workers"].items() if w["name"] == "w1"][0]
    give_up = time.monotonic() + 60
    while not client.processing().get(w1) and time.monotonic() < give_up:
        time.sleep(0.01)
    assert client.processing().get(w1), "w1 never got a task"
    time.sleep(0.3)
    os.kill(workers["w1"].pid, signal.SIGKILL)
    run.join(timeout=300)
    assert not run.is_alive()
    assert workers["w1"].poll() == -signal.SIGKILL
    assert len(client.scheduler_info()["workers"]) == 1  # w2 finished w1's trees
    check_rows(result["rows"], out)

"""Many trees on a Dask cluster: one task per tree, each written by the worker that converts it.

    from dask.distributed import Client
    import treeskel.dask

    rows = treeskel.dask.convert(["scans/"], "models/", client=Client("tcp://scheduler:8786"))
    failed = [r for r in rows if r["status"] != "ok"]

Each task runs the ``treeskel`` command on one tree (``model``, or ``skeletonize`` with
``model=None``), so a tree that crashes or runs out of memory takes its own process down, not the
worker. The inputs are found and named as ``treeskel batch`` finds and names them (files, folders
searched recursively, patterns), the outputs are the same (``NAME.glb``, ``NAME_skeleton.json`` with
``skeleton="json"``, ``NAME_report.json``) and so are the rows of ``summary.csv`` and
``summary.json``, which ``convert`` writes into the output folder and returns. Every output is
written whole or not at all: when a worker dies mid-tree, the scheduler runs the task again
elsewhere and the tree's files are those of the run that finished. The output folder must be one
that every worker sees (a shared file system).
"""

import csv
import io
import json
import os
import shutil
import subprocess
import tempfile
import time

from . import _treeskel

#: The fields of a summary row, in the order of ``treeskel batch``'s summary.csv.
COLUMNS = [
    "input", "name", "status", "resumed", "seconds", "points", "leaf_points", "nodes", "height", "dbh", "volume",
    "branch_points", "endpoints", "branches_by_order", "triangles", "components", "skeleton_coverage",
    "warnings", "outputs", "error",
]


def executable():
    """The ``treeskel`` command the tasks run: $TREESKEL_EXE, else the one built with this package
    (when it is imported from the build tree) or installed with it (PREFIX/bin beside
    PREFIX/lib/pythonX.Y/dist-packages), else the first on the PATH."""
    here = os.path.dirname(os.path.abspath(_treeskel.__file__))
    candidates = [os.environ.get("TREESKEL_EXE")]
    if os.path.realpath(here) == os.path.realpath(_treeskel._built_package):
        candidates.append(_treeskel._built_executable)
    candidates += [os.path.join(here, "..", "..", "..", "..", "bin", "treeskel"), _treeskel._installed_executable]
    for candidate in candidates:
        if candidate and os.access(candidate, os.X_OK):
            return os.path.normpath(candidate)
    found = shutil.which("treeskel")
    if found:
        return found
    raise RuntimeError("the treeskel command was not found: build or install it, or set TREESKEL_EXE")


def _outputs(out_dir, name, model, skeleton, leaves=False):
    """A tree's output files, its report last; with ``leaves``, NAME_leaves.ply before it."""
    base = os.path.join(out_dir, name)
    outputs = []
    if model:
        outputs.append(base + "." + model)
    if skeleton:
        outputs.append(base + "_skeleton." + skeleton)
    if leaves:
        outputs.append(base + "_leaves.ply")
    outputs.append(base + "_report.json")
    return outputs


def _fact(report, *path):
    value = report
    for key in path:
        if not isinstance(value, dict) or key not in value:
            return None
        value = value[key]
    return value


def _row(path, name, status, seconds=None, outputs=(), report=None, error=None, resumed=False):
    report = report or {}
    if status == "ok":
        total = _fact(report, "seconds", "total")
        seconds = total if total is not None else _fact(report, "seconds")
    return {
        "input": path,
        "name": name,
        "status": status,
        "resumed": resumed,
        "seconds": seconds,
        "points": _fact(report, "points"),  # with leaves set aside, the wood's
        "leaf_points": _leaf_points(report),
        "nodes": _fact(report, "nodes"),
        "height": _fact(report, "measurements", "height"),
        "dbh": _fact(report, "measurements", "dbh"),
        "volume": _fact(report, "measurements", "volume"),
        "branch_points": _fact(report, "branch_points"),
        "endpoints": _fact(report, "endpoints"),
        "branches_by_order": _fact(report, "measurements", "branches_by_order"),
        "triangles": _fact(report, "mesh", "triangles"),
        "components": _fact(report, "mesh", "components"),
        "skeleton_coverage": _fact(report, "mesh", "skeleton_coverage"),
        "warnings": report.get("warnings", []),
        "outputs": list(outputs) if status == "ok" else [],
        "error": error,
    }


def _leaf_points(report):
    """The points set aside as leaves: 0 when wood_if_leafy kept the tree whole, None when not looked for."""
    counted = _fact(report, "wood_only", "leaf_points")
    return 0 if counted is None and "wood_if_leafy" in report else counted


def _read_report(path):
    with open(path, encoding="utf-8") as f:
        report = json.load(f)
    if not isinstance(report, dict):
        raise ValueError(path + " is not a treeskel report")
    return report


def _complete(outputs):
    """The earlier run's report, when every output of a tree is there and its report reads."""
    if not all(os.path.isfile(p) for p in outputs):
        return None
    try:
        return _read_report(outputs[-1])
    except (OSError, ValueError):
        return None


def _error_from(stderr, returncode):
    lines = [line for line in stderr.splitlines() if line.strip()]
    errors = [line[len("treeskel: "):] for line in lines if line.startswith("treeskel: ")]
    text = errors[-1] if errors else (lines[-1] if lines else "")
    if text.startswith("error: "):
        text = text[len("error: "):]
    if returncode < 0:
        what = "killed (signal 9: out of memory?)" if returncode == -9 else "ended by signal %d" % -returncode
        return what + (" after: " + text if text else "")
    return text or "exit code %d" % returncode


def _threads_here():
    """Cores for one tree: the machine's, shared among the worker's task threads."""
    try:
        from distributed import get_worker

        worker = get_worker()
        return max(1, (os.cpu_count() or 1) // max(1, getattr(worker, "state", worker).nthreads))
    except (ImportError, ValueError, AttributeError):
        return 1


def convert_one(path, name, out_dir, model="glb", skeleton=None, args=(), command=None, leaves=False):
    """Converts one tree with the ``treeskel`` command, writing its outputs into ``out_dir``; returns
    its summary row (a failure is a row with status "failed", not an exception). ``leaves``: ``args``
    set leaves aside (--wood-only, --wood-if-leafy), written as NAME_leaves.ply, as ``batch`` does."""
    outputs = _outputs(out_dir, name, model, skeleton, leaves)
    os.makedirs(os.path.dirname(outputs[0]) or ".", exist_ok=True)
    cmd = [command or executable(), "--threads", str(_threads_here())]
    if model:
        cmd += ["model", path, "-o", outputs[0]]
        if skeleton:
            cmd += ["--skeleton", outputs[1]]
    else:
        cmd += ["skeletonize", path, "-o", outputs[0]]
    if leaves:
        cmd += ["--leaves", outputs[-2]]
    cmd += ["--report", outputs[-1], "-q"] + list(args)
    start = time.monotonic()
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, errors="replace")
    seconds = time.monotonic() - start
    if done.returncode != 0:
        return _row(path, name, "failed", seconds, error=_error_from(done.stderr, done.returncode))
    try:
        return _row(path, name, "ok", seconds, outputs, _read_report(outputs[-1]))
    except (OSError, ValueError) as e:
        return _row(path, name, "failed", seconds, error="its report could not be read: %s" % e)


def _csv_text(value):
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list):
        return "; ".join(_csv_text(v) for v in value)
    return str(value)


def _write_whole(path, text):
    folder = os.path.dirname(os.path.abspath(path))
    fd, temp = tempfile.mkstemp(prefix=".treeskel-summary-", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(temp, path)
    except BaseException:
        if os.path.exists(temp):
            os.remove(temp)
        raise


def write_summary(rows, out_dir, stem="summary"):
    """Writes ``rows`` as OUT_DIR/STEM.csv and STEM.json (the columns of ``treeskel batch``)."""
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(COLUMNS)
    for r in rows:
        writer.writerow([_csv_text(r[c]) for c in COLUMNS])
    _write_whole(os.path.join(out_dir, stem + ".csv"), text.getvalue())
    ok = sum(r["status"] == "ok" for r in rows)
    failed = sum(r["status"] == "failed" for r in rows)
    doc = {"treeskel": _treeskel.__version__, "output_folder": out_dir, "shard": None, "inputs": len(rows),
           "converted": ok, "failed": failed, "not_run": len(rows) - ok - failed, "trees": rows}
    _write_whole(os.path.join(out_dir, stem + ".json"), json.dumps(doc, indent=2) + "\n")


def convert(paths, out_dir, client=None, *, model="glb", skeleton=None, resume=False, summary=True, **options):
    """Converts every tree that ``paths`` name (files, folders, patterns) on a Dask cluster, one task
    per tree, and returns the summary rows in the inputs' order.

    client: a ``distributed.Client``; None takes the current one, or starts a local cluster (one
        worker process per core) for the call.
    model: the mesh format ("glb", "gltf", "obj", "ply", "stl"), or None for skeletons only.
    skeleton: also the skeleton in this format ("json", "ply", "obj").
    resume: leave out the trees whose outputs and report are all there from an earlier run.
    summary: write summary.csv and summary.json into ``out_dir``.
    options: the ``treeskel model`` (or ``skeletonize``) options, as keyword arguments (up="y",
        exponent=2.5, no_unite=True); checked before any task is submitted (ValueError).
    """
    if model is None and skeleton is None:
        raise ValueError("nothing to write: give a model format, a skeleton format or both")
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    out_dir = os.fspath(out_dir)
    args = _treeskel._command_args(model is not None, **options)
    leaves = "--wood-only" in args or "--wood-if-leafy" in args  # their leaves written, as batch writes them
    command = executable()
    os.makedirs(out_dir, exist_ok=True)
    planned, _passed_over = _treeskel._plan_inputs([os.fspath(p) for p in paths], out_dir)
    if not planned:
        raise ValueError("no input: name cloud files, folders holding them, or patterns")
    rows = [None] * len(planned)
    todo = []
    for i, (path, name, error) in enumerate(planned):
        outputs = _outputs(out_dir, name, model, skeleton, leaves)
        if error:
            rows[i] = _row(path, name, "failed", 0.0, error=error)
            continue
        earlier = _complete(outputs) if resume else None
        if earlier is not None:
            rows[i] = _row(path, name, "ok", outputs=outputs, report=earlier, resumed=True)
            continue
        todo.append((i, path, name))

    if todo:
        from distributed import Client, LocalCluster, as_completed, default_client

        own = None
        if client is None:
            try:
                client = default_client()
            except ValueError:
                own = Client(LocalCluster(n_workers=os.cpu_count() or 1, threads_per_worker=1, processes=True))
                client = own
        try:
            futures = {}
            for i, path, name in todo:
                future = client.submit(convert_one, path, name, out_dir, model, skeleton, args, command, leaves,
                                       pure=False)
                futures[future] = i
            for future in as_completed(list(futures)):
                i = futures[future]
                _, path, name = planned[i]
                try:
                    rows[i] = future.result()
                except Exception as e:  # the task itself failed: its workers died again and again
                    rows[i] = _row(path, name, "failed", error="%s: %s" % (type(e).__name__, e))
        finally:
            if own is not None:
                own.close()
                own.cluster.close()
    if summary:
        write_summary(rows, out_dir)
    return rows

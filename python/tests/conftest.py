import os
import pathlib

import pytest


@pytest.fixture(scope="session")
def data():
    """The bundled example clouds."""
    return pathlib.Path(os.environ.get("TREESKEL_TEST_DATA", pathlib.Path(__file__).parents[2] / "data"))


@pytest.fixture(scope="session")
def exe():
    """The treeskel command of the same build."""
    path = os.environ.get("TREESKEL_EXE")
    if not path:
        pytest.skip("TREESKEL_EXE is not set (run through ctest)")
    return path

"""What the Python tests share: where the data and the command line are,
and a skip for data that is not there."""
import os

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DATA = os.environ.get("DATA", os.path.join(ROOT, "..", "shared", "data"))
CLI = os.environ.get("RELIEF", os.path.join(ROOT, "build", "relief"))


def need(path):
    if not os.path.exists(path):
        pytest.skip(f"{path} not found")
    return path

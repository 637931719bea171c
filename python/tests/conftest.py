"""Shared fixtures: the real-data folder and the plucker program (tests skip without them)."""
import os
import pathlib
import threading

import numpy as np
import pytest


def _shared_data() -> pathlib.Path:
    default = pathlib.Path(__file__).resolve().parents[2] / ".." / "shared" / "data"
    return pathlib.Path(os.environ.get("PLUCKER_SHARED_DATA_DIR", str(default)))


@pytest.fixture
def kitti_sequence() -> pathlib.Path:
    seq = _shared_data() / "kitti-odometry-00" / "sequences" / "00"
    if not (seq / "velodyne").is_dir():
        pytest.skip(f"shared KITTI extract not found at {seq}")
    return seq


@pytest.fixture
def euroc_folder() -> pathlib.Path:
    folder = _shared_data() / "euroc-v101-head"
    if not (folder / "mav0").is_dir():
        pytest.skip(f"shared EuRoC extract not found at {folder}")
    return folder


@pytest.fixture
def plucker_cli() -> str:
    cli = os.environ.get("PLUCKER_CLI", "")
    if not cli or not os.access(cli, os.X_OK):
        pytest.skip("PLUCKER_CLI (the plucker program) is not set")
    return cli


def random_pose(rng: np.random.Generator, translation: float = 2.0) -> np.ndarray:
    import plucker
    return plucker.se3_exp(np.concatenate([rng.uniform(-np.pi / 2, np.pi / 2, 3),
                                           rng.uniform(-translation, translation, 3)]))


def run_in_two_threads(run):
    """run() in two threads at once; their results, after re-raising the first error."""
    results, errors = {}, []

    def body(key):
        try:
            results[key] = run()
        except Exception as e:  # reported by the calling thread
            errors.append(e)

    threads = [threading.Thread(target=body, args=(k,)) for k in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert not errors, errors
    return [results[0], results[1]]

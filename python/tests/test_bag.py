"""plucker.Bag: a simulated LiDAR folder written as a ROS 1 .bag and a ROS 2 .db3 by
`plucker bag from-lidar` reads back in Python as the folder's scans (the same points, in order,
with the same stamps in both formats); bag_info; errors are IoErrors naming the file."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import plucker

FRAMES = 3


@pytest.fixture(scope="module")
def bags(tmp_path_factory):
    cli = os.environ.get("PLUCKER_CLI", "")
    if not cli or not os.access(cli, os.X_OK):
        pytest.skip("PLUCKER_CLI (the plucker program) is not set")
    root = tmp_path_factory.mktemp("bags")
    sim = root / "sim"
    subprocess.run([cli, "sim", "lidar", "--out", str(sim), "--frames", str(FRAMES)], check=True,
                   capture_output=True)
    for name in ("sim.bag", "sim.db3"):
        subprocess.run([cli, "bag", "from-lidar", str(sim), str(root / name), "--quiet"],
                       check=True, capture_output=True)
    return sim, root / "sim.bag", root / "sim.db3"


def scans(path: pathlib.Path):
    bag = plucker.Bag(str(path))
    bag.select(["/points"])
    messages = list(bag)
    assert bag.stats["messages"] == FRAMES and bag.stats["unreadable"] == 0
    return messages


def test_bag_scans_are_the_folders(bags):
    sim, ros1, ros2 = bags
    files = sorted((sim / "velodyne").glob("*.bin"))
    assert len(files) == FRAMES
    for path in (ros1, ros2):
        messages = scans(path)
        assert [m["index"] for m in messages] == list(range(FRAMES))
        for m, f in zip(messages, files):
            assert m["topic"] == "/points" and m["type"] == "sensor_msgs/PointCloud2"
            assert m["error"] == "" and m["data"]["points"].shape[1] == 3
            folder = plucker.read_kitti_bin(str(f))
            assert np.allclose(m["data"]["points"], folder[:, :3], atol=1e-6)
    stamps = [[m["stamp_ns"] for m in scans(p)] for p in (ros1, ros2)]
    assert stamps[0] == stamps[1] and stamps[0] == sorted(stamps[0])


def test_bag_info(bags):
    _, ros1, ros2 = bags
    for path, fmt in ((ros1, "ROS 1"), (ros2, "rosbag2")):
        info = plucker.bag_info(str(path))
        assert info["format"].startswith(fmt) and info["messages"] == FRAMES
        assert [t["topic"] for t in info["topics"]] == ["/points"]
        # ROS 2 names its types with /msg/ (sensor_msgs/msg/PointCloud2), as the bag has them
        assert info["topics"][0]["type"].replace("/msg/", "/") == "sensor_msgs/PointCloud2"
        assert plucker.Bag(str(path)).info == info


def test_bag_errors(bags, tmp_path):
    _, ros1, _ = bags
    not_a_bag = tmp_path / "x.bag"
    not_a_bag.write_text("hello\n")
    with pytest.raises(plucker.IoError, match="x.bag"):
        plucker.Bag(str(not_a_bag))
    with pytest.raises(plucker.BagError, match="no_such"):
        plucker.Bag(str(tmp_path / "no_such.bag"))
    bag = plucker.Bag(str(ros1))
    with pytest.raises(ValueError, match="select"):
        next(iter(bag))
    with pytest.raises(plucker.IoError, match="/points"):  # names the topics the bag has
        bag.select(["/nothing"])

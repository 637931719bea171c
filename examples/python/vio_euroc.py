#!/usr/bin/env python3
"""Visual-inertial odometry on a EuRoC folder from Python, fed as a driver delivers the data.

    PYTHONPATH=<prefix>/lib/python3/dist-packages python3 examples/python/vio_euroc.py \\
        ../shared/data/euroc-v101-head --out vio.tum

The IMU up to each image's time, then the image; prints each frame's status and writes the refined
trajectory T_w_b (body frame, the dataset's clock) as `plucker vio --out` writes it.
"""
import argparse

import numpy as np

import plucker

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("euroc", help="EuRoC folder (mav0/ inside, or mav0 itself)")
parser.add_argument("--out", default="vio.tum", help="TUM trajectory (t tx ty tz qx qy qz qw)")
args = parser.parse_args()

data = plucker.read_euroc(args.euroc)
camera = data["camera"]  # T_b_c_tq: tx ty tz qx qy qz qw, exact (a 4x4 would do, rounded)
vio = plucker.VisualInertialOdometry(camera, camera["T_b_c_tq"], data["imu_model"])
imu, fed = data["imu"], 0
for t, image in zip(data["frame_times"], data["images"]):
    end = min(int(np.searchsorted(imu[:, 0], t)) + 1, len(imu))  # the IMU up to t
    if end > fed:
        vio.add_imu(imu[fed:end])
        fed = end
    r = vio.add_image(float(t), plucker.read_gray_image(image))
    where = "" if r["T_w_b"] is None else " at x y z %.3f %.3f %.3f m" % tuple(r["T_w_b"][:3, 3])
    print(f"frame {r['frame']:4d} t {t:7.3f} s: {r['status']}{where}")
vio.add_imu(imu[fed:])
vio.finish()
refined = vio.refined_trajectory()
plucker.write_tum(args.out, refined["times"], refined["T_w_b_tq"], origin_ns=data["origin_ns"],
                  comments=["T_w_b: the body (IMU) frame, refined (frames before the start backfilled)"])
print(f"{vio.initialization['method']} start; wrote {len(refined['times'])} poses to {args.out}")

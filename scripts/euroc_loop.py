#!/usr/bin/env python3
"""A EuRoC folder of SRC's cam0 images and imu0 samples repeated LOOPS times, the stamps of loop k
shifted by k * PERIOD_S seconds (default 17: longer than the MH_05 clip's IMU log). The images are
symbolic links (nothing copied); for making large bags (`plucker bag from-euroc DST big.db3`) to
measure memory, not for accuracy (the trajectory jumps back at each loop).

    scripts/euroc_loop.py SRC DST LOOPS [PERIOD_S]
"""
import os
import sys


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    src = os.path.abspath(os.path.join(sys.argv[1], "mav0"))
    dst, loops = sys.argv[2], int(sys.argv[3])
    period = int(float(sys.argv[4] if len(sys.argv) == 5 else 17) * 1e9)
    os.makedirs(os.path.join(dst, "mav0", "cam0", "data"))
    os.makedirs(os.path.join(dst, "mav0", "imu0"))
    for f in ("cam0/sensor.yaml", "imu0/sensor.yaml"):
        os.symlink(os.path.join(src, f), os.path.join(dst, "mav0", f))
    cam = open(os.path.join(src, "cam0", "data.csv")).read().splitlines()
    imu = open(os.path.join(src, "imu0", "data.csv")).read().splitlines()
    with open(os.path.join(dst, "mav0", "cam0", "data.csv"), "w") as c, \
            open(os.path.join(dst, "mav0", "imu0", "data.csv"), "w") as i:
        c.write(cam[0] + "\n")
        i.write(imu[0] + "\n")
        for k in range(loops):
            for line in cam[1:]:
                t, name = line.strip().split(",")
                nt = int(t) + k * period
                os.symlink(os.path.join(src, "cam0", "data", name),
                           os.path.join(dst, "mav0", "cam0", "data", f"{nt}.png"))
                c.write(f"{nt},{nt}.png\n")
            for line in imu[1:]:
                t, rest = line.split(",", 1)
                i.write(f"{int(t) + k * period},{rest}\n")


if __name__ == "__main__":
    main()

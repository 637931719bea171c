"""plucker: geometric features for SLAM from Python.

Points, lines (Plücker coordinates, orthonormal representation) and planes with analytic
Jacobians; LOAM-style LiDAR odometry; the online visual(-inertial) odometry; readers and trajectory metrics. Arrays are numpy; poses
are 4x4 matrices named T_a_b (p_a = T_a_b p_b). Errors are exceptions carrying the C++ message
(IoError, an OSError, for files; ValueError / TypeError for bad arrays and options).

    import plucker
    odometry = plucker.LidarOdometry()
    T_w_l = odometry.register(plucker.read_kitti_bin("000000.bin"))
"""
import sys as _sys

from ._plucker import *  # noqa: F401,F403
from ._plucker import (IoError, LidarOdometry, MonocularOdometry,  # noqa: F401
                       VisualInertialOdometry, factors)

_sys.modules[__name__ + ".factors"] = factors  # `import plucker.factors` works too

__version__ = "0.1.0"
